// requires: constants.glsl pbrlib/microfacet/fresnel.glsl
// Thin-film iridescence by Airy summation with analytic spectral integration (Belcour & Barla 2017,
// "A Practical Extension to Microfacet Theory for the Modeling of Varying Iridescence").
// mg_thin_film_airy: per polarization (s, p), with the reflection phase of each interface from its
// complex Fresnel amplitude, summed in CIE XYZ and brought to RGB by the paper's XYZ -> CIE RGB (E)
// matrix; the base's colour enters per XYZ component (component j from the base's channel j).
// mg_thin_film_over_ior: a dielectric or conductor base; mg_thin_film_over_schlick: a generalized Schlick base.
// mg_thin_film_reflectance is the older polarization-averaged form, kept for Enterprise PBR's film.

// Fourier transform of the CIE XYZ sensitivities for optical path difference opd (nm) and phase
// shift (Belcour & Barla 2017, supplemental: Gaussian fits of the colour matching functions).
vec3 mg_thin_film_sensitivity(float opd, vec3 shift)
{
    float phase = MG_TWO_PI * opd * 1.0e-9;
    vec3 val = vec3(5.4856e-13, 4.4201e-13, 5.2481e-13);
    vec3 pos = vec3(1.6810e+06, 1.7953e+06, 2.2084e+06);
    vec3 var = vec3(4.3278e+09, 9.3046e+09, 6.6121e+09);
    vec3 xyz = val * sqrt(MG_TWO_PI * var) * cos(pos * phase + shift) * exp(-phase * phase * var);
    xyz.x += 9.7470e-14 * sqrt(MG_TWO_PI * 4.5282e+09) * cos(2.2399e+06 * phase + shift.x)
             * exp(-4.5282e+09 * phase * phase);
    return xyz / 1.0685e-7;
}

// Reflectance of a film (ior eta2, thickness in nm) over a base whose reflectance at the film-base
// interface is R23 (given the refraction cosine in the film, see mg_thin_film_cos2). cosTheta: incidence in air.
vec3 mg_thin_film_reflectance(float cosTheta, float eta2, float thickness, vec3 R23, float phi23)
{
    float c1 = clamp(cosTheta, 0.0, 1.0);
    float s2 = (1.0 - c1 * c1) / (eta2 * eta2);
    if (s2 >= 1.0)
        return vec3(1.0);
    float c2 = sqrt(1.0 - s2);
    float R12 = mg_fresnel_dielectric(c1, eta2);
    float T121 = 1.0 - R12;
    float phi21 = eta2 > 1.0 ? MG_PI : 0.0;
    float opd = 2.0 * eta2 * thickness * c2;
    vec3 rgb = vec3(0.0);
    // Airy sum, channel by channel of the base reflectance
    for (int ch = 0; ch < 3; ++ch)
    {
        float R123 = clamp(R12 * R23[ch], 1.0e-7, 0.9999);
        float r123 = sqrt(R123);
        float Rs = T121 * T121 * R23[ch] / (1.0 - R123);
        vec3 I = vec3(R12 + Rs);
        float Cm = Rs - T121;
        for (int m = 1; m <= 2; ++m)
        {
            Cm *= r123;
            I += Cm * 2.0 * mg_thin_film_sensitivity(float(m) * opd, vec3(float(m) * (phi21 + phi23)));
        }
        // CIE XYZ to linear Rec.709
        vec3 c = mat3(3.2404542, -0.9692660, 0.0556434, -1.5371385, 1.8760108, -0.2040259,
                      -0.4985314, 0.0415560, 1.0572252) * I;
        rgb[ch] = c[ch];
    }
    return clamp(rgb, 0.0, 1.0);
}

// Cosine of the refraction angle inside a film of ior eta2 (1 when totally reflected).
float mg_thin_film_cos2(float cosTheta, float eta2)
{
    float s2 = (1.0 - cosTheta * cosTheta) / (eta2 * eta2);
    return s2 >= 1.0 ? 1.0 : sqrt(1.0 - s2);
}

// ---- Polarized Airy summation (Belcour & Barla 2017, sec. 4 and supplemental).

vec2 mg_cmul(vec2 a, vec2 b) { return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x); }
vec2 mg_cdiv(vec2 a, vec2 b) { return vec2(a.x * b.x + a.y * b.y, a.y * b.x - a.x * b.y) / max(dot(b, b), 1.0e-20); }

// Principal square root of a complex number (non-negative real part).
vec2 mg_csqrt(vec2 z)
{
    float r = length(z);
    float re = sqrt(max(0.5 * (r + z.x), 0.0));
    float im = sqrt(max(0.5 * (r - z.x), 0.0));
    return vec2(re, z.y < 0.0 ? -im : im);
}

// Complex Fresnel amplitude reflection coefficients (s, p) at an interface from a medium of real index n1
// into one of complex index n2 = eta + i k, for the incidence cosine cos1 (Born & Wolf, sec. 1.5 and 14.2).
void mg_fresnel_amplitudes(float cos1, float n1, vec2 n2, out vec2 rs, out vec2 rp)
{
    vec2 n = n2 / n1;
    vec2 n_sq = mg_cmul(n, n);
    vec2 n_cos_t = mg_csqrt(n_sq - vec2(1.0 - cos1 * cos1, 0.0));   // n cos(theta_t)
    vec2 c = vec2(cos1, 0.0);
    rs = mg_cdiv(c - n_cos_t, c + n_cos_t);
    rp = mg_cdiv(n_sq * cos1 - n_cos_t, n_sq * cos1 + n_cos_t);
}

