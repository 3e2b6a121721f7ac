// requires: stdlib/procedural/perlin.glsl
// noise2d / noise3d (MaterialX Specification 1.39): Perlin gradient noise scaled by amplitude about pivot.

// a fourth channel comes from the scalar noise at a fixed, decorrelating offset
const vec2 MG_NOISE_W_OFFSET_2D = vec2(19.0, 73.0);
const vec3 MG_NOISE_W_OFFSET_3D = vec3(19.0, 73.0, 29.0);

float mg_noise2d(float amplitude, float pivot, vec2 p) { return mg_perlin(p) * amplitude + pivot; }
vec2 mg_noise2d(vec2 amplitude, float pivot, vec2 p) { return mg_perlin_vec3(p).xy * amplitude + pivot; }
vec3 mg_noise2d(vec3 amplitude, float pivot, vec2 p) { return mg_perlin_vec3(p) * amplitude + pivot; }
vec4 mg_noise2d(vec4 amplitude, float pivot, vec2 p)
{
    return vec4(mg_perlin_vec3(p), mg_perlin(p + MG_NOISE_W_OFFSET_2D)) * amplitude + pivot;
}

float mg_noise3d(float amplitude, float pivot, vec3 p) { return mg_perlin(p) * amplitude + pivot; }
vec2 mg_noise3d(vec2 amplitude, float pivot, vec3 p) { return mg_perlin_vec3(p).xy * amplitude + pivot; }
vec3 mg_noise3d(vec3 amplitude, float pivot, vec3 p) { return mg_perlin_vec3(p) * amplitude + pivot; }
vec4 mg_noise3d(vec4 amplitude, float pivot, vec3 p)
{
    return vec4(mg_perlin_vec3(p), mg_perlin(p + MG_NOISE_W_OFFSET_3D)) * amplitude + pivot;
}
