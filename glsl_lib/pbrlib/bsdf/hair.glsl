// requires: constants.glsl lighting/environment_specular.glsl pbrlib/microfacet/fresnel.glsl
// Hair: Chiang, Bitterli, Tappan & Burley 2016, "A Practical and Controllable Hair and Fur Model for
// Production Path Tracing" (lobes R, TT, TRT and a residual TRRT), with d'Eon et al. 2011's longitudinal
// scattering Mp, the trimmed-logistic azimuthal Np and the attenuations Ap of a dielectric cylinder.
// Roughness inputs are (longitudinal variance v, logistic scale s) per lobe (pbrlib chiang_hair_roughness).
// The fibre runs along the curve direction; the shading normal gives the offset h across it.

// log of the modified Bessel function I0 for large arguments (d'Eon et al. 2011, eq. 19)
float mg_hair_log_i0(float x)
{
    if (x > 12.0)
        return x + 0.5 * (-log(MG_TWO_PI) + log(1.0 / x) + 1.0 / (8.0 * x));
    // series I0(x) = sum (x^2/4)^i / (i!)^2
    float s = 1.0, t = 1.0, q = 0.25 * x * x;
    for (int i = 1; i < 10; ++i)
    {
        t *= q / float(i * i);
        s += t;
    }
    return log(s);
}

// Longitudinal scattering Mp (d'Eon et al. 2011, eq. 7), evaluated in log space for small variance.
float mg_hair_mp(float cos_i, float cos_o, float sin_i, float sin_o, float v)
{
    float a = cos_i * cos_o / v;
    float b = sin_i * sin_o / v;
    return exp(mg_hair_log_i0(a) - b - 1.0 / v + 0.6931 + log(1.0 / (2.0 * v)));
}

float mg_hair_logistic(float x, float s)
{
    x = abs(x);
    float e = exp(-x / s);
    return e / (s * (1.0 + e) * (1.0 + e));
}

float mg_hair_logistic_cdf(float x, float s)
{
    return 1.0 / (1.0 + exp(-x / s));
}

// Azimuthal scattering Np: a logistic about the exit azimuth of lobe p, trimmed to [-pi, pi].
float mg_hair_np(float phi, int p, float s, float gamma_o, float gamma_t)
{
    float dphi = phi - (2.0 * float(p) * gamma_t - 2.0 * gamma_o + float(p) * MG_PI);
    dphi = mod(dphi + MG_PI, MG_TWO_PI) - MG_PI;
    return mg_hair_logistic(dphi, s) / (mg_hair_logistic_cdf(MG_PI, s) - mg_hair_logistic_cdf(-MG_PI, s));
}

