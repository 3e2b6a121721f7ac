// conical_edf (MaterialX Specification 1.39, pbrlib): emission `color` inside a cone about the normal.
// Full inside inner_angle (degrees from the normal), falling smoothly (smoothstep in cos θ) to zero at
// outer_angle; where outer_angle <= inner_angle the cone has a hard edge at inner_angle.
vec3 mg_conical_edf(vec3 V, vec3 color, vec3 N, float inner_angle, float outer_angle)
{
    float cos_theta = dot(normalize(N), V);
    float cos_inner = cos(radians(clamp(inner_angle, 0.0, 180.0)));
    if (outer_angle <= inner_angle)
        return cos_theta >= cos_inner ? color : vec3(0.0);
    float cos_outer = cos(radians(clamp(outer_angle, 0.0, 180.0)));
    return color * smoothstep(cos_outer, cos_inner, cos_theta);
}
