// requires: closures.glsl
// absorption_vdf (MaterialX Specification 1.39, pbrlib) applied to what is seen through a surface:
// Beer–Lambert transmittance exp(-σa d) (Beer 1852; Lambert 1760), with the path length d taken as the
// chord of a sphere of radius u_vdfThickness through the point along the view direction, d = 2 r (n·v).
// σ is per scene unit; u_vdfThickness = 1 matches the render harness's unit sphere.
uniform float u_vdfThickness = 1.0;

float mg_vdf_path_length(vec3 N, vec3 V)
{
    return 2.0 * u_vdfThickness * clamp(dot(N, V), 0.0, 1.0);
}

VDF mg_absorption_vdf(vec3 absorption, vec3 N, vec3 V)
{
    return VDF(vec3(0.0), exp(-max(absorption, vec3(0.0)) * mg_vdf_path_length(N, V)));
}
