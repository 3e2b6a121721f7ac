// requires: constants.glsl pbrlib/microfacet/fresnel.glsl
// Thin-film iridescence by Airy summation with analytic spectral integration (Belcour & Barla 2017,
// "A Practical Extension to Microfacet Theory for the Modeling of Varying Iridescence").
// mg_thin_film_airy: per polarization (s, p), with the reflection phase of each interface from its
// complex Fresnel amplitude, summed in CIE XYZ and brought to RGB by the paper's XYZ -> CIE RGB (E)
// matrix; the base's colour enters per XYZ component (component j from the base's channel j).
// mg_thin_film_base (a dielectric or conductor base) or mg_thin_film_schlick_base (a generalized Schlick base) give
// the base's side, mg_thin_film_airy the film's reflectance (pbrlib/microfacet/fresnel_model.glsl: mg_fresnel_film).
// mg_thin_film_reflectance is the older polarization-averaged form, kept for Enterprise PBR's film.

// The CIE XYZ sensitivities' Gaussian fits (Belcour & Barla 2017, supplemental), one lobe each of x, y, z and x's
// second lobe: frequencies, widths (variances) and amplitudes val sqrt(2 pi var), normalized by y's integral.
const vec4 MG_THIN_FILM_XYZ_FREQ = vec4(1.6810e+06, 1.7953e+06, 2.2084e+06, 2.2399e+06);
const vec4 MG_THIN_FILM_XYZ_VAR = vec4(4.3278e+09, 9.3046e+09, 6.6121e+09, 4.5282e+09);
const vec4 MG_THIN_FILM_XYZ_AMP = vec4(5.4856e-13, 4.4201e-13, 5.2481e-13, 9.7470e-14)
                                  * sqrt(MG_TWO_PI * MG_THIN_FILM_XYZ_VAR) / 1.0685e-7;

