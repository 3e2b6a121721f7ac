"""Generation-time folding (mtlxgen/passes/fold.py, issue 14): every foldable category and type gives, folded in Python,
the value the GLSL computes; closures that literals make empty are not emitted; guards on literals are decided.

The values are checked three ways for each case (one nodegraph output holding one node of literal inputs):
  - the complete shader (the node in GLSL, its inputs uniforms) is drawn and its pixel read;
  - reference.node_value (fold.evaluate: the one implementation the folder uses) gives the same value;
  - the reduced shader has no node left: its output is the folded literal, equal to that pixel.
"""
import os

import re

import numpy as np
import pytest

from conftest import ROOT

from mtlxgen.passes import closureplan, fold, reduce
from mtlxgen import pipeline
from mtlxgen.apps.reference import node_value

# (case name, category, output type, [(input, type, value)], output name of a multi-output node or None)
CASES = [
    ("add_float", "add", "float", [("in1", "float", "0.25"), ("in2", "float", "0.5")]),
    ("add_color3", "add", "color3", [("in1", "color3", "0.1, 0.2, 0.3"), ("in2", "color3", "0.5, 0.25, 0.125")]),
    ("add_color3FA", "add", "color3", [("in1", "color3", "0.1, 0.2, 0.3"), ("in2", "float", "0.5")]),
    ("add_integer", "add", "integer", [("in1", "integer", "3"), ("in2", "integer", "-5")]),
    ("subtract_vector3", "subtract", "vector3", [("in1", "vector3", "1, 2, 3"), ("in2", "vector3", "0.5, 4, -1")]),
    ("multiply_vector2", "multiply", "vector2", [("in1", "vector2", "0.5, -2"), ("in2", "vector2", "3, 0.25")]),
    ("multiply_color4FA", "multiply", "color4", [("in1", "color4", "0.1, 0.2, 0.3, 0.4"), ("in2", "float", "2")]),
    ("divide_float", "divide", "float", [("in1", "float", "0.3"), ("in2", "float", "0.7")]),
    ("divide_vector3FA", "divide", "vector3", [("in1", "vector3", "1, -2, 3"), ("in2", "float", "4")]),
    ("modulo_float", "modulo", "float", [("in1", "float", "-1.3"), ("in2", "float", "0.5")]),
    ("modulo_color3FA", "modulo", "color3", [("in1", "color3", "1.7, 2.2, -0.3"), ("in2", "float", "0.75")]),
    ("fract_float", "fract", "float", [("in", "float", "-1.3")]),
    ("invert_float", "invert", "float", [("in", "float", "0.3"), ("amount", "float", "1.5")]),
    ("invert_color3", "invert", "color3", [("in", "color3", "0.3, 0.6, 0.9")]),
    ("absval_vector3", "absval", "vector3", [("in", "vector3", "-1, 2, -3")]),
    ("sign_vector2", "sign", "vector2", [("in", "vector2", "-2, 0")]),
    ("floor_float", "floor", "float", [("in", "float", "-1.5")]),
    ("ceil_vector2", "ceil", "vector2", [("in", "vector2", "-1.5, 2.2")]),
    ("round_float", "round", "float", [("in", "float", "2.4")]),
    ("power_float", "power", "float", [("in1", "float", "0.5"), ("in2", "float", "2.2")]),
    ("power_color3FA", "power", "color3", [("in1", "color3", "0.2, 0.5, 0.9"), ("in2", "float", "0.4545")]),
    ("sin_float", "sin", "float", [("in", "float", "0.7")]),
    ("cos_vector3", "cos", "vector3", [("in", "vector3", "0.1, 1.2, 2.3")]),
    ("tan_float", "tan", "float", [("in", "float", "0.4")]),
    ("asin_float", "asin", "float", [("in", "float", "0.5")]),
    ("acos_float", "acos", "float", [("in", "float", "-0.25")]),
    ("atan2_float", "atan2", "float", [("iny", "float", "1"), ("inx", "float", "-2")]),
    ("sqrt_float", "sqrt", "float", [("in", "float", "2")]),
    ("ln_float", "ln", "float", [("in", "float", "3")]),
    ("exp_vector2", "exp", "vector2", [("in", "vector2", "0.5, -1")]),
    ("clamp_color3FA", "clamp", "color3", [("in", "color3", "-0.5, 0.5, 1.5"), ("low", "float", "0"),
                                           ("high", "float", "1")]),
    ("clamp_float", "clamp", "float", [("in", "float", "0.7"), ("low", "float", "0.1"), ("high", "float", "0.6")]),
    ("min_vector3", "min", "vector3", [("in1", "vector3", "1, 5, -2"), ("in2", "vector3", "2, 3, -4")]),
    ("max_float", "max", "float", [("in1", "float", "0.2"), ("in2", "float", "0.35")]),
    ("normalize_vector3", "normalize", "vector3", [("in", "vector3", "3, 4, 12")]),
    ("magnitude_vector3", "magnitude", "float", [("in", "vector3", "3, 4, 12")]),
    ("dotproduct_vector3", "dotproduct", "float", [("in1", "vector3", "1, 2, 3"), ("in2", "vector3", "0.5, -1, 2")]),
    ("crossproduct_vector3", "crossproduct", "vector3", [("in1", "vector3", "1, 2, 3"),
                                                         ("in2", "vector3", "0.5, -1, 2")]),
    ("mix_color3", "mix", "color3", [("fg", "color3", "1, 0.5, 0"), ("bg", "color3", "0, 0.25, 1"),
                                     ("mix", "float", "0.3")]),
    ("mix_color3_color3", "mix", "color3", [("fg", "color3", "1, 0.5, 0"), ("bg", "color3", "0, 0.25, 1"),
                                            ("mix", "color3", "0.1, 0.5, 0.9")]),
    ("remap_float", "remap", "float", [("in", "float", "0.3"), ("inlow", "float", "0.1"), ("inhigh", "float", "0.9"),
                                       ("outlow", "float", "-1"), ("outhigh", "float", "2")]),
    ("smoothstep_float", "smoothstep", "float", [("in", "float", "0.3"), ("low", "float", "0.1"),
                                                 ("high", "float", "0.9")]),
    ("luminance_color3", "luminance", "color3", [("in", "color3", "0.8, 0.3, 0.1")]),
    ("luminance_color4", "luminance", "color4", [("in", "color4", "0.8, 0.3, 0.1, 0.5")]),
    ("rgbtohsv_color3", "rgbtohsv", "color3", [("in", "color3", "0.8, 0.3, 0.1")]),
    ("rgbtohsv_color3_blue", "rgbtohsv", "color3", [("in", "color3", "0.2, 0.3, 0.9")]),
    ("hsvtorgb_color3", "hsvtorgb", "color3", [("in", "color3", "0.6, 0.5, 0.7")]),
    ("hsvtorgb_color4", "hsvtorgb", "color4", [("in", "color4", "0.1, 0.8, 0.4, 0.25")]),
    ("dot_color3", "dot", "color3", [("in", "color3", "0.1, 0.2, 0.3")]),
    ("constant_vector4", "constant", "vector4", [("value", "vector4", "0.1, 0.2, 0.3, 0.4")]),
    ("combine2_vector2", "combine2", "vector2", [("in1", "float", "0.1"), ("in2", "float", "0.2")]),
    ("combine3_color3", "combine3", "color3", [("in1", "float", "0.1"), ("in2", "float", "0.2"),
                                               ("in3", "float", "0.3")]),
    ("combine4_vector4", "combine4", "vector4", [("in1", "float", "0.1"), ("in2", "float", "0.2"),
                                                 ("in3", "float", "0.3"), ("in4", "float", "0.4")]),
    ("combine2_color4CF", "combine2", "color4", [("in1", "color3", "0.1, 0.2, 0.3"), ("in2", "float", "0.4")]),
    ("separate3_color3", "separate3", "float", [("in", "color3", "0.1, 0.2, 0.3")], "outg"),
    ("separate2_vector2", "separate2", "float", [("in", "vector2", "0.7, 0.9")], "outy"),
    ("convert_float_color3", "convert", "color3", [("in", "float", "0.3")]),
    ("convert_boolean_float", "convert", "float", [("in", "boolean", "true")]),
    ("convert_integer_float", "convert", "float", [("in", "integer", "3")]),
    ("convert_color3_vector3", "convert", "vector3", [("in", "color3", "0.1, 0.2, 0.3")]),
    ("convert_color4_color3", "convert", "color3", [("in", "color4", "0.1, 0.2, 0.3, 0.4")]),
    ("ifgreater_float", "ifgreater", "float", [("value1", "float", "0.5"), ("value2", "float", "0.25"),
                                               ("in1", "float", "0.7"), ("in2", "float", "0.1")]),
    ("ifgreatereq_color3", "ifgreatereq", "color3", [("value1", "float", "0.25"), ("value2", "float", "0.5"),
                                                     ("in1", "color3", "1, 0, 0"), ("in2", "color3", "0, 1, 0")]),
    ("ifequal_vector2", "ifequal", "vector2", [("value1", "float", "0.5"), ("value2", "float", "0.5"),
                                               ("in1", "vector2", "0.3, 0.4"), ("in2", "vector2", "0, 1")]),
    ("ifgreater_boolean", "ifgreater", "boolean", [("value1", "float", "0.5"), ("value2", "float", "0.25")]),
    ("and_boolean", "and", "boolean", [("in1", "boolean", "true"), ("in2", "boolean", "false")]),
    ("or_boolean", "or", "boolean", [("in1", "boolean", "true"), ("in2", "boolean", "false")]),
    ("xor_boolean", "xor", "boolean", [("in1", "boolean", "true"), ("in2", "boolean", "true")]),
    ("not_boolean", "not", "boolean", [("in", "boolean", "false")]),
    ("switch_float", "switch", "float", [("in1", "float", "0.1"), ("in2", "float", "0.2"), ("in3", "float", "0.3"),
                                         ("which", "integer", "2")]),
    ("plus_color3", "plus", "color3", [("fg", "color3", "0.2, 0.4, 0.6"), ("bg", "color3", "0.5, 0.1, 0.3"),
                                       ("mix", "float", "0.75")]),
    ("minus_color3", "minus", "color3", [("fg", "color3", "0.2, 0.4, 0.6"), ("bg", "color3", "0.5, 0.1, 0.3")]),
    ("difference_color3", "difference", "color3", [("fg", "color3", "0.2, 0.4, 0.6"),
                                                   ("bg", "color3", "0.5, 0.1, 0.3")]),
    ("screen_color3", "screen", "color3", [("fg", "color3", "0.2, 0.4, 0.6"), ("bg", "color3", "0.5, 0.1, 0.3")]),
    ("inside_color3", "inside", "color3", [("in", "color3", "0.2, 0.4, 0.6"), ("mask", "float", "0.5")]),
    ("outside_color3", "outside", "color3", [("in", "color3", "0.2, 0.4, 0.6"), ("mask", "float", "0.25")]),
    ("premult_color4", "premult", "color4", [("in", "color4", "0.2, 0.4, 0.6, 0.5")]),
    ("unpremult_color4", "unpremult", "color4", [("in", "color4", "0.2, 0.4, 0.6, 0.5")]),
]


