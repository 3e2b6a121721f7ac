// requires: constants.glsl closures.glsl pbrlib/microfacet/scatter_mode.glsl pbrlib/microfacet/microfacet_reflection.glsl lighting/environment_specular.glsl lighting/environment_refraction.glsl
// generalized_schlick_bsdf (MaterialX Specification 1.39, pbrlib): GGX reflection with a Schlick curve from
// color0 to color90 (exponent, optional F82 tint); transmission by refraction at the IOR whose normal
// reflectance is color0; what it does not reflect passes below (albedo scaling: the
// compensated lobe's albedo E c, so that a layer over a white base stays at 1 in the white furnace).

// IOR of a dielectric whose normal-incidence reflectance is F0 (inverse of ((n-1)/(n+1))^2).
float mg_f0_to_ior(vec3 F0)
{
    float r = sqrt(clamp(dot(F0, vec3(1.0 / 3.0)), 0.0, 0.99));
    return (1.0 + r) / (1.0 - r);
}

// A reflectance below 0 has no meaning: each colour of the curve is held at 0 or above (as MaterialX's GLSL
// does), so that a negative color0 (e.g. glTF's base colour fed from a world position) reflects nothing rather
// than subtracting light, and the curve towards color90 still rises from 0 at grazing angles.
void mg_schlick_colors_nonnegative(inout vec3 color0, inout vec3 color82, inout vec3 color90)
{
    color0 = max(color0, 0.0);
    color82 = max(color82, 0.0);
    color90 = max(color90, 0.0);
}

BSDF mg_schlick_reflection(vec3 L, vec3 V, float weight, vec3 color0, vec3 color82, vec3 color90, float exponent,
                           vec2 roughness, bool retro, float film_thickness, float film_ior, vec3 N, vec3 T, int mode)
{
    if (mode == mg_scatter_T)
        return BSDF(vec3(0.0), vec3(1.0));
    mg_schlick_colors_nonnegative(color0, color82, color90);
    mat3 frame = mg_tangent_frame(N, T);
    vec2 alpha = mg_ggx_alpha(roughness);
    MgFresnel fr = mg_fresnel_schlick_model(color0, color82, color90, exponent, film_thickness, film_ior);
    float NdotV = clamp(dot(N, V), 1.0e-4, 1.0);
    vec3 f = mg_microfacet_reflection(L, V, frame, alpha, fr, retro) * mg_ggx_energy_compensation(NdotV, alpha, color0);
    vec3 E = mg_ggx_albedo(NdotV, alpha, fr) * mg_ggx_energy_compensation(NdotV, alpha, color0);
    return BSDF(f * weight, vec3(1.0 - weight * dot(E, vec3(1.0 / 3.0))));
}

BSDF mg_schlick_indirect(vec3 V, float weight, vec3 color0, vec3 color82, vec3 color90, float exponent,
                         vec2 roughness, bool retro, float film_thickness, float film_ior, vec3 N, vec3 T, int mode)
{
    if (mode == mg_scatter_T)
        return BSDF(vec3(0.0), vec3(1.0));
    mg_schlick_colors_nonnegative(color0, color82, color90);
    mat3 frame = mg_tangent_frame(N, T);
    vec2 alpha = mg_ggx_alpha(roughness);
    MgFresnel fr = mg_fresnel_schlick_model(color0, color82, color90, exponent, film_thickness, film_ior);
    float NdotV = clamp(dot(N, V), 1.0e-4, 1.0);
    vec3 Li = mg_env_specular(V, frame, alpha, fr, retro) * mg_ggx_energy_compensation(NdotV, alpha, color0);
    vec3 E = mg_ggx_albedo(NdotV, alpha, fr) * mg_ggx_energy_compensation(NdotV, alpha, color0);
    return BSDF(Li * weight, vec3(1.0 - weight * dot(E, vec3(1.0 / 3.0))));
}

BSDF mg_schlick_transmission(vec3 V, float weight, vec3 color0, vec3 color82, vec3 color90, float exponent,
                             vec2 roughness, float film_thickness, float film_ior, vec3 N, vec3 T, int mode,
                             bool thin_walled)
{
    mg_schlick_colors_nonnegative(color0, color82, color90);
    vec2 alpha = mg_ggx_alpha(roughness);
    MgFresnel fr = mg_fresnel_schlick_model(color0, color82, color90, exponent, film_thickness, film_ior);
    float NdotV = clamp(dot(N, V), 1.0e-4, 1.0);
    vec3 E = mg_ggx_albedo(NdotV, alpha, fr) * mg_ggx_energy_compensation(NdotV, alpha, color0);
    if (mode == mg_scatter_R)
        return BSDF(vec3(0.0), vec3(1.0 - weight * dot(E, vec3(1.0 / 3.0))));
    vec3 through = 1.0 - E;
    return BSDF(mg_env_refraction(V, N, T, mg_f0_to_ior(color0), alpha, fr, mg_ggx_energy_compensation(NdotV, alpha, color0),
                                  through, thin_walled) * weight, vec3(1.0 - weight));
}
