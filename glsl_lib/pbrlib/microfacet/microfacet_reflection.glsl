// requires: constants.glsl pbrlib/microfacet/ggx.glsl pbrlib/microfacet/fresnel_model.glsl pbrlib/microfacet/albedo.glsl
// GGX microfacet reflection toward V of light from L, times n.l: D F G2 / (4 n.v) (Walter et al. 2007
// eq. 20 with the height-correlated G2 of Heitz 2014), without energy compensation.
vec3 mg_microfacet_reflection(vec3 L, vec3 V, mat3 frame, vec2 alpha, MgFresnel fr, bool retro)
{
    vec3 Lt = L * frame;
    vec3 Vt = V * frame;
    if (Lt.z <= 0.0 || Vt.z <= 0.0)
        return vec3(0.0);
    vec3 Lh = retro ? vec3(-Lt.xy, Lt.z) : Lt;
    vec3 H = normalize(Lh + Vt);
    vec3 F = mg_fresnel_eval(fr, clamp(dot(Vt, H), 0.0, 1.0));
    return F * (mg_ggx_D(H, alpha) * mg_ggx_G2(Lt, Vt, alpha) / (4.0 * Vt.z));
}
