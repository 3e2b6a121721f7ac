// requires: constants.glsl closures.glsl lighting/environment.glsl enterprise/tables.glsl enterprise/frame.glsl enterprise/fresnel.glsl enterprise/specular.glsl enterprise/diffuse.glsl enterprise/sheen.glsl enterprise/flakes.glsl enterprise/transmission.glsl enterprise/environment.glsl
// The Enterprise PBR material (Dassault Systemes DSPBR 2025x; the energy-conservation and reciprocity
// requirements of the seed post, "Physically-Based Materials - Energy Conservation and Reciprocity").
// Bottom to top:
//   core     = m metal + (1 - m)(1 - t) opaque dielectric + (1 - m) t transparent dielectric
//              metal: compensated GGX, F0 = albedo; dielectric: compensated GGX weighted by `specular`,
//              F0 = specularTint f0(ior), over the coupled diffuse (opaque; translucency sends part of it
//              through) or the transmitted light (transparent); thin film on both Fresnel curves
//   sheen    Charlie lobe, albedo-scaled
//   flakes   coverage-weighted mix with a flake lobe
//   coat     clearcoat lobe (F = 0.04 + 0.96 (1 - mu)^5, alpha = r^2) over everything, emission under it.
// Layers scale what lies below by (1 - E_top(mu_v)) (1 - E_top(mu_l)), the same in both directions, so
// the BRDF stays reciprocal; under uniform light the second factor averages to 1 - E_top_avg.

struct MgEpbr
{
    vec3 albedo;
    float metallic;
    float roughness;
    float anisotropy;
    float anisotropyRotation;
    vec3 N;
    vec3 T;
    float translucency;
    vec3 translucencyColor;
    float transparency;
    float specular;
    vec3 specularTint;
    float thinFilm;
    float thinFilmThickness;
    float thinFilmIor;
    vec3 sheenColor;
    float sheenRoughness;
    float flakeCoverage;
    vec3 flakeColor;
    float flakeSize;
    float flakeRoughness;
    float flipFlop;
    vec3 flipFlopColor;
    float clearcoat;
    float clearcoatRoughness;
    vec3 Nc;
    vec3 emissionColor;
    float emissionValue;
    bool thinWalled;
    float ior;
    vec3 attenuationColor;
    float attenuationDistance;
    vec3 subsurfaceColor;
    float subsurfaceAnisotropy;
    vec3 P;                 // world position (flakes)
    float footprint;        // world size of a pixel (flakes below it are statistical)
};

// What every direction shares.
struct MgEpbrLobes
{
    mat3 frame;
    vec2 alpha;
    float r;                // table roughness of the core lobe
    vec3 f0;                // dielectric F0
    mat3 flake_frame;
    vec2 flake_alpha;
    float flake_c;
    mat3 coat_frame;
    vec2 coat_alpha;
    float coat;
    float sheen_w;
};

MgEpbrLobes mg_epbr_lobes(MgEpbr m)
{
    MgEpbrLobes k;
    k.frame = mg_epbr_frame(normalize(m.N), m.T, m.anisotropyRotation);
    k.alpha = mg_epbr_alpha(m.roughness, m.anisotropy);
    k.r = mg_epbr_table_roughness(k.alpha);
    k.f0 = clamp(m.specularTint * mg_epbr_ior_to_f0(m.ior), 0.0, 1.0);
    vec3 Nf;
    float fa;
    mg_epbr_flakes(m.P, k.frame, m.flakeSize, m.flakeCoverage, m.flakeRoughness, m.footprint, Nf, k.flake_c, fa);
    k.flake_frame = mg_tangent_frame(Nf, k.frame[0]);
    k.flake_alpha = vec2(max(fa, 1.0e-4));
    k.coat_frame = mg_tangent_frame(normalize(m.Nc), k.frame[0]);
    k.coat_alpha = mg_epbr_alpha(m.clearcoatRoughness, 0.0);
    k.coat = clamp(m.clearcoat, 0.0, 1.0);
    k.sheen_w = clamp(max(m.sheenColor.r, max(m.sheenColor.g, m.sheenColor.b)), 0.0, 1.0);
    return k;
}

