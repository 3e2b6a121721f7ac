"""The document parser: values of every type, includes, prefixes, file and line on every element."""
import os

import pytest

from mtlxgen.read import document
from mtlxgen.base import mxtypes
from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.read.xmlreader import parse_text
from util import write_doc


@pytest.mark.parametrize("type_name,text,expected", [
    ("float", "1.5", 1.5),
    ("float", "-2e-3", -0.002),
    ("integer", "7", 7),
    ("integer", "-3", -3),
    ("boolean", "true", True),
    ("boolean", "false", False),
    ("color3", "0.1, 0.2, 0.3", (0.1, 0.2, 0.3)),
    ("color3", "0.1 0.2 0.3", (0.1, 0.2, 0.3)),
    ("color4", "0.1,0.2,0.3,0.4", (0.1, 0.2, 0.3, 0.4)),
    ("vector2", "1, 2", (1.0, 2.0)),
    ("vector3", "1, 2, 3", (1.0, 2.0, 3.0)),
    ("vector4", "1, 2, 3, 4", (1.0, 2.0, 3.0, 4.0)),
    ("matrix33", "1,0,0, 0,1,0, 0,0,1", (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)),
    ("matrix44", ",".join(["2"] * 16), (2.0,) * 16),
    ("string", "hello world", "hello world"),
    ("filename", "textures/a.png", "textures/a.png"),
    ("integerarray", "1, 2, 3", (1, 2, 3)),
    ("floatarray", "0.5, 1.5", (0.5, 1.5)),
    ("color3array", "1,0,0, 0,1,0", ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0))),
    ("vector2array", "1,2, 3,4", ((1.0, 2.0), (3.0, 4.0))),
    ("stringarray", "a, b", ("a", "b")),
])
def test_values_parse_into_typed_python_values(type_name, text, expected):
    value = mxtypes.parse_value(type_name, text)
    assert value == expected
    assert type(value) is type(expected)


@pytest.mark.parametrize("type_name,text", [
    ("float", "abc"), ("integer", "1.5"), ("boolean", "maybe"), ("color3", "1, 2"),
    ("vector2", "1, x"), ("matrix33", "1,2,3"), ("vector2array", "1, 2, 3"), ("color3", "1 2"),
    ("matrix33", "1,0,0, 0,1,0, 0,0.5.0,1"),
])
def test_values_that_do_not_fit_their_type_are_rejected(type_name, text):
    with pytest.raises(mxtypes.ValueError_):
        mxtypes.parse_value(type_name, text)


def test_struct_values_parse_member_by_member():
    structs = {"tc": mxtypes.StructType("tc", [("s", "float", "0.5"), ("t", "float", "0.5")])}
    assert mxtypes.parse_value("tc", "{0.1;0.2}", structs) == (0.1, 0.2)


def test_glsl_literals_round_trip_floats_exactly():
    assert mxtypes.glsl_literal("float", 0.1) == "0.1"
    assert mxtypes.glsl_literal("float", 1e-20) == "1.0e-20"
    assert mxtypes.glsl_literal("color3", (1, 0.5, 0)) == "vec3(1.0, 0.5, 0.0)"
    assert mxtypes.glsl_literal("boolean", True) == "true"
    assert mxtypes.glsl_literal("floatarray", (1.0, 2.0)) == "float[2](1.0, 2.0)"


def test_every_element_keeps_its_file_and_line(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="g">
    <constant name="c" type="float">
      <input name="value" type="float" value="0.5" />
    </constant>
    <output name="out" type="float" nodename="c" />
  </nodegraph>""")
    doc = document.load(path)
    g = doc.nodegraphs["g"]
    assert (g.loc.file, g.loc.line) == (path, 4)
    assert g.nodes["c"].loc.line == 5
    assert g.nodes["c"].inputs["value"].loc.line == 6
    assert g.outputs["out"].loc.line == 8


def test_nodedef_inputs_outputs_and_attributes_are_read(tmp_path):
    path = write_doc(tmp_path, """
  <nodedef name="ND_thing" node="thing" nodegroup="math" version="2.0" isdefaultversion="true">
    <input name="a" type="float" value="1" uniform="true" />
    <input name="uv" type="vector2" defaultgeomprop="UV0" />
    <input name="tex" type="filename" value="x.png" colorspace="srgb_texture" />
    <output name="out" type="color3" />
  </nodedef>""")
    nd = document.load(path).nodedefs["ND_thing"]
    assert nd.category == "thing" and nd.version == "2.0" and nd.isdefaultversion
    assert nd.inputs["a"].uniform and nd.inputs["a"].value == 1.0
    assert nd.inputs["uv"].defaultgeomprop == "UV0"
    assert nd.inputs["tex"].colorspace == "srgb_texture"
    assert nd.type == "color3"


def test_fileprefix_and_colorspace_are_inherited_by_filename_inputs(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="g" fileprefix="textures/" colorspace="acescg">
    <image name="i" type="color3">
      <input name="file" type="filename" value="a.png" />
    </image>
    <image name="j" type="color3">
      <input name="file" type="filename" value="b.png" colorspace="srgb_texture" />
    </image>
    <output name="out" type="color3" nodename="i" />
  </nodegraph>""")
    g = document.load(path).nodegraphs["g"]
    assert g.nodes["i"].inputs["file"].value == "textures/a.png"
    assert g.nodes["i"].inputs["file"].colorspace == "acescg"
    assert g.nodes["j"].inputs["file"].colorspace == "srgb_texture"


