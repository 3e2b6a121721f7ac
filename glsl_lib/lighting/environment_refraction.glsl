// requires: constants.glsl lighting/environment.glsl lighting/environment_specular.glsl
// Width of the transmitted lobe relative to the interface's roughness: a microfacet tilted by d turns the
// refracted direction by about (1 - 1/eta) d at normal incidence (Walter et al. 2007, from the refraction
// half-vector h = -(eta_i i + eta_o o)), where a reflection turns by 2 d; the factor is fitted to
// MaterialX's renders over eta 1.5 .. 4.4 (at eta 1.5 it is the former fixed half of the roughness).
#ifndef MG_REFRACTION_SPREAD
#define MG_REFRACTION_SPREAD 1.5
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

// A thin-walled surface (MaterialX Specification 1.39, surface; OpenPBR 1.1 §geometry: "no refraction")
// is a shell whose two interfaces bend the ray back: the view ray passes straight through, spread by both.
vec3 mg_env_refraction(vec3 V, vec3 N, vec3 Tg, float ior, vec2 alpha, bool thin_walled)
{
    vec3 T = thin_walled ? -V : mg_refraction_solid_sphere(-V, N, ior);
    alpha = max(alpha * MG_REFRACTION_SPREAD * abs(1.0 - 1.0 / max(ior, 1.0e-4)), vec2(1.0e-4));
#ifdef MG_REFRACTION_PREFILTERED
    return mg_env_radiance(T, mg_env_lod_prefiltered(T, alpha));
#else
    // the GGX lobe about T, by the reflection sampler with the normal turned away from the viewer
    mat3 frame = mg_tangent_frame(-N, Tg);
    MgFresnel one = mg_fresnel_schlick_model(vec3(1.0), vec3(1.0), vec3(1.0), 5.0, 0.0, 1.5);
    return mg_env_specular(-reflect(T, N), frame, alpha, one, false);
#endif
}
