// requires: closures.glsl
// The lights library's light shaders (MaterialX lights_defs.mtlx: point_light, directional_light,
// spot_light) evaluated at a surface point P: the radiance-scaled intensity arriving there and the
// direction the light travels (from the light towards P). Spot cone angles are cosines, as in
// MaterialX's light-rig documents.

lightshader mg_directional_light(vec3 direction, vec3 color, float intensity)
{
    return lightshader(color * intensity, normalize(direction));
}

// Inverse-power falloff: decay_rate 0 none, 1 linear, 2 physical inverse square.
lightshader mg_point_light(vec3 P, vec3 position, vec3 color, float intensity, float decay_rate)
{
    vec3 d = P - position;
    float dist = max(length(d), 1.0e-6);
    return lightshader(color * (intensity / pow(dist, decay_rate)), d / dist);
}

lightshader mg_spot_light(vec3 P, vec3 position, vec3 direction, vec3 color, float intensity, float decay_rate,
                          float inner_angle, float outer_angle)
{
    lightshader l = mg_point_light(P, position, color, intensity, decay_rate);
    float cos_angle = dot(l.direction, normalize(direction));
    l.intensity *= smoothstep(min(inner_angle, outer_angle), inner_angle, cos_angle);
    return l;
}
