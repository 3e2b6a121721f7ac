"""stdlib compositing nodes (MaterialX Specification 1.39, "Compositing Nodes").

Blend nodes apply F (fg) to B (bg) and mix the result over B by `mix`:  mix(B, blend(F, B), mix).
Merge nodes are the Porter & Duff (1984) operators on premultiplied colour4, where f and b are the
alphas of F and B. overlay is a nodegraph in the data library.
"""

_CD = "stdlib/compositing/"

NODES = {
    # blend nodes
    "plus": "mix({{bg}}, {{bg}} + {{fg}}, {{mix}})",
    "minus": "mix({{bg}}, {{bg}} - {{fg}}, {{mix}})",
    "difference": "mix({{bg}}, abs({{bg}} - {{fg}}), {{mix}})",
    "screen": "mix({{bg}}, {{fg}} + {{bg}} - {{fg}} * {{bg}}, {{mix}})",
    "burn": {"expr": "mg_burn({{fg}}, {{bg}}, {{mix}})", "files": [_CD + "burn.glsl"]},
    "dodge": {"expr": "mg_dodge({{fg}}, {{bg}}, {{mix}})", "files": [_CD + "dodge.glsl"]},
    # merge nodes (Porter-Duff), each mixed over B
    "over": "mix({{bg}}, {{fg}} + {{bg}} * (1.0 - {{fg}}.a), {{mix}})",
    "in": "mix({{bg}}, {{fg}} * {{bg}}.a, {{mix}})",
    "mask": "mix({{bg}}, {{bg}} * {{fg}}.a, {{mix}})",
    "matte": ("mix({{bg}}, vec4({{fg}}.rgb * {{fg}}.a + {{bg}}.rgb * (1.0 - {{fg}}.a), "
              "{{fg}}.a + {{bg}}.a * (1.0 - {{fg}}.a)), {{mix}})"),
    "out": "mix({{bg}}, {{fg}} * (1.0 - {{bg}}.a), {{mix}})",
    "disjointover": {"expr": "mg_disjointover({{fg}}, {{bg}}, {{mix}})", "files": [_CD + "disjointover.glsl"]},
    # masking
    "inside": "{{in}} * {{mask}}",
    "outside": "{{in}} * (1.0 - {{mask}})",
    # alpha association
    "premult": "vec4({{in}}.rgb * {{in}}.a, {{in}}.a)",
    # the spec's plain division: zero alpha gives inf/nan, as in MaterialX's own renders
    "unpremult": "vec4({{in}}.rgb / {{in}}.a, {{in}}.a)",
    # linear interpolation; the per-channel variants take a vector `mix`
    "mix": "mix({{bg}}, {{fg}}, {{mix}})",
}

# shader and closure values are structs: mixed member by member (EDF is a colour, the template serves)
NODEDEFS = {
    nd: {"expr": "mg_mix_%s({{fg}}, {{bg}}, {{mix}})" % t, "files": [_CD + "mix_shader.glsl"]}
    for nd, t in (("ND_mix_surfaceshader", "surfaceshader"), ("ND_mix_volumeshader", "volumeshader"),
                  ("ND_mix_displacementshader", "displacementshader"), ("ND_mix_bsdf", "BSDF"),
                  ("ND_mix_vdf", "VDF"))
}
