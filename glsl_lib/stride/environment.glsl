// requires: constants.glsl lighting/environment.glsl lighting/environment_lod.glsl lighting/hammersley.glsl
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

