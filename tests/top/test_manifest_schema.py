"""Every manifest validates against docs/manifest.schema.json; texture paths relative to the manifest; the
transparency flag as MaterialX's isTransparentSurface tells it.

Every document of examples/ and tests/data (.mtlx and USD stages) is generated for the desktop target (a few for
essl and vulkan) and written as `generate` writes it; each NAME.json and each in-memory manifest is validated.
The corpus (../shared, marked corpus) is validated in the same way.
"""
import glob
import json
import os

import pytest

from conftest import CORPUS, CORPUS_ABSENT, HAVE_CORPUS, ROOT
from util import write_doc

jsonschema = pytest.importorskip("jsonschema", reason="jsonschema (the test extra) validates the manifests")

SCHEMA_PATH = os.path.join(ROOT, "docs", "manifest.schema.json")
DATA = os.path.join(ROOT, "tests", "data")
USD = (".usd", ".usda", ".usdc", ".usdz")


def _validator():
    with open(SCHEMA_PATH, encoding="utf-8") as f:
        schema = json.load(f)
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def _documents(*roots):
    found = []
    for root in roots:
        for ext in (".mtlx",) + USD:
            found += glob.glob(os.path.join(root, "**", "*" + ext), recursive=True)
    return sorted(set(found))


def _check_folder(validator, paths, out, targets=("glsl",)):
    """Generate each document (elements with problems left out, as generate does), write and validate; returns
    (manifests validated, problems as lines)."""
    from mtlxgen.api import generate_partial
    from mtlxgen.base.diagnostics import MtlxError
    count, bad = 0, []
    for k, path in enumerate(paths):
        for target in targets:
            try:
                shaders, _ = generate_partial(path, target=target)
            except (MtlxError, ValueError, TypeError):
                continue                # a document that does not open (the tests of bad input hold those)
            folder = os.path.join(out, "%d-%s" % (k, target))
            for s in shaders:
                for manifest in (s.manifest, json.load(open(s.write(folder)[2], encoding="utf-8"))):
                    count += 1
                    bad += ["%s:%s (%s): %s at %s" % (path, s.element, target, e.message, list(e.absolute_path))
                            for e in validator.iter_errors(manifest)]
    return count, bad


def test_the_schema_is_draft_2020_12_and_refuses_what_it_should():
    v = _validator()
    from mtlxgen.api import generate
    m = generate(os.path.join(ROOT, "examples", "quick_start.mtlx"))[0].manifest
    assert not list(v.iter_errors(m))
    for broken in (dict(m, transparent="no"), {k: x for k, x in m.items() if k != "uniforms"},
                   dict(m, surprise=1), dict(m, target="hlsl"),
                   dict(m, application=[dict(m["application"][0], name="u_notOurs")])):
        assert list(v.iter_errors(broken)), broken


def test_every_manifest_of_the_examples_and_test_data_validates(tmp_path):
    v = _validator()
    count, bad = _check_folder(v, _documents(os.path.join(ROOT, "examples"), DATA), str(tmp_path))
    assert count > 600, count               # each element twice: in memory and as written
    assert not bad, "\n".join(bad[:20])


def test_essl_and_vulkan_manifests_validate(tmp_path):
    v = _validator()
    count, bad = _check_folder(v, _documents(os.path.join(ROOT, "examples")), str(tmp_path), ("essl", "vulkan"))
    assert count > 50 and not bad, "\n".join(bad[:20])


@pytest.mark.corpus
@pytest.mark.skipif(not HAVE_CORPUS, reason=CORPUS_ABSENT)
def test_every_manifest_of_the_corpus_validates(tmp_path):
    v = _validator()
    count, bad = _check_folder(v, _documents(os.path.dirname(CORPUS)), str(tmp_path))
    assert count > 1000 and not bad, "\n".join(bad[:20])


# ---------------------------------------------------------------- texture paths

def test_texture_files_are_relative_to_the_manifest_unless_absolute_paths(tmp_path):
    from mtlxgen.apps.cli import main
    from mtlxgen.base.interface import absolute_textures
    doc = os.path.join(DATA, "web", "textured.mtlx")
    out = tmp_path / "deep" / "out"
    assert main(["generate", doc, "-o", str(out), "-q"]) == 0
    (written,) = glob.glob(str(out / "*.json"))
    files = [t["file"] for t in json.load(open(written))["textures"]]
    assert files and not any(os.path.isabs(f) for f in files)
    for f in files:             # joined to the manifest's folder, each names the file the document names
        assert os.path.isfile(os.path.join(out, f)), f
    assert main(["generate", doc, "-o", str(tmp_path / "abs"), "-q", "--absolute-paths"]) == 0
    (absolute,) = glob.glob(str(tmp_path / "abs" / "*.json"))
    old = json.load(open(absolute))
    assert all(os.path.isabs(t["file"]) and os.path.isfile(t["file"]) for t in old["textures"])
    back = absolute_textures(json.load(open(written)), str(out))
    assert [t["file"] for t in back["textures"]] == [os.path.normpath(t["file"]) for t in old["textures"]]


