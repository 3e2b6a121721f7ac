"""Emission is a pure function of the graph: emitting one graph twice gives byte-identical shaders, and the
graph is what it was before (deep comparison), for every document of examples/, tests/data/materialx/ and
tests/fuzz_seeds/, and for documents whose handlers add and drop uniforms (UDIM tiles, USD primvar flags).
"""
import copy
import glob
import os

import numpy as np
import pytest

from conftest import ROOT
from util import write_doc

from mtlxgen.emit import emitter as emit
from mtlxgen.base import images, targets
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError

FOLDERS = ["examples", os.path.join("tests", "data", "materialx"), os.path.join("tests", "fuzz_seeds")]
DOCUMENTS = sorted(os.path.relpath(p, ROOT) for f in FOLDERS
                   for p in glob.glob(os.path.join(ROOT, f, "**", "*.mtlx"), recursive=True))


def _snapshot(g):
    """Everything of a Graph but its library (shared, read-only), deep-copied."""
    return copy.deepcopy({k: v for k, v in vars(g).items() if k != "library"})


def graphs(path):
    """(element, Graph) of every element of a document that builds."""
    try:
        session = pipeline.Session(path)
    except MtlxError:
        return []
    out = []
    for name in session.elements:
        try:
            out.append((name, session.graph(name)))
        except MtlxError:
            pass
    return out


def assert_pure(path, environment="fis"):
    """Emit every element of `path` twice, for every target; returns how many emitted."""
    emitted = 0
    for (name, g), target in [(ng, t) for ng in graphs(path) for t in targets.NAMES]:
        before, library = _snapshot(g), g.library
        try:
            first = emit.emit(g, environment, target)
        except MtlxError:
            assert _snapshot(g) == before, "%s: emitting %s (which failed) changed its graph" % (path, name)
            continue
        assert _snapshot(g) == before, "%s: emitting %s changed its graph" % (path, name)
        second = emit.emit(g, environment, target)
        assert g.library is library
        for part in ("vertex", "fragment", "manifest", "document_code"):
            assert getattr(second, part) == getattr(first, part), "%s: %s's %s (%s) differs the second time" % (
                path, name, part, target)
        assert _snapshot(g) == before
        emitted += 1
    return emitted


def test_the_corpus_is_found():
    assert len(DOCUMENTS) >= 40 and any("udim" in d for d in DOCUMENTS)


@pytest.mark.parametrize("path", DOCUMENTS)
def test_emitting_a_graph_twice_gives_the_same_shaders_and_leaves_the_graph(path):
    assert_pure(os.path.join(ROOT, path))


def _tiles(tmp_path, stem):
    for tile, c in {1001: (1, 0, 0), 1002: (0, 1, 0), 1011: (0, 0, 1)}.items():
        images.write_image(str(tmp_path / ("%s.%d.png" % (stem, tile))),
                           np.tile(np.array(c + (1,), np.float32), (4, 4, 1)))


UDIM_IMAGE = (
    '<texcoord name="tc" type="vector2" />'
    '<image name="img" type="color3"><input name="file" type="filename" value="t.<UDIM>.png" colorspace="srgb_texture" />'
    '<input name="texcoord" type="vector2" nodename="tc" /><input name="default" type="color3" value="1, 1, 0" />'
    '</image><output name="out" type="color3" nodename="img" />')

USD_UDIM = (
    '<UsdPrimvarReader name="st" type="vector2"><input name="varname" type="string" value="st" /></UsdPrimvarReader>'
    '<UsdUVTexture name="tex" type="multioutput"><input name="file" type="filename" value="u.<UDIM>.png" />'
    '<input name="sourceColorSpace" type="string" value="raw" />'
    '<input name="st" type="vector2" nodename="st" output="result" /></UsdUVTexture>'
    '<UsdPreviewSurface name="s" type="surfaceshader">'
    '<input name="diffuseColor" type="color3" nodename="tex" output="rgb" /></UsdPreviewSurface>'
    '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" />'
    '</surfacematerial>')


@pytest.mark.parametrize("body, stem", [(UDIM_IMAGE, "t"), (USD_UDIM, "u")], ids=["image", "UsdUVTexture"])
def test_a_udim_graph_emits_twice_and_keeps_its_uniforms(tmp_path, body, stem):
    """A UDIM image reads one sampler per tile, which emission adds, and leaves the <UDIM> pattern's
    uniform undeclared: the graph keeps the pattern (the second emission failed on a graph without it)."""
    _tiles(tmp_path, stem)
    path = write_doc(tmp_path, body)
    (name, g), = graphs(path)
    patterns = [u for u in g.uniforms.values() if "<UDIM>" in str(u.value)]
    assert len(patterns) == 1
    assert assert_pure(path) == len(targets.NAMES)
    shader = emit.emit(g)
    samplers = sorted(t["uniform"] for t in shader.manifest["textures"])
    assert len(samplers) == 3 and patterns[0].name not in samplers
    assert "uniform sampler2D %s;" % patterns[0].name not in shader.fragment
    assert all(s not in g.uniforms for s in samplers)     # the tiles are the shader's, not the graph's
    if stem == "u":
        assert shader.manifest["primvars"] and shader.manifest["primvars"][0]["uniform"] not in g.uniforms
