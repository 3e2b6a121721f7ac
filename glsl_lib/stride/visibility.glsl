// requires: constants.glsl
// Stride's visibility terms V = G / (4 NL NV) * 4, i.e. the shadowing-masking G already divided by
// NL NV (Stride manual, "Shading attributes" > Specular model > Visibility; formulas in
// docs/material-models.md sec. 5). All take (alpha, NL, NV, NH, VH) with NL, NV >= 1e-4.

// Implicit: G = NL NV, so V = 1 (Stride docs, visibility "Implicit").
float mg_stride_vis_implicit(float alpha, float NL, float NV, float NH, float VH)
{
    return 1.0;
}

// Neumann: G = NL NV / max(NL, NV) (Stride docs, visibility "Neumann").
float mg_stride_vis_neumann(float alpha, float NL, float NV, float NH, float VH)
{
    return 1.0 / max(NL, NV);
}

// Cook-Torrance: G = min(1, 2 NH NV / VH, 2 NH NL / VH) (Stride docs, visibility "Cook-Torrance").
float mg_stride_vis_cook_torrance(float alpha, float NL, float NV, float NH, float VH)
{
    float vh = max(VH, 1.0e-4);
    float G = min(1.0, min(2.0 * NH * NV / vh, 2.0 * NH * NL / vh));
    return G / (NL * NV);
}

// Kelemen: V = 1 / VH^2 (Stride docs, visibility "Kelemen").
float mg_stride_vis_kelemen(float alpha, float NL, float NV, float NH, float VH)
{
    float vh = max(VH, 1.0e-4);
    return 1.0 / (vh * vh);
}

// Smith-Beckmann G1, rational fit in c = x / (alpha sqrt(1 - x^2)) (Stride docs, "Smith-Beckmann").
float mg_stride_g1_smith_beckmann(float alpha, float x)
{
    float c = x / (alpha * sqrt(max(1.0 - x * x, 1.0e-12)));
    if (c >= 1.6)
        return 1.0;
    return (3.535 * c + 2.181 * c * c) / (1.0 + 2.276 * c + 2.577 * c * c);
}

float mg_stride_vis_smith_beckmann(float alpha, float NL, float NV, float NH, float VH)
{
    return mg_stride_g1_smith_beckmann(alpha, NL) * mg_stride_g1_smith_beckmann(alpha, NV) / (NL * NV);
}

// Smith-GGX height-correlated: Lambda(x) = sqrt(1 + alpha^2 (1 - x^2) / x^2), V = 2 / (Lambda(NL) + Lambda(NV)) / (NL NV)
// (Stride docs, visibility "Smith-GGX correlated").
float mg_stride_lambda_ggx(float alpha, float x)
{
    return sqrt(1.0 + alpha * alpha * (1.0 - x * x) / (x * x));
}

float mg_stride_vis_smith_ggx_correlated(float alpha, float NL, float NV, float NH, float VH)
{
    return 2.0 / (mg_stride_lambda_ggx(alpha, NL) + mg_stride_lambda_ggx(alpha, NV)) / (NL * NV);
}

// Schlick's G1 = x / (x (1 - k) + k) (Stride docs, "Schlick-Beckmann" k = alpha sqrt(2/pi), "Schlick-GGX" k = alpha/2).
float mg_stride_g1_schlick(float k, float x)
{
    return x / (x * (1.0 - k) + k);
}

float mg_stride_vis_schlick_beckmann(float alpha, float NL, float NV, float NH, float VH)
{
    float k = alpha * sqrt(2.0 / MG_PI);
    return mg_stride_g1_schlick(k, NL) * mg_stride_g1_schlick(k, NV) / (NL * NV);
}

float mg_stride_vis_schlick_ggx(float alpha, float NL, float NV, float NH, float VH)
{
    float k = 0.5 * alpha;
    return mg_stride_g1_schlick(k, NL) * mg_stride_g1_schlick(k, NV) / (NL * NV);
}
