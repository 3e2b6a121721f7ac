"""cmlib colour transforms in GLSL (MaterialX Specification 1.39, "Color Management"): encoded colour
spaces to the working space lin_rec709, as MaterialX's default colour-management system applies them.

COLORSPACES: colour space name -> (glsl_lib files, GLSL expression of a vec3 "{c}"), one entry for each
space of colorspaces.SPACES (which names convert, and the same transforms on values, are there: graph
building needs them, and knows no GLSL). It serves the cmlib nodes (NODEDEFS below, which replace the
library's nodegraphs with one call) and the image nodes, which apply the transform of their file's
`colorspace` right after the texture read (handlers.image). Colour values with a `colorspace` are
graph building's (graph.GraphBuilder.color_managed): a public uniform keeps its authored value and a
cmlib node converts it in the shader, a constant is converted there (colorspaces.convert_value).
"""
from mtlxgen.base.colorspaces import (REMAP, SPACES, WORKING_SPACE, WORKING_SPACES, canonical,  # noqa: F401 (cmlib.X)
                                      convert_value, is_working_space, nodedef_name, to_rec709_matrix)
from mtlxgen.nodes.nodevalue import np

_SRGB = "cmlib/srgb_transfer.glsl"
_GAMMA = "cmlib/gamma_transfer.glsl"
_AP1 = "cmlib/ap1_to_rec709.glsl"
_ADOBE = "cmlib/adobergb_to_rec709.glsl"
_P3 = "cmlib/displayp3_to_rec709.glsl"

COLORSPACES = {
    "srgb_texture": ((_SRGB,), "mg_srgb_to_linear({c})"),
    "g22_rec709": ((_GAMMA,), "mg_gamma_to_linear({c}, 2.2)"),
    "g18_rec709": ((_GAMMA,), "mg_gamma_to_linear({c}, 1.8)"),
    "rec709_display": ((_GAMMA,), "mg_gamma_to_linear({c}, 2.4)"),
    "acescg": ((_AP1,), "mg_ap1_to_rec709({c})"),
    "g22_ap1": ((_GAMMA, _AP1), "mg_ap1_to_rec709(mg_gamma_to_linear({c}, 2.2))"),
    "lin_adobergb": ((_ADOBE,), "mg_adobergb_to_rec709({c})"),
    "adobergb": ((_GAMMA, _ADOBE), "mg_adobergb_to_rec709(mg_gamma_to_linear({c}, 563.0 / 256.0))"),
    "lin_displayp3": ((_P3,), "mg_displayp3_to_rec709({c})"),
    "srgb_displayp3": ((_SRGB, _P3), "mg_displayp3_to_rec709(mg_srgb_to_linear({c}))"),
}
if set(COLORSPACES) != set(SPACES):
    raise RuntimeError("cmlib's GLSL transforms and colorspaces.SPACES name different spaces")


def transform(colorspace):
    """(files, template) converting `colorspace` to the working space, or None when nothing is to do."""
    name = canonical(colorspace)
    return COLORSPACES[name] if name else None


def _converter(space):
    """The evaluator (nodevalue.py) of a conversion from `space`: colour3 or colour4, the alpha kept."""
    return lambda i, t, o: np.asarray(convert_value(space, tuple(float(v) for v in i["in"])))


def _nodedefs():
    out = {}
    for name, (files, template) in COLORSPACES.items():
        value = _converter(name)          # the same transform on a value (colorspaces.convert_value)
        out["ND_%s_to_lin_rec709_color3" % name] = {"expr": template.format(c="{{in}}"), "files": list(files),
                                                    "evaluate": value}
        out["ND_%s_to_lin_rec709_color4" % name] = {
            "expr": "vec4(%s, {{in}}.a)" % template.format(c="{{in}}.rgb"), "files": list(files), "evaluate": value}
    return out


NODEDEFS = _nodedefs()
