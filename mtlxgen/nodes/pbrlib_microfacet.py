"""Microfacet BSDF nodes of pbrlib (MaterialX Specification 1.39): dielectric_bsdf, conductor_bsdf and
generalized_schlick_bsdf, over anisotropic GGX with height-correlated Smith shadowing.

Each is evaluated per closure context (see pbrlib_shading): "reflection" per direct light, "indirect"
for the environment (filtered importance sampling, glsl_lib/lighting/environment_specular.glsl) and
"transmission" for what is seen through (environment refraction; straight through a thin-walled surface). scatter_mode picks R, T or RT
through the constants of glsl_lib/pbrlib/microfacet/scatter_mode.glsl.
"""

_FILM = "{{thinfilm_thickness}}, {{thinfilm_ior}}"
_FRAME = "{{normal}}, {{tangent}}"

_DIELECTRIC = "{{weight}}, {{tint}}, {{ior}}, {{roughness}}"
_CONDUCTOR = "{{weight}}, {{ior}}, {{extinction}}, {{roughness}}"
_SCHLICK = "{{weight}}, {{color0}}, {{color82}}, {{color90}}, {{exponent}}, {{roughness}}"
_MODE = "mg_scatter_{{=scatter_mode}}"

NODES = {
    "dielectric_bsdf": {
        "closure": {
            "reflection": "mg_dielectric_reflection(mg_L, mg_V, %s, {{=retroreflective}}, %s, %s, %s)" % (_DIELECTRIC, _FILM, _FRAME, _MODE),
            "indirect": "mg_dielectric_indirect(mg_V, %s, {{=retroreflective}}, %s, %s, %s)" % (_DIELECTRIC, _FILM, _FRAME, _MODE),
            "transmission": "mg_dielectric_transmission(mg_V, %s, %s, %s, %s, mg_thin_walled)" % (_DIELECTRIC, _FILM, _FRAME, _MODE),
        },
        "files": ["pbrlib/microfacet/dielectric.glsl"]},
    "conductor_bsdf": {
        "closure": {
            "reflection": "mg_conductor_reflection(mg_L, mg_V, %s, {{=retroreflective}}, %s, %s)" % (_CONDUCTOR, _FILM, _FRAME),
            "indirect": "mg_conductor_indirect(mg_V, %s, {{=retroreflective}}, %s, %s)" % (_CONDUCTOR, _FILM, _FRAME),
            "transmission": "BSDF(vec3(0.0), vec3(1.0 - {{weight}}))",
        },
        "opaque": True,
        "files": ["pbrlib/microfacet/conductor.glsl"]},
    "generalized_schlick_bsdf": {
        "closure": {
            "reflection": "mg_schlick_reflection(mg_L, mg_V, %s, {{=retroreflective}}, %s, %s, %s)" % (_SCHLICK, _FILM, _FRAME, _MODE),
            "indirect": "mg_schlick_indirect(mg_V, %s, {{=retroreflective}}, %s, %s, %s)" % (_SCHLICK, _FILM, _FRAME, _MODE),
            "transmission": "mg_schlick_transmission(mg_V, %s, %s, %s, %s, mg_thin_walled)" % (_SCHLICK, _FILM, _FRAME, _MODE),
        },
        "files": ["pbrlib/microfacet/generalized_schlick.glsl"]},
}
