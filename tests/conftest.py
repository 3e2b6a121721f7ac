"""Shared fixtures (one renderer and one MaterialX reference per test session) and where test data lives.

Two sources of MaterialX documents, both laid out as MaterialX's own resources/ folder:
- DATA (tests/data/materialx): the few files the core tests read, copied with MaterialX's licence; always here.
- CORPUS (../shared/corpus/materialx): the scoreboard's corpus, for sweeps over many files. It is not part of
  the project (absent on a clone): tests that read it are marked `corpus` and skip, with CORPUS_ABSENT, there.
"""
import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
DATA = os.path.join(ROOT, "tests", "data", "materialx")
DATA_TESTSUITE = os.path.join(DATA, "resources", "Materials", "TestSuite")
DATA_EXAMPLES = os.path.join(DATA, "resources", "Materials", "Examples")
DATA_IMAGES = os.path.join(DATA, "resources", "Images")
SHARED = os.path.abspath(os.path.join(ROOT, "..", "shared"))
CORPUS = os.path.join(SHARED, "corpus", "materialx")
TESTSUITE = os.path.join(CORPUS, "resources", "Materials", "TestSuite")
EXAMPLES = os.path.join(CORPUS, "resources", "Materials", "Examples")
HAVE_CORPUS = os.path.isdir(os.path.join(CORPUS, "resources", "Materials"))
CORPUS_ABSENT = "needs ../shared/corpus (the scoreboard's corpus), absent on a clone"
TEST_SIZE = 128
# MaterialX resolves resources/... file names against these; the copied subset first, so that a test reads
# the same files with or without ../shared
REFERENCE_SEARCH = [DATA] + ([CORPUS] if HAVE_CORPUS else [])


def corpus_params(make, width=1):
    """Parameters built from the corpus by `make()` (a list of values or pytest.param), or, with the corpus
    absent, one case that skips with CORPUS_ABSENT (not an empty set, and `make` never runs)."""
    if HAVE_CORPUS:
        return list(make())
    values = (None,) * width
    return [pytest.param(*values, id="corpus-absent", marks=pytest.mark.skip(reason=CORPUS_ABSENT))]


def generate_switched(path, switches, **options):
    """pipeline.generate(path, partial=True, **options) with module flags set for the call ({module: value}, e.g.
    {emitcache: False} sets emitcache.REUSE), as comparable data: ([(element, stem, vertex, fragment, manifest)],
    problem lines or None), or (None, lines) for a document that does not open."""
    from mtlxgen import pipeline
    from mtlxgen.diagnostics import MtlxError
    saved = {m: m.REUSE for m in switches}
    for m, value in switches.items():
        m.REUSE = value
    try:
        shaders, error = pipeline.generate(path, partial=True, **options)
    except MtlxError as e:              # (a document that does not open: the same either way)
        return None, e.lines()
    finally:
        for m, value in saved.items():
            m.REUSE = value
    return [(s.element, s.stem, s.vertex, s.fragment, s.manifest) for s in shaders], \
        (error.lines() if error is not None else None)


def pytest_collection_modifyitems(config, items):
    """Tests marked `corpus` skip, saying why, where ../shared is absent."""
    if HAVE_CORPUS:
        return
    skip = pytest.mark.skip(reason=CORPUS_ABSENT)
    for item in items:
        if item.get_closest_marker("corpus"):
            item.add_marker(skip)


@pytest.fixture(scope="session")
def renderer():
    from mtlxgen.render import Renderer
    with Renderer(size=TEST_SIZE) as r:
        yield r


@pytest.fixture(scope="session")
def reference():
    """MaterialX's GenGlsl. Fails (not skips) when the wheel is missing: parity must be checked."""
    from mtlxgen.reference import MaterialXReference, ReferenceUnavailable
    try:
        return MaterialXReference(REFERENCE_SEARCH)
    except ReferenceUnavailable as e:
        pytest.fail(str(e))


@pytest.fixture(scope="session")
def cms_reference():
    """MaterialX's GenGlsl with its colour management on (sRGB files converted as the spec says)."""
    from mtlxgen.reference import MaterialXReference
    return MaterialXReference(REFERENCE_SEARCH, color_management=True)


@pytest.fixture(scope="session")
def harness():
    """Our Renderer in the scoreboard's scene (render.SCOREBOARD_SCENE: what ../shared/tools/mxharness.py
    draws; tests/test_scoreboard_scene.py checks that), at the tests' size."""
    from mtlxgen.render import Renderer
    with Renderer.scoreboard(size=TEST_SIZE) as r:
        yield r


@pytest.fixture(scope="session")
def library():
    from mtlxgen.library import load_library
    return load_library()


# ---------------------------------------------------------------- golden images

def pytest_addoption(parser):
    parser.addoption("--update-goldens", action="store_true", default=False,
                     help="rewrite golden_images/ from the current renders instead of checking against them")


@pytest.fixture(scope="session")
def update_goldens(request):
    """True under `pytest --update-goldens`: golden tests rewrite their goldens, then pass."""
    return request.config.getoption("--update-goldens")