def test_the_scoreboard_harness_finds_relative_texture_files(tmp_path):
    """../shared/tools/scoreboard.py resolves a relative texture against the manifest's folder first."""
    tools = os.path.join(os.path.dirname(ROOT), "shared", "tools")
    if not os.path.isfile(os.path.join(tools, "scoreboard.py")):
        pytest.skip("needs ../shared/tools/scoreboard.py (absent on a clone)")
    import importlib.util
    spec = importlib.util.spec_from_file_location("scoreboard_for_test", os.path.join(tools, "scoreboard.py"))
    scoreboard = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(scoreboard)
    from mtlxgen.apps.cli import main
    doc = os.path.join(DATA, "web", "textured.mtlx")
    assert main(["generate", doc, "-o", str(tmp_path / "o"), "-q"]) == 0
    (written,) = glob.glob(str(tmp_path / "o" / "*.json"))
    found = scoreboard.project_textures(json.load(open(written)), str(tmp_path / "o"), "/nowhere/doc.mtlx")
    assert found and all(os.path.isfile(f) for f in found.values())


# ---------------------------------------------------------------- transparency

TRANSPARENCY_DOC = """
  <standard_surface name="opaque" type="surfaceshader" />
  <surfacematerial name="M_opaque" type="material"><input name="surfaceshader" type="surfaceshader" nodename="opaque" /></surfacematerial>
  <standard_surface name="glass" type="surfaceshader"><input name="transmission" type="float" value="0.8" /></standard_surface>
  <surfacematerial name="M_glass" type="material"><input name="surfaceshader" type="surfaceshader" nodename="glass" /></surfacematerial>
  <standard_surface name="cutout" type="surfaceshader"><input name="opacity" type="color3" nodename="mask" /></standard_surface>
  <constant name="mask" type="color3"><input name="value" type="color3" value="1, 1, 1" /></constant>
  <surfacematerial name="M_cutout" type="material"><input name="surfaceshader" type="surfaceshader" nodename="cutout" /></surfacematerial>
  <open_pbr_surface name="veil" type="surfaceshader"><input name="geometry_opacity" type="float" value="0.5" /></open_pbr_surface>
  <surfacematerial name="M_veil" type="material"><input name="surfaceshader" type="surfaceshader" nodename="veil" /></surfacematerial>
  <open_pbr_surface name="solid" type="surfaceshader"><input name="geometry_opacity" type="float" value="1" /></open_pbr_surface>
  <surfacematerial name="M_solid" type="material"><input name="surfaceshader" type="surfaceshader" nodename="solid" /></surfacematerial>
  <UsdPreviewSurface name="usd" type="surfaceshader" />
  <surfacematerial name="M_usd" type="material"><input name="surfaceshader" type="surfaceshader" nodename="usd" /></surfacematerial>"""


def test_the_transparency_flag(tmp_path):
    from mtlxgen.api import generate
    flags = {s.name: s.manifest["transparent"] for s in generate(write_doc(tmp_path, TRANSPARENCY_DOC))}
    # UsdPreviewSurface: its nodegraph feeds the opacity through a node (MaterialX calls it see-through too)
    assert flags == {"M_opaque": False, "M_glass": True, "M_cutout": True, "M_veil": True, "M_solid": False,
                     "M_usd": True}


def test_the_transparency_flag_is_materialx_isTransparentSurface(tmp_path):
    """Each renderable element of examples/ and tests/data: our flag and MaterialX's own function agree."""
    mx = pytest.importorskip("MaterialX")
    gen = pytest.importorskip("MaterialX.PyMaterialXGenShader")
    from mtlxgen import pipeline
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    paths = [p for p in _documents(os.path.join(ROOT, "examples"), DATA) if p.endswith(".mtlx")]
    compared, differ = 0, []
    for path in paths + [write_doc(tmp_path, TRANSPARENCY_DOC)]:
        try:
            session = pipeline.Session(path)
            doc = mx.createDocument()
            mx.readFromXmlFile(doc, path)
            doc.importLibrary(lib)
        except Exception:       # a document either side does not open
            continue
        for name in session.elements:
            element = doc.getDescendant(name)
            if element is None:
                continue
            ours = pipeline.transparent_surface(session.doc, session.library, name)
            compared += 1
            if ours != gen.isTransparentSurface(element, "genglsl"):
                differ.append("%s:%s ours %s" % (path, name, ours))
    assert compared > 300 and not differ, differ
