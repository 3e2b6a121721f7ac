"""Graph building at any size and on any shape: long chains and wide fan-in build without recursion per
node (MaterialX builds a 10,000-node chain), cycles within a scope and between nodegraphs are reported
as cycles with their line, nesting across scopes is bounded with a clear line, and string enum inputs
hold one of their nodedef's values."""
import re

import pytest

from mtlxgen.apps import cli
from mtlxgen.graph import build as graph
from mtlxgen.base.diagnostics import MtlxError
from util import build_graph, write_doc


def chain(n, fan_in=False):
    """n float nodes, each adding the one before it (and, with fan_in, the one before that too)."""
    lines = ['<constant name="n0" type="float"><input name="value" type="float" value="0.5" /></constant>',
             '<constant name="n1" type="float"><input name="value" type="float" value="0.25" /></constant>']
    for i in range(2, n):
        second = ('nodename="n%d"' % (i - 2)) if fan_in else 'value="0.001"'
        lines.append('<add name="n%d" type="float"><input name="in1" type="float" nodename="n%d" />'
                     '<input name="in2" type="float" %s /></add>' % (i, i - 1, second))
    lines.append('<output name="out" type="float" nodename="n%d" />' % (n - 1))
    return "\n".join(lines)


build = build_graph


@pytest.mark.parametrize("n", [1000, 10000])
def test_long_chain_builds_every_node_in_dependency_order(tmp_path, library, n):
    g = build(tmp_path, chain(n), "out", library)
    ids = [node.id for node in g.nodes]
    assert len(ids) == n - 1                      # n0 feeds n2 only through n1... n1 is the chain's head
    assert ids[0] == "n1" and ids[-1] == "n%d" % (n - 1)
    position = {i: k for k, i in enumerate(ids)}
    for node in g.nodes:                          # every producer comes before its reader
        for src in node.inputs.values():
            if src.linked:
                assert position[src.node] < position[node.id]


def test_fan_in_lattice_builds_each_node_once(tmp_path, library):
    g = build(tmp_path, chain(3000, fan_in=True), "out", library)
    ids = [node.id for node in g.nodes]
    assert len(ids) == len(set(ids)) == 3000
    assert g.nodes[-1].inputs["in2"].node == "n2997"


def test_ten_thousand_node_chain_generates_from_the_cli(tmp_path, capsys):
    path = write_doc(tmp_path, chain(10000))
    assert cli.main(["generate", path, "-o", str(tmp_path / "out")]) == 0
    frag = (tmp_path / "out" / "out.frag").read_text()
    assert frag.count(" n9999_out") >= 1 and frag.count("n5000_out") >= 2


def test_cycle_names_every_node_on_it_and_the_line_that_closes_it(tmp_path, library):
    body = """<add name="a" type="float"><input name="in1" type="float" nodename="c" /></add>
<add name="b" type="float"><input name="in1" type="float" nodename="a" /></add>
<add name="c" type="float"><input name="in1" type="float" nodename="b" /></add>
<output name="out" type="float" nodename="c" />"""
    with pytest.raises(MtlxError) as e:
        build(tmp_path, body, "out", library)
    (loc, msg), = e.value.problems
    assert loc.line == 3 and msg == "cycle: 'c' -> 'b' -> 'a' -> 'c'"


def test_node_reading_itself_is_a_cycle(tmp_path, library):
    body = """<multiply name="m" type="float"><input name="in1" type="float" nodename="m" /></multiply>
<output name="out" type="float" nodename="m" />"""
    with pytest.raises(MtlxError) as e:
        build(tmp_path, body, "out", library)
    assert e.value.problems[0][0].line == 3 and "cycle: 'm' -> 'm'" in e.value.problems[0][1]


def test_nodegraphs_reading_each_others_outputs_are_a_cycle(tmp_path, library):
    body = """<nodegraph name="A">
  <add name="n" type="float"><input name="in1" type="float" nodegraph="B" output="out" /></add>
  <output name="out" type="float" nodename="n" />
</nodegraph>
<nodegraph name="B">
  <add name="m" type="float"><input name="in1" type="float" nodegraph="A" output="out" /></add>
  <output name="out" type="float" nodename="m" />
</nodegraph>"""
    with pytest.raises(MtlxError) as e:
        build(tmp_path, body, "A/out", library)
    (loc, msg), = e.value.problems
    assert msg == "cycle: nodegraph outputs 'A.out' -> 'B.out' -> 'A.out'" and loc.line == 5


def test_nodegraph_input_reading_its_own_output_is_a_cycle(tmp_path, library):
    body = """<nodegraph name="A">
  <input name="i" type="float" nodegraph="A" output="out" />
  <add name="n" type="float"><input name="in1" type="float" interfacename="i" /></add>
  <output name="out" type="float" nodename="n" />
</nodegraph>
<output name="o" type="float" nodegraph="A" output="out" />"""
    with pytest.raises(MtlxError) as e:
        build(tmp_path, body, "o", library)
    assert e.value.problems[0][1].startswith("cycle: ")


