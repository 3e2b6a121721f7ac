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

// ---- energy compensation: EON (Portsmouth, Kutz & Hill 2025, "EON: A practical energy-preserving rough
// diffuse BRDF"): Fujii's Oren-Nayar (FON) single scattering plus a Kulla-Conty style multiple-scattering lobe.

const float MG_EON_C1 = 0.5 - 2.0 / (3.0 * MG_PI);        // FON: A = 1 / (1 + C1 r), B = r A
const float MG_EON_C2 = 2.0 / 3.0 - 28.0 / (15.0 * MG_PI); // FON mean albedo: A (1 + C2 r)

// Directional albedo of FON for unit rho, the paper's quartic fit in (1 - mu).
float mg_eon_fon_albedo(float mu, float r)
{
    float m = 1.0 - mu;
    float g_over_pi = m * (0.0571085289 + m * (0.491881867 + m * (-0.332181442 + m * 0.0714429953)));
    return (1.0 + r * g_over_pi) / (1.0 + MG_EON_C1 * r);
}

float mg_eon_fon_mean_albedo(float r)
{
    return (1.0 + MG_EON_C2 * r) / (1.0 + MG_EON_C1 * r);
}

// Albedo of the multiple-scattering lobe: rho^2 Eavg / (1 - rho (1 - Eavg)).
vec3 mg_eon_rho_ms(vec3 rho, float avg)
{
    return rho * rho * avg / (vec3(1.0) - rho * (1.0 - avg));
}

// f_EON cos(theta_l), for colour rho.
vec3 mg_eon_reflection(float NdotL, float NdotV, float LdotV, vec3 rho, float r)
{
    float s = LdotV - NdotL * NdotV;
    float s_over_t = s > 0.0 ? s / max(NdotL, NdotV) : s;
    float AF = 1.0 / (1.0 + MG_EON_C1 * r);
    vec3 f_ss = rho / MG_PI * (AF * (1.0 + r * s_over_t));
    float avg = mg_eon_fon_mean_albedo(r);
    vec3 f_ms = mg_eon_rho_ms(rho, avg) / MG_PI * (max(1.0e-7, 1.0 - mg_eon_fon_albedo(NdotV, r))
              * max(1.0e-7, 1.0 - mg_eon_fon_albedo(NdotL, r)) / max(1.0e-7, 1.0 - avg));
    return (f_ss + f_ms) * NdotL;
}

// Directional albedo of EON: rho E(mu) + rho_ms (1 - E(mu)).
vec3 mg_eon_albedo(float mu, vec3 rho, float r)
{
    float e = mg_eon_fon_albedo(mu, r);
    return rho * e + mg_eon_rho_ms(rho, mg_eon_fon_mean_albedo(r)) * (1.0 - e);
}

BSDF mg_oren_nayar_reflection(vec3 L, vec3 V, float weight, vec3 color, float roughness, vec3 N, bool compensate)
{
    if (!compensate)
        return mg_oren_nayar_reflection(L, V, weight, color, roughness, N);
    float NdotL = clamp(dot(N, L), 1.0e-6, 1.0);
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    return BSDF(weight * mg_eon_reflection(NdotL, NdotV, dot(L, V), color, roughness), vec3(0.0));
}

BSDF mg_oren_nayar_indirect(vec3 V, float weight, vec3 color, float roughness, vec3 N, bool compensate)
{
    if (!compensate)
        return mg_oren_nayar_indirect(V, weight, color, roughness, N);
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    return BSDF(weight * mg_eon_albedo(NdotV, color, roughness) * mg_env_irradiance(N), vec3(0.0));
}
