// requires: constants.glsl
// uniforms: u_envMatrix u_envRadiance u_envIrradiance u_envLightIntensity u_envRadianceMips u_envRadianceSamples
// Image-based lighting from a lat-long environment (interface.md): u = atan(d.x, -d.z) / 2pi + 0.5,
// v = -asin(d.y) / pi + 0.5 of the direction d after u_envMatrix; row 0 of the image is the top.

// Lat-long coordinates of a direction d in the map's own frame (after u_envMatrix).
vec2 mg_latlong_uv_map(vec3 d)
{
    return vec2(atan(d.x, -d.z) / MG_TWO_PI + 0.5, -asin(clamp(d.y, -1.0, 1.0)) / MG_PI + 0.5);
}

vec2 mg_latlong_uv(vec3 dir)
{
    return mg_latlong_uv_map((u_envMatrix * vec4(dir, 0.0)).xyz);
}

// Radiance arriving from direction dir, read at a mip level (0 = sharpest).
vec3 mg_env_radiance(vec3 dir, float lod)
{
    return textureLod(u_envRadiance, mg_latlong_uv(dir), lod).rgb * u_envLightIntensity;
}

// Cosine-weighted irradiance over the hemisphere about n, divided by pi (the diffuse reflectance's scale).
// Read at level 0: the map is already band-limited, and screen derivatives of n (normal maps, the
// lat-long seam) would otherwise pick blurred mips of a mipmapped map.
vec3 mg_env_irradiance(vec3 n)
{
    return textureLod(u_envIrradiance, mg_latlong_uv(n), 0.0).rgb * u_envLightIntensity;
}
