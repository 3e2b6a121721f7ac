// requires: stdlib/procedural/hash.glsl
// Gradient noise after Ken Perlin, "Improving Noise" (SIGGRAPH 2002): quintic fade, hashed gradient selection.

float mg_fade(float t)
{
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// gradient . offset for one lattice corner; 8 directions in 2D, 12 (+4 repeated) edges of a cube in 3D
float mg_grad(uint h, float x, float y)
{
    uint k = h & 7u;
    float u = k < 4u ? x : y;
    float v = 2.0 * (k < 4u ? y : x);
    return ((k & 1u) != 0u ? -u : u) + ((k & 2u) != 0u ? -v : v);
}

float mg_grad(uint h, float x, float y, float z)
{
    uint k = h & 15u;
    float u = k < 8u ? x : y;
    float v = k < 4u ? y : ((k == 12u || k == 14u) ? x : z);
    return ((k & 1u) != 0u ? -u : u) + ((k & 2u) != 0u ? -v : v);
}

vec3 mg_grad(uvec3 h, float x, float y)
{
    return vec3(mg_grad(h.x, x, y), mg_grad(h.y, x, y), mg_grad(h.z, x, y));
}

vec3 mg_grad(uvec3 h, float x, float y, float z)
{
    return vec3(mg_grad(h.x, x, y, z), mg_grad(h.y, x, y, z), mg_grad(h.z, x, y, z));
}

// bilinear / trilinear blends of lattice corners, corner index bits = (x, y, z)
float mg_bilerp(float v0, float v1, float v2, float v3, float s, float t)
{
    float s1 = 1.0 - s;
    return (1.0 - t) * (v0 * s1 + v1 * s) + t * (v2 * s1 + v3 * s);
}

vec3 mg_bilerp(vec3 v0, vec3 v1, vec3 v2, vec3 v3, float s, float t)
{
    float s1 = 1.0 - s;
    return (1.0 - t) * (v0 * s1 + v1 * s) + t * (v2 * s1 + v3 * s);
}

float mg_trilerp(float v0, float v1, float v2, float v3, float v4, float v5, float v6, float v7,
                 float s, float t, float r)
{
    float s1 = 1.0 - s;
    float t1 = 1.0 - t;
    float r1 = 1.0 - r;
    return r1 * (t1 * (v0 * s1 + v1 * s) + t * (v2 * s1 + v3 * s))
         + r * (t1 * (v4 * s1 + v5 * s) + t * (v6 * s1 + v7 * s));
}

vec3 mg_trilerp(vec3 v0, vec3 v1, vec3 v2, vec3 v3, vec3 v4, vec3 v5, vec3 v6, vec3 v7,
                float s, float t, float r)
{
    float s1 = 1.0 - s;
    float t1 = 1.0 - t;
    float r1 = 1.0 - r;
    return r1 * (t1 * (v0 * s1 + v1 * s) + t * (v2 * s1 + v3 * s))
         + r * (t1 * (v4 * s1 + v5 * s) + t * (v6 * s1 + v7 * s));
}

// scale factors bringing the raw gradient noise to roughly [-1, 1]
const float MG_PERLIN_SCALE_2D = 0.6616;
const float MG_PERLIN_SCALE_3D = 0.9820;

// One definition per dimension serves both results: R is float (one gradient per corner from the corner
// hash) or vec3 (three decorrelated channels, each gradient from its own byte of the hash: HASH_OF).
#define MG_HASH_ONE(h) (h)
#define MG_PERLIN_2D(R, NAME, HASH_OF)                                                          \
    R NAME(vec2 p)                                                                              \
    {                                                                                           \
        int X, Y;                                                                               \
        float fx = mg_floorfrac(p.x, X);                                                        \
        float fy = mg_floorfrac(p.y, Y);                                                        \
        R n = mg_bilerp(                                                                        \
            mg_grad(HASH_OF(mg_hash(X, Y)), fx, fy),                                            \
            mg_grad(HASH_OF(mg_hash(X + 1, Y)), fx - 1.0, fy),                                  \
            mg_grad(HASH_OF(mg_hash(X, Y + 1)), fx, fy - 1.0),                                  \
            mg_grad(HASH_OF(mg_hash(X + 1, Y + 1)), fx - 1.0, fy - 1.0),                        \
            mg_fade(fx), mg_fade(fy));                                                          \
        return MG_PERLIN_SCALE_2D * n;                                                          \
    }
#define MG_PERLIN_3D(R, NAME, HASH_OF)                                                          \
    R NAME(vec3 p)                                                                              \
    {                                                                                           \
        int X, Y, Z;                                                                            \
        float fx = mg_floorfrac(p.x, X);                                                        \
        float fy = mg_floorfrac(p.y, Y);                                                        \
        float fz = mg_floorfrac(p.z, Z);                                                        \
        R n = mg_trilerp(                                                                       \
            mg_grad(HASH_OF(mg_hash(X, Y, Z)), fx, fy, fz),                                     \
            mg_grad(HASH_OF(mg_hash(X + 1, Y, Z)), fx - 1.0, fy, fz),                           \
            mg_grad(HASH_OF(mg_hash(X, Y + 1, Z)), fx, fy - 1.0, fz),                           \
            mg_grad(HASH_OF(mg_hash(X + 1, Y + 1, Z)), fx - 1.0, fy - 1.0, fz),                 \
            mg_grad(HASH_OF(mg_hash(X, Y, Z + 1)), fx, fy, fz - 1.0),                           \
            mg_grad(HASH_OF(mg_hash(X + 1, Y, Z + 1)), fx - 1.0, fy, fz - 1.0),                 \
            mg_grad(HASH_OF(mg_hash(X, Y + 1, Z + 1)), fx, fy - 1.0, fz - 1.0),                 \
            mg_grad(HASH_OF(mg_hash(X + 1, Y + 1, Z + 1)), fx - 1.0, fy - 1.0, fz - 1.0),       \
            mg_fade(fx), mg_fade(fy), mg_fade(fz));                                             \
        return MG_PERLIN_SCALE_3D * n;                                                          \
    }

MG_PERLIN_2D(float, mg_perlin, MG_HASH_ONE)
MG_PERLIN_3D(float, mg_perlin, MG_HASH_ONE)
MG_PERLIN_2D(vec3, mg_perlin_vec3, mg_hash_bytes3)
MG_PERLIN_3D(vec3, mg_perlin_vec3, mg_hash_bytes3)
