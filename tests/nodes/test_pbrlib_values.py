"""pbrlib nodes that compute values (roughness, IOR, blackbody colour, hair absorption and roughness)
against MaterialX's own GLSL, both drawn by our harness.

Each case drives the node's inputs from the texture coordinates, so one image covers a range of
parameter values, and scales the result into [0, 1] for display so that no difference hides in
clipped pixels. Ranges reach past the documented domains where MaterialX clamps (or does not).
"""
import numpy as np
import pytest

from mtlxgen.draw import compare
from util import assert_parity_with_materialx, generate_one, save_side_by_side, write_doc

UV = '<texcoord name="uv" type="vector2" />'
# the texcoords most of the sphere's visible pixels show (u 0.6-0.9, v 0.25-0.75); ramps extrapolate past them
VISIBLE = ((0.6, 0.9), (0.25, 0.75))


def _ramp(name, index, lo, hi):
    """A float running from lo to hi across the visible range of texcoord component `index` (0 = u, 1 = v)."""
    return ('<extract name="{n}_t" type="float"><input name="in" type="vector2" nodename="uv" />'
            '<input name="index" type="integer" value="{i}" /></extract>'
            '<range name="{n}" type="float"><input name="in" type="float" nodename="{n}_t" />'
            '<input name="inlow" type="float" value="{a}" /><input name="inhigh" type="float" value="{b}" />'
            '<input name="outlow" type="float" value="{lo}" /><input name="outhigh" type="float" value="{hi}" />'
            '</range>').format(n=name, i=index, lo=lo, hi=hi, a=VISIBLE[index][0], b=VISIBLE[index][1])


def _color(name, r, g, b):
    """A color3 from three float node names or literals."""
    def ch(c, x):
        return ('<input name="%s" type="float" nodename="%s" />' % (c, x) if isinstance(x, str)
                else '<input name="%s" type="float" value="%g" />' % (c, x))
    return '<combine3 name="%s" type="color3">%s%s%s</combine3>' % (name, ch("in1", r), ch("in2", g), ch("in3", b))


def _node(category, typ, name, inputs):
    """inputs: {name: (type, node name or literal string)}; a literal is marked by a leading '='."""
    parts = []
    for k, (t, v) in inputs.items():
        if v.startswith("="):
            parts.append('<input name="%s" type="%s" value="%s" />' % (k, t, v[1:]))
        else:
            parts.append('<input name="%s" type="%s" nodename="%s" />' % (k, t, v))
    return '<%s name="%s" type="%s">%s</%s>' % (category, name, typ, "".join(parts), category)


def _shown(typ, scale, output=None):
    """The node n (or its output) times `scale`, as the color3 node 'shown'."""
    src = 'nodename="n"%s' % (' output="%s"' % output if output else "")
    if typ == "color3":
        return ('<multiply name="shown" type="color3"><input name="in1" type="color3" %s />'
                '<input name="in2" type="float" value="%g" /></multiply>' % (src, scale))
    v3 = "v3"
    pre = ""
    if typ == "vector2":
        pre = '<convert name="v2" type="vector3"><input name="in" type="vector2" %s /></convert>' % src
        src = 'nodename="v2"'
    return pre + ('<multiply name="%s" type="vector3"><input name="in1" type="vector3" %s />'
                  '<input name="in2" type="float" value="%g" /></multiply>'
                  '<convert name="shown" type="color3"><input name="in" type="vector3" nodename="%s" /></convert>'
                  % (v3, src, scale, v3))


# case: (nodes, node, (output type, display scale, output name or None))
CASES = {
    # α = r², the aspect √(1 − anisotropy) with anisotropy capped at 0.98, negative values isotropic
    "roughness_anisotropy": (UV + _ramp("r", 0, -0.2, 1.2) + _ramp("a", 1, -0.2, 1.2),
                             _node("roughness_anisotropy", "vector2", "n",
                                   {"roughness": ("float", "r"), "anisotropy": ("float", "a")}), ("vector2", 1.0, None)),
    "roughness_anisotropy_const": ("", _node("roughness_anisotropy", "vector2", "n",
                                             {"roughness": ("float", "=0.6"), "anisotropy": ("float", "=0.7")}),
                                   ("vector2", 1.0, None)),
    # a negative second component repeats the first
    "roughness_dual": (UV + _ramp("rx", 0, -0.3, 1.2) + _ramp("ry", 1, -0.5, 1.2) +
                       '<combine2 name="r" type="vector2"><input name="in1" type="float" nodename="rx" />'
                       '<input name="in2" type="float" nodename="ry" /></combine2>',
                       _node("roughness_dual", "vector2", "n", {"roughness": ("vector2", "r")}), ("vector2", 1.0, None)),
    # a nodegraph over invert + roughness_anisotropy
    "glossiness_anisotropy": (UV + _ramp("g", 0, 0.0, 1.0) + _ramp("a", 1, 0.0, 1.0),
                              _node("glossiness_anisotropy", "vector2", "n",
                                    {"glossiness": ("float", "g"), "anisotropy": ("float", "a")}),
                              ("vector2", 1.0, None)),
    # below, inside and above the fit's 1667-25000 K, across its 2222 K and 4000 K segments
    "blackbody": (UV + _ramp("t", 0, 500.0, 30000.0), _node("blackbody", "color3", "n", {"temperature": ("float", "t")}),
                  ("color3", 0.5, None)),
    "blackbody_const": ("", _node("blackbody", "color3", "n", {"temperature": ("float", "=3200")}), ("color3", 0.5, None)),
    # complex IOR from reflectivity and edge colour; per channel, reflectivity past 0.99 clamped
    "artistic_ior_ior": (UV + _ramp("r", 0, 0.0, 0.85) + _ramp("g", 1, -0.1, 1.1) + _color("rc", "r", 0.5, 1.2) +
                         _color("gc", "g", 0.9, "r"),
                         _node("artistic_ior", "multioutput", "n",
                               {"reflectivity": ("color3", "rc"), "edge_color": ("color3", "gc")}),
                         ("color3", 0.1, "ior")),
    "artistic_ior_extinction": (UV + _ramp("r", 0, 0.0, 0.85) + _ramp("g", 1, -0.1, 1.1) + _color("rc", "r", 0.5, 1.2) +
                                _color("gc", "g", 0.9, "r"),
                                _node("artistic_ior", "multioutput", "n",
                                      {"reflectivity": ("color3", "rc"), "edge_color": ("color3", "gc")}),
                                ("color3", 0.1, "extinction")),
    "artistic_ior_defaults": ("", '<artistic_ior name="n" type="multioutput" />', ("color3", 0.25, "extinction")),
}

