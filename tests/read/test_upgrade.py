"""Older documents mean what MaterialX 1.39 makes of them: renders against MaterialX (which upgrades
on read) and direct checks on the upgraded document."""
import os

import pytest

from conftest import DATA_TESTSUITE
from util import assert_parity_with_materialx, write_doc

from mtlxgen.read import document
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError

SWIZZLES_138 = """
  <nodegraph name="g">
    <position name="p" type="vector3" />
    <convert name="c" type="color3"><input name="in" type="vector3" nodename="p" /></convert>
    <swizzle name="s1" type="color3"><input name="in" type="color3" nodename="c" /><input name="channels" type="string" value="bgr" /></swizzle>
    <output name="bgr" type="color3" nodename="s1" />
    <swizzle name="s2" type="float"><input name="in" type="color3" nodename="c" /><input name="channels" type="string" value="g" /></swizzle>
    <output name="g" type="float" nodename="s2" />
    <swizzle name="s3" type="color4"><input name="in" type="float" nodename="s2" /><input name="channels" type="string" value="r01r" /></swizzle>
    <output name="r01r" type="color4" nodename="s3" />
    <swizzle name="s4" type="vector2"><input name="in" type="vector4" value="1, 0.2, 0.3, 0.4" /><input name="channels" type="string" value="wy" /></swizzle>
    <output name="wy" type="vector2" nodename="s4" />
    <swizzle name="s5" type="vector3"><input name="in" type="color3" nodename="c" /><input name="channels" type="string" value="rgb" /></swizzle>
    <output name="as_vector" type="vector3" nodename="s5" />
    <multiply name="m" type="color3"><input name="in1" type="color3" nodename="c" channels="brg" /><input name="in2" type="color3" value="1, 0.5, 0.25" /></multiply>
    <output name="chan" type="color3" nodename="m" />
    <atan2 name="at" type="float"><input name="in1" type="float" nodename="s2" /><input name="in2" type="float" value="-0.3" /></atan2>
    <output name="out_atan" type="float" nodename="at" />
    <normalmap name="nm" type="vector3"><input name="in" type="vector3" nodename="p" /><input name="space" type="string" value="object" /></normalmap>
    <output name="nmobj" type="vector3" nodename="nm" />
  </nodegraph>"""

SHADERREF_137 = """
  <nodegraph name="NG_col">
    <position name="p" type="vector3" />
    <extract name="e" type="float"><input name="in" type="vector3" nodename="p" /><parameter name="index" type="integer" value="1" /></extract>
    <multiply name="m" type="color3"><input name="in1" type="color3" nodename="e" channels="rrr" /><input name="in2" type="color3" value="1, 0.5, 0.25" /></multiply>
    <atan2 name="at" type="float"><input name="in1" type="float" nodename="e" /><input name="in2" type="float" value="-0.3" /></atan2>
    <add name="a" type="color3"><input name="in1" type="color3" nodename="m" /><input name="in2" type="float" nodename="at" /></add>
    <output name="out" type="color3" nodename="a" />
  </nodegraph>
  <material name="M_unlit">
    <shaderref name="SR_unlit" node="surface_unlit">
      <bindinput name="emission_color" type="color3" nodegraph="NG_col" output="out" />
      <bindinput name="emission" type="float" value="0.8" />
    </shaderref>
  </material>"""

