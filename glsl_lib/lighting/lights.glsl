// Direct lights bound by the application as u_lightData[] (the lights library's point, directional and
// spot lights). type: 1 point, 2 directional, 3 spot (the order of lights_defs.mtlx); 0 = unused.
#define MG_MAX_LIGHTS 8

struct LightData
{
    int type;
    vec3 position;
    vec3 direction;
    vec3 color;
    float intensity;
    float decay_rate;
    float inner_angle;
    float outer_angle;
};

uniform LightData u_lightData[MG_MAX_LIGHTS];
uniform int u_numActiveLightSources = 0;

// Direction towards the light (L) and the radiance-scaled irradiance it delivers at P.
void mg_sample_light(LightData light, vec3 P, out vec3 L, out vec3 intensity)
{
    if (light.type == 2)
    {
        L = -normalize(light.direction);
        intensity = light.color * light.intensity;
        return;
    }
    vec3 to_light = light.position - P;
    float dist = length(to_light);
    L = to_light / max(dist, 1.0e-6);
    // inverse-power falloff: decay_rate 0 none, 1 linear, 2 physical inverse square
    intensity = light.color * (light.intensity / pow(max(dist, 1.0e-6), light.decay_rate));
    if (light.type == 3)
    {
        float cos_angle = dot(-L, normalize(light.direction));
        intensity *= smoothstep(cos(light.outer_angle), cos(light.inner_angle), cos_angle);
    }
}
