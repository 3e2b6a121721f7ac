// requires: constants.glsl
// Stride's normal distribution functions of alpha = max((1 - gloss)^2, 0.001) (Stride manual, "Shading
// attributes" > Specular model > Normal distribution; formulas in docs/material-models.md sec. 5), and
// for each the sampling of cos(theta_h) with density D(h) NH, used for the environment's specular.

// GGX: alpha^2 / (pi max(NH^2 (alpha^2 - 1) + 1, 1e-4)^2) (Stride docs, NDF "GGX").
float mg_stride_ndf_ggx(float alpha, float NH)
{
    float a2 = alpha * alpha;
    float d = max(NH * NH * (a2 - 1.0) + 1.0, 1.0e-4);
    return a2 / (MG_PI * d * d);
}

// Beckmann with a = max(alpha^2, 0.1), c = max(NH^2, 1e-4): exp((c - 1) / (a c)) / (pi a c^2) (Stride docs, NDF "Beckmann").
float mg_stride_ndf_beckmann(float alpha, float NH)
{
    float a = max(alpha * alpha, 0.1);
    float c = max(NH * NH, 1.0e-4);
    return exp((c - 1.0) / (a * c)) / (MG_PI * a * c * c);
}

// Blinn-Phong with a = max(alpha^2, 0.1): max(NH, 1e-5)^(2/a - 2) / (pi a) (Stride docs, NDF "Blinn-Phong").
float mg_stride_ndf_blinn_phong(float alpha, float NH)
{
    float a = max(alpha * alpha, 0.1);
    return pow(max(NH, 1.0e-5), 2.0 / a - 2.0) / (MG_PI * a);
}

// cos(theta_h) distributed as D(h) NH, by inverting each NDF's cumulative distribution in u in [0, 1)
// (Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eqs. 28 and 35;
// Blinn-Phong: cos^(n+1) density, n = 2/a - 2).
float mg_stride_sample_ggx(float alpha, float u)
{
    float a2 = alpha * alpha;
    return sqrt((1.0 - u) / (1.0 + (a2 - 1.0) * u));
}

float mg_stride_sample_beckmann(float alpha, float u)
{
    float a = max(alpha * alpha, 0.1);
    return 1.0 / sqrt(1.0 - a * log(1.0 - u));
}

float mg_stride_sample_blinn_phong(float alpha, float u)
{
    float a = max(alpha * alpha, 0.1);
    return pow(1.0 - u, a / 2.0);
}
