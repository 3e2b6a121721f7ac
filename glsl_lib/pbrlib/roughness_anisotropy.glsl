// requires: constants.glsl
// Roughness/anisotropy to GGX alphas (Burley 2012, "Physically Based Shading at Disney", sec. 5.4: α = r², aspect = √(1 − anisotropy)).

// (α along the tangent, α along the bitangent): α = roughness², stretched by the aspect ratio;
// anisotropy is capped at 0.98 so that the bitangent α never collapses to 0
vec2 mg_roughness_anisotropy(float roughness, float anisotropy)
{
    float alpha = clamp(roughness * roughness, MG_EPS, 1.0);
    if (anisotropy <= 0.0)
        return vec2(alpha);
    float aspect = sqrt(1.0 - clamp(anisotropy, 0.0, 0.98));
    return vec2(min(alpha / aspect, 1.0), alpha * aspect);
}
