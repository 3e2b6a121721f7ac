// requires: constants.glsl lighting/environment.glsl
// Burley diffuse reflection (Burley 2012, "Physically-Based Shading at Disney", section 5.3):
// f = rho/pi (1 + (F90 - 1)(1 - mu_l)^5)(1 + (F90 - 1)(1 - mu_v)^5), F90 = 0.5 + 2 r cos^2(theta_d).

float mg_burley_factor(float NdotL, float NdotV, float LdotH, float roughness)
{
    float f90 = 0.5 + 2.0 * roughness * LdotH * LdotH;
    float fl = 1.0 + (f90 - 1.0) * pow(1.0 - NdotL, 5.0);
    float fv = 1.0 + (f90 - 1.0) * pow(1.0 - NdotV, 5.0);
    return fl * fv;
}

// Directional albedo for unit rho. f is quadratic in r, so E = e0 + r e1 + r^2 e2 exactly; each e_i is
// a polynomial in x = 1 - mu fitted to numerical integration (tools/fit_burley.py, error < 3e-6).
float mg_burley_albedo(float mu, float r)
{
    float x = 1.0 - mu;
    float x2 = x * x;
    float x5 = x2 * x2 * x;
    float e0 = 0.976194 - 0.488097 * x5;
    float e1 = 0.0595261 - 0.0119048 * x + x5 * (1.60715 - 0.654764 * x);
    float e2 = -2.88356e-06 + x * (0.000224311 + x * (-0.0033476 + x * (0.0196253 + x * (-0.0559672
             + x * (0.158272 - 0.0493469 * x)))));
    return e0 + r * (e1 + r * e2);
}

BSDF mg_burley_reflection(vec3 L, vec3 V, float weight, vec3 color, float roughness, vec3 N)
{
    float NdotL = clamp(dot(N, L), 0.0, 1.0);
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    float LdotH = clamp(dot(L, normalize(L + V)), 0.0, 1.0);
    return BSDF(color * (weight * NdotL * mg_burley_factor(NdotL, NdotV, LdotH, roughness) / MG_PI), vec3(0.0));
}

BSDF mg_burley_indirect(vec3 V, float weight, vec3 color, float roughness, vec3 N)
{
    float NdotV = clamp(dot(N, V), 1.0e-6, 1.0);
    return BSDF(color * (weight * mg_burley_albedo(NdotV, roughness)) * mg_env_irradiance(N), vec3(0.0));
}
