"""stdlib compositing nodes (MaterialX Specification 1.39, "Compositing Nodes").

Blend nodes apply F (fg) to B (bg) and mix the result over B by `mix`:  mix(B, blend(F, B), mix).
Merge nodes are the Porter & Duff (1984) operators on premultiplied colour4, where f and b are the
alphas of F and B. overlay is a nodegraph in the data library.
"""

from mtlxgen.nodes.nodevalue import need, np

_CD = "stdlib/compositing/"


# evaluators (nodevalue.py): the templates' values in Python, term for term

def _blend(f):
    """mix(bg, f(fg, bg), mix)."""
    def fn(i, t, o):
        return i["bg"] * (1.0 - i["mix"]) + f(i["fg"], i["bg"]) * i["mix"]
    return fn


def _unpremult(i, t, o):
    c = i["in"]
    need(c[3] != 0.0, "unpremult of zero alpha")
    return np.concatenate([c[:3] / c[3], c[3:]])


def _premult(i, t, o):
    return np.concatenate([i["in"][:3] * i["in"][3], i["in"][3:]])


def _mix(i, t, o):
    return i["bg"] * (1.0 - i["mix"]) + i["fg"] * i["mix"]


NODES = {
    # blend nodes
    "plus": {"expr": "mix({{bg}}, {{bg}} + {{fg}}, {{mix}})", "evaluate": _blend(lambda f, b: b + f)},
    "minus": {"expr": "mix({{bg}}, {{bg}} - {{fg}}, {{mix}})", "evaluate": _blend(lambda f, b: b - f)},
    "difference": {"expr": "mix({{bg}}, abs({{bg}} - {{fg}}), {{mix}})",
                   "evaluate": _blend(lambda f, b: np.abs(b - f))},
    "screen": {"expr": "mix({{bg}}, {{fg}} + {{bg}} - {{fg}} * {{bg}}, {{mix}})",
               "evaluate": _blend(lambda f, b: f + b - f * b)},
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
    "inside": {"expr": "{{in}} * {{mask}}", "evaluate": lambda i, t, o: i["in"] * i["mask"]},
    "outside": {"expr": "{{in}} * (1.0 - {{mask}})", "evaluate": lambda i, t, o: i["in"] * (1.0 - i["mask"])},
    # alpha association
    "premult": {"expr": "vec4({{in}}.rgb * {{in}}.a, {{in}}.a)", "evaluate": _premult},
    # the spec's plain division: zero alpha gives inf/nan, as in MaterialX's own renders
    "unpremult": {"expr": "vec4({{in}}.rgb / {{in}}.a, {{in}}.a)", "evaluate": _unpremult},
    # linear interpolation; the per-channel variants take a vector `mix`
    "mix": {"expr": "mix({{bg}}, {{fg}}, {{mix}})", "evaluate": _mix},
}

# shader and closure values are structs: mixed member by member (EDF is a colour, the template serves)
NODEDEFS = {
    nd: {"expr": "mg_mix_%s({{fg}}, {{bg}}, {{mix}})" % t, "files": [_CD + "mix_shader.glsl"]}
    for nd, t in (("ND_mix_surfaceshader", "surfaceshader"), ("ND_mix_volumeshader", "volumeshader"),
                  ("ND_mix_displacementshader", "displacementshader"), ("ND_mix_bsdf", "BSDF"),
                  ("ND_mix_vdf", "VDF"))
}
