"""Colour spaces as MaterialX's default colour management names them, and its conversions of values.

Which spaces convert to the working space lin_rec709 (SPACES: those with a `ND_<space>_to_lin_rec709_*`
nodedef in cmlib, plus the names REMAP gives another), the nodedef converting each, and the same
transforms on values (convert_value), for colour constants folded at graph building
(graph.GraphBuilder.color_managed). The GLSL of each transform is the emit side's (nodes/cmlib.py).
Any other name (lin_srgb, g18_ap1, raw, an OCIO name, "sRGB") is left unconverted, as MaterialX leaves it;
so is a document whose working space is not lin_rec709 or lin_rec709_scene (the only target cmlib has).
"""
WORKING_SPACE = "lin_rec709"

# the spaces cmlib converts from, in MaterialX's names, case and all
SPACES = ("srgb_texture", "g22_rec709", "g18_rec709", "rec709_display", "acescg", "g22_ap1", "lin_adobergb",
          "adobergb", "lin_displayp3", "srgb_displayp3")
# names MaterialX's default colour-management system reads as another space (and only these): the older
# aliases, and the ASWF Color Interop Forum's scene-referred names (MaterialX 1.39.5, measured with the wheel:
# tests/read/test_unseen_classes.py). g24_rec709_scene, srgb_ap1_scene, lin_ap0_scene, lin_rec2020_scene and
# lin_ciexyzd65_scene it names but does not convert, nor do we.
REMAP = {"gamma18": "g18_rec709", "gamma22": "g22_rec709", "gamma24": "rec709_display", "lin_ap1": "acescg",
         "srgb_rec709_scene": "srgb_texture", "g22_rec709_scene": "g22_rec709", "g18_rec709_scene": "g18_rec709",
         "lin_ap1_scene": "acescg", "g22_ap1_scene": "g22_ap1", "lin_adobergb_scene": "lin_adobergb",
         "g22_adobergb_scene": "adobergb", "srgb_p3d65_scene": "srgb_displayp3", "lin_p3d65_scene": "lin_displayp3"}
# the working space under its interop name too
WORKING_SPACES = (WORKING_SPACE, "lin_rec709_scene")


def canonical(colorspace):
    """The cmlib space that `colorspace` converts from (one of SPACES), or None: nothing to do."""
    name = REMAP.get(colorspace or "", colorspace or "")
    return name if name in SPACES else None


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
