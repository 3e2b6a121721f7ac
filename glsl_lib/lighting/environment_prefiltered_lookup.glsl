// requires: constants.glsl lighting/environment.glsl lighting/environment_prefiltered_level.glsl
// The split-sum lookup (MG_ENV_PREFILTERED; Karis 2013, "Real Shading in Unreal Engine 4"): where and at which level
// a lobe reads the GGX-prefiltered u_envRadiance (lighting/environment_prefilter.glsl makes it), for the pbrlib
// lobes (lighting/environment_specular.glsl, environment_refraction.glsl) and the Enterprise PBR's
// (enterprise/environment.glsl).

// Level of the GGX-prefiltered u_envRadiance holding the lobe of roughness alpha (an anisotropic lobe: the isotropic
// one of its solid angle), by the prefilter's own mapping (lighting/environment_prefiltered_level.glsl).
float mg_env_lod_prefiltered(vec2 alpha)
{
    return mg_env_prefiltered_lod(mg_env_prefiltered_isotropic(alpha), float(textureSize(u_envRadiance, 0).x),
                                  u_envRadianceMips);
}

// The split sum's direction for an isotropic lobe of roughness alpha about the normal N of the tangent frame, seen
// from Vt: the GGX lobe times the cosine and masking peaks between the mirror direction and the normal, the more so
// the rougher it is, so the mirror direction is pulled towards N by 1 - s (sqrt(s) + alpha), s = 1 - alpha (the
// dominant direction of Lagarde & de Rousiers 2014, "Moving Frostbite to Physically Based Rendering", sec. 4.9).
vec3 mg_env_prefiltered_dominant(vec3 Vt, vec3 N, float alpha)
{
    vec3 R = reflect(-Vt, N);
    float a = clamp(alpha, 0.0, 1.0);
    float s = 1.0 - a;
    return normalize(mix(N, R, s * (sqrt(s) + a)));
}

// The mirror of a tangent-frame direction about the normal (the retroreflected lobe's).
vec3 mg_retro_direction(vec3 Lt)
{
    return vec3(-Lt.xy, Lt.z);
}

// Taps an anisotropic lobe is read with (an isotropic one takes one).
#ifndef MG_ENV_PREFILTERED_TAPS
#define MG_ENV_PREFILTERED_TAPS 8
#endif

// The lobe-weighted mean radiance of the GGX lobe of roughness alpha (x the tangent) seen from Vt in the tangent
// frame `frame`, from the prefiltered u_envRadiance (retro: the retroreflected lobe, each direction mirrored about
// the normal). An isotropic lobe is one lookup along its dominant direction at the level of its roughness.
// An anisotropic lobe is several isotropic ones (the "bent normal plus taps along the stretched axis" of
// McAuley 2015, "Rendering the World of Far Cry 4", GDC, with the taps placed and weighted by the lobe itself):
// anisotropic GGX is the unit-roughness distribution of slopes stretched by (ax, ay), so a lobe of (a, b), a > b,
// is close to isotropic lobes of roughness b whose microfacet normals are spread along the major axis with slopes
// s p, s = sqrt(a^2 - b^2) (widths adding in quadrature) and p distributed as the unit distribution's marginal slope,
// density 1 / (2 (1 + p^2)^(3/2)), CDF 1/2 + p / (2 sqrt(1 + p^2)). Tap k takes the normal of the slope at the
// marginal's quantile (k + 1/2) / N, p = q / sqrt(1 - q^2), q = 2 (k + 1/2) / N - 1: equal shares of projected
// microfacet area. Each is weighted by what of it the view sees, (v.h) / (n.h) (the visible-normal density over the
// projected-area one; Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 2), and dropped where its
// reflection falls below the horizon. Each tap reads the level of b itself: widening the taps
// by their spacing (b^2 + (c s / N)^2, c = 0.5 to 3) measured 1.2 to 5x more error on the two brushed metals of
// docs/measuring.md; 4, 6, 8 and 16 taps measured 9.6, 9.0, 8.6 and 7.9 (1/255, the two summed; one tap 27.9).
vec3 mg_env_prefiltered_lobe(vec3 Vt, mat3 frame, vec2 alpha, bool retro)
{
    float lod_width = float(textureSize(u_envRadiance, 0).x);
    float major = max(alpha.x, alpha.y);
    float minor = min(alpha.x, alpha.y);
    float spread = sqrt(max(major * major - minor * minor, 0.0));
    if (spread <= 1.0e-3 * major || spread < 1.0e-5)
    {
        vec3 Lt = mg_env_prefiltered_dominant(Vt, vec3(0.0, 0.0, 1.0), mg_env_prefiltered_isotropic(alpha));
        if (retro)
            Lt = mg_retro_direction(Lt);
        return mg_env_radiance(frame * Lt, mg_env_lod_prefiltered(alpha));
    }
    vec3 axis = alpha.x >= alpha.y ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    const int N = MG_ENV_PREFILTERED_TAPS;
    float lod = mg_env_prefiltered_lod(minor, lod_width, u_envRadianceMips);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (int k = 0; k < N; ++k)
    {
        float q = (2.0 * float(k) + 1.0) / float(N) - 1.0;
        float p = spread * q / sqrt(1.0 - q * q);
        vec3 H = normalize(vec3(0.0, 0.0, 1.0) - p * axis);
        float w = max(dot(Vt, H), 0.0) / H.z;
        vec3 Lt = mg_env_prefiltered_dominant(Vt, H, minor);
        if (Lt.z <= 0.0 || w <= 0.0)
            continue;
        if (retro)
            Lt = mg_retro_direction(Lt);
        sum += mg_env_radiance(frame * Lt, lod) * w;
        weight += w;
    }
    if (weight <= 0.0)
        return mg_env_radiance(frame * mg_env_prefiltered_dominant(Vt, vec3(0.0, 0.0, 1.0), minor), lod);
    return sum / weight;
}
