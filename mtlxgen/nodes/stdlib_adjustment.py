"""stdlib adjustment nodes (MaterialX Specification 1.39, "Adjustment Nodes").

contrast, range, hsvadjust, saturate, colorcorrect and most smoothstep types are nodegraphs in the
data library.
"""
import math

from mtlxgen.nodes.nodevalue import need, np


# evaluators (nodevalue.py): the templates' values in Python, term for term

def _remap(i, t, o):
    d = i["inhigh"] - i["inlow"]
    need(d != 0.0, "remap of an empty range")
    return i["outlow"] + (i["in"] - i["inlow"]) * (i["outhigh"] - i["outlow"]) / d


def _smoothstep(i, t, o):
    x, lo, hi = i["in"], i["low"], i["high"]
    if x >= hi:
        return np.float64(1.0)
    if x <= lo:
        return np.float64(0.0)
    s = (x - lo) / (hi - lo)
    return s * s * (3.0 - 2.0 * s)


def _luminance(i, t, o):
    c = i["in"]
    y = np.dot(c[:3], i["lumacoeffs"])
    return np.array([y, y, y] + list(c[3:]))


def rgb_to_hsv(c):
    """glsl_lib/stdlib/adjustment/rgbtohsv.glsl, for a colour (alpha kept)."""
    r, g, b = (float(v) for v in c[:3])
    hi, lo = max(r, g, b), min(r, g, b)
    delta = hi - lo
    s = delta / hi if hi > 0.0 else 0.0
    h = 0.0
    if s > 0.0:
        if r >= hi:
            h = (g - b) / delta
        elif g >= hi:
            h = 2.0 + (b - r) / delta
        else:
            h = 4.0 + (r - g) / delta
        h /= 6.0
        if h < 0.0:
            h += 1.0
    return np.array([h, s, hi] + [float(v) for v in c[3:]])


def hsv_to_rgb(c):
    """glsl_lib/stdlib/adjustment/hsvtorgb.glsl, for a colour (alpha kept)."""
    x, s, v = (float(a) for a in c[:3])
    h = (x - math.floor(x)) * 6.0
    rest = [float(a) for a in c[3:]]
    if s <= 0.0:
        return np.array([v, v, v] + rest)
    sector = math.floor(h)
    f = h - sector
    p, q, t = v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f))
    rgb = ([v, t, p] if sector < 1 else [q, v, p] if sector < 2 else [p, v, t] if sector < 3 else
           [p, q, v] if sector < 4 else [t, p, v] if sector < 5 else [v, p, q])
    return np.array(rgb + rest)


NODES = {
    # linear map of [inlow, inhigh] onto [outlow, outhigh], unclamped
    "remap": {"expr": "{{outlow}} + ({{in}} - {{inlow}}) * ({{outhigh}} - {{outlow}}) / ({{inhigh}} - {{inlow}})",
              "evaluate": _remap},
    "smoothstep": {"expr": "mg_smoothstep({{in}}, {{low}}, {{high}})", "files": ["stdlib/adjustment/smoothstep.glsl"],
                   "evaluate": _smoothstep},
    "luminance": {"expr": "mg_luminance({{in}}, {{lumacoeffs}})", "files": ["stdlib/adjustment/luminance.glsl"],
                  "evaluate": _luminance},
    # hexcone colour model (Smith 1978); colour4 keeps its alpha
    "rgbtohsv": {"expr": "mg_rgbtohsv({{in}})", "files": ["stdlib/adjustment/rgbtohsv.glsl"],
                 "evaluate": lambda i, t, o: rgb_to_hsv(i["in"])},
    "hsvtorgb": {"expr": "mg_hsvtorgb({{in}})", "files": ["stdlib/adjustment/hsvtorgb.glsl"],
                 "evaluate": lambda i, t, o: hsv_to_rgb(i["in"])},
}
