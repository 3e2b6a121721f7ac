// requires: constants.glsl lighting/environment.glsl pbrlib/irradiance_behind.glsl
// Diffuse transmission (MaterialX Specification 1.39, pbrlib "translucent_bsdf"): a Lambertian lobe on
// the far side of the surface, f = color/pi for light arriving from below. Nothing under it shows through, at
// any weight (the weight scales what it sends on, as MaterialX's: a layer over it is hidden).

BSDF mg_translucent_reflection(vec3 L, vec3 V, float weight, vec3 color, vec3 N)
{
    float NdotL = clamp(-dot(N, L), 0.0, 1.0);
    return BSDF(color * (weight * NdotL / MG_PI), vec3(0.0));
}

// Light from the environment behind the surface: the cosine-weighted irradiance about -N.
BSDF mg_translucent_indirect(float weight, vec3 color, vec3 N)
{
    return BSDF(color * weight * mg_env_irradiance_behind(N), vec3(0.0));
}
