// requires: constants.glsl closures.glsl pbrlib/microfacet/microfacet_reflection.glsl lighting/environment_specular.glsl
// conductor_bsdf (MaterialX Specification 1.39, pbrlib): GGX reflection with the complex-IOR Fresnel
// curve of a metal. Nothing under it shows through, at any weight (the weight scales what it reflects, as
// MaterialX's: a layer under a metal is hidden; what is seen through it: the "transmission" template).

BSDF mg_conductor_reflection(vec3 L, vec3 V, float weight, vec3 ior, vec3 extinction, vec2 roughness, bool retro,
                             float film_thickness, float film_ior, vec3 N, vec3 T)
{
    mat3 frame = mg_tangent_frame(N, T);
    vec2 alpha = mg_ggx_alpha(roughness);
    MgFresnel fr = mg_fresnel_conductor_model(ior, extinction, film_thickness, film_ior);
    float NdotV = clamp(dot(N, V), 1.0e-4, 1.0);
    vec3 f = mg_microfacet_reflection(L, V, frame, alpha, fr, retro) * mg_ggx_energy_compensation(NdotV, alpha, fr.F0);
    return BSDF(f * weight, vec3(0.0));
}

BSDF mg_conductor_indirect(vec3 V, float weight, vec3 ior, vec3 extinction, vec2 roughness, bool retro,
                           float film_thickness, float film_ior, vec3 N, vec3 T)
{
    mat3 frame = mg_tangent_frame(N, T);
    vec2 alpha = mg_ggx_alpha(roughness);
    MgFresnel fr = mg_fresnel_conductor_model(ior, extinction, film_thickness, film_ior);
    float NdotV = clamp(dot(N, V), 1.0e-4, 1.0);
    vec3 Li = mg_env_specular(V, frame, alpha, fr, retro) * mg_ggx_energy_compensation(NdotV, alpha, fr.F0);
    return BSDF(Li * weight, vec3(0.0));
}
