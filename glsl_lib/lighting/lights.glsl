// requires: lighting/light_shaders.glsl
// uniforms: u_lightData u_numActiveLightSources
// Direct lights bound by the application as u_lightData[] (the lights library's point, directional and
// spot lights; `mtlxgen render --lights RIG.mtlx` binds a light-rig document). type: 1 point,
// 2 directional, 3 spot (the order of lights_defs.mtlx); 0 = unused. Spot angles are cosines. The record
// (struct LightData) and MG_MAX_LIGHTS are declared with the uniforms (mtlxgen/interface.py).

// Direction towards the light (L) and the radiance-scaled irradiance it delivers at P.
void mg_sample_light(LightData light, vec3 P, out vec3 L, out vec3 intensity)
{
    lightshader l;
    if (light.type == 2)
        l = mg_directional_light(light.direction, light.color, light.intensity);
    else if (light.type == 3)
        l = mg_spot_light(P, light.position, light.direction, light.color, light.intensity, light.decay_rate,
                          light.inner_angle, light.outer_angle);
    else if (light.type == 1)
        l = mg_point_light(P, light.position, light.color, light.intensity, light.decay_rate);
    else
        l = lightshader(vec3(0.0), vec3(0.0, 0.0, -1.0));
    L = -l.direction;
    intensity = l.intensity;
}