// Albedo of the dielectric's specular lobe at mu, `specular` included (per channel of F0).
vec3 mg_epbr_dielectric_albedo(MgEpbr m, MgEpbrLobes k, float mu)
{
    return m.specular * mg_epbr_base_e3(k.f0, k.r, mu);
}

// 1 - clearcoat E_coat(mu): the share of light the coat lets through at mu.
float mg_epbr_coat_scale(MgEpbrLobes k, float mu)
{
    return 1.0 - k.coat * mg_epbr_base_e(0.04, mg_epbr_table_roughness(k.coat_alpha), mu);
}

// ---------------------------------------------------------------- BSDF for a pair of directions

vec3 mg_epbr_core(MgEpbr m, MgEpbrLobes k, vec3 L, vec3 V)
{
    float mu_l = dot(L, k.frame[2]);
    float mu_v = max(dot(V, k.frame[2]), 1.0e-4);
    float met = clamp(m.metallic, 0.0, 1.0);
    float tr = clamp(m.transparency, 0.0, 1.0);
    float tl = clamp(m.translucency, 0.0, 1.0);
    vec3 e_v = mg_epbr_dielectric_albedo(m, k, mu_v);
    vec3 e_avg = m.specular * mg_epbr_base_eavg3(k.f0, k.r);
    if (mu_l <= 0.0)        // light from behind: the opaque dielectric's diffuse transmission
        return (1.0 - met) * (1.0 - tr) * tl * m.translucencyColor
               * mg_epbr_diffuse_complement(mg_epbr_dielectric_albedo(m, k, -mu_l), e_v, e_avg);
    MgEpbrGeometry g = mg_epbr_geometry(L, V, k.frame, k.alpha);
    vec3 metal = mg_epbr_lobe(g, m.albedo, m.thinFilm, m.thinFilmThickness, m.thinFilmIor);
    vec3 dielectric = m.specular * mg_epbr_lobe(g, k.f0, m.thinFilm, m.thinFilmThickness, m.thinFilmIor);
    vec3 diffuse = m.albedo * (1.0 - tl) * mg_epbr_diffuse_complement(mg_epbr_dielectric_albedo(m, k, mu_l), e_v, e_avg);
    return met * metal + (1.0 - met) * (dielectric + (1.0 - tr) * diffuse);
}

// f(l, v) of the whole material (no cosine): V toward the viewer, L toward the light.
vec3 mg_epbr_bsdf(MgEpbr m, MgEpbrLobes k, vec3 L, vec3 V)
{
    vec3 N = k.frame[2];
    float mu_l = dot(L, N);
    float mu_v = max(dot(V, N), 1.0e-4);
    vec3 f = mg_epbr_core(m, k, L, V);
    if (k.sheen_w > 0.0)
    {
        f *= mg_epbr_sheen_scale(k.sheen_w, m.sheenRoughness, abs(mu_l)) * mg_epbr_sheen_scale(k.sheen_w, m.sheenRoughness, mu_v);
        if (mu_l > 0.0)
            f += m.sheenColor * mg_epbr_sheen(mu_l, mu_v, dot(N, normalize(L + V)), m.sheenRoughness);
    }
    if (k.flake_c > 0.0)
    {
        vec3 color = mg_epbr_flake_color(m.flakeColor, m.flipFlopColor, m.flipFlop, dot(V, normalize(L + V)));
        f = (1.0 - k.flake_c) * f + k.flake_c * mg_epbr_specular_lobe(L, V, k.flake_frame, k.flake_alpha, color, 0.0, 0.0, 1.0);
    }
    if (k.coat > 0.0)
    {
        float cl = dot(L, k.coat_frame[2]);
        float cv = max(dot(V, k.coat_frame[2]), 1.0e-4);
        f *= mg_epbr_coat_scale(k, abs(cl)) * mg_epbr_coat_scale(k, cv);
        f += k.coat * mg_epbr_specular_lobe(L, V, k.coat_frame, k.coat_alpha, vec3(0.04), 0.0, 0.0, 1.0);
    }
    return f;
}

// ---------------------------------------------------------------- environment and emission

