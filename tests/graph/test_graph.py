"""Typed graph building: nodedef resolution, type checks, nodegraph expansion, geomprops, pruning, cycles."""
import os
import pytest

from mtlxgen.read import document
from mtlxgen.graph import build as graph
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError
from util import build_graph, write_doc


build = build_graph


def test_nodes_resolve_to_the_nodedef_matching_output_and_input_types(tmp_path, library):
    g = build(tmp_path, """
  <add name="a" type="color3">
    <input name="in1" type="color3" value="0.1, 0.2, 0.3" />
    <input name="in2" type="float" value="0.5" />
  </add>
  <add name="b" type="vector2">
    <input name="in1" type="vector2" value="1, 2" />
  </add>
  <output name="o1" type="color3" nodename="a" />
  <output name="o2" type="vector2" nodename="b" />""", "o1", library)
    assert [n.nodedef.name for n in g.nodes] == ["ND_add_color3FA"]
    g2 = graph.GraphBuilder(document.load(str(tmp_path / "doc.mtlx")), library, pipeline.graph_rules()).build("o2")
    assert [n.nodedef.name for n in g2.nodes] == ["ND_add_vector2"]


def test_nodedef_attribute_overrides_matching(tmp_path, library):
    g = build(tmp_path, """
  <multiply name="m" type="color3" nodedef="ND_multiply_color3FA">
    <input name="in1" type="color3" value="1, 1, 1" />
  </multiply>
  <output name="o" type="color3" nodename="m" />""", "o", library)
    assert g.nodes[0].nodedef.name == "ND_multiply_color3FA"


def test_unconnected_inputs_get_nodedef_defaults_as_public_uniforms(tmp_path, library):
    g = build(tmp_path, """
  <clamp name="c" type="float">
    <input name="in" type="float" value="2.0" />
  </clamp>
  <output name="o" type="float" nodename="c" />""", "o", library)
    node = g.nodes[0]
    assert node.inputs["in"].value == 2.0
    assert node.inputs["low"].value == 0.0 and node.inputs["high"].value == 1.0
    assert {u.name: u.value for u in g.uniforms.values()} == {"c_in": 2.0, "c_low": 0.0, "c_high": 1.0}


def test_library_nodegraph_implementations_are_expanded(tmp_path, library):
    # ND_separate3_color3 is a nodegraph of extract nodes in the standard library
    g = build(tmp_path, """
  <separate3 name="s" type="multioutput">
    <input name="in" type="color3" value="0.1, 0.2, 0.3" />
  </separate3>
  <output name="o" type="float" nodename="s" output="outg" />""", "o", library)
    assert [n.category for n in g.nodes] == ["extract"]
    assert g.nodes[0].inputs["index"].value == 1
    # the outer node's public input feeds the inner node through interfacename
    assert g.nodes[0].inputs["in"].uniform == "s_in"


def test_document_nodedefs_and_their_nodegraphs_are_expanded(tmp_path, library):
    g = build(tmp_path, """
  <nodedef name="ND_twice" node="twice">
    <input name="x" type="float" value="1.5" />
    <output name="out" type="float" />
  </nodedef>
  <nodegraph name="NG_twice" nodedef="ND_twice">
    <add name="sum" type="float">
      <input name="in1" type="float" interfacename="x" />
      <input name="in2" type="float" interfacename="x" />
    </add>
    <output name="out" type="float" nodename="sum" />
  </nodegraph>
  <twice name="t" type="float">
    <input name="x" type="float" value="0.25" />
  </twice>
  <output name="o" type="float" nodename="t" />""", "o", library)
    assert len(g.nodes) == 1 and g.nodes[0].category == "add"
    assert g.nodes[0].inputs["in1"].uniform == g.nodes[0].inputs["in2"].uniform == "t_x"
    assert g.uniforms["t_x"].value == 0.25


