// requires: constants.glsl pbrlib/microfacet/fresnel.glsl
// Thin-film iridescence by Airy summation with analytic spectral integration (Belcour & Barla 2017,
// "A Practical Extension to Microfacet Theory for the Modeling of Varying Iridescence"), polarization
// averaged; the base's reflection phase is taken as 0 or pi.

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
