// requires: constants.glsl lighting/environment.glsl
// Environment seen through a transmitting surface: the view ray refracted by Snell's law at the shading
// normal, read at a mip level that widens with roughness (a prefiltered approximation of the rough
// transmission lobe, Walter et al. 2007).
vec3 mg_env_refraction(vec3 V, vec3 N, float ior, vec2 alpha)
{
    vec3 T = refract(-V, N, 1.0 / max(ior, 1.0e-4));
    if (dot(T, T) < 1.0e-8)
        return vec3(0.0);
    float lod = sqrt(sqrt(alpha.x * alpha.y)) * float(u_envRadianceMips - 1);
    return mg_env_radiance(T, lod);
}