BSDF mg_chiang_hair_reflection(vec3 L, vec3 V, vec3 tint_R, vec3 tint_TT, vec3 tint_TRT, float ior,
                               vec2 rough_R, vec2 rough_TT, vec2 rough_TRT, float cuticle_angle,
                               vec3 absorption, vec3 N, vec3 X)
{
    // fibre frame: x along the fibre, y the normal's part across it, z completing it
    vec3 fx = normalize(X);
    vec3 fy = N - fx * dot(N, fx);
    fy = dot(fy, fy) > 1.0e-8 ? normalize(fy) : normalize(cross(fx, abs(fx.y) < 0.99 ? vec3(0, 1, 0) : vec3(1, 0, 0)));
    vec3 fz = cross(fx, fy);
    float sin_o = clamp(dot(V, fx), -1.0, 1.0), cos_o = sqrt(1.0 - sin_o * sin_o);
    float sin_i = clamp(dot(L, fx), -1.0, 1.0), cos_i = sqrt(1.0 - sin_i * sin_i);
    float phi_o = atan(dot(V, fz), dot(V, fy));
    float phi = atan(dot(L, fz), dot(L, fy)) - phi_o;
    // offset across the fibre where the view ray meets it: h = sin(gamma_o)
    float h = clamp(sin(phi_o), -0.999, 0.999);
    float gamma_o = asin(h);
    // refracted direction (Bravais' effective index for the azimuthal plane)
    float sin_t = sin_o / ior, cos_t = sqrt(max(1.0 - sin_t * sin_t, 0.0));
    float etap = sqrt(max(ior * ior - sin_o * sin_o, 0.0)) / max(cos_o, 1.0e-4);
    float gamma_t = asin(clamp(h / etap, -1.0, 1.0));
    vec3 T = exp(-absorption * (2.0 * cos(gamma_t) / max(cos_t, 1.0e-4)));
    // attenuations Ap
    float f = mg_fresnel_dielectric(cos_o * cos(gamma_o), ior);
    vec3 A0 = vec3(f);
    vec3 A1 = (1.0 - f) * (1.0 - f) * T;
    vec3 A2 = A1 * f * T;
    vec3 A3 = A2 * f * T / max(vec3(1.0) - T * f, vec3(1.0e-4));
    // cuticle scales tilt the lobes by -2a (R), a (TT), 4a (TRT); cuticle_angle 0.5 = no tilt, 0..1 spans
    // -pi/2..pi/2 / 10 (scales are a few degrees)
    float alpha = (cuticle_angle - 0.5) * MG_PI / 10.0;
    float s1 = sin(alpha), c1 = cos(alpha);
    float s2 = 2.0 * s1 * c1, c2 = c1 * c1 - s1 * s1;
    float s4 = 2.0 * s2 * c2, c4 = c2 * c2 - s2 * s2;
    float so0 = sin_o * c2 - cos_o * s2, co0 = abs(cos_o * c2 + sin_o * s2);
    float so1 = sin_o * c1 + cos_o * s1, co1 = abs(cos_o * c1 - sin_o * s1);
    float so2 = sin_o * c4 + cos_o * s4, co2 = abs(cos_o * c4 - sin_o * s4);
    vec3 f_sum = tint_R * A0 * mg_hair_mp(cos_i, co0, sin_i, so0, max(rough_R.x, 1.0e-3))
                 * mg_hair_np(phi, 0, max(rough_R.y, 1.0e-3), gamma_o, gamma_t)
               + tint_TT * A1 * mg_hair_mp(cos_i, co1, sin_i, so1, max(rough_TT.x, 1.0e-3))
                 * mg_hair_np(phi, 1, max(rough_TT.y, 1.0e-3), gamma_o, gamma_t)
               + tint_TRT * A2 * mg_hair_mp(cos_i, co2, sin_i, so2, max(rough_TRT.x, 1.0e-3))
                 * mg_hair_np(phi, 2, max(rough_TRT.y, 1.0e-3), gamma_o, gamma_t)
               // residual lobe: isotropic in azimuth, longitudinally as wide as TRT
               + tint_TRT * A3 * mg_hair_mp(cos_i, cos_o, sin_i, sin_o, max(rough_TRT.x, 1.0e-3)) / MG_TWO_PI;
    // the pbrt convention: f |cos theta_i| = f_sum
    return BSDF(f_sum, vec3(0.0));
}

// Environment: a single specular lobe standing in for the fibre's lobes, Fresnel-weighted, at the mean
// roughness of the lobes and tinted by their mean tint.
BSDF mg_chiang_hair_indirect(vec3 V, vec3 tint_R, vec3 tint_TT, vec3 tint_TRT, float ior, vec2 rough_R,
                             vec2 rough_TT, vec2 rough_TRT, vec3 N, vec3 X)
{
    float r = (rough_R.x + rough_R.y + rough_TT.x + rough_TT.y + rough_TRT.x + rough_TRT.y) / 6.0;
    vec2 alpha = mg_ggx_alpha(vec2(r));
    MgFresnel fr = mg_fresnel_dielectric_model(ior, 0.0, 1.5);
    vec3 tint = (tint_R + tint_TT + tint_TRT) / 3.0;
    return BSDF(tint * mg_env_specular(V, mg_tangent_frame(N, X), alpha, fr, false), vec3(0.0));
}
