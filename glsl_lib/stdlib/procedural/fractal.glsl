// requires: stdlib/procedural/perlin.glsl
// Fractional Brownian motion (Musgrave, "Texturing and Modeling", ch. 16): octaves of Perlin noise summed.

float mg_fbm(vec2 p, int octaves, float lacunarity, float diminish)
{
    float sum = 0.0;
    float weight = 1.0;
    for (int i = 0; i < octaves; ++i)
    {
        sum += weight * mg_perlin(p);
        weight *= diminish;
        p *= lacunarity;
    }
    return sum;
}

float mg_fbm(vec3 p, int octaves, float lacunarity, float diminish)
{
    float sum = 0.0;
    float weight = 1.0;
    for (int i = 0; i < octaves; ++i)
    {
        sum += weight * mg_perlin(p);
        weight *= diminish;
        p *= lacunarity;
    }
    return sum;
}

vec3 mg_fbm_vec3(vec2 p, int octaves, float lacunarity, float diminish)
{
    vec3 sum = vec3(0.0);
    float weight = 1.0;
    for (int i = 0; i < octaves; ++i)
    {
        sum += weight * mg_perlin_vec3(p);
        weight *= diminish;
        p *= lacunarity;
    }
    return sum;
}

vec3 mg_fbm_vec3(vec3 p, int octaves, float lacunarity, float diminish)
{
    vec3 sum = vec3(0.0);
    float weight = 1.0;
    for (int i = 0; i < octaves; ++i)
    {
        sum += weight * mg_perlin_vec3(p);
        weight *= diminish;
        p *= lacunarity;
    }
    return sum;
}

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
