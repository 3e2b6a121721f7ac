// Directional tint of an EDF (MaterialX Specification 1.39, pbrlib "generalized_schlick_edf"):
// Schlick's interpolation (Schlick 1994) from color0 at normal view to color90 at grazing,
// with a free exponent: color0 + (color90 - color0) (1 - |N.V|)^exponent.

vec3 mg_generalized_schlick_edf(vec3 N, vec3 V, vec3 color0, vec3 color90, float exponent, vec3 base)
{
    float NdotV = clamp(abs(dot(N, V)), 0.0, 1.0);
    return base * mix(color0, color90, pow(1.0 - NdotV, exponent));
}
