// requires: closures.glsl
// uniforms: u_vdfThickness
// absorption_vdf (MaterialX Specification 1.39, pbrlib) applied to what is seen through a surface:
// Beer–Lambert transmittance exp(-σa d) (Beer 1852; Lambert 1760). A surface shader does not know how far
// the view ray travels inside the object, so the path length d is a fixed u_vdfThickness scene units
// (1 by default: σ reads as the optical depth of one unit, the convention of MaterialX's renders).

float mg_vdf_path_length()
{
    return max(u_vdfThickness, 0.0);
}

VDF mg_absorption_vdf(vec3 absorption)
{
    return VDF(vec3(0.0), exp(-max(absorption, vec3(0.0)) * mg_vdf_path_length()));
}
