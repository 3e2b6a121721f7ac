// requires: constants.glsl lighting/environment.glsl
// Oren-Nayar diffuse reflection, the qualitative model of Oren & Nayar 1994 ("Generalization of
// Lambert's reflectance model") in Fujii's s/t form: f = rho/pi (A + B s/t).

float mg_oren_nayar_factor(float NdotL, float NdotV, float LdotV, float roughness)
{
    float s = LdotV - NdotL * NdotV;
    float st = s > 0.0 ? s / max(NdotL, NdotV) : 0.0;
    float sigma2 = roughness * roughness;
    float A = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33);
    float B = 0.45 * sigma2 / (sigma2 + 0.09);
    return A + B * st;
}

// Mean of the s/t term over the lit hemisphere, G(mu) = 1/pi int (s/t) cos(theta_l) dw: a quintic fit
// (max error 0.013) of the numerical integration in tools/fit_oren_nayar.py.
float mg_oren_nayar_st_mean(float mu)
{
    return ((((-2.05204 * mu + 4.36828) * mu - 3.16885) * mu + 0.800182) * mu - 0.437521) * mu + 0.502599;
}

// Directional albedo of the model for unit rho: A + B G(mu).
float mg_oren_nayar_albedo(float mu, float r)
{
    float sigma2 = r * r;
    float A = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33);
    float B = 0.45 * sigma2 / (sigma2 + 0.09);
    return A + B * mg_oren_nayar_st_mean(mu);
}

BSDF mg_oren_nayar_reflection(vec3 L, vec3 V, float weight, vec3 color, float roughness, vec3 N)
{
    float NdotL = clamp(dot(N, L), 1.0e-6, 1.0);
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    float f = mg_oren_nayar_factor(NdotL, NdotV, dot(L, V), roughness);
    return BSDF(color * (weight * NdotL * f / MG_PI), vec3(0.0));
}

BSDF mg_oren_nayar_indirect(vec3 V, float weight, vec3 color, float roughness, vec3 N)
{
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    float albedo = mg_oren_nayar_albedo(NdotV, roughness);
    return BSDF(color * (weight * albedo) * mg_env_irradiance(N), vec3(0.0));
}
