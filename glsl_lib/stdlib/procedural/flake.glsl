// requires: stdlib/procedural/hash.glsl
// Flake pattern (mtlxgen's own construction, not MaterialX's): one randomly rotated square platelet per lattice cell, stacked by random depth.

struct MgFlake
{
    int id;            // 24-bit cell hash, 0 where no flake covers the point
    float rand;        // uniform random value of the flake
    float presence;    // 1 for the shallowest possible flake, falling to 0 with depth
    vec3 normal;       // the flake's tilted normal
};

// four uniform values in [0, 1) for a cell, from one hash per channel
vec4 mg_flake_cell_random(ivec3 cell)
{
    return vec4(mg_hash_to_01(mg_hash(cell.x, cell.y, cell.z, 0)), mg_hash_to_01(mg_hash(cell.x, cell.y, cell.z, 1)),
                mg_hash_to_01(mg_hash(cell.x, cell.y, cell.z, 2)), mg_hash_to_01(mg_hash(cell.x, cell.y, cell.z, 3)));
}

// The flake's normal: the surface normal tilted in the tangent frame by a random direction whose
// slope grows with roughness.
vec3 mg_flake_normal(ivec3 cell, float roughness, vec3 N, vec3 T, vec3 B)
{
    float phi = 6.28318530718 * mg_hash_to_01(mg_hash(cell.x, cell.y, cell.z, 4));
    float slope = roughness * sqrt(mg_hash_to_01(mg_hash(cell.x, cell.y, cell.z, 5)));
    return normalize(N + slope * (cos(phi) * T + sin(phi) * B));
}

MgFlake mg_flake_none(vec3 N)
{
    return MgFlake(0, 0.0, 0.0, N);
}

MgFlake mg_flake_hit(ivec3 cell, vec4 r, float roughness, vec3 N, vec3 T, vec3 B)
{
    int id = int(mg_hash(cell.x, cell.y, cell.z) & 0xFFFFFFu) | 1;
    float rand = mg_hash_to_01(mg_hash(cell.x, cell.y, cell.z, 6));
    return MgFlake(id, rand, 1.0 - r.z, mg_flake_normal(cell, roughness, N, T, B));
}

// 2D: squares of half-width 0.7 cell centred at a random point of their cell, at random orientation;
// a cell carries a flake with probability `coverage`; the shallowest flake covering the point wins.
MgFlake mg_flake2d(float size, float roughness, float coverage, vec2 texcoord, vec3 N, vec3 T, vec3 B)
{
    vec2 p = texcoord / max(size, 1e-6);
    ivec2 base = ivec2(floor(p));
    float best = 2.0;
    MgFlake result = mg_flake_none(N);
    for (int i = -1; i <= 1; ++i)
    {
        for (int j = -1; j <= 1; ++j)
        {
            ivec3 cell = ivec3(base + ivec2(i, j), 0);
            vec4 r = mg_flake_cell_random(cell);
            if (r.w >= coverage || r.z >= best)
                continue;
            float angle = 6.28318530718 * r.y;
            vec2 d = p - (vec2(cell.xy) + vec2(r.x, fract(r.x * 7.0 + r.y * 13.0)));
            vec2 local = mat2(cos(angle), -sin(angle), sin(angle), cos(angle)) * d;
            if (max(abs(local.x), abs(local.y)) < 0.7)
            {
                best = r.z;
                result = mg_flake_hit(cell, r, roughness, N, T, B);
            }
        }
    }
    return result;
}

// 3D: spheres of radius 0.7 cell about a random point of their cell; otherwise as in 2D.
MgFlake mg_flake3d(float size, float roughness, float coverage, vec3 position, vec3 N, vec3 T, vec3 B)
{
    vec3 p = position / max(size, 1e-6);
    ivec3 base = ivec3(floor(p));
    float best = 2.0;
    MgFlake result = mg_flake_none(N);
    for (int i = -1; i <= 1; ++i)
    {
        for (int j = -1; j <= 1; ++j)
        {
            for (int k = -1; k <= 1; ++k)
            {
                ivec3 cell = base + ivec3(i, j, k);
                vec4 r = mg_flake_cell_random(cell);
                if (r.w >= coverage || r.z >= best)
                    continue;
                vec3 centre = vec3(cell) + vec3(r.x, r.y, fract(r.x * 7.0 + r.y * 13.0));
                if (length(p - centre) < 0.7)
                {
                    best = r.z;
                    result = mg_flake_hit(cell, r, roughness, N, T, B);
                }
            }
        }
    }
    return result;
}
