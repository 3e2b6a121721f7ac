// Stride's Fresnel models (Stride manual, "Shading attributes" > Specular model > Fresnel; formulas in
// docs/material-models.md sec. 5). f0 is the specular colour, LH = sat(l.h), NV >= 1e-4.

// Schlick: f0 + (1 - f0)(1 - LH)^5 (Stride docs, Fresnel "Schlick").
vec3 mg_stride_fresnel_schlick(vec3 f0, float LH)
{
    float m = 1.0 - LH;
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// None: the specular colour as-is (Stride docs, Fresnel "None").
vec3 mg_stride_fresnel_none(vec3 f0)
{
    return f0;
}

// Thin glass, view based: a slab's two interfaces with absorption K = base^(1/cos theta_t)
// (Stride docs, Fresnel "Thin glass"). Returns the reflectance; transmittance through `transmittance`.
vec3 mg_stride_thin_glass(vec3 base, float NV, float ior, out vec3 transmittance)
{
    float eta = max(ior, 1.0001);
    float sin2_t = (1.0 - NV * NV) / (eta * eta);
    float ct = sqrt(max(1.0 - sin2_t, 0.0));
    float rs = (eta * ct - NV) / (eta * ct + NV);
    float rp = (eta * NV - ct) / (eta * NV + ct);
    float R = 0.5 * clamp(rs * rs + rp * rp, 0.0, 1.0);
    float T = 1.0 - R;
    vec3 K = pow(max(base, vec3(0.001)), vec3(1.0 / ct));
    transmittance = clamp(T * T * K / (1.0 - R * R * K * K), 0.0, 1.0);
    return clamp(R * K * transmittance + R, 0.0, 1.0);
}

vec3 mg_stride_fresnel_thin_glass(vec3 base, float NV, float ior)
{
    vec3 transmittance;
    return mg_stride_thin_glass(base, NV, ior, transmittance);
}
