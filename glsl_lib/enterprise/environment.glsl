// requires: constants.glsl lighting/environment.glsl lighting/environment_lod.glsl lighting/hammersley.glsl lighting/environment_prefiltered_lookup.glsl pbrlib/microfacet/ggx.glsl
// Environment light in a GGX lobe for the Enterprise PBR material. The lobe's shape comes from filtered
// importance sampling of visible normals (Krivanek & Colbert 2008, "Real-time Shading with Filtered
// Importance Sampling"; Heitz 2018, "Sampling the GGX Distribution of Visible Normals") and is
// normalised: the result is the lobe-weighted mean radiance, which the caller scales by the lobe's
// tabulated albedo. So uniform light is reflected exactly in the amount the energy tables give.

// Mean radiance over the GGX reflection lobe of V (weights G2 / G1(v), the VNDF estimator's).
vec3 mg_epbr_env_lobe(vec3 V, mat3 frame, vec2 alpha)
{
    vec3 Vt = V * frame;
    Vt.z = max(Vt.z, 1.0e-4);
    Vt = normalize(Vt);
#ifdef MG_ENV_PREFILTERED
    // split sum (Karis 2013): the GGX-prefiltered map at the lobe's level (lighting/environment_prefiltered_lookup.glsl)
    return mg_env_prefiltered_lobe(Vt, frame, alpha, false);
#else
    bool mirror = mg_ggx_is_mirror(alpha);      // one sample, along the normal (microfacet/ggx.glsl)
    int n = mg_env_lobe_samples(alpha);
    float G1V = mg_ggx_G1(Vt, alpha);
    vec3 sum = vec3(0.0);
    float wsum = 0.0;
    int texels = mg_env_texels();
    for (int i = 0; i < n; ++i)
    {
        vec3 H = mg_env_lobe_normal(Vt, alpha, mirror, i, n);
        vec3 Lt = reflect(-Vt, H);
        if (!mirror && Lt.z <= 0.0)
            continue;
        float pdf = G1V * mg_ggx_D(H, alpha) / (4.0 * Vt.z);
        vec3 L = frame * Lt;
        float w = mg_ggx_G2(Lt, Vt, alpha) / G1V;
        float lod = mg_env_lod(L, pdf, texels, mg_env_sample_total(n));
        sum += mg_env_radiance(L, lod) * w;
        wsum += w;
    }
    if (wsum <= 0.0)
        return mg_env_radiance(frame * vec3(-Vt.xy, Vt.z), 0.0);
    return sum / wsum;
#endif
}

// Mean radiance over a GGX lobe about the direction D (a view straight down the lobe's own axis).
vec3 mg_epbr_env_around(vec3 D, vec3 T, vec2 alpha)
{
    return mg_epbr_env_lobe(D, mg_tangent_frame(D, T), alpha);
}
