"""Geometric-property nodes (an input's defaultgeomprop: Nworld, Tworld, UV0, Pobject...) are built once per library
and made again from that record for the next graph (build.GraphBuilder.geom_source, Library.geom_nodes): a graph
built after others is the graph a fresh session builds, node for node, down to the locations its errors would name."""
from mtlxgen import pipeline

DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  <standard_surface name="SR_a" type="surfaceshader"><input name="base" type="float" value="0.5" /></standard_surface>
  <surfacematerial name="M_a" type="material"><input name="surfaceshader" type="surfaceshader" nodename="SR_a" />
  </surfacematerial>
  <nodegraph name="NG_b">
    <texcoord name="uv" type="vector2" />
    <position name="p" type="vector3"><input name="space" type="string" value="object" /></position>
    <image name="img" type="color3"><input name="file" type="filename" value="missing.png" /></image>
    <noise3d name="n" type="float"><input name="position" type="vector3" nodename="p" /></noise3d>
    <mix name="c" type="color3"><input name="fg" type="color3" nodename="img" />
      <input name="bg" type="color3" value="0.1, 0.2, 0.3" /><input name="mix" type="float" nodename="n" /></mix>
    <output name="out" type="color3" nodename="c" />
  </nodegraph>
  <standard_surface name="SR_b" type="surfaceshader">
    <input name="base_color" type="color3" nodegraph="NG_b" output="out" />
  </standard_surface>
  <surfacematerial name="M_b" type="material"><input name="surfaceshader" type="surfaceshader" nodename="SR_b" />
  </surfacematerial>
</materialx>
"""


def _nodes(g):
    return [(n.id, n.category, n.nodedef.name, sorted((k, v.type, v.value, v.node, v.uniform, v.loc)
                                                      for k, v in n.inputs.items()), sorted(n.static.items()), n.loc)
            for n in g.nodes]


def test_a_graph_built_after_others_is_the_fresh_sessions(tmp_path):
    path = tmp_path / "geom.mtlx"
    path.write_text(DOC)
    for functions in (True, False):
        warm = pipeline.Session(str(path))
        for name in ("M_a", "M_b", "M_a"):
            warm.graph(name, functions=functions)
        assert warm.library.geom_nodes, "no geometric-property node was kept"
        for name in ("M_a", "M_b"):
            fresh = pipeline.Session(str(path))
            again, first = warm.graph(name, functions=functions), fresh.graph(name, functions=functions)
            assert _nodes(again) == _nodes(first)
            assert warm.shader(name).fragment == fresh.shader(name).fragment


def test_a_changed_library_forgets_its_geometric_nodes(tmp_path):
    path = tmp_path / "geom.mtlx"
    path.write_text(DOC)
    s = pipeline.Session(str(path))
    s.graph("M_a", functions=True)
    assert s.library.geom_nodes
    s.library._changed()
    assert not s.library.geom_nodes
