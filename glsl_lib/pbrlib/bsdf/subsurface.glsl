// requires: constants.glsl lighting/environment.glsl
// Subsurface scattering, approximated for a single shading point (MaterialX Specification 1.39, pbrlib
// "subsurface_bsdf" leaves the method to the renderer). Direct light: energy-conserving wrap lighting
// (Green 2004, "Real-Time Approximations to Subsurface Scattering", GPU Gems ch. 16), the wrap growing
// with the mean free path relative to the surface's radius of curvature, and a Henyey-Greenstein
// weighting of light passing through (anisotropy g). Environment: the diffuse irradiance.

// Radius of curvature of the surface, from the screen-space change of normal and position.
float mg_curvature(vec3 N, vec3 P)
{
    return length(fwidth(N)) / max(length(fwidth(P)), 1.0e-6);
}

// Henyey-Greenstein phase function, normalized so that it is 1 for an isotropic medium (g = 0).
float mg_henyey_greenstein_4pi(float cos_theta, float g)
{
    float d = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (d * sqrt(max(d, 1.0e-6)));
}

BSDF mg_subsurface_reflection(vec3 L, vec3 V, vec3 P, float weight, vec3 color, vec3 radius, float anisotropy,
                              vec3 N)
{
    float NdotL = dot(N, L);
    vec3 wrap = clamp(radius * mg_curvature(N, P), 0.0, 1.0);
    // (N.L + w) / (1 + w)^2 keeps the lobe's cosine-weighted integral at that of Lambert
    vec3 lit = max((vec3(NdotL) + wrap) / ((1.0 + wrap) * (1.0 + wrap)), 0.0);
    // light reaching the far side has crossed the medium: weight it by the phase function towards V
    float phase = mg_henyey_greenstein_4pi(dot(-L, V), anisotropy);
    lit *= mix(1.0, phase, clamp(-NdotL, 0.0, 1.0));
    return BSDF(color * (weight / MG_PI) * lit, vec3(0.0));
}

BSDF mg_subsurface_indirect(float weight, vec3 color, vec3 N)
{
    return BSDF(color * weight * mg_env_irradiance(N), vec3(0.0));
}
