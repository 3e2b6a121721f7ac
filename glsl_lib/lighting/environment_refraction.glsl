// requires: constants.glsl lighting/environment.glsl lighting/environment_specular.glsl
#ifndef MG_REFRACTION_ALPHA_SCALE
#define MG_REFRACTION_ALPHA_SCALE 0.5
#endif
// Environment seen through a transmitting surface, modelled as a solid sphere of the given IOR: the view
// ray refracts in at the shading normal (Snell's law), crosses the sphere along a chord and refracts out
// at the exit normal; read at a mip level that widens with roughness (a prefiltered stand-in for the
// rough transmission lobe of Walter et al. 2007).
vec3 mg_refraction_solid_sphere(vec3 I, vec3 N, float ior)
{
    float eta = max(ior, 1.0e-4);
    vec3 R1 = refract(I, N, 1.0 / eta);
    if (dot(R1, R1) < 1.0e-8)
        return reflect(I, N);
    vec3 N2 = normalize(N + 2.0 * dot(R1, -N) * R1);      // exit point of the unit sphere's chord
    vec3 R2 = refract(R1, -N2, eta);
    return dot(R2, R2) < 1.0e-8 ? reflect(R1, -N2) : R2;
}

vec3 mg_env_refraction(vec3 V, vec3 N, vec3 Tg, float ior, vec2 alpha)
{
    vec3 T = mg_refraction_solid_sphere(-V, N, ior);
#ifdef MG_REFRACTION_PREFILTERED
    return mg_env_radiance(T, mg_env_lod_prefiltered(T, alpha * MG_REFRACTION_ALPHA_SCALE));
#else
    // the GGX lobe about T, by the reflection sampler with the normal turned away from the viewer
    mat3 frame = mg_tangent_frame(-N, Tg);
    MgFresnel one = mg_fresnel_schlick_model(vec3(1.0), vec3(1.0), vec3(1.0), 5.0, 0.0, 1.5);
    return mg_env_specular(-reflect(T, N), frame, alpha * MG_REFRACTION_ALPHA_SCALE, one, false);
#endif
}
