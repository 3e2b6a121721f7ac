// Hair absorption from melanin: d'Eon et al. 2011, "An Energy-Conserving Hair Reflectance Model" (σa = c_eu·σ_eu + c_pheo·σ_pheo); colours hold exp(−σ).

// melanin in [0, 1] becomes a concentration with −log(1 − m) (1 = opaque black), which redness splits
// between pheomelanin (redness, not clamped) and eumelanin (1 − redness)
vec3 mg_deon_hair_absorption_from_melanin(float melanin, float redness, vec3 eumelanin_color, vec3 pheomelanin_color)
{
    float concentration = -log(max(1.0 - clamp(melanin, 0.0, 1.0), 1.0e-4));
    return concentration * ((1.0 - redness) * -log(eumelanin_color) + redness * -log(pheomelanin_color));
}