RENAMES_136 = """
  <nodegraph name="g">
    <position name="p" type="vector3" />
    <dotproduct name="d" type="float"><input name="in1" type="vector3" nodename="p" /><input name="in2" type="vector3" value="1, 0, 0" /></dotproduct>
    <compare name="cmp" type="color3">
      <input name="intest" type="float" nodename="d" /><parameter name="cutoff" type="float" value="0.2" />
      <input name="in1" type="color3" value="1, 0.5, 0" /><input name="in2" type="color3" value="0, 0.2, 1" />
    </compare>
    <output name="out_cmp" type="color3" nodename="cmp" />
    <combine name="cb" type="color3"><input name="in1" type="float" nodename="d" /><input name="in2" type="float" value="0.3" /><input name="in3" type="float" value="0.6" /></combine>
    <output name="comb" type="color3" nodename="cb" />
    <combine name="cb2" type="color2"><input name="in1" type="float" nodename="d" /><input name="in2" type="float" value="0.3" /></combine>
    <output name="comb2" type="color2" nodename="cb2" />
    <rotate name="rot" type="vector2"><input name="in" type="vector2" value="0.5, 0.2" /><input name="amount" type="float" nodename="d" /></rotate>
    <output name="out_rot" type="vector2" nodename="rot" />
  </nodegraph>"""

OVERRIDES_125 = """
  <shader name="unlit" shadertype="surface" shaderprogram="surface_unlit">
    <input name="emission" type="float" value="1.0" publicname="em" />
    <input name="emission_color" type="color3" value="0.8, 0.8, 0.8" publicname="emc" />
  </shader>
  <material name="mat">
    <shaderref name="unlit" shadertype="surface" />
    <override name="emc" type="color3" value="0.1, 0.6, 0.85" />
  </material>"""

OPGRAPH_122 = """
  <opgraph name="og">
    <constant name="c" type="color3"><parameter name="color" type="color3" value="0.2, 0.7, 0.4" /></constant>
    <output name="col" type="color3"><parameter name="in" type="opgraphnode" value="c" /></output>
  </opgraph>
  <shader name="sh" shadertype="surface" shadername="surface_unlit">
    <input name="emission_color" graphoutput="col" graphname="og" type="color3" />
  </shader>
  <material name="mat">
    <shaderref name="sh" shadertype="surface" />
  </material>"""

CASES = [("1.38", SWIZZLES_138), ("1.37", SHADERREF_137), ("1.36", RENAMES_136), ("1.25", OVERRIDES_125),
         ("1.22", OPGRAPH_122)]


@pytest.mark.parametrize("version,body", CASES, ids=[c[0] for c in CASES])
def test_old_document_renders_as_materialx_reads_it(version, body, tmp_path, renderer, reference):
    path = write_doc(tmp_path, body, version=version)
    elements = reference.elements(path)
    assert elements
    for element in elements:
        assert_parity_with_materialx(renderer, reference, path, element)


def _load(tmp_path, body, version):
    return document.load(write_doc(tmp_path, body, version=version))


def test_swizzle_node_becomes_channel_nodes(tmp_path):
    doc = _load(tmp_path, SWIZZLES_138, "1.38")
    g = doc.nodegraphs["g"]
    assert not any(n.category == "swizzle" for n in g.nodes.values())
    assert g.nodes["s1"].category == "combine3"
    assert g.nodes["s2"].category == "extract" and g.nodes["s2"].inputs["index"].value == 1
    assert g.nodes["s3"].category == "combine4"
    assert g.nodes["s4"].category == "constant" and g.nodes["s4"].inputs["value"].value == (0.4, 0.2)
    assert g.nodes["s5"].category == "convert"
    # channels on an input: the input now reads a new node that does the swizzle
    src = g.nodes[g.nodes["m"].inputs["in1"].nodename]
    assert src.category == "combine3" and g.nodes["m"].inputs["in1"].channels is None
    assert set(g.nodes["at"].inputs) == {"iny", "inx"} and g.nodes["at"].inputs["iny"].nodename == "s2"
    assert g.nodes["nm"].category == "normalize"


