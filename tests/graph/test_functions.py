"""Nodegraph implementations as GLSL functions (functions.py): emitted once per shader, called per instance, the same
pixels as expanded in place; specialised on the inputs a body reads at compile time; inlined where they cannot be."""
import re

import numpy as np
import pytest

from mtlxgen.graph import functions
from mtlxgen import pipeline
from mtlxgen.draw import renderer as render
from mtlxgen.apps.glslvalidate import GLSLANG, validate
from util import write_doc

TWO_CHECKERS = """
  <nodegraph name="NG">
    <checkerboard name="a" type="color3"><input name="uvtiling" type="vector2" value="4, 4" /></checkerboard>
    <checkerboard name="b" type="color3"><input name="uvtiling" type="vector2" value="9, 2" /></checkerboard>
    <mix name="m" type="color3"><input name="fg" type="color3" nodename="a" /><input name="bg" type="color3" nodename="b" />
      <input name="mix" type="float" value="0.5" /></mix>
    <output name="out" type="color3" nodename="m" />
  </nodegraph>
  <standard_surface name="SR" type="surfaceshader">
    <input name="base_color" type="color3" nodegraph="NG" output="out" />
    <input name="specular_roughness" type="float" value="0.3" />
  </standard_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="SR" /></surfacematerial>"""

# a nodedef of the document's own whose body reads an input at compile time (extract's index: {{=index}})
PICK = """
  <nodedef name="ND_pick" node="pick">
    <input name="in" type="color3" value="0.2, 0.5, 0.8" />
    <input name="which" type="integer" value="0" />
    <output name="out" type="float" />
  </nodedef>
  <nodegraph name="NG_pick" nodedef="ND_pick">
    <extract name="e" type="float"><input name="in" type="color3" interfacename="in" />
      <input name="index" type="integer" interfacename="which" /></extract>
    <output name="out" type="float" nodename="e" />
  </nodegraph>"""

PICKS = PICK + """
  <nodegraph name="G">
    <pick name="p0" type="float"><input name="which" type="integer" value="0" /></pick>
    <pick name="p2" type="float"><input name="which" type="integer" value="2" /></pick>
    <pick name="q2" type="float"><input name="which" type="integer" value="2" /></pick>
    <add name="s" type="float"><input name="in1" type="float" nodename="p0" /><input name="in2" type="float" nodename="p2" /></add>
    <add name="t" type="float"><input name="in1" type="float" nodename="s" /><input name="in2" type="float" nodename="q2" /></add>
    <output name="out" type="float" nodename="t" />
  </nodegraph>"""


def definitions(fragment):
    return re.findall(r"^void (mg_\w+)\(", fragment, re.M)


def calls(fragment, name):
    return len(re.findall(r"\b%s\(" % name, fragment)) - 1


def inline_shader(path, element=None):
    """The shader with every implementation expanded in place (the generator before functions)."""
    saved = functions.signature_ok
    functions.signature_ok = lambda nd: False
    try:
        return pipeline.generate(path, elements=[element] if element else None)[0]
    finally:
        functions.signature_ok = saved


def test_an_implementation_is_one_function_called_per_instance(tmp_path):
    path = write_doc(tmp_path, TWO_CHECKERS)
    s = pipeline.generate(path)[0]
    names = definitions(s.fragment)
    assert "mg_ND_checkerboard_color3" in names and "mg_ND_standard_surface_surfaceshader" in names
    assert len(names) == len(set(names))                     # each defined once
    assert calls(s.fragment, "mg_ND_checkerboard_color3") == 2
    assert calls(s.fragment, "mg_ND_standard_surface_surfaceshader") == 1
    # callees before callers; the functions before main
    assert s.fragment.index("void mg_ND_checkerboard_color3(") < s.fragment.index("void main()")
    body = s.fragment[s.fragment.index("void mg_ND_standard_surface_surfaceshader("):]
    assert names.index("mg_ND_convert_float_color3") < names.index("mg_ND_standard_surface_surfaceshader")
    assert "out surfaceshader" in body.split("\n")[0]
    # the public interface is the inlined shader's
    flat = inline_shader(path)
    assert "void mg_ND_standard_surface_surfaceshader(" not in flat.fragment
    assert s.manifest == flat.manifest and s.vertex == flat.vertex
    assert flat.fragment.count("mod(floor(") == 2 * s.fragment.count("mod(floor(")    # the checker's body, once


def test_emitted_once_per_library_and_settings(tmp_path):
    path = write_doc(tmp_path, TWO_CHECKERS)
    session = pipeline.Session(path)
    first = session.shader("M")
    family = next(n.function for n in session.graph("M", functions=True).nodes if n.category == "standard_surface")
    assert family in session.library.functions.values()       # kept by the library

    def codes(target):
        return {k: e[1] for k, e in family.variants.items() if e[0] == "code" and k[0][1] == target}

    glsl = codes("glsl")
    assert len(glsl) >= 1 and all(c.name == "mg_ND_standard_surface_surfaceshader" for c in glsl.values())
    again = session.shader("M")
    assert codes("glsl") == glsl and all(codes("glsl")[k] is c for k, c in glsl.items())   # reused, not emitted again
    assert again.fragment == first.fragment
    pipeline.Session(path, target="essl").shader("M")
    assert codes("essl") and codes("glsl") == glsl                                       # one more per settings


