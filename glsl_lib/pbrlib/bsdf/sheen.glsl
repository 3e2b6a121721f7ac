// requires: constants.glsl lighting/environment.glsl
// Sheen: a retro-reflective microfacet lobe for cloth-like surfaces, in two modes.
//   conty_kulla: Conty & Kulla 2017, "Production Friendly Microfacet Sheen BRDF" (the "Charlie" NDF),
//                with the smooth visibility 1 / (4 (mu_l + mu_v - mu_l mu_v)) of Neubelt & Pettineo 2013.
//   zeltner:     Zeltner, Burley & Chiang 2022, "Practical Multiple-Scattering Sheen Using Linearly
//                Transformed Cosines": an LTC lobe with the paper's fitted coefficients and albedo.
// Both scale what lies below by 1 - weight * albedo (albedo scaling).

// ---- Conty-Kulla

// D(m) = (2 + 1/r) sin(theta_m)^(1/r) / (2 pi)
float mg_sheen_charlie_ndf(float NdotH, float r)
{
    float inv_r = 1.0 / r;
    float sin2 = max(1.0 - NdotH * NdotH, 0.0);
    return (2.0 + inv_r) * pow(sin2, 0.5 * inv_r) / MG_TWO_PI;
}

// Directional albedo E[r][mu] at r, mu = i / 15, integrated numerically (tools/fit_sheen.py).
const float MG_SHEEN_CK_ALBEDO[256] = float[256](
    5.4089, 1.3467, 0.3866, 0.1011, 0.0227, 0.0042, 0.0006, 0.0001, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000,
    1.5957, 1.0104, 0.7121, 0.5117, 0.3682, 0.2630, 0.1854, 0.1281, 0.0863, 0.0562, 0.0350, 0.0205, 0.0110, 0.0051, 0.0018, 0.0003,
    1.1834, 0.8383, 0.6497, 0.5137, 0.4085, 0.3246, 0.2565, 0.2008, 0.1551, 0.1176, 0.0870, 0.0623, 0.0426, 0.0271, 0.0152, 0.0065,
    1.0080, 0.7503, 0.6062, 0.4995, 0.4145, 0.3444, 0.2854, 0.2352, 0.1920, 0.1549, 0.1228, 0.0952, 0.0715, 0.0512, 0.0340, 0.0196,
    0.9074, 0.6953, 0.5756, 0.4859, 0.4133, 0.3524, 0.3001, 0.2546, 0.2146, 0.1792, 0.1477, 0.1197, 0.0948, 0.0725, 0.0527, 0.0352,
    0.8413, 0.6573, 0.5530, 0.4743, 0.4102, 0.3557, 0.3085, 0.2668, 0.2296, 0.1962, 0.1659, 0.1385, 0.1134, 0.0905, 0.0696, 0.0505,
    0.7941, 0.6292, 0.5356, 0.4647, 0.4067, 0.3571, 0.3137, 0.2751, 0.2403, 0.2087, 0.1798, 0.1532, 0.1286, 0.1057, 0.0845, 0.0647,
    0.7587, 0.6075, 0.5218, 0.4567, 0.4033, 0.3574, 0.3171, 0.2810, 0.2483, 0.2184, 0.1907, 0.1650, 0.1411, 0.1186, 0.0974, 0.0775,
    0.7309, 0.5902, 0.5105, 0.4500, 0.4001, 0.3573, 0.3194, 0.2854, 0.2545, 0.2260, 0.1995, 0.1748, 0.1516, 0.1296, 0.1087, 0.0889,
    0.7086, 0.5761, 0.5012, 0.4442, 0.3973, 0.3568, 0.3211, 0.2888, 0.2594, 0.2322, 0.2068, 0.1830, 0.1605, 0.1391, 0.1186, 0.0990,
    0.6903, 0.5643, 0.4933, 0.4393, 0.3947, 0.3563, 0.3223, 0.2915, 0.2634, 0.2373, 0.2129, 0.1899, 0.1681, 0.1473, 0.1273, 0.1081,
    0.6749, 0.5544, 0.4865, 0.4349, 0.3924, 0.3557, 0.3231, 0.2937, 0.2667, 0.2416, 0.2181, 0.1959, 0.1748, 0.1545, 0.1351, 0.1162,
    0.6619, 0.5458, 0.4806, 0.4311, 0.3903, 0.3551, 0.3238, 0.2955, 0.2695, 0.2453, 0.2226, 0.2011, 0.1806, 0.1609, 0.1419, 0.1235,
    0.6506, 0.5384, 0.4755, 0.4278, 0.3884, 0.3545, 0.3243, 0.2970, 0.2719, 0.2485, 0.2265, 0.2056, 0.1857, 0.1666, 0.1481, 0.1301,
    0.6408, 0.5319, 0.4710, 0.4248, 0.3867, 0.3539, 0.3247, 0.2982, 0.2739, 0.2512, 0.2299, 0.2097, 0.1903, 0.1717, 0.1536, 0.1360,
    0.6322, 0.5262, 0.4669, 0.4221, 0.3852, 0.3533, 0.3250, 0.2993, 0.2757, 0.2537, 0.2330, 0.2133, 0.1944, 0.1762, 0.1586, 0.1414
);

