// requires: constants.glsl lighting/environment.glsl
// uniforms: u_envIrradiance u_envLightIntensity
// The environment's irradiance about -n, read from n's lat-long coordinates (lighting/environment.glsl's
// mapping, u = atan(d.x, -d.z) / 2pi + 0.5, v = -asin(d.y) / pi + 0.5; u_envMatrix is linear, so it maps -n to -d):
// atan(-x, z) is atan(x, -z) turned half a turn and asin is odd, so -d sits at u + 1/2 (wrapped into [0, 1]) and
// 1 - v. A lobe that also reads the irradiance about n shares that direction's arctangent and arcsine (the costly
// part of a read) instead of computing a second pair.
vec2 mg_latlong_uv_opposite(vec2 uv)
{
    return vec2(uv.x < 0.5 ? uv.x + 0.5 : uv.x - 0.5, 1.0 - uv.y);
}

vec3 mg_env_irradiance_behind(vec3 n)
{
    return textureLod(u_envIrradiance, mg_latlong_uv_opposite(mg_latlong_uv(n)), 0.0).rgb * u_envLightIntensity;
}
