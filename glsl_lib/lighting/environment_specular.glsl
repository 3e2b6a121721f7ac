// requires: constants.glsl lighting/environment.glsl lighting/environment_lod.glsl lighting/hammersley.glsl lighting/environment_prefiltered_lookup.glsl pbrlib/microfacet/ggx.glsl pbrlib/microfacet/fresnel_model.glsl pbrlib/microfacet/albedo.glsl
// Environment light reflected by a GGX lobe. Default: filtered importance sampling (Krivanek & Colbert
// 2008, "Real-time Shading with Filtered Importance Sampling") of visible normals with u_envRadianceSamples
// Hammersley points; define MG_ENV_PREFILTERED for the split-sum alternative (Karis 2013, "Real Shading
// in Unreal Engine 4"): u_envRadiance is then the GGX-prefiltered map (lighting/environment_prefilter.glsl), read
// once at the level holding the lobe's roughness, times the lobe's albedo from our own table.

// The lobe's albedo for the split sum: the Schlick-split albedo, plus the node's own Fresnel curve's
// departure from its Schlick endpoints at the view angle (exact for a mirror; conductors, F82 and films
// bend away from Schlick's curve).
vec3 mg_ggx_albedo_at_view(float mu, vec2 alpha, MgFresnel fr)
{
    vec3 E = mg_ggx_albedo(mu, alpha, fr);
    if (fr.film_thickness > 0.0 && fr.model != MG_FRESNEL_DIELECTRIC)
        return E;                               // already the film's curve times the lobe's total albedo
    vec2 ab = mg_ggx_albedo_split(mu, alpha);
    vec3 schlick = mix(fr.F0, fr.F90, pow(1.0 - mu, 5.0));
    return max(E + (mg_fresnel_eval(fr, mu) - schlick) * (ab.x + ab.y), 0.0);
}

// Mirror of a direction about the normal (retroreflection exchanges it for the incident one).
vec3 mg_retro(vec3 Lt)
{
    return vec3(-Lt.xy, Lt.z);
}

// The sample loop of mg_env_specular over the Fresnel curve FRESNEL(fr, cosine): NAME sums over n samples the
// reflected radiance times F G2 / G1(v), each read at the level (lighting/environment_lod.glsl) of the reflected
// direction's density D_v(h) / (4 v.h) = G1(v) D(h) / (4 n.v); a mirror (mg_ggx_is_mirror) takes one sample, along
// the normal, whose reflection is never below the surface. One loop, whose curve tests the lobe's thin film per sample
// (mg_fresnel_eval; the thickness is a uniform, so every pixel takes the same side): a film's copy of the loop
// beside the bare curve's cost the GPU compilers 10% more instructions and compile time for no draw time gained on
// llvmpipe (docs/measuring.md, 2026-11-27). (The backslashes are not aligned: a macro is joined into one line,
// padding included, in every shader.)
#define MG_ENV_SPECULAR_SAMPLES(NAME, FRESNEL) \
vec3 NAME(vec3 Vt, mat3 frame, vec2 alpha, MgFresnel fr, bool retro, int n, float G1V) \
{ \
    vec3 sum = vec3(0.0); \
    bool mirror = mg_ggx_is_mirror(alpha); \
    int texels = mg_env_texels(); \
    for (int i = 0; i < n; ++i) \
    { \
        vec3 H = mg_env_lobe_normal(Vt, alpha, mirror, i, n); \
        vec3 Lt = reflect(-Vt, H); \
        if (!mirror && Lt.z <= 0.0) \
            continue; \
        float VdotH = clamp(dot(Vt, H), 0.0, 1.0); \
        float pdf = G1V * mg_ggx_D(H, alpha) / (4.0 * Vt.z); \
        vec3 L = frame * (retro ? mg_retro(Lt) : Lt); \
        vec3 F = FRESNEL(fr, VdotH); \
        float lod = mg_env_lod(L, pdf, texels, mg_env_sample_total(n)); \
        sum += mg_env_radiance(L, lod) * F * (mg_ggx_G2(Lt, Vt, alpha) / G1V); \
    } \
    return sum; \
}

MG_ENV_SPECULAR_SAMPLES(mg_env_specular_samples, mg_fresnel_eval)

// Reflected environment radiance times the lobe's Fresnel and shadowing (without compensation).
vec3 mg_env_specular(vec3 V, mat3 frame, vec2 alpha, MgFresnel fr, bool retro)
{
    vec3 Vt = V * frame;
    Vt.z = max(Vt.z, 1.0e-4);
    Vt = normalize(Vt);
#ifdef MG_ENV_PREFILTERED
    return mg_env_prefiltered_lobe(Vt, frame, alpha, retro) * mg_ggx_albedo_at_view(Vt.z, alpha, fr);
#else
    int n = mg_env_lobe_samples(alpha);
    float G1V = mg_ggx_G1(Vt, alpha);
    return mg_env_specular_samples(Vt, frame, alpha, fr, retro, n, G1V) / float(n);
#endif
}
