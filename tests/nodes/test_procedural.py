"""Procedural nodes (noise, cellular, fractal, ramps, splits, shapes, random) against MaterialX's own
GLSL, both drawn by our harness: patterns must match pixel for pixel, so the hashes, gradient choices
and constants are pinned here.

Each case is a small graph of its own; values are kept mostly inside [0, 1] (signed noises are moved
up by a pivot or an add) so that no difference hides in clipped pixels.
"""
import pytest

from util import assert_parity_with_materialx, write_doc

# texture space scaled so that many lattice cells show, and shifted to reach negative coordinates
UV = ('<texcoord name="uv0" type="vector2" />'
      '<multiply name="uv" type="vector2"><input name="in1" type="vector2" nodename="uv0" />'
      '<input name="in2" type="vector2" value="10, 10" /></multiply>'
      '<subtract name="uvs" type="vector2"><input name="in1" type="vector2" nodename="uv" />'
      '<input name="in2" type="vector2" value="5, 3" /></subtract>')
# object space (the unit sphere) scaled so that several cells show
POS = ('<position name="p0" type="vector3" />'
       '<multiply name="pos" type="vector3"><input name="in1" type="vector3" nodename="p0" />'
       '<input name="in2" type="vector3" value="4, 4, 4" /></multiply>')


def _inputs(**values):
    out = []
    for name, (typ, value) in values.items():
        if typ == "node":
            t, node = value
            out.append('<input name="%s" type="%s" nodename="%s" />' % (name, t, node))
        else:
            out.append('<input name="%s" type="%s" value="%s" />' % (name, typ, value))
    return "".join(out)


def _node(category, typ, name="n", **inputs):
    return '<%s name="%s" type="%s">%s</%s>' % (category, name, typ, _inputs(**inputs), category)


def _lifted(category, typ, lift, **inputs):
    """A node whose signed output is moved up by `lift` before display."""
    return _node(category, typ, name="raw", **inputs) + _node(
        "add", typ, in1=("node", (typ, "raw")), in2=(typ, lift))


TC = ("node", ("vector2", "uvs"))
P3 = ("node", ("vector3", "pos"))

