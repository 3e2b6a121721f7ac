// requires: constants.glsl lighting/environment.glsl lighting/hammersley.glsl
// Helpers for the Stride material's environment specular: importance sampling of the selected NDF with
// filtered lookups in the environment's mip chain (Krivanek & Colbert 2008, "Real-time Shading with
// Filtered Importance Sampling").

// The unit half vector with polar cosine cos_h and azimuth phi about the normal N.
vec3 mg_stride_half_vector(vec3 N, float cos_h, float phi)
{
    vec3 up = abs(N.z) < 0.999 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    vec3 T = normalize(cross(up, N));
    vec3 B = cross(N, T);
    float sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
    return normalize(T * (sin_h * cos(phi)) + B * (sin_h * sin(phi)) + N * cos_h);
}

// Mip level of the lat-long map whose texels cover the solid angle of one of n samples of density pdf
// (Krivanek & Colbert 2008, eq. 8: lod = 1/2 log2(Omega_s / Omega_p) + 1).
float mg_stride_env_lod(vec3 dir, float pdf, int n)
{
    vec2 size = vec2(textureSize(u_envRadiance, 0));
    float omega_s = 1.0 / (float(n) * max(pdf, 1.0e-8));
    float omega_p = 2.0 * MG_PI * MG_PI * sqrt(max(1.0 - dir.y * dir.y, 1.0e-4)) / (size.x * size.y);
    return clamp(0.5 * log2(omega_s / omega_p) + 1.0, 0.0, float(u_envRadianceMips - 1));
}