# MaterialX keeps its hair helpers in the hair BSDF's GLSL file, which only compiles in a lit shader:
# MaterialX's side of these is drawn as a uniform_edf surface emitting the value (exact: no BSDF).
HAIR_CASES = {
    # melanin clamped to [0, 1] then −log(1 − m); redness not clamped
    "deon_hair_absorption_from_melanin": (UV + _ramp("m", 0, -0.2, 1.1) + _ramp("red", 1, -0.2, 1.2),
                                          _node("deon_hair_absorption_from_melanin", "vector3", "n",
                                                {"melanin_concentration": ("float", "m"),
                                                 "melanin_redness": ("float", "red")}), ("vector3", 0.1, None)),
    "deon_hair_absorption_custom_colors": ("", _node("deon_hair_absorption_from_melanin", "vector3", "n",
                                                     {"melanin_concentration": ("float", "=0.6"),
                                                      "eumelanin_color": ("color3", "=0.5, 0.4, 0.2"),
                                                      "pheomelanin_color": ("color3", "=0.9, 0.6, 0.3")}),
                                           ("vector3", 0.25, None)),
    # colour clamped to [0.001, 1]
    "chiang_hair_absorption_from_color": (UV + _ramp("c", 0, -0.1, 1.1) + _ramp("b", 1, 0.0, 1.0) +
                                          _color("cc", "c", 0.3, 0.8),
                                          _node("chiang_hair_absorption_from_color", "vector3", "n",
                                                {"color": ("color3", "cc"), "azimuthal_roughness": ("float", "b")}),
                                          ("vector3", 0.15, None)),
    "chiang_hair_roughness_R": (UV + _ramp("l", 0, -0.1, 0.7) + _ramp("az", 1, -0.1, 1.05),
                                _node("chiang_hair_roughness", "multioutput", "n",
                                      {"longitudinal": ("float", "l"), "azimuthal": ("float", "az")}),
                                ("vector2", 0.15, "roughness_R")),
    "chiang_hair_roughness_TT": (UV + _ramp("l", 0, -0.1, 0.7) + _ramp("az", 1, -0.1, 1.05),
                                 _node("chiang_hair_roughness", "multioutput", "n",
                                       {"longitudinal": ("float", "l"), "azimuthal": ("float", "az"),
                                        "scale_TT": ("float", "=0.7")}), ("vector2", 0.15, "roughness_TT")),
    "chiang_hair_roughness_TRT": (UV + _ramp("l", 0, -0.1, 0.7) + _ramp("az", 1, -0.1, 1.05),
                                  _node("chiang_hair_roughness", "multioutput", "n",
                                        {"longitudinal": ("float", "l"), "azimuthal": ("float", "az")}),
                                  ("vector2", 0.05, "roughness_TRT")),
}


def _graph(case, cases):
    nodes, node, (typ, scale, output) = cases[case]
    return '<nodegraph name="g">%s%s%s<output name="out" type="color3" nodename="shown" /></nodegraph>' % (
        nodes, node, _shown(typ, scale, output))


@pytest.mark.parametrize("case", sorted(CASES))
def test_pbrlib_value_matches_materialx(case, tmp_path, renderer, reference):
    path = write_doc(tmp_path, _graph(case, CASES), name=case + ".mtlx")
    assert_parity_with_materialx(renderer, reference, path, "g/out")


@pytest.mark.parametrize("case", sorted(HAIR_CASES))
def test_hair_value_matches_materialx(case, tmp_path, renderer, reference):
    graph = _graph(case, HAIR_CASES)
    ours = renderer.render(generate_one(write_doc(tmp_path, graph, name=case + ".mtlx"), "g/out"))
    lit = graph + ('<uniform_edf name="e" type="EDF"><input name="color" type="color3" nodegraph="g" output="out" />'
                   '</uniform_edf><surface name="s" type="surfaceshader"><input name="edf" type="EDF" nodename="e" />'
                   '</surface><surfacematerial name="m" type="material"><input name="surfaceshader" '
                   'type="surfaceshader" nodename="s" /></surfacematerial>')
    vs, fs, tex, _ = reference.generate(write_doc(tmp_path, lit, name=case + "_lit.mtlx"), "m")
    theirs, _ = renderer.render_timed(vs, fs, {}, tex)
    p = compare.parity(ours, theirs)
    if not p.passes:
        raise AssertionError("%s: %s (side by side: %s)" % (case, p, save_side_by_side(case, ours, theirs)))
    covered = theirs[..., 3] > 0
    np.testing.assert_allclose(ours[covered][:, :3], theirs[covered][:, :3], rtol=1e-3, atol=1e-5)
