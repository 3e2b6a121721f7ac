// requires: constants.glsl lighting/environment.glsl lighting/hammersley.glsl pbrlib/microfacet/ggx.glsl lighting/environment_prefiltered_level.glsl
// The GGX-prefiltered radiance map the split-sum method reads (MG_ENV_PREFILTERED; lighting/environment_specular.glsl):
// each texel of level l is the radiance around its direction R weighted by the GGX lobe of alpha_l
// (lighting/environment_prefiltered_level.glsl) reflected about n = v = R (Karis 2013, "Real Shading in Unreal Engine
// 4", the split sum's first factor), and by the masking G1(l): with n = v the BRDF times the cosine is D G2 F / 4 and
// Smith's height-correlated G2 is G1(l) there (Karis weighs by n.l instead, which darkens the lobe's rim). The lobe is importance-sampled (n Hammersley points,
// halfway vectors drawn from D(h) (n.h)); each sample reads the box-filtered source chain at the level whose texels
// cover the sample's share of the sphere, 1 / (n pdf) (Krivanek & Colbert 2008, "Real-time Shading with Filtered
// Importance Sampling", eq. 8, biased one level up as there), so that a few hundred samples do not alias. All in the
// map's own frame: a texel (u, v) is the direction d with u = atan(d.x, -d.z) / 2 pi + 0.5, v = -asin(d.y) / pi + 0.5.

// The map-frame direction of lat-long coordinates uv (the inverse of lighting/environment.glsl's mg_latlong_uv_map).
vec3 mg_latlong_direction(vec2 uv)
{
    float elevation = (0.5 - uv.y) * MG_PI;
    float azimuth = (uv.x - 0.5) * MG_TWO_PI;
    return vec3(cos(elevation) * sin(azimuth), sin(elevation), -cos(elevation) * cos(azimuth));
}

// The GGX lobe of roughness alpha about R over the radiance chain `source` (mips levels), n samples.
vec3 mg_env_prefilter(sampler2D source, int mips, vec3 R, float alpha, int n)
{
    mat3 frame = mg_tangent_frame(R, vec3(0.0, 1.0, 0.0));
    vec2 size = vec2(textureSize(source, 0));
    vec2 a = vec2(max(alpha, 1.0e-4));
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (int i = 0; i < n; ++i)
    {
        // the distribution of visible normals seen head-on is D(h) (n.h)
        vec3 H = mg_ggx_sample_vndf(vec3(0.0, 0.0, 1.0), a, mg_hammersley(i, n));
        vec3 L = vec3(2.0 * H.z * H.xy, 2.0 * H.z * H.z - 1.0);      // reflect(-n, H)
        if (L.z <= 0.0)
            continue;
        float pdf = mg_ggx_D(H, a) * 0.25;                           // D(h) (n.h) / (4 v.h), with n = v
        vec3 d = frame * L;
        float omega_s = 1.0 / (float(n) * max(pdf, 1.0e-8));
        float omega_p = 2.0 * MG_PI * MG_PI * sqrt(max(1.0 - d.y * d.y, 1.0e-4)) / (size.x * size.y);
        float lod = clamp(0.5 * log2(omega_s / omega_p) + 1.0, 0.0, float(mips - 1));
        float w = mg_ggx_G1(L, a);
        sum += textureLod(source, mg_latlong_uv_map(d), lod).rgb * w;
        weight += w;
    }
    return sum / max(weight, 1.0e-8);
}

// Texel `texel` of level `level` (size `size`) of the prefiltered map: level 0 copies the source's texel (a mirror),
// the others hold the lobe of mg_env_prefiltered_alpha(level, width of level 0).
vec3 mg_env_prefilter_texel(sampler2D source, int mips, ivec2 texel, ivec2 size, int level, int n)
{
    if (level <= 0)
        return texelFetch(source, texel, 0).rgb;
    vec2 uv = (vec2(texel) + 0.5) / vec2(size);
    float width = float(textureSize(source, 0).x);
    return mg_env_prefilter(source, mips, mg_latlong_direction(uv), mg_env_prefiltered_alpha(level, width), n);
}
