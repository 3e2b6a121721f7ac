// requires: constants.glsl enterprise/tables.glsl
// Sheen of the Enterprise PBR material (DSPBR 2025x, "Sheen"): the "Charlie" distribution of Estevez &
// Kulla 2017 ("Production Friendly Microfacet Sheen BRDF") with the visibility 1 / (4 (mu_l + mu_v -
// mu_l mu_v)) of Neubelt & Pettineo 2013 ("Crafting a Next-Gen Material Pipeline for The Order: 1886"),
// alpha = max(sheenRoughness, 0.1)^2; what lies below is albedo-scaled in both directions.

float mg_epbr_sheen_alpha(float r)
{
    float x = max(r, 0.1);
    return x * x;
}

// f (no cosine) of the sheen lobe.
float mg_epbr_sheen(float mu_l, float mu_v, float NdotH, float r)
{
    float inv = 1.0 / mg_epbr_sheen_alpha(r);
    float sin2 = max(1.0 - NdotH * NdotH, 0.0);
    float D = (2.0 + inv) * pow(sin2, 0.5 * inv) / MG_TWO_PI;
    return D / (4.0 * max(mu_l + mu_v - mu_l * mu_v, 1.0e-4));
}

// 1 - w E_sheen(mu): the share of light passing the sheen layer at mu (w = the sheen colour's maximum).
float mg_epbr_sheen_scale(float w, float r, float mu)
{
    return 1.0 - w * mg_epbr_sheen_e(r, mu);
}
