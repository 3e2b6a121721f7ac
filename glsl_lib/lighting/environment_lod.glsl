// requires: constants.glsl lighting/environment.glsl
// The mip level of filtered importance sampling (Krivanek & Colbert 2008, "Real-time Shading with Filtered
// Importance Sampling", eq. 8): lod = 1/2 log2(Omega_s / Omega_p) + bias, Omega_s = 1 / (n pdf) the solid angle
// of one of n samples of density pdf, Omega_p = 2 pi^2 cos(elevation) / (w h) the solid angle of a w x h
// lat-long map's texel at the sample's elevation. Split as
//     lod = [1/2 log2(w h / (2 pi^2 n)) + bias] - 1/2 log2(pdf cos(elevation)),
// the bracket the same for every sample of a loop (mg_env_lod_base) and the rest per sample. A sampler reads the
// map's size before its loop (mg_env_texels: one read for all the shader's samplers) and mg_env_lod computes the
// bracket inside it: a float computed before the loop stays live across it, and gave complete shaders 168 VGPRs
// instead of 128 on RADV's ACO (benchmarks/bench_gpu_compilers.py, 2026-11-28).
#ifndef MG_ENV_LOD_BIAS
#define MG_ENV_LOD_BIAS 1.0
#endif

// The radiance map's texel count w h: an integer, so a sampler reads it once before its loop (GPU compilers keep a
// uniform integer in a scalar register, and merge the reads of the shader's samplers into one).
int mg_env_texels()
{
    ivec2 size = textureSize(u_envRadiance, 0);
    return size.x * size.y;
}

// The part of the level shared by a loop's samples, for a map of `texels` texels and n samples taken in all.
float mg_env_lod_base(int texels, int n)
{
    return 0.5 * log2(float(texels) / (2.0 * MG_PI * MG_PI * float(n))) + MG_ENV_LOD_BIAS;
}

// The level for one sample of density pdf in direction dir, one of n samples in all of a map of `texels` texels,
// clamped to the map's mip chain.
float mg_env_lod(vec3 dir, float pdf, int texels, int n)
{
    float cos_el = sqrt(max(1.0 - dir.y * dir.y, 1.0e-4));
    return clamp(mg_env_lod_base(texels, n) - 0.5 * log2(max(pdf, 1.0e-8) * cos_el), 0.0, float(u_envRadianceMips - 1));
}
