"""Expansions of library nodegraph implementations kept per library (graph.GraphBuilder.expansion): a graph built
from a kept template is the graph a full walk builds, node for node, and so is its shader, wherever the key must
tell two outer nodes apart (which inputs are one Source, literal values, types, the document's colour space)."""
import glob
import os

import pytest

from conftest import DATA_EXAMPLES, EXAMPLES, HAVE_CORPUS, ROOT, TESTSUITE
from mtlxgen import elementcache, library, pipeline
from mtlxgen.diagnostics import MtlxError
from mtlxgen.graph import _Expansion
from mtlxgen.graphtypes import GNode

DOCUMENTS = sorted(glob.glob(os.path.join(ROOT, "examples", "**", "*.mtlx"), recursive=True)
                   + glob.glob(os.path.join(ROOT, "tests", "data", "targets", "*.mtlx"))
                   + glob.glob(os.path.join(DATA_EXAMPLES, "**", "*.mtlx"), recursive=True))
CORPUS_DOCUMENTS = sorted(glob.glob(os.path.join(EXAMPLES, "**", "*.mtlx"), recursive=True)
                          + glob.glob(os.path.join(TESTSUITE, "pbrlib", "**", "*.mtlx"), recursive=True)) \
    if HAVE_CORPUS else ["(corpus absent)"]

# standard_surface nodes whose expansions differ only where the key must see it: the normal read alone or shared with
# coat_normal (both the geometry's: one Source), a normal map, a literal string input of a nested node, values
MATERIALS = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <standard_surface name="plain" type="surfaceshader">
    <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />
  </standard_surface>
  <surfacematerial name="A" type="material"><input name="surfaceshader" type="surfaceshader" nodename="plain" /></surfacematerial>
  <normalmap name="nmap" type="vector3"><input name="in" type="vector3" value="0.5, 0.6, 1.0" /></normalmap>
  <standard_surface name="mapped" type="surfaceshader">
    <input name="normal" type="vector3" nodename="nmap" />
    <input name="coat" type="float" value="1.0" />
  </standard_surface>
  <surfacematerial name="B" type="material"><input name="surfaceshader" type="surfaceshader" nodename="mapped" /></surfacematerial>
  <position name="pos" type="vector3" />
  <standard_surface name="coated" type="surfaceshader">
    <input name="coat_normal" type="vector3" nodename="pos" />
    <input name="base_color" type="color3" value="0.1, 0.2, 0.8" colorspace="srgb_texture" />
  </standard_surface>
  <surfacematerial name="C" type="material"><input name="surfaceshader" type="surfaceshader" nodename="coated" /></surfacematerial>
  <open_pbr_surface name="op" type="surfaceshader"><input name="base_weight" type="float" value="0.5" /></open_pbr_surface>
  <surfacematerial name="D" type="material"><input name="surfaceshader" type="surfaceshader" nodename="op" /></surfacematerial>
  <standard_surface name="plain2" type="surfaceshader">
    <input name="base_color" type="color3" value="0.3, 0.3, 0.3" />
    <input name="specular_roughness" type="float" value="0.9" />
  </standard_surface>
  <surfacematerial name="E" type="material"><input name="surfaceshader" type="surfaceshader" nodename="plain2" /></surfacematerial>
  <gltf_pbr name="gl" type="surfaceshader"><input name="alpha_mode" type="integer" value="1" /></gltf_pbr>
  <surfacematerial name="F" type="material"><input name="surfaceshader" type="surfaceshader" nodename="gl" /></surfacematerial>
</materialx>
"""


def _graphs(path, order, fresh):
    """{element: (nodes as tuples, result, uniforms)} of the elements of `path` built in `order`; fresh: every
    kept expansion forgotten before each build (a full walk each time)."""
    session = pipeline.Session(path)
    out = {}
    for name in order:
        if fresh:
            session.library.expansions.clear()
        g = session.graph(name)
        out[name] = ([(n.id, n.category, n.nodedef.name, n.inputs, n.outputs, n.loc, n.static) for n in g.nodes],
                     g.result, g.uniforms, g.warnings)
    return out


def test_a_kept_expansion_builds_the_graph_a_full_walk_builds(tmp_path):
    path = tmp_path / "materials.mtlx"
    path.write_text(MATERIALS)
    order = ["A", "B", "C", "D", "E", "F", "A", "C", "B", "E", "A", "C", "B", "E"]   # (recorded second, replayed third)
    kept = _graphs(str(path), order, fresh=False)
    assert any(isinstance(t, _Expansion) for t in library.load_library().expansions.values()), \
        "nothing was kept: the test tests nothing"
    assert kept == _graphs(str(path), order, fresh=True)
    ids = {name: [n[0] for n in kept[name][0]] for name in "ABC"}
    assert "mapped_coat_tangent_rotate" in ids["B"] and "plain_coat_tangent_rotate" in ids["A"]


def test_shaders_with_kept_expansions_are_those_of_full_walks(tmp_path, monkeypatch):
    """The same shaders from one session in which every element after the first replays kept expansions, and from
    sessions where nothing is kept (reduced too: its folding reads the literals the replay copied)."""
    path = tmp_path / "materials.mtlx"
    path.write_text(MATERIALS)
    monkeypatch.setattr(elementcache, "REUSE", False)      # (every element walked: none instantiated)
    for interface in ("complete", "reduced"):
        library.load_library().expansions.clear()
        # each element three times in one run: its expansions met, recorded, then replayed
        shaders = pipeline.generate(str(path), list("ABCDEF") * 3, interface=interface)
        assert len(shaders) == 18
        assert any(isinstance(t, _Expansion) for t in library.load_library().expansions.values())
        kept = [(s.fragment, s.vertex, s.manifest) for s in shaders[12:]]
        fresh = []
        for name in "ABCDEF":
            library.load_library().expansions.clear()
            s = pipeline.generate(str(path), [name], interface=interface)[0]
            fresh.append((s.fragment, s.vertex, s.manifest))
        assert kept == fresh


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: os.path.relpath(p, ROOT))
def test_documents_build_the_same_graphs_from_kept_expansions(path):
    _same_graphs(path)


@pytest.mark.corpus
@pytest.mark.parametrize("path", CORPUS_DOCUMENTS, ids=lambda p: os.path.relpath(p, ROOT))
def test_corpus_documents_build_the_same_graphs_from_kept_expansions(path):
    _same_graphs(path)


def _same_graphs(path):
    """Every example document's elements, each built twice after the others (its expansions then kept, from other
    documents and elements too), against full walks."""
    try:
        session = pipeline.Session(path)
    except MtlxError as e:                  # (an included file the corpus lacks; nothing to render): said, not hidden
        pytest.skip("the document does not open: %s" % e.lines()[0][:160])
    names = list(session.elements) * 3         # (a key is recorded the second time it is met, replayed from the third)
    try:
        fresh = _graphs(path, names, fresh=True)
    except Exception:
        pytest.skip("an element does not build")
    assert _graphs(path, names, fresh=False) == fresh


def test_gnode_equality_compares_what_a_replay_makes():
    """The comparisons above are meaningful: GNode and Source compare by value, field by field."""
    a = GNode("x", "add", None, {}, {"out": "float"}, None)
    assert a == GNode("x", "add", None, {}, {"out": "float"}, None)
    assert a != GNode("y", "add", None, {}, {"out": "float"}, None)