def test_defaultgeomprops_become_geometric_nodes(tmp_path, library):
    g = build(tmp_path, """
  <ramplr name="r" type="float" />
  <output name="o" type="float" nodename="r" />""", "o", library)
    texcoord = [n for n in g.nodes if n.category == "texcoord"]
    assert len(texcoord) == 1 and texcoord[0].inputs["index"].value == 0


def test_unused_nodes_are_pruned(tmp_path, library):
    g = build(tmp_path, """
  <nodegraph name="ng">
    <sin name="used" type="float" />
    <cos name="unused" type="float" />
    <output name="out" type="float" nodename="used" />
  </nodegraph>""", "ng/out", library)
    assert [n.id for n in g.nodes] == ["used"]


@pytest.mark.parametrize("body,message", [
    ("""<add name="a" type="float"><input name="in1" type="float" nodename="b" /></add>
        <add name="b" type="float"><input name="in1" type="float" nodename="a" /></add>
        <output name="o" type="float" nodename="a" />""", r"doc\.mtlx:\d+: cycle: '(a|b)' -> '(a|b)' -> '(a|b)'"),
    ("""<frobnicate name="f" type="float" /><output name="o" type="float" nodename="f" />""",
     r"doc\.mtlx:3: unknown node category 'frobnicate'"),
    ("""<constant name="c" type="float"><input name="value" type="float" value="1" /></constant>
        <sin name="s" type="vector3"><input name="in" type="vector3" nodename="c" /></sin>
        <output name="o" type="vector3" nodename="s" />""",
     r"doc\.mtlx:4: input 'in' of node 's' has type vector3 but is connected to a value of type float"),
    ("""<sin name="s" type="color3" /><output name="o" type="color3" nodename="s" />""",
     r"doc\.mtlx:3: node 's': no 'sin' nodedef outputs type color3"),
    ("""<sin name="s" type="float"><input name="bogus" type="float" value="1" /></sin>
        <output name="o" type="float" nodename="s" />""",
     r"doc\.mtlx:3: node 's' \(sin, type float\) has no input 'bogus'"),
])
def test_graph_errors_name_file_and_line(tmp_path, library, body, message):
    with pytest.raises(MtlxError) as e:
        build(tmp_path, body, "o", library)
    assert len(e.value.lines()) == 1
    import re
    assert re.search(message, e.value.lines()[0]), e.value.lines()[0]


