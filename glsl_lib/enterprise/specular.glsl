// requires: constants.glsl pbrlib/microfacet/ggx.glsl enterprise/tables.glsl enterprise/frame.glsl enterprise/fresnel.glsl
// The microfacet lobe of the Enterprise PBR material (DSPBR 2025x, "Microfacet BRDF"): anisotropic GGX
// (Walter et al. 2007; Burley 2012) with height-correlated Smith masking-shadowing (Heitz 2014,
// "Understanding the Masking-Shadowing Function", eq. 99), plus the Kulla-Conty multiple-scattering
// lobe that returns the energy single scattering loses (Kulla & Conty 2017, after Kelemen &
// Szirmay-Kalos 2001). Values are the BRDF f without the cosine.

// D G2 / (4 mu_l mu_v) for unit L and V; 0 below either horizon. VdotH: the Fresnel cosine.
float mg_epbr_ggx(vec3 L, vec3 V, mat3 frame, vec2 alpha, out float VdotH)
{
    vec3 Lt = L * frame;
    vec3 Vt = V * frame;
    VdotH = 1.0;
    if (Lt.z <= 0.0 || Vt.z <= 0.0)
        return 0.0;
    vec3 H = normalize(Lt + Vt);
    VdotH = clamp(dot(Vt, H), 0.0, 1.0);
    return mg_ggx_D(H, alpha) * mg_ggx_G2(Lt, Vt, alpha) / (4.0 * Lt.z * Vt.z);
}

// Albedo at F = 1 of the single-scattering lobe, E(mu) = A + B.
float mg_epbr_ggx_albedo(float r, float mu)
{
    return dot(mg_epbr_ggx_e(r, mu), vec2(1.0));
}

// Shape of the multiple-scattering lobe, (1 - E(mu_l)) (1 - E(mu_v)) / (pi (1 - E_avg)): symmetric in
// mu_l and mu_v, and its albedo is exactly 1 - E(mu_v).
float mg_epbr_ms_shape(float r, float mu_l, float mu_v)
{
    float e_avg = dot(mg_epbr_ggx_eavg(r), vec2(1.0));
    return (1.0 - mg_epbr_ggx_albedo(r, mu_l)) * (1.0 - mg_epbr_ggx_albedo(r, mu_v)) / (MG_PI * max(1.0 - e_avg, 1.0e-4));
}

// What the lobes of one frame and roughness share for a pair of directions.
struct MgEpbrGeometry
{
    float dg;           // D G2 / (4 mu_l mu_v)
    float VdotH;
    float ms;           // mg_epbr_ms_shape
    float e_avg;        // E_avg at F = 1
    bool above;         // both directions above the horizon
};

MgEpbrGeometry mg_epbr_geometry(vec3 L, vec3 V, mat3 frame, vec2 alpha)
{
    MgEpbrGeometry g;
    float mu_l = dot(L, frame[2]);
    float mu_v = dot(V, frame[2]);
    g.above = mu_l > 0.0 && mu_v > 0.0;
    g.dg = mg_epbr_ggx(L, V, frame, alpha, g.VdotH);
    float r = mg_epbr_table_roughness(alpha);
    g.e_avg = dot(mg_epbr_ggx_eavg(r), vec2(1.0));
    g.ms = g.above ? mg_epbr_ms_shape(r, mu_l, mu_v) : 0.0;
    return g;
}

// The compensated lobe for Schlick F0 (F90 = 1) and an optional thin film.
vec3 mg_epbr_lobe(MgEpbrGeometry g, vec3 f0, float film, float film_thickness, float film_ior)
{
    if (!g.above)
        return vec3(0.0);
    return mg_epbr_fresnel(f0, g.VdotH, film, film_thickness, film_ior) * g.dg + mg_epbr_ms_color(f0, g.e_avg) * g.ms;
}

vec3 mg_epbr_specular_lobe(vec3 L, vec3 V, mat3 frame, vec2 alpha, vec3 f0, float film, float film_thickness,
                           float film_ior)
{
    return mg_epbr_lobe(mg_epbr_geometry(L, V, frame, alpha), f0, film, film_thickness, film_ior);
}

// Directional albedo of that lobe at mu: F0 A + B + F_ms (1 - E); a film is taken at its reflectance at mu.
vec3 mg_epbr_specular_albedo(float mu, vec2 alpha, vec3 f0, float film, float film_thickness, float film_ior)
{
    float r = mg_epbr_table_roughness(alpha);
    vec2 ab = mg_epbr_ggx_e(r, mu);
    float E = ab.x + ab.y;
    float e_avg = dot(mg_epbr_ggx_eavg(r), vec2(1.0));
    vec3 single = f0 * ab.x + ab.y;
    if (film > 0.0 && film_thickness > 0.0)
        single = mix(single, mg_epbr_fresnel(f0, mu, 1.0, film_thickness, film_ior) * E, clamp(film, 0.0, 1.0));
    return single + mg_epbr_ms_color(f0, e_avg) * (1.0 - E);
}
