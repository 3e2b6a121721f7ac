"""pbrlib BSDFs beyond Oren-Nayar and the microfacet family (MaterialX Specification 1.39): Burley diffuse,
translucent, subsurface, sheen (conty_kulla and zeltner modes), Chiang hair; the generalized Schlick EDF;
the `light` constructor and the lights library's point, directional and spot lights.

Closure templates follow pbrlib_shading: "reflection" runs once per direct light (mg_L towards it),
"indirect" lights by the environment; the GLSL lives one concern a file in glsl_lib/pbrlib/bsdf/.
"""

_BSDF = "pbrlib/bsdf/"
_LIGHTS = ["closures.glsl", "lighting/light_shaders.glsl"]


def light(node, em):
    """lightshader from an EDF: its emission (evaluated as seen along the surface normal) x intensity x 2^exposure."""
    out = em.fresh(node.id + "_out")
    em.line("%s %s = lightshader(vec3(0.0), vec3(0.0));" % (em.glsl_type("lightshader"), out))
    edf = node.inputs["edf"]
    if edf.linked:
        em.require("closures.glsl")
        em.app_uniform("u_viewPosition")
        em.open_block("emission", "light emission")
        em.line("vec3 mg_P = %s;" % em.stream("position_world"))
        em.line("vec3 mg_V = normalize(u_viewPosition - mg_P);")
        em.line("vec3 mg_L = vec3(0.0);")
        em.line("float mg_occlusion = 1.0;")
        e = em.closure(edf, "emission")
        em.line("%s.intensity = %s * (%s * exp2(%s));" % (out, e, em.input_expr(node, "intensity"),
                                                          em.input_expr(node, "exposure")))
        em.close_block()
    return {"out": out}


NODES = {
    "burley_diffuse_bsdf": {
        "closure": {
            "reflection": "mg_burley_reflection(mg_L, mg_V, {{weight}}, {{color}}, {{roughness}}, {{normal}})",
            "indirect": "mg_burley_indirect(mg_V, {{weight}}, {{color}}, {{roughness}}, {{normal}})",
        },
        "opaque": True,
        "files": [_BSDF + "burley.glsl"]},
    "translucent_bsdf": {
        "closure": {
            "reflection": "mg_translucent_reflection(mg_L, mg_V, {{weight}}, {{color}}, {{normal}})",
            "indirect": "mg_translucent_indirect({{weight}}, {{color}}, {{normal}})",
        },
        "opaque": True,
        "files": [_BSDF + "translucent.glsl"]},
    "subsurface_bsdf": {
        "closure": {
            "reflection": "mg_subsurface_reflection(mg_L, mg_V, mg_P, {{weight}}, {{color}}, {{radius}}, "
                          "{{anisotropy}}, {{normal}})",
            "indirect": "mg_subsurface_indirect({{weight}}, {{color}}, {{normal}})",
        },
        "opaque": True,
        "files": [_BSDF + "subsurface.glsl"]},
    "sheen_bsdf": {
        # mode is a uniform string: conty_kulla or zeltner picks the function family
        "closure": {
            "reflection": "mg_sheen_{{=mode}}_reflection(mg_L, mg_V, {{weight}}, {{color}}, {{roughness}}, {{normal}})",
            "indirect": "mg_sheen_{{=mode}}_indirect(mg_V, {{weight}}, {{color}}, {{roughness}}, {{normal}})",
        },
        "files": [_BSDF + "sheen.glsl"]},
    "generalized_schlick_edf": {
        "closure": {"emission": "mg_generalized_schlick_edf({{@normal_world}}, mg_V, {{color0}}, {{color90}}, "
                                "{{exponent}}, {{base}})"},
        "files": ["pbrlib/edf/generalized_schlick_edf.glsl"]},
    "light": {"handler": light},
    "directional_light": {"expr": "mg_directional_light({{direction}}, {{color}}, {{intensity}})", "files": _LIGHTS},
    "point_light": {"expr": "mg_point_light({{@position_world}}, {{position}}, {{color}}, {{intensity}}, "
                            "{{decay_rate}})", "files": _LIGHTS},
    "spot_light": {"expr": "mg_spot_light({{@position_world}}, {{position}}, {{direction}}, {{color}}, "
                           "{{intensity}}, {{decay_rate}}, {{inner_angle}}, {{outer_angle}})", "files": _LIGHTS},
}

_HAIR = "{{tint_R}}, {{tint_TT}}, {{tint_TRT}}, {{ior}}, {{roughness_R}}, {{roughness_TT}}, {{roughness_TRT}}"
NODES["chiang_hair_bsdf"] = {
    "closure": {
        "reflection": "mg_chiang_hair_reflection(mg_L, mg_V, " + _HAIR + ", {{cuticle_angle}}, "
                      "{{absorption_coefficient}}, {{normal}}, {{curve_direction}})",
        "indirect": "mg_chiang_hair_indirect(mg_V, " + _HAIR + ", {{normal}}, {{curve_direction}})",
    },
    "files": [_BSDF + "hair.glsl"]}
