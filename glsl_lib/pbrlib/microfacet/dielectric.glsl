// requires: constants.glsl closures.glsl pbrlib/microfacet/scatter_mode.glsl pbrlib/microfacet/microfacet_reflection.glsl lighting/environment_specular.glsl lighting/environment_refraction.glsl
// dielectric_bsdf (MaterialX Specification 1.39, pbrlib): GGX reflection with the dielectric Fresnel
// curve, tinted (a tint below 0 held at 0, as MaterialX's GLSL holds it: no negative light); transmission by
// refraction; what it does not reflect passes below (albedo scaling: the
// compensated lobe's albedo E c, so that a layer over a white base stays at 1 in the white furnace).

// Multiple-scattering compensation (Turquin 2019's scaling form) for a dielectric lobe: from F0 of |IOR| (the
// Fresnel equations hold the IOR squared; a negative one, e.g. varying, would give F0 = ((n-1)/(n+1))^2 > 1);
// through a film, whose interference F0 alone does not see, and below an IOR of 1, where the curve rises to total
// reflection, from the curve at the view angle (as MaterialX's)
vec3 mg_dielectric_compensation(float NdotV, vec2 alpha, MgFresnel fr, float film_thickness, float film_ior)
{
    bool film = film_thickness > 0.0 && film_ior > 1.0;       // a film IOR below 1 is read as 1: no film
    bool below_one = abs(fr.ior.x) < 1.0;                      // total internal reflection beyond an angle
    vec3 F = (film || below_one) ? mg_fresnel_eval(fr, NdotV) : vec3(mg_ior_to_f0(abs(fr.ior.x)));
    return mg_ggx_energy_compensation(NdotV, alpha, F);
}

vec3 mg_dielectric_reflected_albedo(vec3 V, mat3 frame, vec2 alpha, MgFresnel fr)
{
    return mg_ggx_albedo(clamp(dot(frame[2], V), 1.0e-4, 1.0), alpha, fr);
}

BSDF mg_dielectric_reflection(vec3 L, vec3 V, float weight, vec3 tint, float ior, vec2 roughness, bool retro,
                              float film_thickness, float film_ior, vec3 N, vec3 T, int mode)
{
    if (mode == mg_scatter_T)
        return BSDF(vec3(0.0), vec3(1.0));
    mat3 frame = mg_tangent_frame(N, T);
    vec2 alpha = mg_ggx_alpha(roughness);
    MgFresnel fr = mg_fresnel_dielectric_model(ior, film_thickness, film_ior);
    float NdotV = clamp(dot(N, V), 1.0e-4, 1.0);
    vec3 comp = mg_dielectric_compensation(NdotV, alpha, fr, film_thickness, film_ior);
    vec3 f = mg_microfacet_reflection(L, V, frame, alpha, fr, retro) * comp;
    vec3 E = mg_ggx_albedo(NdotV, alpha, fr) * comp;
    return BSDF(f * max(tint, 0.0) * weight, 1.0 - weight * E);
}

BSDF mg_dielectric_indirect(vec3 V, float weight, vec3 tint, float ior, vec2 roughness, bool retro,
                            float film_thickness, float film_ior, vec3 N, vec3 T, int mode)
{
    if (mode == mg_scatter_T)
        return BSDF(vec3(0.0), vec3(1.0));
    mat3 frame = mg_tangent_frame(N, T);
    vec2 alpha = mg_ggx_alpha(roughness);
    MgFresnel fr = mg_fresnel_dielectric_model(ior, film_thickness, film_ior);
    float NdotV = clamp(dot(N, V), 1.0e-4, 1.0);
    vec3 comp = mg_dielectric_compensation(NdotV, alpha, fr, film_thickness, film_ior);
    vec3 Li = mg_env_specular(V, frame, alpha, fr, retro) * comp;
    vec3 E = mg_ggx_albedo(NdotV, alpha, fr) * comp;
    return BSDF(Li * max(tint, 0.0) * weight, 1.0 - weight * E);
}

BSDF mg_dielectric_transmission(vec3 V, float weight, vec3 tint, float ior, vec2 roughness,
                                float film_thickness, float film_ior, vec3 N, vec3 T, int mode, bool thin_walled)
{
    vec2 alpha = mg_ggx_alpha(roughness);
    MgFresnel fr = mg_fresnel_dielectric_model(ior, film_thickness, film_ior);
    float NdotV = clamp(dot(N, V), 1.0e-4, 1.0);
    vec3 E = mg_ggx_albedo(NdotV, alpha, fr) * mg_ggx_energy_compensation(NdotV, alpha, fr.F0);
    if (mode == mg_scatter_R)
        return BSDF(vec3(0.0), 1.0 - weight * E);
    // what the interface transmits: 1 - the lobe's albedo with the exact dielectric curve at n.v, through the
    // thin film where there is one (so that an interface of IOR 1 lets everything through, as MaterialX's does;
    // the Schlick split's F90 = 1 would not)
    vec3 through = max(1.0 - mg_fresnel_eval(fr, NdotV) * dot(mg_ggx_albedo_split(NdotV, alpha), vec2(1.0))
                             * mg_ggx_energy_compensation(NdotV, alpha, fr.F0), 0.0);
    return BSDF(mg_env_refraction(V, N, T, ior, alpha, fr, mg_ggx_energy_compensation(NdotV, alpha, mg_fresnel_eval(fr, NdotV)),
                                  through, thin_walled) * max(tint, 0.0) * weight, vec3(1.0 - weight));
}
