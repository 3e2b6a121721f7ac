// Fresnel reflectance curves of the microfacet BSDFs. cosTheta is the cosine between the incident
// direction and the microfacet normal.

// Unpolarized Fresnel reflectance of a dielectric interface of relative IOR eta (Walter et al. 2007 eq. 22).
float mg_fresnel_dielectric(float cosTheta, float eta)
{
    float c = abs(cosTheta);
    float g2 = eta * eta - 1.0 + c * c;
    if (g2 < 0.0)
        return 1.0;                     // total internal reflection
    float g = sqrt(g2);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    return 0.5 * a * a * (1.0 + b * b);
}

// Normal-incidence reflectance of a dielectric of relative IOR eta.
float mg_ior_to_f0(float eta)
{
    float r = (eta - 1.0) / (eta + 1.0);
    return r * r;
}

// Fresnel reflectance of a conductor of complex IOR eta + i k, per channel (exact unpolarized form of
// the Fresnel equations for an absorbing medium, Born & Wolf, "Principles of Optics", sec. 14.2).
vec3 mg_fresnel_conductor(float cosTheta, vec3 eta, vec3 k)
{
    float c2 = clamp(cosTheta * cosTheta, 0.0, 1.0);
    float s2 = 1.0 - c2;
    vec3 t0 = eta * eta - k * k - s2;
    vec3 a2b2 = sqrt(t0 * t0 + 4.0 * eta * eta * k * k);
    vec3 a = sqrt(max(0.5 * (a2b2 + t0), 0.0));
    vec3 t1 = a2b2 + c2;
    vec3 t2 = 2.0 * a * sqrt(c2);
    vec3 rs = (t1 - t2) / max(t1 + t2, vec3(1.0e-8));
    vec3 t3 = c2 * a2b2 + s2 * s2;
    vec3 t4 = t2 * s2;
    vec3 rp = rs * (t3 - t4) / max(t3 + t4, vec3(1.0e-8));
    return 0.5 * (rp + rs);
}

// Schlick's approximation with an arbitrary exponent (Schlick 1994, generalized in the MaterialX spec).
vec3 mg_fresnel_schlick(float cosTheta, vec3 F0, vec3 F90, float exponent)
{
    float x = clamp(1.0 - cosTheta, 0.0, 1.0);
    return mix(F0, F90, pow(x, exponent));
}

// Schlick with an F82 tint (Hoffman 2023, "Generalization of Adobe's Fresnel Model"): subtracts
// a mu (1 - mu)^6 so that the curve at mu = 1/7 equals F82 times the plain Schlick value there.
vec3 mg_fresnel_schlick_f82(float cosTheta, vec3 F0, vec3 F82, vec3 F90, float exponent)
{
    const float mu_bar = 1.0 / 7.0;
    vec3 s_bar = mg_fresnel_schlick(mu_bar, F0, F90, exponent);
    vec3 a = s_bar * (1.0 - F82) / (mu_bar * pow(1.0 - mu_bar, 6.0));
    float mu = clamp(cosTheta, 0.0, 1.0);
    return max(mg_fresnel_schlick(mu, F0, F90, exponent) - a * mu * pow(1.0 - mu, 6.0), vec3(0.0));
}
