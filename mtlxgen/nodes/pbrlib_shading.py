"""Shader nodes that light closures (MaterialX Specification 1.39, pbrlib "surface"), and the
closure-combining nodes.

A surface (in the skeleton of lit_surface.py) evaluates its BSDF graph once per context: "reflection"
for each direct light (mg_L is the direction to the light), "indirect" for the environment,
"transmission" for what is seen through it, and its EDF in "emission". Closure templates may read the block's mg_L, mg_V, mg_P and
mg_occlusion, and in "transmission" mg_thin_walled (the surface is a thin shell: what is seen through it
is not bent by a solid interior). Opacity scales the colour and blends the transparency towards 1.
"""
from mtlxgen.nodes.lit_surface import light_loop, lit_surface, takes_lights


def shade(em, bsdf=None, edf=None, opacity="1.0", stem="surface", thin_walled="false"):
    """Emit the lighting of a BSDF and/or EDF Source; returns the surfaceshader variable."""
    with lit_surface(em, stem) as out:
        em.line("float mg_occlusion = 1.0;")
        if bsdf is not None and bsdf.linked:
            if takes_lights(em):
                with light_loop(em):
                    em.line("%s.color += mg_light * %s.response;" % (out, em.closure(bsdf, "reflection")))
            em.open_block("indirect", "environment")
            em.line("%s.color += mg_occlusion * %s.response;" % (out, em.closure(bsdf, "indirect")))
            em.close_block()
            em.open_block("transmission", "seen through the surface")
            em.line("bool mg_thin_walled = %s;" % thin_walled)
            em.line("%s.color += %s.response;" % (out, em.closure(bsdf, "transmission")))
            em.close_block()
        if edf is not None and edf.linked:
            em.open_block("emission", "emission")
            em.line("%s.color += %s;" % (out, em.closure(edf, "emission")))
            em.close_block()
        if opacity != "1.0":
            em.line("%s.color *= %s;" % (out, opacity))
            em.line("%s.transparency = mix(vec3(1.0), %s.transparency, %s);" % (out, out, opacity))
    return out


def surface(node, em):
    out = shade(em, node.inputs["bsdf"], node.inputs["edf"], em.input_expr(node, "opacity"), node.id,
                em.input_expr(node, "thin_walled"))
    return {"out": out}


_COMBINE = ["pbrlib/closures_combine.glsl"]

NODES = {
    "surface": {"handler": surface},
    "oren_nayar_diffuse_bsdf": {
        "closure": {
            "reflection": "mg_oren_nayar_reflection(mg_L, mg_V, {{weight}}, {{color}}, {{roughness}}, {{normal}}, "
                          "{{=energy_compensation}})",
            "indirect": "mg_oren_nayar_indirect(mg_V, {{weight}}, {{color}}, {{roughness}}, {{normal}}, "
                        "{{=energy_compensation}})",
        },
        "opaque": True,
        "files": ["pbrlib/bsdf/oren_nayar.glsl"]},
    "uniform_edf": {"closure": {"emission": "{{color}}"}},
    # displacement (MaterialX Specification 1.39): a scalar moves along the normal; a vector is given
    # in the (dPdu, dPdv, N) frame. Applied in the vertex stage (emit/emitter.py), in object space.
    "displacement": "displacementshader({{@normal_object}} * {{displacement}}, {{scale}})",
}

# Combinators work the same in every context (EDF sums and products are the stdlib templates: EDF is a colour).
NODEDEFS = {
    "ND_displacement_vector3": "displacementshader({{@tangent_object}} * {{displacement}}.x + "
                               "{{@bitangent_object}} * {{displacement}}.y + {{@normal_object}} * {{displacement}}.z, "
                               "{{scale}})",
    "ND_layer_bsdf": {"expr": "mg_layer({{top}}, {{base}})", "files": _COMBINE},
    "ND_add_bsdf": {"expr": "mg_add({{in1}}, {{in2}})", "files": _COMBINE},
    "ND_add_vdf": {"expr": "mg_add({{in1}}, {{in2}})", "files": _COMBINE},
    # a BSDF's weight stays in [0, 1] (the spec: no more than 1 to conserve energy; below 0 it would return
    # negative light); a VDF's may exceed 1 (a denser medium)
    "ND_multiply_bsdfC": {"expr": "mg_scale({{in1}}, clamp({{in2}}, 0.0, 1.0))", "files": _COMBINE},
    "ND_multiply_bsdfF": {"expr": "mg_scale({{in1}}, clamp({{in2}}, 0.0, 1.0))", "files": _COMBINE},
    "ND_multiply_vdfC": {"expr": "mg_scale({{in1}}, {{in2}})", "files": _COMBINE},
    "ND_multiply_vdfF": {"expr": "mg_scale({{in1}}, {{in2}})", "files": _COMBINE},
}
