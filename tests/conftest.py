"""Shared fixtures: one renderer and one MaterialX reference per test session."""
import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
CORPUS = os.path.join(ROOT, "..", "shared", "corpus", "materialx")
TESTSUITE = os.path.join(CORPUS, "resources", "Materials", "TestSuite")
TEST_SIZE = 128


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
        return MaterialXReference([CORPUS])
    except ReferenceUnavailable as e:
        pytest.fail(str(e))


@pytest.fixture(scope="session")
def cms_reference():
    """MaterialX's GenGlsl with its colour management on (sRGB files converted as the spec says)."""
    from mtlxgen.reference import MaterialXReference
    return MaterialXReference([CORPUS], color_management=True)


@pytest.fixture(scope="session")
def harness():
    """The scoreboard's own render harness (../shared/tools/mxharness.py), at the tests' size."""
    sys.path.insert(0, os.path.join(ROOT, "..", "shared", "tools"))
    import mxharness
    return mxharness.Harness(size=TEST_SIZE)


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
