// requires: stdlib/procedural/cellnoise.glsl
// Cellular noise after Steven Worley, "A Cellular Texture Basis Function" (SIGGRAPH 1996): one jittered feature point per cell.

// Squared distances to the three nearest feature points among the 3x3 (3x3x3) neighbouring cells,
// and the cell holding the nearest one.
vec3 mg_worley_sqdist(vec2 p, float jitter, out vec2 nearest_cell)
{
    int X, Y;
    vec2 local = vec2(mg_floorfrac(p.x, X), mg_floorfrac(p.y, Y));
    vec3 d = vec3(1e6);
    nearest_cell = vec2(0.0);
    for (int i = -1; i <= 1; ++i)
    {
        for (int j = -1; j <= 1; ++j)
        {
            vec2 cell = vec2(float(X + i), float(Y + j));
            vec2 feature = (mg_cellnoise_vec3(cell).xy - 0.5) * jitter + 0.5;
            vec2 diff = vec2(float(i), float(j)) + feature - local;
            float dist = dot(diff, diff);
            if (dist < d.x)
            {
                d = vec3(dist, d.xy);
                nearest_cell = cell;
            }
            else if (dist < d.y)
                d = vec3(d.x, dist, d.y);
            else if (dist < d.z)
                d.z = dist;
        }
    }
    return d;
}

vec3 mg_worley_sqdist(vec3 p, float jitter, out vec3 nearest_cell)
{
    int X, Y, Z;
    vec3 local = vec3(mg_floorfrac(p.x, X), mg_floorfrac(p.y, Y), mg_floorfrac(p.z, Z));
    vec3 d = vec3(1e6);
    nearest_cell = vec3(0.0);
    for (int i = -1; i <= 1; ++i)
    {
        for (int j = -1; j <= 1; ++j)
        {
            for (int k = -1; k <= 1; ++k)
            {
                vec3 cell = vec3(float(X + i), float(Y + j), float(Z + k));
                vec3 feature = (mg_cellnoise_vec3(cell) - 0.5) * jitter + 0.5;
                vec3 diff = vec3(float(i), float(j), float(k)) + feature - local;
                float dist = dot(diff, diff);
                if (dist < d.x)
                {
                    d = vec3(dist, d.xy);
                    nearest_cell = cell;
                }
                else if (dist < d.y)
                    d = vec3(d.x, dist, d.y);
                else if (dist < d.z)
                    d.z = dist;
            }
        }
    }
    return d;
}

// style 0 (Distance): distances to the nearest 1, 2 or 3 feature points;
// style 1 (Solid): a constant random value per Voronoi cell (that of the nearest feature point's cell).
#define MG_WORLEY(R, NAME, P, SOLID, DIST)                                      \
    R NAME(P p, float jitter, int style)                                        \
    {                                                                           \
        P c;                                                                    \
        vec3 d = mg_worley_sqdist(p, jitter, c);                                \
        return style == 1 ? SOLID : DIST;                                       \
    }

MG_WORLEY(float, mg_worley_float, vec2, mg_cellnoise(c), sqrt(d.x))
MG_WORLEY(vec2, mg_worley_vec2, vec2, mg_cellnoise_vec3(c).xy, sqrt(d.xy))
MG_WORLEY(vec3, mg_worley_vec3, vec2, mg_cellnoise_vec3(c), sqrt(d))
MG_WORLEY(float, mg_worley_float, vec3, mg_cellnoise(c), sqrt(d.x))
MG_WORLEY(vec2, mg_worley_vec2, vec3, mg_cellnoise_vec3(c).xy, sqrt(d.xy))
MG_WORLEY(vec3, mg_worley_vec3, vec3, mg_cellnoise_vec3(c), sqrt(d))