CASES = {
    # Perlin gradient noise: the 2D and 3D gradient sets, the per-channel byte hashes, the 4th channel
    "noise2d_float": (UV, _node("noise2d", "float", texcoord=TC, amplitude=("float", "0.5"), pivot=("float", "0.5"))),
    "noise2d_vector2": (UV, _node("noise2d", "vector2", texcoord=TC, amplitude=("vector2", "0.5, 0.5"),
                                  pivot=("float", "0.5"))),
    "noise2d_vector4": (UV, _node("noise2d", "vector4", texcoord=TC, amplitude=("vector4", "0.5, 0.5, 0.5, 0.5"),
                                  pivot=("float", "0.5"))),
    "noise2d_color3_graph": (UV, _node("noise2d", "color3", texcoord=TC, amplitude=("float", "0.6"),
                                       pivot=("float", "0.5"))),
    "noise3d_float": (POS, _node("noise3d", "float", position=P3, amplitude=("float", "0.5"), pivot=("float", "0.5"))),
    "noise3d_vector3": (POS, _node("noise3d", "vector3", position=P3, amplitude=("vector3", "0.5, 0.5, 0.5"),
                                   pivot=("float", "0.5"))),
    "noise3d_color4_graph": (POS, _node("noise3d", "color4", position=P3, amplitude=("vector4", "0.5, 0.4, 0.3, 1"),
                                        pivot=("float", "0.5"))),
    # fBm: octave count, lacunarity, diminish, and the offset decorrelating the extra channels
    "fractal2d_float": (UV, _lifted("fractal2d", "float", "0.5", texcoord=TC, octaves=("integer", "4"))),
    "fractal2d_vector2": (UV, _lifted("fractal2d", "vector2", "0.5, 0.5", texcoord=TC)),
    "fractal3d_float": (POS, _lifted("fractal3d", "float", "0.5", position=P3, octaves=("integer", "5"),
                                     lacunarity=("float", "2.5"), diminish=("float", "0.6"))),
    "fractal3d_vector4": (POS, _lifted("fractal3d", "vector4", "0.5, 0.5, 0.5, 0.5", position=P3)),
    "fractal3d_color3_graph": (POS, _lifted("fractal3d", "color3", "0.5, 0.5, 0.5", position=P3,
                                            amplitude=("vector3", "1, 0.5, 0.8"))),
    # cell noise: the lookup3 hash of the cell, negative cells included
    "cellnoise2d": (UV, _node("cellnoise2d", "float", texcoord=TC)),
    "cellnoise3d": (POS, _node("cellnoise3d", "float", position=P3)),
    # Worley: F1/F2/F3 distances, jitter, and the solid (per-cell value) style
    "worleynoise2d_float_jitter": (UV, _node("worleynoise2d", "float", texcoord=TC, jitter=("float", "0.6"))),
    "worleynoise2d_vector3": (UV, _node("worleynoise2d", "vector3", texcoord=TC)),
    "worleynoise2d_vector2_solid": (UV, _node("worleynoise2d", "vector2", texcoord=TC, style=("integer", "1"))),
    "worleynoise3d_vector2": (POS, _node("worleynoise3d", "vector2", position=P3, jitter=("float", "0.8"))),
    "worleynoise3d_float_solid": (POS, _node("worleynoise3d", "float", position=P3, style=("integer", "1"))),
    # unified noise (a nodegraph over all of the above)
    "unifiednoise2d_worley": ("", _node("unifiednoise2d", "float", freq=("vector2", "8, 8"), type=("integer", "2"),
                                        jitter=("float", "0.7"))),
    "unifiednoise3d_fractal": ("", _node("unifiednoise3d", "float", freq=("vector3", "3, 3, 3"),
                                         type=("integer", "3"), outmin=("float", "-0.3"))),
    # ramps and splits (which way is top, the antialiased edge)
    "ramplr_color3": ("", _node("ramplr", "color3", valuel=("color3", "1, 0, 0"), valuer=("color3", "0, 0, 1"))),
    "ramptb_vector3": ("", _node("ramptb", "vector3", valuet=("vector3", "1, 0.5, 0"), valueb=("vector3", "0, 0, 1"))),
    "splitlr_float": ("", _node("splitlr", "float", valuel=("float", "0.1"), valuer=("float", "0.9"),
                               center=("float", "0.8"))),
    "splittb_color4": ("", _node("splittb", "color4", valuet=("color4", "1, 0, 0, 1"), valueb=("color4", "0, 1, 0, 1"),
                                center=("float", "0.35"))),
    "ramp4_color3": ("", _node("ramp4", "color3", valuetl=("color3", "1, 0, 0"), valuetr=("color3", "0, 1, 0"),
                               valuebl=("color3", "0, 0, 1"), valuebr=("color3", "1, 1, 0"))),
    "ramp_radial_step": ("", _node("ramp", "color4", type=("integer", "1"), interpolation=("integer", "2"),
                                   num_intervals=("integer", "3"), interval2=("float", "0.4"),
                                   color2=("color4", "1, 0, 0, 1"))),
    # shapes and tilings (nodegraphs)
    "checkerboard": ("", _node("checkerboard", "color3", color2=("color3", "0.2, 0.3, 0.9"),
                               uvtiling=("vector2", "12, 6"))),
    "line": ("", _node("line", "float", center=("vector2", "0.5, 0.5"), point1=("vector2", "0.6, 0.3"))),
    "circle": ("", _node("circle", "float", center=("vector2", "0.7, 0.5"), radius=("float", "0.2"))),
    "hexagon": ("", _node("hexagon", "float", center=("vector2", "0.7, 0.5"), radius=("float", "0.2"))),
    "tiledcircles_staggered": ("", _node("tiledcircles", "color3", uvtiling=("vector2", "12, 12"),
                                         staggered=("boolean", "true"))),
    "tiledhexagons": ("", _node("tiledhexagons", "color3", uvtiling=("vector2", "12, 12"), size=("float", "0.7"))),
    # random values per cell id
    "randomfloat": (UV + '<floor name="cell" type="vector2"><input name="in" type="vector2" nodename="uv" /></floor>'
                    '<dotproduct name="id" type="float"><input name="in1" type="vector2" nodename="cell" />'
                    '<input name="in2" type="vector2" value="1, 37" /></dotproduct>',
                    _node("randomfloat", "float", seed=("integer", "3"), min=("float", "0.2"),
                          **{"in": ("node", ("float", "id"))})),
    "randomcolor_integer": (UV + '<floor name="cell" type="vector2"><input name="in" type="vector2" nodename="uv" />'
                            '</floor><dotproduct name="id" type="float"><input name="in1" type="vector2" '
                            'nodename="cell" /><input name="in2" type="vector2" value="1, 37" /></dotproduct>'
                            '<floor name="idi" type="integer"><input name="in" type="float" nodename="id" /></floor>',
                            _node("randomcolor", "color3", saturationlow=("float", "0.3"),
                                  brightnesslow=("float", "0.4"), **{"in": ("node", ("integer", "idi"))})),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_procedural_matches_materialx(case, tmp_path, renderer, reference):
    prelude, node = CASES[case]
    body = '<nodegraph name="g">%s%s<output name="out" type="%s" nodename="n" /></nodegraph>' % (
        prelude, node, _out_type(node))
    path = write_doc(tmp_path, body, name=case + ".mtlx")
    assert_parity_with_materialx(renderer, reference, path, "g/out")


def _out_type(node):
    """The type of the last node of a case (the one named n)."""
    i = node.rfind('name="n" type="')
    return node[i + len('name="n" type="'):].split('"', 1)[0]


# flake2d / flake3d are our own construction (MaterialX publishes no algorithm): no parity, only the contract
@pytest.mark.parametrize("category,space", [("flake2d", "texcoord"), ("flake3d", "position")])
def test_flake_coverage_sets_the_covered_fraction(category, space, tmp_path, renderer):
    import numpy as np

    from util import generate_one
    covered = []
    for coverage in ("0", "0.5", "1"):
        node = _node(category, "multioutput", size=("float", "0.05"), coverage=("float", coverage))
        body = ('<nodegraph name="g">%s<output name="id" type="integer" nodename="n" output="id" />'
                '<output name="rand" type="float" nodename="n" output="rand" /></nodegraph>' % node)
        path = write_doc(tmp_path, body, name="%s_%s.mtlx" % (category, coverage))
        ids = renderer.render(generate_one(path, "g/id"))
        rand = renderer.render(generate_one(path, "g/rand"))
        on_sphere = ids[..., 3] > 0
        assert rand[..., :3].min() >= 0.0 and rand[..., :3].max() <= 1.0
        covered.append(float(np.mean(ids[..., 0][on_sphere] > 0)))
    assert covered[0] == 0.0
    assert 0.2 < covered[1] < covered[2]