def test_shaderref_material_becomes_shader_node_and_surfacematerial(tmp_path):
    doc = _load(tmp_path, SHADERREF_137, "1.37")
    assert doc.version == "1.37"
    mat = doc.nodes["M_unlit"]
    assert (mat.category, mat.type) == ("surfacematerial", "material")
    assert mat.inputs["surfaceshader"].nodename == "SR_unlit"
    shader = doc.nodes["SR_unlit"]
    assert (shader.category, shader.type) == ("surface_unlit", "surfaceshader")
    assert shader.inputs["emission_color"].nodegraph == "NG_col"
    # 1.37's atan2(in1, in2) reaches 1.39 as inx = in1, iny = in2
    at = doc.nodegraphs["NG_col"].nodes["at"]
    assert at.inputs["inx"].nodename == "e" and at.inputs["iny"].value == -0.3


def test_legacy_bsdf_with_base_becomes_layer(tmp_path):
    body = """
  <nodegraph name="g">
    <dielectric_btdf name="t" type="BSDF"><input name="ior" type="float" value="1.4" /></dielectric_btdf>
    <dielectric_brdf name="d" type="BSDF"><input name="base" type="BSDF" nodename="t" /></dielectric_brdf>
    <conductor_brdf name="c" type="BSDF"><input name="reflectivity" type="color3" value="0.9, 0.6, 0.2" /></conductor_brdf>
    <output name="out" type="BSDF" nodename="d" />
  </nodegraph>"""
    g = _load(tmp_path, body, "1.37").nodegraphs["g"]
    assert g.nodes["t"].category == "dielectric_bsdf" and g.nodes["t"].inputs["scatter_mode"].value == "T"
    assert g.nodes["d"].category == "layer"
    top = g.nodes[g.nodes["d"].inputs["top"].nodename]
    assert top.category == "dielectric_bsdf" and g.nodes["d"].inputs["base"].nodename == "t"
    ior = g.nodes["c"].inputs["ior"]
    assert g.nodes[ior.nodename].category == "artistic_ior" and ior.output == "ior"


def test_renamed_nodes_of_1_36(tmp_path):
    body = """
  <invert name="inv" type="matrix33" />
  <separate name="sep" type="multioutput"><input name="in" type="vector4" value="1, 2, 3, 4" /></separate>
  <transformpoint name="tp" type="vector3"><input name="mat" type="matrix44" value="1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1" /></transformpoint>
  <geomattrvalue name="ga" type="integer" attrname="surfid" />"""
    doc = _load(tmp_path, body, "1.36")
    assert doc.nodes["inv"].category == "invertmatrix"
    assert doc.nodes["sep"].category == "separate4"
    assert doc.nodes["tp"].category == "transformmatrix"
    assert doc.nodes["ga"].category == "geompropvalue" and doc.nodes["ga"].inputs["geomprop"].value == "surfid"


def test_current_documents_are_left_alone(tmp_path):
    body = '<swizzle name="s" type="float"><input name="in" type="color3" value="1, 2, 3" /></swizzle>'
    doc = _load(tmp_path, body, "1.39")
    assert doc.nodes["s"].category == "swizzle"


def test_corpus_upgrade_documents_build(library):
    from mtlxgen.graph import build as graph
    folder = os.path.join(DATA_TESTSUITE, "stdlib", "upgrade")
    for name in ("syntax_1_22.mtlx", "syntax_1_25.mtlx", "syntax_1_37.mtlx", "syntax_1_38.mtlx"):
        doc = pipeline.load_document(os.path.join(folder, name))
        elements = graph.renderable_elements(doc)
        assert elements, name
        for element in elements:
            builder = graph.GraphBuilder(doc, library, pipeline.graph_rules())
            kind, result = builder._element_result(element)
            assert result.type in ("material", "surfaceshader"), (name, element)


def test_broken_old_document_reports_file_and_line(tmp_path):
    body = """
  <material name="m">
    <shaderref name="sr" node="no_such_shader" />
  </material>"""
    path = write_doc(tmp_path, body, version="1.37")
    with pytest.raises(MtlxError) as e:
        pipeline.generate(path)
    line = e.value.lines()[0]
    assert line.startswith(path + ":") and "no_such_shader" in line
