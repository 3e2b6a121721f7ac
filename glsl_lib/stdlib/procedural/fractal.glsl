// requires: stdlib/procedural/perlin.glsl
// Fractional Brownian motion (Musgrave, "Texturing and Modeling", ch. 16): octaves of Perlin noise summed.

// One definition per (result type, point type, noise): octaves of noise, each lacunarity times finer
// and diminish times weaker.
#define MG_FBM(R, P, NOISE, NAME)                                               \
    R NAME(P p, int octaves, float lacunarity, float diminish)                  \
    {                                                                           \
        R sum = R(0.0);                                                         \
        float weight = 1.0;                                                     \
        for (int i = 0; i < octaves; ++i)                                       \
        {                                                                       \
            sum += weight * NOISE(p);                                           \
            weight *= diminish;                                                 \
            p *= lacunarity;                                                    \
        }                                                                       \
        return sum;                                                             \
    }

MG_FBM(float, vec2, mg_perlin, mg_fbm)
MG_FBM(float, vec3, mg_perlin, mg_fbm)
MG_FBM(vec3, vec2, mg_perlin_vec3, mg_fbm_vec3)
MG_FBM(vec3, vec3, mg_perlin_vec3, mg_fbm_vec3)

// extra scalar channels sample the scalar fBm at a fixed, decorrelating offset
const vec2 MG_FBM_OFFSET_2D = vec2(19.0, 193.0);
const vec3 MG_FBM_OFFSET_3D = vec3(19.0, 193.0, 17.0);

float mg_fractal2d(float a, int octaves, float lacunarity, float diminish, vec2 p)
{
    return mg_fbm(p, octaves, lacunarity, diminish) * a;
}
vec2 mg_fractal2d(vec2 a, int octaves, float lacunarity, float diminish, vec2 p)
{
    return vec2(mg_fbm(p, octaves, lacunarity, diminish),
                mg_fbm(p + MG_FBM_OFFSET_2D, octaves, lacunarity, diminish)) * a;
}
vec3 mg_fractal2d(vec3 a, int octaves, float lacunarity, float diminish, vec2 p)
{
    return mg_fbm_vec3(p, octaves, lacunarity, diminish) * a;
}
vec4 mg_fractal2d(vec4 a, int octaves, float lacunarity, float diminish, vec2 p)
{
    return vec4(mg_fbm_vec3(p, octaves, lacunarity, diminish),
                mg_fbm(p + MG_FBM_OFFSET_2D, octaves, lacunarity, diminish)) * a;
}

float mg_fractal3d(float a, int octaves, float lacunarity, float diminish, vec3 p)
{
    return mg_fbm(p, octaves, lacunarity, diminish) * a;
}
vec2 mg_fractal3d(vec2 a, int octaves, float lacunarity, float diminish, vec3 p)
{
    return vec2(mg_fbm(p, octaves, lacunarity, diminish),
                mg_fbm(p + MG_FBM_OFFSET_3D, octaves, lacunarity, diminish)) * a;
}
vec3 mg_fractal3d(vec3 a, int octaves, float lacunarity, float diminish, vec3 p)
{
    return mg_fbm_vec3(p, octaves, lacunarity, diminish) * a;
}
vec4 mg_fractal3d(vec4 a, int octaves, float lacunarity, float diminish, vec3 p)
{
    return vec4(mg_fbm_vec3(p, octaves, lacunarity, diminish),
                mg_fbm(p + MG_FBM_OFFSET_3D, octaves, lacunarity, diminish)) * a;
}