def test_nodedefs_whose_implementations_use_each_other_are_refused(tmp_path, library):
    body = """<nodedef name="ND_foo" node="foo"><input name="x" type="float" value="1" /><output name="out" type="float" /></nodedef>
<nodedef name="ND_bar" node="bar"><input name="x" type="float" value="1" /><output name="out" type="float" /></nodedef>
<nodegraph name="NG_foo" nodedef="ND_foo">
  <bar name="b" type="float"><input name="x" type="float" interfacename="x" /></bar>
  <output name="out" type="float" nodename="b" />
</nodegraph>
<nodegraph name="NG_bar" nodedef="ND_bar">
  <foo name="f" type="float"><input name="x" type="float" interfacename="x" /></foo>
  <output name="out" type="float" nodename="f" />
</nodegraph>
<foo name="top" type="float" />
<output name="o" type="float" nodename="top" />"""
    with pytest.raises(MtlxError) as e:
        build(tmp_path, body, "o", library)
    assert "uses it inside itself" in e.value.problems[0][1] and e.value.problems[0][0].line > 0


def test_nodegraphs_chained_past_the_scope_limit_are_one_clear_line(tmp_path, capsys):
    n = graph.MAX_SCOPE_DEPTH + 20
    lines = []
    for i in range(n):
        src = 'nodegraph="G%d" output="out"' % (i - 1) if i else 'value="1"'
        lines.append('<nodegraph name="G%d"><add name="a" type="float"><input name="in1" type="float" %s />'
                     '</add><output name="out" type="float" nodename="a" /></nodegraph>' % (i, src))
    lines.append('<output name="o" type="float" nodegraph="G%d" output="out" />' % (n - 1))
    path = write_doc(tmp_path, "\n".join(lines))
    assert cli.main(["generate", path, "-o", str(tmp_path / "out"), "--element", "o"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and re.match(r"^.+\.mtlx:\d+: nodegraph outputs read each other more than %d deep"
                                      % graph.MAX_SCOPE_DEPTH, err[0])
    # within the limit the same shape builds
    short = "\n".join(lines[:10] + ['<output name="o" type="float" nodegraph="G9" output="out" />'])
    assert cli.main(["generate", write_doc(tmp_path, short, name="short.mtlx"), "-o", str(tmp_path / "o2"),
                     "--element", "o"]) == 0


def test_string_enum_value_outside_the_nodedef_is_an_error_at_its_line(tmp_path, library):
    body = """<dielectric_bsdf name="b" type="BSDF">
  <input name="scatter_mode" type="string" value="bogus" />
</dielectric_bsdf>
<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="b" /></surface>"""
    with pytest.raises(MtlxError) as e:
        build(tmp_path, body, "s", library)
    (loc, msg), = e.value.problems
    assert loc.line == 4 and msg == "node 'b' (ND_dielectric_bsdf): scatter_mode 'bogus' is not one of R, T, RT"
    ok = build(tmp_path, body.replace("bogus", "RT"), "s", library)
    bsdf, = [n for n in ok.nodes if n.category == "dielectric_bsdf"]
    assert bsdf.static["scatter_mode"] == "RT"


def test_long_names_make_bounded_identifiers_that_compile(tmp_path, library, renderer):
    long_name = "n" + "x" * 300
    body = ('<add name="%s" type="float"><input name="in1" type="float" value="0.5" /></add>'
            '<output name="out" type="float" nodename="%s" />' % (long_name, long_name))
    path = write_doc(tmp_path, body)
    g = build(tmp_path, body, "out", library)
    assert all(len(n.id) <= graph.IDENTIFIER_CHARS for n in g.nodes)
    assert all(len(u) <= graph.IDENTIFIER_CHARS for u in g.uniforms)
    from mtlxgen import pipeline
    shader, = pipeline.generate(path)
    renderer.ctx.__enter__()
    renderer.ctx.program(vertex_shader=shader.vertex, fragment_shader=shader.fragment).release()
    # two long names that differ only past the cut stay two identifiers
    assert graph.glsl_identifier(long_name + "a") != graph.glsl_identifier(long_name + "b")


def test_uniform_names_never_take_a_struct_types_name(tmp_path, library):
    body = """<typedef name="m_in1"><member name="v" type="float" value="1" /></typedef>
<multiply name="m" type="float"><input name="in2" type="float" value="2" /></multiply>
<output name="out" type="float" nodename="m" />"""
    g = build(tmp_path, body, "out", library)
    assert "m_in1" not in g.uniforms and any(u.startswith("m_in1") for u in g.uniforms)
