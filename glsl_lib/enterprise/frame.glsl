// requires: constants.glsl pbrlib/microfacet/ggx.glsl
// Shading frame and GGX roughness of the Enterprise PBR material (Dassault Systemes DSPBR 2025x,
// "Roughness" and "Anisotropy"): alpha = r^2, stretched along the rotated tangent.

// Frame (tangent, bitangent, normal) with the tangent turned about N by rotation * 2 pi (1 = 360 degrees).
mat3 mg_epbr_frame(vec3 N, vec3 T, float rotation)
{
    mat3 f = mg_tangent_frame(N, T);
    float phi = MG_TWO_PI * rotation;
    vec3 t = cos(phi) * f[0] + sin(phi) * f[1];
    return mat3(t, cross(f[2], t), f[2]);
}

// (alpha_t, alpha_b) = r^2 (1 + a, 1 - a) (the anisotropy mapping of Kulla & Conty 2017, "Revisiting
// Physically Based Shading at Imageworks"), kept off the singular mirror limit.
vec2 mg_epbr_alpha(float roughness, float anisotropy)
{
    float r = clamp(roughness, 0.0, 1.0);
    float k = clamp(anisotropy, 0.0, 1.0);
    return clamp(r * r * vec2(1.0 + k, 1.0 - k), vec2(1.0e-4), vec2(1.0));
}

// The roughness coordinate of the energy tables for an anisotropic lobe: r of the isotropic lobe of
// the same alpha_t alpha_b (Kulla & Conty 2017 tabulate the isotropic albedo).
float mg_epbr_table_roughness(vec2 alpha)
{
    return sqrt(sqrt(alpha.x * alpha.y));
}
