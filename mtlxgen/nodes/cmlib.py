"""cmlib colour transforms (MaterialX Specification 1.39, "Color Management"): encoded colour spaces to
the working space lin_rec709, as MaterialX's default colour-management system applies them.

COLORSPACES is the one table: colour space name -> (glsl_lib files, GLSL expression of a vec3 "{c}").
It serves the cmlib nodes (NODEDEFS below, which replace the library's nodegraphs with one call), the
image nodes, which apply the transform of their file's `colorspace` right after the texture read
(handlers.image), and colour values with a `colorspace` (graph.GraphBuilder.color_managed): a public
uniform keeps its authored value and a cmlib node converts it in the shader, a constant is converted
here (convert_value, the same formulas in numpy).

The names are MaterialX's, case and all: its default system knows exactly the spaces with a
`ND_<space>_to_lin_rec709_*` nodedef, plus the names REMAP gives another (gamma18, gamma22, gamma24,
lin_ap1, and the Color Interop Forum's *_scene names). Any other name (lin_srgb, g18_ap1, raw, an OCIO
name, "sRGB") it leaves unconverted, and so do we; so does a document whose working space is not
lin_rec709 or lin_rec709_scene (the only target cmlib has).
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
    "g22_ap1": ((_GAMMA, _AP1), "mg_ap1_to_rec709(mg_gamma_to_linear({c}, 2.2))"),
    "lin_adobergb": ((_ADOBE,), "mg_adobergb_to_rec709({c})"),
    "adobergb": ((_GAMMA, _ADOBE), "mg_adobergb_to_rec709(mg_gamma_to_linear({c}, 563.0 / 256.0))"),
    "lin_displayp3": ((_P3,), "mg_displayp3_to_rec709({c})"),
    "srgb_displayp3": ((_SRGB, _P3), "mg_displayp3_to_rec709(mg_srgb_to_linear({c}))"),
}
# names MaterialX's default colour-management system reads as another space (and only these): the older
# aliases, and the ASWF Color Interop Forum's scene-referred names (MaterialX 1.39.5, measured with the wheel:
# tests/test_unseen_classes.py). g24_rec709_scene, srgb_ap1_scene, lin_ap0_scene, lin_rec2020_scene and
# lin_ciexyzd65_scene it names but does not convert, nor do we.
REMAP = {"gamma18": "g18_rec709", "gamma22": "g22_rec709", "gamma24": "rec709_display", "lin_ap1": "acescg",
         "srgb_rec709_scene": "srgb_texture", "g22_rec709_scene": "g22_rec709", "g18_rec709_scene": "g18_rec709",
         "lin_ap1_scene": "acescg", "g22_ap1_scene": "g22_ap1", "lin_adobergb_scene": "lin_adobergb",
         "g22_adobergb_scene": "adobergb", "srgb_p3d65_scene": "srgb_displayp3", "lin_p3d65_scene": "lin_displayp3"}
# the working space under its interop name too
WORKING_SPACES = (WORKING_SPACE, "lin_rec709_scene")


def canonical(colorspace):
    """The cmlib space that `colorspace` converts from (a COLORSPACES key), or None: nothing to do."""
    name = REMAP.get(colorspace or "", colorspace or "")
    return name if name in COLORSPACES else None


def transform(colorspace):
    """(files, template) converting `colorspace` to the working space, or None when nothing is to do."""
    name = canonical(colorspace)
    return COLORSPACES[name] if name else None


def is_working_space(colorspace):
    """Whether a document colour space is lin_rec709 (or its interop name lin_rec709_scene), the one space
    cmlib converts to (MaterialX compares the names as they are: a document in lin_srgb has no transforms
    to it)."""
    return colorspace in WORKING_SPACES


def nodedef_name(colorspace, type_name):
    """The cmlib nodedef converting a value of `type_name` (color3 / color4) from `colorspace`."""
    return "ND_%s_to_lin_rec709_%s" % (canonical(colorspace), type_name)


# ---- the same transforms on values (constants folded at generation time) ----
# Chromaticities (CIE 1931 xy) of the primaries R, G, B and the white point: ITU-R BT.709-6 (D65);
# SMPTE ST 2065-1 / Academy S-2014-004 (ACES AP1, ACES white); Adobe RGB (1998) Color Image Encoding
# section 4.3.1.1; SMPTE EG 432-1 (P3 primaries) with D65 white (Display P3).
_D65 = (0.3127, 0.3290)
_ACES_WHITE = (0.32168, 0.33767)
PRIMARIES = {
    "rec709": (((0.64, 0.33), (0.30, 0.60), (0.15, 0.06)), _D65),
    "ap1": (((0.713, 0.293), (0.165, 0.830), (0.128, 0.044)), _ACES_WHITE),
    "adobergb": (((0.64, 0.33), (0.21, 0.71), (0.15, 0.06)), _D65),
    "displayp3": (((0.680, 0.320), (0.265, 0.690), (0.150, 0.060)), _D65),
}
# the Bradford cone response matrix (Lam 1985, as in ICC.1 Annex E), for the AP1 white to D65
_BRADFORD = ((0.8951, 0.2664, -0.1614), (-0.7502, 1.7135, 0.0367), (0.0389, -0.0685, 1.0296))


def _xyz(xy):
    import numpy as np      # here, not at import: generating a shader without colour values needs none
    x, y = xy
    return np.array([x / y, 1.0, (1.0 - x - y) / y])


def _rgb_to_xyz(name):
    import numpy as np
    prims, white = PRIMARIES[name]
    p = np.stack([_xyz(c) for c in prims], 1)
    return p * np.linalg.solve(p, _xyz(white))


def to_rec709_matrix(name):
    """3x3 matrix taking linear RGB of primaries `name` to linear Rec.709 (c709 = M @ c), white points
    matched by a Bradford adaptation where they differ."""
    import numpy as np
    m = _rgb_to_xyz(name)
    white = PRIMARIES[name][1]
    if white != _D65:
        bradford = np.array(_BRADFORD)
        a, b = bradford @ _xyz(white), bradford @ _xyz(_D65)
        m = np.linalg.inv(bradford) @ np.diag(b / a) @ bradford @ m
    return np.linalg.inv(_rgb_to_xyz("rec709")) @ m


def _srgb_decode(c):
    import numpy as np
    # IEC 61966-2-1:1999 section 4.7; negative values on the linear segment, as the GLSL (srgb_transfer.glsl)
    return np.where(c <= 0.04045, c / 12.92, np.power(np.maximum(c + 0.055, 0.0) / 1.055, 2.4))


def _gamma(g):
    def decode(c):
        import numpy as np
        return np.power(np.maximum(c, 0.0), g)
    return decode


# space -> (decoding, primaries): what COLORSPACES's GLSL does, term for term
_VALUE_TRANSFORMS = {
    "srgb_texture": (_srgb_decode, None),
    "g22_rec709": (_gamma(2.2), None),
    "g18_rec709": (_gamma(1.8), None),
    "rec709_display": (_gamma(2.4), None),
    "acescg": (None, "ap1"),
    "g22_ap1": (_gamma(2.2), "ap1"),
    "lin_adobergb": (None, "adobergb"),
    "adobergb": (_gamma(563.0 / 256.0), "adobergb"),
    "lin_displayp3": (None, "displayp3"),
    "srgb_displayp3": (_srgb_decode, "displayp3"),
}


def convert_value(colorspace, value):
    """A color3 / color4 value (tuple) converted from `colorspace` to lin_rec709; alpha kept. The value
    unchanged where the space has no transform."""
    name = canonical(colorspace)
    if name is None:
        return value
    import numpy as np
    decode, primaries = _VALUE_TRANSFORMS[name]
    c = np.array(value[:3], dtype=np.float64)
    if decode is not None:
        c = decode(c)
    if primaries is not None:
        c = to_rec709_matrix(primaries) @ c
    return tuple(float(v) for v in c) + tuple(value[3:])


def _nodedefs():
    out = {}
    for name, (files, template) in COLORSPACES.items():
        out["ND_%s_to_lin_rec709_color3" % name] = {"expr": template.format(c="{{in}}"), "files": list(files)}
        out["ND_%s_to_lin_rec709_color4" % name] = {
            "expr": "vec4(%s, {{in}}.a)" % template.format(c="{{in}}.rgb"), "files": list(files)}
    return out


NODEDEFS = _nodedefs()
