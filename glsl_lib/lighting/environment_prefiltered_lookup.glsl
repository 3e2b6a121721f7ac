// requires: constants.glsl lighting/environment.glsl lighting/environment_prefiltered_level.glsl
// The split-sum lookup (MG_ENV_PREFILTERED; Karis 2013, "Real Shading in Unreal Engine 4"): where and at which level
// a lobe reads the GGX-prefiltered u_envRadiance (lighting/environment_prefilter.glsl makes it), for the pbrlib
// lobes (lighting/environment_specular.glsl, environment_refraction.glsl) and the Enterprise PBR's
// (enterprise/environment.glsl).

// Levels read sharper than the lobe's own by this much: a read between two levels blends a lobe of alpha_l with one
// of 2 alpha_l, and bilinear filtering of a level widens its lobes by about a texel, both broader than the lobe
// wanted. Measured (docs/measuring.md, 2026-11-27): over the seven materials, 0, -0.2, -0.3, -0.4 gave 17.9 (no
// bias, taps too), 16.7, 16.6, 17.4 (1/255, 48 px, 8 taps); on five standard_surface lobes outside that set
// (metal at roughness 0.2, 0.4, 0.6, dielectric at 0.3, 0.5) -0.3 lowered the error from 15.2 to 13.4.
#ifndef MG_ENV_PREFILTER_LOD_BIAS
#define MG_ENV_PREFILTER_LOD_BIAS -0.3
#endif

// Level of the GGX-prefiltered u_envRadiance holding the lobe of roughness alpha (an anisotropic lobe: the isotropic
// one of its solid angle), by the prefilter's own mapping (lighting/environment_prefiltered_level.glsl).
float mg_env_lod_prefiltered(vec2 alpha)
{
    return max(mg_env_prefiltered_lod(mg_env_prefiltered_isotropic(alpha), float(textureSize(u_envRadiance, 0).x),
                                      u_envRadianceMips) + MG_ENV_PREFILTER_LOD_BIAS, 0.0);
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
#ifndef MG_ENV_PREFILTER_TAPS
#define MG_ENV_PREFILTER_TAPS 12
#endif

// The lobe-weighted mean radiance of the GGX lobe of roughness alpha (x the tangent) seen from Vt in the tangent
// frame `frame`, from the prefiltered u_envRadiance (retro: the retroreflected lobe, each direction mirrored about
// the normal). An isotropic lobe is one lookup along its dominant direction at the level of its roughness.
// An anisotropic lobe cannot be one lookup of an isotropic map: the bent reflection vector (McAuley 2015,
// "Rendering the World of Far Cry 4", GDC) points one read at the stretched lobe's middle and loses its length (it
// measured 16.7 and 11.2 on the two brushed metals, FIS-64 7.0 and 4.2). Here the stretched axis is read with N
// taps instead, placed and weighted by the lobe's own distribution (our derivation): anisotropic GGX is the
// unit-roughness distribution of slopes stretched by (ax, ay) (Heitz 2014, "Understanding the Masking-Shadowing
// Function in Microfacet-Based BRDFs", the stretch invariance), so a lobe of (a, b), a > b, is close to isotropic
// lobes of roughness b whose microfacet normals spread along the major axis with slopes s p, s = sqrt(a^2 - b^2)
// (widths adding in quadrature), p distributed as the unit distribution's marginal slope, density
// 1 / (2 (1 + p^2)^(3/2)), CDF 1/2 + p / (2 sqrt(1 + p^2)). Tap k takes the normal of the slope at the marginal's
// quantile (k + 1/2) / N, p = q / sqrt(1 - q^2), q = 2 (k + 1/2) / N - 1: equal shares of projected microfacet
// area. Each is weighted by what of it the view sees, (v.h) / (n.h) (the visible-normal density over the
// projected-area one; Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using the Distribution of
// Visible Normals"), read along its own dominant direction, and all but dropped where that falls below the horizon.
// Measured on the two brushed metals (1/255 summed, 48 px, no level bias): 4, 6, 8, 16 taps 9.6, 9.0, 8.6, 7.9;
// widening each tap by the gap between taps (b^2 + (c s / N)^2, c = 0.5 to 3) 1.2 to 5x more. With the level bias,
// 8, 12, 16 taps bring the seven materials to 17.2, 16.7, 16.4 against FIS-64's 17.6 (96 px): 12 is the default.
vec3 mg_env_prefiltered_lobe(vec3 Vt, mat3 frame, vec2 alpha, bool retro)
{
    float major = max(alpha.x, alpha.y);
    float minor = min(alpha.x, alpha.y);
    float spread = sqrt(max(major * major - minor * minor, 0.0));
    // one loop for both (one copy of the read in the shader): an isotropic lobe is its one tap q = 0, H = n
    bool stretched = spread > 1.0e-3 * major && spread >= 1.0e-5;
    int n = stretched ? MG_ENV_PREFILTER_TAPS : 1;
    float tap_alpha = stretched ? minor : mg_env_prefiltered_isotropic(alpha);
    float lod = max(mg_env_prefiltered_lod(tap_alpha, float(textureSize(u_envRadiance, 0).x), u_envRadianceMips) +
                    MG_ENV_PREFILTER_LOD_BIAS, 0.0);
    vec3 axis = alpha.x >= alpha.y ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (int k = 0; k < n; ++k)
    {
        float q = (2.0 * float(k) + 1.0) / float(n) - 1.0;
        float p = spread * q / sqrt(1.0 - q * q);
        vec3 H = normalize(vec3(0.0, 0.0, 1.0) - p * axis);
        vec3 Lt = mg_env_prefiltered_dominant(Vt, H, tap_alpha);
        // below the horizon a tap keeps a trace of weight, so that a view seeing none still reads the lobe's taps
        float w = Lt.z > 0.0 ? max(dot(Vt, H), 0.0) / H.z : 0.0;
        w = max(w, 1.0e-6);
        if (retro)
            Lt = mg_retro_direction(Lt);
        sum += mg_env_radiance(frame * Lt, lod) * w;
        weight += w;
    }
    return sum / weight;
}