// Light the transparent dielectric lets through toward V (before its Fresnel weight): thin-walled, both
// faces at once, straight through; else refracted through the solid, absorbed on the way, and what the
// medium takes out but scatters (subsurfaceColor: its scattering albedo) leaves diffusely.
vec3 mg_epbr_through(MgEpbr m, MgEpbrLobes k, vec3 V)
{
    vec3 N = k.frame[2];
    float chord = 0.0;
    vec3 D = m.thinWalled ? -V : mg_epbr_refract_sphere(-V, N, m.ior, chord);
    vec3 att = mg_epbr_attenuation(m.attenuationColor, m.attenuationDistance, chord);
    vec3 scattered = (1.0 - att) * m.subsurfaceColor * 0.5 * (mg_env_irradiance(N) + mg_env_irradiance(-N));
    return m.albedo * (att * mg_epbr_env_around(D, k.frame[0], k.alpha) + scattered);
}

// Environment light reflected and transmitted toward V.
vec3 mg_epbr_environment(MgEpbr m, MgEpbrLobes k, vec3 V)
{
    vec3 N = k.frame[2];
    float mu_v = max(dot(V, N), 1.0e-4);
    float met = clamp(m.metallic, 0.0, 1.0);
    float tr = clamp(m.transparency, 0.0, 1.0);
    float tl = clamp(m.translucency, 0.0, 1.0);
    vec3 R = mg_epbr_env_lobe(V, k.frame, k.alpha);
    vec3 e_metal = mg_epbr_specular_albedo(mu_v, k.alpha, m.albedo, m.thinFilm, m.thinFilmThickness, m.thinFilmIor);
    vec3 e_d = mg_epbr_dielectric_albedo(m, k, mu_v);
    if (m.thinFilm > 0.0 && m.thinFilmThickness > 0.0)
        e_d = mix(e_d, m.specular * mg_epbr_specular_albedo(mu_v, k.alpha, k.f0, 1.0, m.thinFilmThickness, m.thinFilmIor),
                  clamp(m.thinFilm, 0.0, 1.0));
    e_d = clamp(e_d, 0.0, 1.0);
    vec3 below = vec3(0.0);
    if (tr < 1.0)
        below += (1.0 - tr) * (m.albedo * (1.0 - tl) * mg_env_irradiance(N) + tl * m.translucencyColor * mg_env_irradiance(-N));
    if (tr > 0.0 && met < 1.0)
        below += tr * mg_epbr_through(m, k, V);
    vec3 c = met * e_metal * R + (1.0 - met) * (e_d * R + (1.0 - e_d) * below);
    if (k.sheen_w > 0.0)
        c = c * mg_epbr_sheen_scale(k.sheen_w, m.sheenRoughness, mu_v) * (1.0 - k.sheen_w * mg_epbr_sheen_eavg(m.sheenRoughness))
            + m.sheenColor * mg_epbr_sheen_e(m.sheenRoughness, mu_v) * mg_env_irradiance(N);
    if (k.flake_c > 0.0)
    {
        float fv = max(dot(V, k.flake_frame[2]), 1.0e-4);
        vec3 color = mg_epbr_flake_color(m.flakeColor, m.flipFlopColor, m.flipFlop, fv);
        vec3 flake = mg_epbr_specular_albedo(fv, k.flake_alpha, color, 0.0, 0.0, 1.0)
                     * mg_epbr_env_lobe(V, k.flake_frame, k.flake_alpha);
        c = (1.0 - k.flake_c) * c + k.flake_c * flake;
    }
    if (k.coat > 0.0)
    {
        float cv = max(dot(V, k.coat_frame[2]), 1.0e-4);
        float rc = mg_epbr_table_roughness(k.coat_alpha);
        float e_c = k.coat * mg_epbr_base_e(0.04, rc, cv);
        c = c * (1.0 - e_c) * (1.0 - k.coat * mg_epbr_base_eavg(0.04, rc)) + e_c * mg_epbr_env_lobe(V, k.coat_frame, k.coat_alpha);
    }
    return c;
}

// Emission (emissionColor x emissionValue) below the clear coat.
vec3 mg_epbr_emission(MgEpbr m, MgEpbrLobes k, vec3 V)
{
    vec3 e = m.emissionColor * max(m.emissionValue, 0.0);
    if (k.coat > 0.0)
        e *= mg_epbr_coat_scale(k, max(dot(V, k.coat_frame[2]), 1.0e-4));
    return e;
}