def test_renderable_elements_follow_materialx_precedence(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="ng"><sin name="s" type="float" /><output name="out" type="float" nodename="s" /></nodegraph>
  <surface_unlit name="shader" type="surfaceshader" />
  <surfacematerial name="mat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="shader" />
  </surfacematerial>""")
    assert graph.renderable_elements(document.load(path)) == ["mat"]
    path = write_doc(tmp_path, """
  <nodegraph name="ng"><sin name="s" type="float" /><output name="out" type="float" nodename="s" /></nodegraph>
  <output name="top" type="float" nodegraph="ng" output="out" />""", name="b.mtlx")
    # a top-level output reading a nodegraph (nodegraph=) is not drawn: MaterialX 1.39.5 finds only ng/out
    assert graph.renderable_elements(document.load(path)) == ["ng/out"]
    path = write_doc(tmp_path, """<surface_unlit name="shader" type="surfaceshader" />""", name="c.mtlx")
    assert graph.renderable_elements(document.load(path)) == ["shader"]


@pytest.mark.corpus
def test_renderable_elements_match_materialx_on_the_corpus(reference):
    import glob
    import os
    from conftest import TESTSUITE
    files = sorted(glob.glob(os.path.join(TESTSUITE, "stdlib", "*", "*.mtlx")))
    assert files, "corpus not found at %s" % TESTSUITE
    checked = 0
    for path in files:
        try:
            theirs = reference.elements(path)
        except Exception:
            continue            # MaterialX itself cannot read it
        try:
            ours = graph.renderable_elements(document.load(path))
        except MtlxError:
            continue
        assert ours == theirs, path
        checked += 1
    assert checked > 40


VERSIONED = """
  <nodedef name="ND_shade_v1" node="shade" version="1.0" isdefaultversion="true">
    <input name="k" type="float" value="0.25" />
    <output name="out" type="float" />
  </nodedef>
  <nodedef name="ND_shade_v2" node="shade" version="2.0">
    <input name="k" type="float" value="0.75" />
    <output name="out" type="float" />
  </nodedef>
  <nodegraph name="NG_shade_v1" nodedef="ND_shade_v1">
    <sin name="s" type="float"><input name="in" type="float" interfacename="k" /></sin>
    <output name="out" type="float" nodename="s" />
  </nodegraph>
  <nodegraph name="NG_shade_v2" nodedef="ND_shade_v2">
    <cos name="c" type="float"><input name="in" type="float" interfacename="k" /></cos>
    <output name="out" type="float" nodename="c" />
  </nodegraph>
  <shade name="plain" type="float" />
  <shade name="pinned" type="float" version="2.0" />
  <output name="o_plain" type="float" nodename="plain" />
  <output name="o_pinned" type="float" nodename="pinned" />"""


def test_versions_pick_the_default_unless_a_node_names_one(tmp_path, library):
    path = write_doc(tmp_path, VERSIONED)
    doc = document.load(path)
    plain = pipeline.build_graph(doc, library, "o_plain")
    pinned = pipeline.build_graph(doc, library, "o_pinned")
    assert [n.category for n in plain.nodes] == ["sin"]
    assert plain.uniforms["plain_k"].value == 0.25
    assert [n.category for n in pinned.nodes] == ["cos"]
    assert pinned.uniforms["pinned_k"].value == 0.75


def test_unknown_version_is_an_error(tmp_path, library):
    path = write_doc(tmp_path, VERSIONED.replace('version="2.0" />', 'version="3.0" />'))
    with pytest.raises(MtlxError, match=r"doc\.mtlx:\d+: node 'pinned'"):
        pipeline.build_graph(document.load(path), library, "o_pinned")


def test_library_option_adds_definitions(tmp_path):
    import subprocess
    import sys
    libdir = tmp_path / "lib"
    libdir.mkdir()
    (libdir / "defs.mtlx").write_text("""<?xml version="1.0"?>
<materialx version="1.39">
  <nodedef name="ND_half_float" node="half"><input name="in" type="float" value="1" /><output name="out" type="float" /></nodedef>
  <nodegraph name="NG_half_float" nodedef="ND_half_float">
    <multiply name="m" type="float"><input name="in1" type="float" interfacename="in" /><input name="in2" type="float" value="0.5" /></multiply>
    <output name="out" type="float" nodename="m" />
  </nodegraph>
</materialx>
""")
    path = write_doc(tmp_path, """<nodegraph name="g"><half name="h" type="float" />
      <output name="out" type="float" nodename="h" /></nodegraph>""")
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    cli = [sys.executable, os.path.join(root, "cli.py"), "generate", path, "-o", str(tmp_path / "o")]
    without = subprocess.run(cli, capture_output=True, text=True)
    assert without.returncode == 1 and "unknown node category 'half'" in without.stderr
    with_lib = subprocess.run(cli + ["--library", str(libdir)], capture_output=True, text=True)
    assert with_lib.returncode == 0, with_lib.stderr
    assert "* 0.5" in (tmp_path / "o" / "g_out.frag").read_text()


def test_a_nodegraph_inputs_malformed_value_is_its_problem(tmp_path, library):
    """A nodegraph's own interface input whose value does not parse is reported at its line, as a node's input is
    (it was read as 0.0 without a word)."""
    with pytest.raises(MtlxError) as e:
        build(tmp_path, """
  <nodegraph name="NG">
    <input name="amount" type="float" value="abc" />
    <multiply name="m" type="float">
      <input name="in1" type="float" interfacename="amount" />
      <input name="in2" type="float" value="2" />
    </multiply>
    <output name="out" type="float" nodename="m" />
  </nodegraph>""", "NG/out", library)
    assert e.value.lines() == ["%s:5: input 'amount' of type float: not a number: 'abc'" % (tmp_path / "doc.mtlx")]
