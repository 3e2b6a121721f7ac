"""cmlib colour transforms (MaterialX Specification 1.39, "Color Management"): encoded colour spaces to
the working space lin_rec709.

COLORSPACES is the one table: colour space name -> (glsl_lib files, GLSL expression of a vec3 "{c}").
It serves both the cmlib nodes (NODEDEFS below, which replace the library's nodegraphs with one call)
and the image nodes, which apply the transform of their file's `colorspace` right after the texture
read (handlers.image). Colour spaces not listed (and lin_rec709 itself) pass through unchanged.
"""

WORKING_SPACE = "lin_rec709"

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
    "lin_ap1": ((_AP1,), "mg_ap1_to_rec709({c})"),
    "g22_ap1": ((_GAMMA, _AP1), "mg_ap1_to_rec709(mg_gamma_to_linear({c}, 2.2))"),
    "lin_adobergb": ((_ADOBE,), "mg_adobergb_to_rec709({c})"),
    "adobergb": ((_GAMMA, _ADOBE), "mg_adobergb_to_rec709(mg_gamma_to_linear({c}, 563.0 / 256.0))"),
    "lin_displayp3": ((_P3,), "mg_displayp3_to_rec709({c})"),
    "srgb_displayp3": ((_SRGB, _P3), "mg_displayp3_to_rec709(mg_srgb_to_linear({c}))"),
}
# alternative names MaterialX and OCIO configs use for the same spaces
ALIASES = {"lin_srgb": WORKING_SPACE, "srgb_linear": WORKING_SPACE, "scene-linear rec.709-srgb": WORKING_SPACE,
           "srgb": "srgb_texture", "srgb_tx": "srgb_texture", "acescg_ap1": "acescg",
           "gamma22_rec709": "g22_rec709", "gamma18_rec709": "g18_rec709"}


def transform(colorspace):
    """(files, template) converting `colorspace` to the working space, or None when nothing is to do."""
    name = ALIASES.get((colorspace or "").lower(), (colorspace or "").lower())
    return COLORSPACES.get(name)


def is_working_space(colorspace):
    """Whether a document colour space is lin_rec709, the one space cmlib converts to."""
    c = (colorspace or "").lower()
    return bool(c) and ALIASES.get(c, c) == WORKING_SPACE


def _nodedefs():
    out = {}
    for name, (files, template) in COLORSPACES.items():
        if name in ("lin_ap1",):        # no cmlib node of that name (acescg is the same space)
            continue
        out["ND_%s_to_lin_rec709_color3" % name] = {"expr": template.format(c="{{in}}"), "files": list(files)}
        out["ND_%s_to_lin_rec709_color4" % name] = {
            "expr": "vec4(%s, {{in}}.a)" % template.format(c="{{in}}.rgb"), "files": list(files)}
    return out


NODEDEFS = _nodedefs()