def test_compile_time_inputs_specialise_the_function(tmp_path):
    path = write_doc(tmp_path, PICKS)
    s = pipeline.generate(path, elements=["G/out"])[0]
    names = [n for n in definitions(s.fragment) if n.startswith("mg_ND_pick")]
    assert len(names) == 2                                   # index 0 and index 2: two variants, q2 shares p2's
    texts = {n: s.fragment[s.fragment.index("void %s(" % n):] for n in names}
    assert sorted(t.split("}")[0].count("[0]") + 2 * t.split("}")[0].count("[2]") for t in texts.values()) == [1, 2]
    for n in names:                                          # `which` is no parameter: only `in`
        assert re.search(r"void %s\(vec3 n_in, out float out_out\)" % n, s.fragment)


def test_output_depends_on_the_shader_alone_not_on_what_was_generated_before(tmp_path):
    one = write_doc(tmp_path, PICKS, "one.mtlx")
    other = write_doc(tmp_path, PICK + """
  <nodegraph name="G">
    <pick name="p2" type="float"><input name="which" type="integer" value="2" /></pick>
    <output name="out" type="float" nodename="p2" />
  </nodegraph>""", "other.mtlx")
    before = pipeline.generate(other, elements=["G/out"])[0]
    assert "mg_ND_pick" in before.fragment
    pipeline.generate(one, elements=["G/out"])
    assert pipeline.generate(other, elements=["G/out"])[0].fragment == before.fragment
    fresh = pipeline.generate(write_doc(tmp_path, open(other).read().split("\n", 2)[2].rsplit("</materialx>", 1)[0],
                                        "again.mtlx"), elements=["G/out"])[0]
    assert fresh.fragment.replace("again.mtlx", "other.mtlx") == before.fragment


def test_a_connected_compile_time_input_is_expanded_in_place(tmp_path):
    path = write_doc(tmp_path, PICK + """
  <nodegraph name="G">
    <constant name="k" type="integer"><input name="value" type="integer" value="1" /></constant>
    <pick name="p" type="float"><input name="which" type="integer" nodename="k" /></pick>
    <output name="out" type="float" nodename="p" />
  </nodegraph>""")
    with pytest.raises(pipeline.MtlxError, match="must be a constant, it is connected") as e:
        pipeline.generate(path, elements=["G/out"])      # as expanded in place: extract's index is compile-time
    with pytest.raises(pipeline.MtlxError) as flat:
        inline_shader(path, "G/out")
    assert e.value.lines() == flat.value.lines()


@pytest.mark.parametrize("body, why", [
    ("""<nodedef name="ND_lobe" node="lobe"><input name="w" type="float" value="1" /><output name="out" type="BSDF" /></nodedef>
  <nodegraph name="NG_lobe" nodedef="ND_lobe">
    <oren_nayar_diffuse_bsdf name="d" type="BSDF"><input name="weight" type="float" interfacename="w" /></oren_nayar_diffuse_bsdf>
    <output name="out" type="BSDF" nodename="d" />
  </nodegraph>
  <lobe name="l" type="BSDF" />
  <surface name="S" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="l" /></surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>""",
     "a closure output is evaluated per lighting context"),
    ("""<nodedef name="ND_tex" node="tex"><input name="file" type="filename" value="" /><output name="out" type="color3" /></nodedef>
  <nodegraph name="NG_tex" nodedef="ND_tex">
    <image name="i" type="color3"><input name="file" type="filename" interfacename="file" /></image>
    <output name="out" type="color3" nodename="i" />
  </nodegraph>
  <tex name="t" type="color3" />
  <output name="o" type="color3" nodename="t" />""", "a sampler is the material's uniform"),
])
def test_inlined_where_a_function_cannot_be(tmp_path, body, why):
    path = write_doc(tmp_path, body)
    s = pipeline.generate(path)[0]
    assert not [n for n in definitions(s.fragment) if n.startswith(("mg_ND_lobe", "mg_ND_tex"))], why
    assert s.fragment == inline_shader(path).fragment


def test_an_implementation_using_itself_is_refused_as_before(tmp_path):
    path = write_doc(tmp_path, """
  <nodedef name="ND_loop" node="loop"><input name="x" type="float" value="1" /><output name="out" type="float" /></nodedef>
  <nodegraph name="NG_loop" nodedef="ND_loop">
    <loop name="again" type="float"><input name="x" type="float" interfacename="x" /></loop>
    <output name="out" type="float" nodename="again" />
  </nodegraph>
  <loop name="l" type="float" />
  <output name="o" type="float" nodename="l" />""")
    with pytest.raises(pipeline.MtlxError) as e:
        pipeline.generate(path)
    assert "NG_loop" in str(e.value) and "inside itself" in str(e.value)


@pytest.mark.gl
@pytest.mark.skipif(GLSLANG is None, reason="glslangValidator is not installed")
@pytest.mark.parametrize("target", ["glsl", "essl", "vulkan"])
def test_function_shaders_are_valid_for_every_target(tmp_path, target):
    for doc in (TWO_CHECKERS, PICKS):
        path = write_doc(tmp_path, doc)
        for s in pipeline.generate(path, elements=["M" if doc is TWO_CHECKERS else "G/out"], target=target):
            assert definitions(s.fragment)
            assert validate(s, str(tmp_path), target) == []


@pytest.mark.gl
def test_the_same_pixels_as_expanded_in_place(tmp_path):
    r = render.Renderer(size=48, env_samples=8)
    for doc in (TWO_CHECKERS, PICKS):
        path = write_doc(tmp_path, doc)
        element = "M" if doc is TWO_CHECKERS else "G/out"
        a, b = pipeline.generate(path, elements=[element])[0], inline_shader(path, element)
        assert a.fragment != b.fragment
        assert np.array_equal(np.asarray(r.render(a)), np.asarray(r.render(b)))