def _case_xml(case):
    name, category, out_type, inputs = case[:4]
    output = case[4] if len(case) > 4 else None
    ins = "".join('<input name="%s" type="%s" value="%s" />' % i for i in inputs)
    node_type = "multioutput" if output else out_type
    out = '<output name="out" type="%s" nodename="n"%s />' % (out_type, ' output="%s"' % output if output else "")
    return '<nodegraph name="%s"><%s name="n" type="%s">%s</%s>%s</nodegraph>' % (
        name, category, node_type, ins, category, out)


def _document(tmp_path, body, colorspace=None):
    path = os.path.join(str(tmp_path), "fold.mtlx")
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<materialx version="1.39"%s>\n%s\n</materialx>\n'
                % (' colorspace="%s"' % colorspace if colorspace else "", body))
    return path


def _pixel(renderer, shader):
    img = renderer.render(shader)
    h, w = img.shape[:2]
    return img[h // 2, w // 2]


def _as_rgba(out_type, value):
    v = np.atleast_1d(np.asarray(value, dtype=np.float64))
    if out_type in ("float", "integer", "boolean"):
        return np.array([v[0], v[0], v[0], 1.0])
    if v.size == 2:
        return np.array([v[0], v[1], 0.0, 1.0])
    if v.size == 3:
        return np.array([v[0], v[1], v[2], 1.0])
    return v


# llvmpipe's asin/acos/atan are approximations good to about 4e-4 (GLSL sets no precision for them); a wrong formula
# is off by far more
TOL = dict(rtol=1e-3, atol=1e-4)


@pytest.fixture(scope="module")
def folded_cases(tmp_path_factory):
    path = _document(tmp_path_factory.mktemp("fold"), "\n".join(_case_xml(c) for c in CASES))
    complete = {s.element: s for s in pipeline.generate(path)}
    reduced = {s.element: s for s in pipeline.generate(path, interface="reduced")}
    session = pipeline.Session(path)
    return path, session, complete, reduced


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_folded_value_is_what_the_glsl_computes(case, folded_cases, renderer):
    path, session, complete, reduced = folded_cases
    name, out_type = case[0], case[2]
    element = name + "/out"
    # the reduced shader computes nothing: every node folded, the literal written out directly
    g = reduce.reduce(session.graph(element), reduce.Interface("reduced"))[0]
    folded = fold.fold(g)
    assert folded.nodes == [] and folded.result.node is None, [n.category for n in folded.nodes]
    assert "_out = " not in reduced[element].fragment.split("void main()")[1]
    # the GLSL of the unfolded node gives the folded value
    glsl = _pixel(renderer, complete[element])
    assert np.allclose(glsl, _as_rgba(out_type, folded.result.value), **TOL), (glsl, folded.result.value)
    assert np.allclose(_pixel(renderer, reduced[element]), glsl, **TOL)
    # and the one Python implementation (reference.node_value) is the folder's: the leaf node's value
    leaves = [n for n in session.graph(element).nodes]
    if len(leaves) == 1:
        n = leaves[0]
        (otype,) = n.outputs.values()
        values = {k: s.value for k, s in n.inputs.items() if s.type not in ("string", "geomname")}
        expected = node_value(n.category, n.nodedef.name, values,
                              {k: s.type for k, s in n.inputs.items() if k in values}, otype)
        assert np.allclose(_as_rgba(out_type, expected), glsl, **TOL)


def test_colour_space_conversions_fold_as_the_glsl_converts(tmp_path, renderer):
    spaces = ["srgb_texture", "g22_rec709", "acescg", "adobergb", "srgb_displayp3"]
    body = "\n".join('<nodegraph name="g_%s"><constant name="n" type="color3"><input name="value" type="color3" '
                     'value="0.5, 0.2, 0.8" colorspace="%s" /></constant><output name="out" type="color3" '
                     'nodename="n" /></nodegraph>' % (s, s) for s in spaces)
    path = _document(tmp_path, body, colorspace="lin_rec709")
    complete = {s.element: s for s in pipeline.generate(path)}
    reduced = {s.element: s for s in pipeline.generate(path, interface="reduced")}
    for s in spaces:
        e = "g_%s/out" % s
        assert "_cm" in complete[e].fragment            # converted in the shader where it is a uniform
        main = reduced[e].fragment.split("void main()")[1]
        assert "_cm" not in main and "mg_" not in main   # and at generation time where it is a constant
        assert np.allclose(_pixel(renderer, reduced[e]), _pixel(renderer, complete[e]), **TOL), s


@pytest.mark.parametrize("category, inputs", [
    ("sqrt", [("in", "float", "-1")]),
    ("ln", [("in", "float", "0")]),
    ("divide", [("in1", "float", "1"), ("in2", "float", "0")]),
    ("power", [("in1", "float", "-2"), ("in2", "float", "0.5")]),
    ("asin", [("in", "float", "1.5")]),
    ("normalize", [("in", "vector3", "0, 0, 0")]),
])
def test_undefined_values_are_left_to_the_gpu(tmp_path, category, inputs):
    out_type = "vector3" if category == "normalize" else "float"
    path = _document(tmp_path, _case_xml(("g", category, out_type, inputs)))
    g = reduce.reduce(pipeline.Session(path).graph("g/out"), reduce.Interface("reduced"))[0]
    folded = fold.fold(g)
    assert [n.category for n in folded.nodes] == [category]
    pipeline.generate(path, interface="reduced")          # and it still generates


def test_static_conditions():
    # the guards the emitter writes, decided on the literals they compare (closureplan.decide, over the tree)
    lit = {("one", "weight"): 1.0, ("zero", "weight"): 0.0, ("z", "mix"): 0.0, ("h", "mix"): 0.5, ("u", "mix"): 1.0}
    value = lambda node_id, name: lit.get((node_id, name), closureplan.UNKNOWN)     # noqa: E731
    x, y = closureplan.compare("x", "mix", "!=", 0.0), closureplan.compare("y", "mix", "!=", 1.0)
    c = closureplan.weighed("c")
    def ne0(n):
        return closureplan.compare(n, "mix", "!=", 0.0)

    def ne1(n):
        return closureplan.compare(n, "mix", "!=", 1.0)

    decide, conjoin, disjoin = closureplan.decide, closureplan.conjoin, closureplan.disjoin
    assert decide(closureplan.weighed("one"), value) is True
    assert decide(closureplan.weighed("zero"), value) is False
    assert decide(conjoin(x, closureplan.weighed("one")), value) is x
    assert decide(disjoin(ne0("z"), y), value) is y
    assert decide(conjoin(ne0("h"), ne1("h")), value) is True
    assert decide(conjoin(x, ne0("z")), value) is False
    assert decide(disjoin(conjoin(x, ne1("u")), conjoin(y, c)), value) == conjoin(y, c)
    assert decide(conjoin(disjoin(x, y), closureplan.weighed("one")), value) == disjoin(x, y)


def _ss_document(tmp_path, inputs):
    ins = "".join('<input name="%s" type="%s" value="%s" />' % i for i in inputs)
    return _document(tmp_path, '<standard_surface name="ss" type="surfaceshader">%s</standard_surface>'
                                '<surfacematerial name="m" type="material"><input name="surfaceshader" '
                                'type="surfaceshader" nodename="ss" /></surfacematerial>' % ins)


def test_zero_weight_lobes_are_not_emitted(tmp_path):
    path = _ss_document(tmp_path, [("coat", "float", "0"), ("sheen", "float", "0"), ("transmission", "float", "0"),
                                   ("metalness", "float", "0"), ("subsurface", "float", "0"),
                                   ("emission", "float", "0")])
    # with a light loop, so that the reflection context's calls are there to be dropped too
    # (the complete interface calls standard_surface's function: its body, then main)
    complete = pipeline.generate(path, max_lights=1)[0].fragment
    complete = complete[complete.index("\nvoid mg_ND_standard_surface_surfaceshader("):]
    reduced = pipeline.generate(path, interface="reduced", max_lights=1)[0].fragment.split("void main()")[1]
    for call in ("mg_sheen_conty_kulla_reflection(", "mg_conductor_indirect(", "mg_translucent_indirect(",
                 "mg_subsurface_indirect(", "mg_scatter_T", "coat_bsdf", "mg_generalized_schlick_edf("):
        assert call in complete
        assert call not in reduced, call
    assert "1.0e-6" not in reduced and "if (" not in reduced            # no guard left: each folded to true
    assert reduced.count("mg_dielectric_indirect(") == 1                 # the specular lobe alone
    assert "// emission" not in reduced                                  # emission 0: no EDF at all


def test_partial_weights_keep_both_sides_without_guards(tmp_path):
    path = _ss_document(tmp_path, [("metalness", "float", "0.5"), ("coat", "float", "0.25")])
    reduced = pipeline.generate(path, interface="reduced")[0].fragment.split("void main()")[1]
    assert "mg_conductor_indirect(" in reduced and "mg_dielectric_indirect(" in reduced
    assert "mg_mix_BSDF(" in reduced
    assert " != 0.0" not in reduced and " != 1.0" not in reduced and "1.0e-6" not in reduced


def test_a_kept_weight_keeps_its_guard(tmp_path):
    path = _ss_document(tmp_path, [("coat", "float", "0")])
    iface = reduce.interface("reduced", ["ss_coat"])
    reduced = pipeline.generate(path, interface=iface)[0]
    main = reduced.fragment.split("void main()")[1]
    assert re.search(r"if \(ss_coat >= 1\.0e-6\)\n\s+\w+ = mg_dielectric_indirect\(", main)
    assert reduced.manifest["kept"] == ["ss_coat"]
