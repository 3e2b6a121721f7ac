// requires: pbrlib/microfacet/fresnel.glsl pbrlib/microfacet/thin_film.glsl
// The Fresnel curve of one microfacet BSDF node, as data: which model, its parameters, and an optional
// thin film on top (thickness in nm; 0 = none).
#define MG_FRESNEL_DIELECTRIC 0
#define MG_FRESNEL_CONDUCTOR 1
#define MG_FRESNEL_SCHLICK 2

struct MgFresnel
{
    int model;
    vec3 ior;          // dielectric: ior.x; conductor: eta
    vec3 extinction;   // conductor: k
    vec3 F0;           // schlick
    vec3 F82;
    vec3 F90;
    float exponent;
    float film_thickness;
    float film_ior;
};

MgFresnel mg_fresnel_dielectric_model(float ior, float film_thickness, float film_ior)
{
    return MgFresnel(MG_FRESNEL_DIELECTRIC, vec3(ior), vec3(0.0), vec3(mg_ior_to_f0(ior)), vec3(1.0), vec3(1.0),
                     5.0, film_thickness, film_ior);
}

MgFresnel mg_fresnel_conductor_model(vec3 eta, vec3 k, float film_thickness, float film_ior)
{
    return MgFresnel(MG_FRESNEL_CONDUCTOR, eta, k, mg_fresnel_conductor(1.0, eta, k), vec3(1.0), vec3(1.0),
                     5.0, film_thickness, film_ior);
}

MgFresnel mg_fresnel_schlick_model(vec3 F0, vec3 F82, vec3 F90, float exponent, float film_thickness, float film_ior)
{
    return MgFresnel(MG_FRESNEL_SCHLICK, vec3(1.5), vec3(0.0), F0, F82, F90, exponent, film_thickness, film_ior);
}

// Reflectance of the curve alone (no film) at cosTheta.
vec3 mg_fresnel_base(MgFresnel f, float cosTheta)
{
    if (f.model == MG_FRESNEL_DIELECTRIC)
        return vec3(mg_fresnel_dielectric(cosTheta, f.ior.x));
    if (f.model == MG_FRESNEL_CONDUCTOR)
        return mg_fresnel_conductor(cosTheta, f.ior, f.extinction);
    return mg_fresnel_schlick_f82(cosTheta, f.F0, f.F82, f.F90, f.exponent);
}

// Reflectance of the curve under its thin film (film_thickness > 0) at cosTheta, with one Airy sum whatever the
// model: the model only picks the base's film-side reflectance and phase (a dielectric is the complex IOR ior + 0 i).
// (A sum per model would be inlined three times into every call before the constant model folds: the GPU
// compilers' largest input, the film being evaluated in and around every sample loop.) A film IOR below the
// outside air's 1 (a varying one driven low) is read as 1, as MaterialX reads it: taken as given, light from
// outside would be totally reflected beyond sin = film_ior, a bright ring inside the sphere; at 1 the film vanishes
// and the base's own curve remains.
vec3 mg_fresnel_film(MgFresnel f, float cosTheta)
{
    float eta2 = max(f.film_ior, 1.0);
    float c1 = clamp(cosTheta, 0.0, 1.0);
    float cos2 = mg_thin_film_cos2(c1, eta2);
    vec3 Rs, Rp, us_re, us_im, up_re, up_im;
    if (f.model == MG_FRESNEL_SCHLICK)
        mg_thin_film_schlick_base(cos2, eta2, f.F0, f.F82, f.F90, f.exponent, Rs, Rp, us_re, us_im, up_re, up_im);
    else
        mg_thin_film_base(cos2, eta2, f.ior, f.model == MG_FRESNEL_CONDUCTOR ? f.extinction : vec3(0.0),
                          Rs, Rp, us_re, us_im, up_re, up_im);
    return mg_thin_film_airy(c1, eta2, cos2, f.film_thickness, Rs, Rp, us_re, us_im, up_re, up_im);
}

// Reflectance at cosTheta, through the thin film where there is one. The sample loops call this in their body, one
// loop per estimator, the film chosen per sample (lighting/environment_specular.glsl: a film copy of each loop beside
// the bare one cost the GPU compilers more instructions and compile time than the per-sample test of a uniform
// thickness, every pixel of which takes the same side; docs/measuring.md, 2026-11-28). The model needs no test at
// run time, being a constant each BSDF's call folds. MG_NO_THIN_FILM: a switch the generator resolves when it
// pastes this code (mtlxgen/emit/glsldeps.py, SWITCHES) for a shader whose film thicknesses are all literal zeros,
// which then holds no film code at all.
vec3 mg_fresnel_eval(MgFresnel f, float cosTheta)
{
#ifndef MG_NO_THIN_FILM
    if (f.film_thickness > 0.0)
        return mg_fresnel_film(f, cosTheta);
#endif
    return mg_fresnel_base(f, cosTheta);
}
