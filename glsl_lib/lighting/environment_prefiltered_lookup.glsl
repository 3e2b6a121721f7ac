// requires: constants.glsl lighting/environment.glsl lighting/environment_prefiltered_level.glsl
// The split-sum lookup (MG_ENV_PREFILTERED; Karis 2013, "Real Shading in Unreal Engine 4"): where and at which level
// a lobe reads the GGX-prefiltered u_envRadiance (lighting/environment_prefilter.glsl makes it), for the pbrlib
// lobes (lighting/environment_specular.glsl, environment_refraction.glsl) and the Enterprise PBR's
// (enterprise/environment.glsl).

// Level of the GGX-prefiltered u_envRadiance holding the lobe of roughness alpha (an anisotropic lobe: the isotropic
// one of its solid angle), by the prefilter's own mapping (lighting/environment_prefiltered_level.glsl).
float mg_env_lod_prefiltered(vec2 alpha)
{
    return mg_env_prefiltered_lod(mg_env_prefiltered_isotropic(alpha), float(textureSize(u_envRadiance, 0).x),
                                  u_envRadianceMips);
}

// Where the split sum reads the prefiltered map for a view Vt in the tangent frame (x the tangent, alpha.x its
// roughness). The map's lobes are centred on the mirror direction of a surface seen head-on; two corrections for
// the lobe seen obliquely:
// - anisotropy: the lobe stretches along the rougher tangent direction, as if the facets tilted freely that way and
//   not at all the other: the normal is bent, by the anisotropy (ax - ay) / (ax + ay), towards the normal of the view
//   turned about the smoother direction (the bent reflection vector of McAuley 2015, "Rendering the World of Far
//   Cry 4", GDC, as Filament's documentation describes it, sec. 5.7.2);
// - the GGX lobe times the cosine and masking peaks between the mirror direction and the normal, the more so the
//   rougher it is: the mirror direction is pulled towards the (bent) normal by 1 - s (sqrt(s) + alpha), s = 1 - alpha
//   (the dominant direction of Lagarde & de Rousiers 2014, "Moving Frostbite to Physically Based Rendering", sec. 4.9).
vec3 mg_env_prefiltered_direction(vec3 Vt, vec2 alpha)
{
    vec3 N = vec3(0.0, 0.0, 1.0);
    float aniso = (alpha.x - alpha.y) / max(alpha.x + alpha.y, 1.0e-7);
    if (abs(aniso) > 1.0e-4)
    {
        vec3 smooth_dir = aniso > 0.0 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
        vec3 facing = cross(cross(smooth_dir, Vt), smooth_dir);
        if (dot(facing, facing) > 1.0e-8)
            N = normalize(mix(N, normalize(facing), abs(aniso)));
    }
    vec3 R = reflect(-Vt, N);
    float a = clamp(mg_env_prefiltered_isotropic(alpha), 0.0, 1.0);
    float s = 1.0 - a;
    return normalize(mix(N, R, s * (sqrt(s) + a)));
}