def test_xinclude_splices_the_included_document_with_its_own_locations(tmp_path):
    inc = write_doc(tmp_path, """
  <constant name="shared" type="float">
    <input name="value" type="float" value="0.25" />
  </constant>""", name="inc.mtlx")
    path = write_doc(tmp_path, """
  <xi:include xmlns:xi="http://www.w3.org/2001/XInclude" href="inc.mtlx" />
  <output name="out" type="float" nodename="shared" />""")
    doc = document.load(path)
    assert doc.nodes["shared"].loc.file == inc
    assert doc.nodes["shared"].loc.line == 4      # line 3 is the blank line write_doc leaves


def test_include_cycles_and_missing_includes_are_errors(tmp_path):
    write_doc(tmp_path, '<xi:include href="b.mtlx" />', name="a.mtlx")
    write_doc(tmp_path, '<xi:include href="a.mtlx" />', name="b.mtlx")
    with pytest.raises(MtlxError, match="include cycle"):
        document.load(os.path.join(str(tmp_path), "a.mtlx"))
    path = write_doc(tmp_path, '<xi:include href="nowhere.mtlx" />', name="c.mtlx")
    with pytest.raises(MtlxError, match=r"c\.mtlx:3: included file not found"):
        document.load(path)


def test_malformed_xml_names_file_and_line():
    with pytest.raises(MtlxError) as e:
        parse_text('<?xml version="1.0"?>\n<materialx>\n  <node name="a">\n</materialx>\n', "bad.mtlx")
    assert e.value.lines()[0].startswith("bad.mtlx:4: malformed XML")


def test_entity_declarations_are_refused():
    text = ('<?xml version="1.0"?>\n<!DOCTYPE m [<!ENTITY boom "aaaa">]>\n'
            '<materialx><constant name="&boom;" type="float"/></materialx>')
    with pytest.raises(MtlxError, match="entity declarations are not allowed"):
        parse_text(text, "x.mtlx")


def test_typedef_members_define_struct_types(tmp_path):
    path = write_doc(tmp_path, """
  <typedef name="pair">
    <member name="a" type="float" value="1.0" />
    <member name="b" type="vector2" value="0, 1" />
  </typedef>""")
    doc = document.load(path)
    assert doc.structs["pair"].members == [("a", "float", "1.0"), ("b", "vector2", "0, 1")]


def test_filename_tokens_come_from_the_node_its_graph_and_the_implemented_nodedef(tmp_path):
    path = write_doc(tmp_path, """
  <token name="ext" type="string" value="top" />
  <nodedef name="ND_tok" node="tok">
    <token name="name" type="string" value="from_nodedef" />
    <output name="out" type="color3" />
  </nodedef>
  <nodegraph name="NG_tok" nodedef="ND_tok">
    <token name="ext" type="string" value="png" />
    <image name="img" type="color3"><input name="file" type="filename" value="[name].[ext]" /></image>
    <image name="own" type="color3">
      <token name="name" type="string" value="mine" />
      <input name="file" type="filename" value="[name].[ext]" />
    </image>
    <output name="out" type="color3" nodename="img" />
  </nodegraph>""")
    g = document.load(path).nodegraphs["NG_tok"]
    assert g.nodes["img"].inputs["file"].value == "from_nodedef.png"    # top-level tokens are not used
    assert g.nodes["own"].inputs["file"].value == "mine.png"            # the node's own token wins
