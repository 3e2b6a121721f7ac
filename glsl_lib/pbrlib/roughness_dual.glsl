// requires: constants.glsl
// Dual roughness to GGX alphas (Burley 2012, "Physically Based Shading at Disney": alpha = roughness², per axis).

// A negative second roughness repeats the first (isotropic).
vec2 mg_roughness_dual(vec2 roughness)
{
    float ry = roughness.y < 0.0 ? roughness.x : roughness.y;
    return clamp(vec2(roughness.x * roughness.x, ry * ry), vec2(MG_EPS), vec2(1.0));
}