// Fourier transform of the CIE XYZ sensitivities for optical path difference opd (nm) and phase
// shift (Belcour & Barla 2017, supplemental: Gaussian fits of the colour matching functions).
vec3 mg_thin_film_sensitivity(float opd, vec3 shift)
{
    float phase = MG_TWO_PI * opd * 1.0e-9;
    vec4 xyz = MG_THIN_FILM_XYZ_AMP * cos(MG_THIN_FILM_XYZ_FREQ * phase + vec4(shift, shift.x))
               * exp(-phase * phase * MG_THIN_FILM_XYZ_VAR);
    return xyz.xyz + vec3(xyz.w, 0.0, 0.0);
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

// ---- Polarized Airy summation (Belcour & Barla 2017, sec. 4 and supplemental), without angles.
// An interface's phase phi enters the sum only as cos(m A + m phi) for the orders m = 1, 2 (A: the spectral
// frequency times the round trip's phase), that is Re(e^{i m A} z^m) with z = e^{i phi}: each phase is carried as
// the unit phasor r / |r| of its complex amplitude, its powers by complex products, and e^{2iA} comes from e^{iA}
// by the double angle. One sin, cos and exp of four frequencies per evaluation, all three channels as vectors,
// and no atan (eight per evaluation before: the GPU compilers' costliest part of a film).
// Complex numbers per channel are (re, im) pairs of vec3.

// Reflectance |r|^2 and unit phasor r / |r| (0 where r = 0) of the amplitude r = num / den, per channel.
void mg_film_ratio(vec3 num_re, vec3 num_im, vec3 den_re, vec3 den_im, out vec3 R, out vec3 u_re, out vec3 u_im)
{
    vec3 nn = num_re * num_re + num_im * num_im;
    vec3 dd = den_re * den_re + den_im * den_im;
    R = nn / max(dd, vec3(1.0e-20));
    vec3 scale = inversesqrt(max(nn * dd, vec3(1.0e-30)));      // num conj(den) / (|num| |den|)
    u_re = (num_re * den_re + num_im * den_im) * scale;
    u_im = (num_im * den_re - num_re * den_im) * scale;
}

// Reflectance and phase (unit phasor) of the s and p amplitudes at an interface from a film of index n1 into a base
// of complex IOR eta + i k per channel (k = 0: a dielectric), at the cosine cos2 in the film (Born & Wolf, sec. 1.5
// and 14.2: r_s = (cos - n cos_t) / (cos + n cos_t), r_p = (n^2 cos - n cos_t) / (n^2 cos + n cos_t), n the
// relative index, n cos_t = sqrt(n^2 - sin^2) its principal root).
void mg_thin_film_base(float cos2, float n1, vec3 eta, vec3 k, out vec3 Rs, out vec3 Rp,
                       out vec3 us_re, out vec3 us_im, out vec3 up_re, out vec3 up_im)
{
    vec3 a = eta / n1;
    vec3 b = k / n1;
    vec3 nsq_re = a * a - b * b;
    vec3 nsq_im = 2.0 * a * b;
    vec3 w_re = nsq_re - (1.0 - cos2 * cos2);
    vec3 r = sqrt(w_re * w_re + nsq_im * nsq_im);
    vec3 q_re = sqrt(max(0.5 * (r + w_re), 0.0));
    vec3 q_im = sqrt(max(0.5 * (r - w_re), 0.0));
    q_im = mix(q_im, -q_im, lessThan(nsq_im, vec3(0.0)));
    mg_film_ratio(cos2 - q_re, -q_im, cos2 + q_re, q_im, Rs, us_re, us_im);
    vec3 pc_re = nsq_re * cos2;
    vec3 pc_im = nsq_im * cos2;
    mg_film_ratio(pc_re - q_re, pc_im - q_im, pc_re + q_re, pc_im + q_im, Rp, up_re, up_im);
}

// One polarization's share of the Airy sum (half of it: the light is unpolarized). R12, t12: the first interface's
// reflectance and the sign of its (real) amplitude; R23 and (u_re, u_im): the base's reflectance and phasor.
// Adds the order-0 weight to I0 and the orders' complex weights C_m z^m to (w1, w2) (each pair: re, im), with
// z = e^{i (pi - phi12 + phi23)} = -sign(r12) u23 (the way back up through the first interface: pi minus its phase
// going in, by the Stokes relations) and C_m = (Rs - T121) r123^m.
void mg_thin_film_order_weights(float R12, float t12, vec3 R23, vec3 u_re, vec3 u_im, inout vec3 I0,
                                inout vec3 w1_re, inout vec3 w1_im, inout vec3 w2_re, inout vec3 w2_im)
{
    float T121 = 1.0 - R12;
    vec3 R123 = clamp(R12 * R23, 0.0, 0.9999);
    vec3 r123 = sqrt(R123);
    vec3 Rs = T121 * T121 * R23 / (1.0 - R123);
    I0 += 0.5 * (R12 + Rs);
    vec3 C1 = 0.5 * (Rs - T121) * r123;
    vec3 z_re = -t12 * u_re;
    vec3 z_im = -t12 * u_im;
    w1_re += C1 * z_re;
    w1_im += C1 * z_im;
    vec3 C2 = C1 * r123;
    w2_re += C2 * (z_re * z_re - z_im * z_im);
    w2_im += C2 * (2.0 * z_re * z_im);
}

// Reflectance of a film (index eta2 >= 1, thickness in nm) in air over a base whose film-side reflectance and phase
// (unit phasor) are given per polarization and channel (mg_thin_film_base, mg_thin_film_schlick_base), at the
// incidence cosine c1 in [0, 1], whose refraction cosine in the film is cos2 (mg_thin_film_cos2).
// The spectral integral of each order is the Fourier transform of the CIE XYZ sensitivities (Belcour & Barla 2017,
// supplemental: Gaussian fits, x with a second lobe: MG_THIN_FILM_XYZ_*) at the order's path difference: frequencies f,
// amplitudes val sqrt(2 pi var), widths var, for the round trip's phase p = 2 pi opd;
// order m weighs each by exp(-m^2 p^2 var) cos(m f p + m phi). XYZ component j takes the base's channel j.
vec3 mg_thin_film_airy(float c1, float eta2, float cos2, float thickness, vec3 R23s, vec3 R23p,
                       vec3 u23s_re, vec3 u23s_im, vec3 u23p_re, vec3 u23p_im)
{
    // the air-film interface: real amplitudes (eta2 >= 1, no total reflection from the air)
    float nc = eta2 * cos2;
    float rs12 = (c1 - nc) / (c1 + nc);
    float rp12 = (eta2 * eta2 * c1 - nc) / (eta2 * eta2 * c1 + nc);
    vec3 I0 = vec3(0.0), w1_re = vec3(0.0), w1_im = vec3(0.0), w2_re = vec3(0.0), w2_im = vec3(0.0);
    mg_thin_film_order_weights(min(rs12 * rs12, 1.0), sign(rs12), R23s, u23s_re, u23s_im, I0, w1_re, w1_im, w2_re, w2_im);
    mg_thin_film_order_weights(min(rp12 * rp12, 1.0), sign(rp12), R23p, u23p_re, u23p_im, I0, w1_re, w1_im, w2_re, w2_im);

    const vec4 amp = MG_THIN_FILM_XYZ_AMP;
    float p = MG_TWO_PI * 2.0e-9 * eta2 * thickness * cos2;        // round trip: opd = 2 eta2 d cos2 (nm)
    vec4 A = MG_THIN_FILM_XYZ_FREQ * p;
    vec4 c = cos(A), s = sin(A);
    vec4 g = exp(-(p * p) * MG_THIN_FILM_XYZ_VAR);
    vec4 g2 = g * g;
    vec4 G1 = amp * g;
    vec4 G2 = amp * (g2 * g2);                          // exp(-4 p^2 var)
    vec4 c2 = 2.0 * c * c - 1.0;                         // cos 2A, sin 2A
    vec4 s2 = 2.0 * s * c;
    // x's second lobe takes the x channel's weights
    vec4 W1_re = vec4(w1_re, w1_re.x), W1_im = vec4(w1_im, w1_im.x);
    vec4 W2_re = vec4(w2_re, w2_re.x), W2_im = vec4(w2_im, w2_im.x);
    vec4 orders = G1 * (c * W1_re - s * W1_im) + G2 * (c2 * W2_re - s2 * W2_im);
    vec3 I = I0 * vec3(amp.x + amp.w, amp.y, amp.z) + 2.0 * orders.xyz;
    I.x += 2.0 * orders.w;
    // CIE XYZ to CIE RGB under the equal-energy illuminant E (the paper's matrix: white maps to white)
    return clamp(mat3(2.3706743, -0.5138850, 0.0052982, -0.9000405, 1.4253036, -0.0146949,
                      -0.4706338, 0.0885814, 1.0093968) * I, 0.0, 1.0);
}

// The film-side reflectance and phase of a generalized Schlick base (generalized_schlick_bsdf; MaterialX PBR spec,
// Thin-Film Iridescence Model): the base's curve (F82 tint included) at the refraction cosine cos2 in the film (of
// index eta2) is the reflectance of both polarizations, and the phase there is a step, from the base IOR that
// color0 gives by the Schlick-to-IOR inversion (F0 held to [0.01, 0.99]). In the amplitude convention of
// mg_thin_film_base (r_p = -r_s head-on) that step is pi for s and 0 for p on a base denser than the film, 0 and
// pi on a rarer one, as the exact dielectric gives below its Brewster angle.
// MG_THIN_FILM_SCHLICK_R23: the share of the curve each polarization takes. 1 as the spec says: a film of IOR 1
// then leaves the base's curve unchanged, and a film over a perfect mirror (color0 = color90 = 1) reflects
// everything. MaterialX 1.39's GLSL takes 0.5 (docs/differences: thin_film_schlick).
#ifndef MG_THIN_FILM_SCHLICK_R23
#define MG_THIN_FILM_SCHLICK_R23 1.0
#endif
void mg_thin_film_schlick_base(float cos2, float eta2, vec3 F0, vec3 F82, vec3 F90, float exponent,
                               out vec3 Rs, out vec3 Rp, out vec3 us_re, out vec3 us_im, out vec3 up_re, out vec3 up_im)
{
    Rs = MG_THIN_FILM_SCHLICK_R23 * mg_fresnel_schlick_f82(cos2, F0, F82, F90, exponent);
    Rp = Rs;
    vec3 s = sqrt(clamp(F0, 0.01, 0.99));
    vec3 eta3 = (1.0 + s) / (1.0 - s);
    us_re = mix(vec3(-1.0), vec3(1.0), lessThan(eta3, vec3(eta2)));    // e^{i phi}: phi = pi or 0 for s
    us_im = vec3(0.0);
    up_re = -us_re;                                                     // p: pi - phi
    up_im = vec3(0.0);
}
