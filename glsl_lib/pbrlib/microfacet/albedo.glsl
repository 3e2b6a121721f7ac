// requires: pbrlib/microfacet/albedo_fit.glsl pbrlib/microfacet/albedo_table.glsl pbrlib/microfacet/fresnel_model.glsl
// Directional albedo of the GGX reflection lobe and its energy compensation. The analytic fit is the
// default; define MG_GGX_ALBEDO_TABLE to read the numerically integrated table instead.

// (A, B): the lobe's albedo is F0 * A + F90 * B.
vec2 mg_ggx_albedo_split(float mu, vec2 alpha)
{
    float a = sqrt(alpha.x * alpha.y);
#ifdef MG_GGX_ALBEDO_TABLE
    return mg_ggx_albedo_table(mu, a);
#else
    return mg_ggx_albedo_fit(mu, a);
#endif
}

// Albedo of the single-scattering lobe with the node's Fresnel curve (its Schlick endpoints). A thin film
// on a dielectric leaves this albedo (what the lobe takes from the layers below) at the bare interface's,
// as MaterialX's layering does (measured); on other curves the film's reflectance at mu scales the lobe.
vec3 mg_ggx_albedo(float mu, vec2 alpha, MgFresnel f)
{
    vec2 ab = mg_ggx_albedo_split(mu, alpha);
    if (f.film_thickness > 0.0 && f.model != MG_FRESNEL_DIELECTRIC)
        return mg_fresnel_eval(f, mu) * (ab.x + ab.y);
    return f.F0 * ab.x + f.F90 * ab.y;
}

// Multiple-scattering compensation factor of the lobe, 1 + F (1 - E) / E (Kulla & Conty 2017,
// "Revisiting Physically Based Shading at Imageworks"; the scaling form of Turquin 2019).
vec3 mg_ggx_energy_compensation(float mu, vec2 alpha, vec3 F)
{
    vec2 ab = mg_ggx_albedo_split(mu, alpha);
    float E = max(ab.x + ab.y, 1.0e-4);
    return 1.0 + F * (1.0 - E) / E;
}