float mg_sheen_conty_kulla_albedo(float mu, float r)
{
    vec2 x = clamp(vec2(mu, r), 0.0, 1.0) * 15.0;
    vec2 i = min(floor(x), 14.0);
    vec2 t = x - i;
    int k = int(i.y) * 16 + int(i.x);
    float a = mix(MG_SHEEN_CK_ALBEDO[k], MG_SHEEN_CK_ALBEDO[k + 1], t.x);
    float b = mix(MG_SHEEN_CK_ALBEDO[k + 16], MG_SHEEN_CK_ALBEDO[k + 17], t.x);
    return clamp(mix(a, b, t.y), 0.0, 1.0);
}

float mg_sheen_conty_kulla_roughness(float roughness)
{
    return clamp(roughness, 0.005, 1.0);
}

BSDF mg_sheen_conty_kulla_reflection(vec3 L, vec3 V, float weight, vec3 color, float roughness, vec3 N)
{
    float r = mg_sheen_conty_kulla_roughness(roughness);
    float NdotL = clamp(dot(N, L), 0.0, 1.0);
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    float NdotH = clamp(dot(N, normalize(L + V)), 0.0, 1.0);
    float f = mg_sheen_charlie_ndf(NdotH, r) / (4.0 * (NdotL + NdotV - NdotL * NdotV));
    float albedo = mg_sheen_conty_kulla_albedo(NdotV, r);
    return BSDF(color * (weight * f * NdotL), vec3(1.0 - weight * albedo));
}

BSDF mg_sheen_conty_kulla_indirect(vec3 V, float weight, vec3 color, float roughness, vec3 N)
{
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    float albedo = mg_sheen_conty_kulla_albedo(NdotV, mg_sheen_conty_kulla_roughness(roughness));
    return BSDF(color * (weight * albedo) * mg_env_irradiance(N), vec3(1.0 - weight * albedo));
}

// ---- Zeltner (LTC): x = cos(theta_v), y = roughness; the paper's rational and Gaussian fits.

float mg_sheen_zeltner_albedo(float x, float y)
{
    float s = y * (0.0206607 + 1.58491 * y) / (0.0379424 + y * (1.32227 + y));
    float m = y * (-0.193854 + y * (-1.14885 + y * (1.7932 - 0.95943 * y * y))) / (0.046391 + y);
    float o = y * (0.000654023 + (-0.0207818 + 0.119681 * y) * y) / (1.26264 + y * (-1.92021 + y));
    float z = (x - m) / s;
    return max(exp(-0.5 * z * z) / (s * sqrt(MG_TWO_PI)) + o, 0.0);
}

// The inverse LTC matrix [[a 0 b] [0 a 0] [0 0 1]] in the frame whose x axis is V's tangential part.
vec2 mg_sheen_zeltner_ltc(float x, float y)
{
    float a = (2.58126 * x + 0.813703 * y) * y / (1.0 + 0.310327 * x * x + 2.60994 * x * y);
    float b = sqrt(1.0 - x) * (y - 1.0) * y * y * y / (0.0000254053 + 1.71228 * x - 1.71506 * x * y + 1.34174 * y * y);
    return vec2(a, b);
}

BSDF mg_sheen_zeltner_reflection(vec3 L, vec3 V, float weight, vec3 color, float roughness, vec3 N)
{
    float r = clamp(roughness, 0.01, 1.0);
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    vec3 X = V - N * NdotV;
    float len2 = dot(X, X);
    X = len2 > 1.0e-12 ? X * inversesqrt(len2) : normalize(abs(N.x) < 0.9 ? cross(N, vec3(1.0, 0.0, 0.0))
                                                                         : cross(N, vec3(0.0, 1.0, 0.0)));
    vec3 Y = cross(N, X);
    vec3 w = vec3(dot(L, X), dot(L, Y), dot(L, N));
    vec2 ab = mg_sheen_zeltner_ltc(NdotV, r);
    vec3 wo = vec3(ab.x * w.x + ab.y * w.z, ab.x * w.y, w.z);
    float len = length(wo);
    // clamped cosine distribution at the transformed direction, times the Jacobian |M^-1| / |M^-1 w|^3
    float d = max(wo.z / len, 0.0) / MG_PI * (ab.x * ab.x) / (len * len * len);
    float albedo = mg_sheen_zeltner_albedo(NdotV, r);
    return BSDF(color * (weight * albedo * d), vec3(1.0 - weight * albedo));
}

BSDF mg_sheen_zeltner_indirect(vec3 V, float weight, vec3 color, float roughness, vec3 N)
{
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    float albedo = mg_sheen_zeltner_albedo(NdotV, clamp(roughness, 0.01, 1.0));
    return BSDF(color * (weight * albedo) * mg_env_irradiance(N), vec3(1.0 - weight * albedo));
}
