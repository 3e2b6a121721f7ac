// requires: constants.glsl pbrlib/microfacet/thin_film.glsl
// Fresnel terms of the Enterprise PBR material (DSPBR 2025x, "Fresnel"): Schlick with F90 = 1 for the
// metal (F0 = albedo) and the dielectric (F0 = specularTint ((ior - 1) / (ior + 1))^2), its hemispherical
// average for Kulla-Conty compensation, the clear coat's fixed curve, and an optional thin film on top.

// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering": F0 + (1 - F0)(1 - c)^5.
vec3 mg_epbr_schlick(vec3 f0, float c)
{
    float x = clamp(1.0 - c, 0.0, 1.0);
    float x2 = x * x;
    return f0 + (1.0 - f0) * (x2 * x2 * x);
}

// Clear coat (DSPBR 2025x, "Clearcoat"): F = 0.04 + 0.96 (1 - mu)^5.
float mg_epbr_clearcoat_fresnel(float c)
{
    return mg_epbr_schlick(vec3(0.04), c).x;
}

// Normal-incidence reflectance of a dielectric of relative IOR eta.
float mg_epbr_ior_to_f0(float eta)
{
    float r = (eta - 1.0) / (eta + 1.0);
    return r * r;
}

// 2 int F(mu) mu dmu of Schlick's curve: f0 + (1 - f0) / 21 (Kulla & Conty 2017, F_avg).
vec3 mg_epbr_fresnel_avg(vec3 f0)
{
    return f0 + (1.0 - f0) / 21.0;
}

// Colour of the multiple-scattering lobe: F_avg^2 E_avg / (1 - F_avg (1 - E_avg)) (Kulla & Conty 2017,
// the geometric series of inter-reflections each scaled by F_avg).
vec3 mg_epbr_ms_color(vec3 f0, float e_avg)
{
    vec3 fa = mg_epbr_fresnel_avg(f0);
    return fa * fa * e_avg / (1.0 - fa * (1.0 - e_avg));
}

// Schlick, blended by `film` with the reflectance through a thin film of the given thickness (um) and
// IOR over a base of that Schlick curve (Belcour & Barla 2017, "A Practical Extension to Microfacet
// Theory for the Modeling of Varying Iridescence"; the base's phase shift taken as pi).
vec3 mg_epbr_fresnel(vec3 f0, float c, float film, float thickness_um, float film_ior)
{
    vec3 F = mg_epbr_schlick(f0, c);
    if (film <= 0.0 || thickness_um <= 0.0)
        return F;
    float c2 = mg_thin_film_cos2(c, film_ior);
    vec3 R = mg_thin_film_reflectance(c, film_ior, thickness_um * 1000.0, mg_epbr_schlick(f0, c2), MG_PI);
    return mix(F, R, clamp(film, 0.0, 1.0));
}
