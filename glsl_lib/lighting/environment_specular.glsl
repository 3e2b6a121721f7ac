// requires: constants.glsl lighting/environment.glsl lighting/hammersley.glsl pbrlib/microfacet/ggx.glsl pbrlib/microfacet/fresnel_model.glsl pbrlib/microfacet/albedo.glsl
// Environment light reflected by a GGX lobe. Default: filtered importance sampling (Krivanek & Colbert
// 2008, "Real-time Shading with Filtered Importance Sampling") of visible normals with u_envRadianceSamples
// Hammersley points; define MG_ENV_PREFILTERED for the split-sum alternative (Karis 2013, "Real Shading
// in Unreal Engine 4"): one lookup in the mip chain at a roughness-chosen level times the lobe's albedo.
#ifndef MG_ENV_LOD_BIAS
#define MG_ENV_LOD_BIAS 1.0
#endif

// Mip level whose texels cover the solid angle of one sample of density pdf among n
// (Krivanek & Colbert 2008 eq. 8: lod = 1/2 log2(Omega_s / Omega_p) + bias), for a lat-long map whose
// texels span 2 pi^2 cos(elevation) / (w h) steradians.
float mg_env_lod(vec3 dir, float pdf, int n)
{
    vec2 size = vec2(textureSize(u_envRadiance, 0));
    float omega_s = 1.0 / (float(n) * max(pdf, 1.0e-8));
    float cos_el = sqrt(max(1.0 - dir.y * dir.y, 1.0e-4));
    float omega_p = 2.0 * MG_PI * MG_PI * cos_el / (size.x * size.y);
    return clamp(0.5 * log2(omega_s / omega_p) + MG_ENV_LOD_BIAS, 0.0, float(u_envRadianceMips - 1));
}

// Mirror of a direction about the normal (retroreflection exchanges it for the incident one).
vec3 mg_retro(vec3 Lt)
{
    return vec3(-Lt.xy, Lt.z);
}

// Reflected environment radiance times the lobe's Fresnel and shadowing (without compensation).
vec3 mg_env_specular(vec3 V, mat3 frame, vec2 alpha, MgFresnel fr, bool retro)
{
    vec3 Vt = V * frame;
    Vt.z = max(Vt.z, 1.0e-4);
    Vt = normalize(Vt);
#ifdef MG_ENV_PREFILTERED
    vec3 Lt = reflect(-Vt, vec3(0.0, 0.0, 1.0));
    if (retro)
        Lt = mg_retro(Lt);
    float lod = sqrt(sqrt(alpha.x * alpha.y)) * float(u_envRadianceMips - 1);
    return mg_env_radiance(frame * Lt, lod) * mg_ggx_albedo(Vt.z, alpha, fr);
#else
    int n = max(u_envRadianceSamples, 1);
    float G1V = mg_ggx_G1(Vt, alpha);
    vec3 sum = vec3(0.0);
    for (int i = 0; i < n; ++i)
    {
        vec3 H = mg_ggx_sample_vndf(Vt, alpha, mg_hammersley(i, n));
        vec3 Lt = reflect(-Vt, H);
        if (Lt.z <= 0.0)
            continue;
        float VdotH = clamp(dot(Vt, H), 0.0, 1.0);
        // density of the reflected direction: D_v(h) / (4 v.h) = G1(v) D(h) / (4 n.v)
        float pdf = G1V * mg_ggx_D(H, alpha) / (4.0 * Vt.z);
        vec3 L = frame * (retro ? mg_retro(Lt) : Lt);
        vec3 F = mg_fresnel_eval(fr, VdotH);
        sum += mg_env_radiance(L, mg_env_lod(L, pdf, n)) * F * (mg_ggx_G2(Lt, Vt, alpha) / G1V);
    }
    return sum / float(n);
#endif
}
