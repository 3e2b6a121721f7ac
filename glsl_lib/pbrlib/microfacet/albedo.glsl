// requires: pbrlib/microfacet/albedo_fit.glsl pbrlib/microfacet/fresnel_model.glsl
// Directional albedo of the GGX reflection lobe and its energy compensation, by the analytic fit of the
// table tools/ggx_albedo.py integrates with numpy (the table itself stays out of shaders: 25 kB of text).

// (A, B): the lobe's albedo is F0 * A + F90 * B.
vec2 mg_ggx_albedo_split(float mu, vec2 alpha)
{
    return mg_ggx_albedo_fit(mu, sqrt(alpha.x * alpha.y));
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