// Reflectance |r|^2 and phase arg(r) of the s and p amplitudes at an interface into a base of complex IOR
// eta + i k per channel (k = 0: a dielectric), from a film of index n1 at the cosine cos2 in the film.
void mg_thin_film_base(float cos2, float n1, vec3 eta, vec3 k, out vec3 Rs, out vec3 Rp, out vec3 phis, out vec3 phip)
{
    for (int ch = 0; ch < 3; ++ch)
    {
        vec2 rs, rp;
        mg_fresnel_amplitudes(cos2, n1, vec2(eta[ch], k[ch]), rs, rp);
        Rs[ch] = dot(rs, rs);
        Rp[ch] = dot(rp, rp);
        phis[ch] = atan(rs.y, rs.x);
        phip[ch] = atan(rp.y, rp.x);
    }
}

// Reflectance of a film (index eta2, thickness in nm) in air over a base whose film-side reflectance and
// phase are given per polarization and channel (see mg_thin_film_base), at the incidence cosine cos1.
// The first interface's phase on the way back up is pi minus its phase going in (Stokes relations).
vec3 mg_thin_film_airy(float cos1, float eta2, float thickness, vec3 R23s, vec3 R23p, vec3 phi23s, vec3 phi23p)
{
    eta2 = max(eta2, 1.0);              // a film rarer than the air outside reads as air (see mg_thin_film_over_ior)
    float c1 = clamp(cos1, 0.0, 1.0);
    float cos2 = mg_thin_film_cos2(c1, eta2);
    vec2 r12[2];
    mg_fresnel_amplitudes(c1, 1.0, vec2(eta2, 0.0), r12[0], r12[1]);
    float opd = 2.0 * eta2 * thickness * cos2;         // optical path difference of one round trip
    vec3 S0 = mg_thin_film_sensitivity(0.0, vec3(0.0));
    vec3 I = vec3(0.0);
    for (int pol = 0; pol < 2; ++pol)
    {
        vec3 R23 = pol == 0 ? R23s : R23p;
        vec3 phi = (MG_PI - atan(r12[pol].y, r12[pol].x)) + (pol == 0 ? phi23s : phi23p);
        float R12 = min(dot(r12[pol], r12[pol]), 1.0);
        float T121 = 1.0 - R12;
        vec3 R123 = clamp(R12 * R23, 0.0, 0.9999);
        vec3 r123 = sqrt(R123);
        vec3 Rs = T121 * T121 * R23 / (1.0 - R123);
        I += 0.5 * (R12 + Rs) * S0;                     // m = 0
        vec3 Cm = Rs - T121;
        for (int m = 1; m <= 2; ++m)
        {
            Cm *= r123;
            I += Cm * mg_thin_film_sensitivity(float(m) * opd, float(m) * phi);    // 0.5 (polarization) * 2
        }
    }
    // CIE XYZ to CIE RGB under the equal-energy illuminant E (the paper's matrix: white maps to white)
    return clamp(mat3(2.3706743, -0.5138850, 0.0052982, -0.9000405, 1.4253036, -0.0146949,
                      -0.4706338, 0.0885814, 1.0093968) * I, 0.0, 1.0);
}

// Film over a base of complex IOR eta + i k per channel (k = 0: a dielectric). A film IOR below the outside
// air's 1 (a varying one driven low) is read as 1, as MaterialX reads it: taken as given, light from outside
// would be totally reflected beyond sin = eta2, a bright ring inside the sphere; at 1 the film vanishes and the
// base's own curve remains.
vec3 mg_thin_film_over_ior(float cos1, float eta2, float thickness, vec3 eta, vec3 k)
{
    eta2 = max(eta2, 1.0);
    vec3 Rs, Rp, phis, phip;
    mg_thin_film_base(mg_thin_film_cos2(clamp(cos1, 0.0, 1.0), eta2), eta2, eta, k, Rs, Rp, phis, phip);
    return mg_thin_film_airy(cos1, eta2, thickness, Rs, Rp, phis, phip);
}

// Film over a generalized Schlick base (generalized_schlick_bsdf; MaterialX PBR spec, Thin-Film Iridescence
// Model): the base's curve (F82 tint included) at the refraction cosine in the film is the film-base
// reflectance of both polarizations, and the phase there is a step, from the base IOR that color0 gives by
// the Schlick-to-IOR inversion (F0 held to [0.01, 0.99]). In the amplitude convention of mg_fresnel_amplitudes
// (r_p = -r_s head-on) that step is pi for s and 0 for p on a base denser than the film, 0 and pi on a rarer
// one, as the exact dielectric gives below its Brewster angle.
// MG_THIN_FILM_SCHLICK_R23: the share of the curve each polarization takes. 1 as the spec says: a film of IOR 1
// then leaves the base's curve unchanged, and a film over a perfect mirror (color0 = color90 = 1) reflects
// everything. MaterialX 1.39's GLSL takes 0.5 (docs/differences: thin_film_schlick).
#ifndef MG_THIN_FILM_SCHLICK_R23
#define MG_THIN_FILM_SCHLICK_R23 1.0
#endif
vec3 mg_thin_film_over_schlick(float cos1, float eta2, float thickness, vec3 F0, vec3 F82, vec3 F90, float exponent)
{
    eta2 = max(eta2, 1.0);
    float cos2 = mg_thin_film_cos2(clamp(cos1, 0.0, 1.0), eta2);
    vec3 R23 = MG_THIN_FILM_SCHLICK_R23 * mg_fresnel_schlick_f82(cos2, F0, F82, F90, exponent);
    vec3 s = sqrt(clamp(F0, 0.01, 0.99));
    vec3 eta3 = (1.0 + s) / (1.0 - s);
    vec3 phi23s = mix(vec3(MG_PI), vec3(0.0), lessThan(eta3, vec3(eta2)));
    return mg_thin_film_airy(cos1, eta2, thickness, R23, R23, phi23s, MG_PI - phi23s);
}
