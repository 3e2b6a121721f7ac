"""mtlxgen: MaterialX documents to GLSL shaders.

Subpackages by stage, each importing only itself and the stages below (docs/architecture.md):

    base     the shared vocabulary: problems with FILE:LINE, file rules, MaterialX types, GLSL names, images
    read     .mtlx documents (xi:include, older versions upgraded), USD stages, the data libraries
    graph    the typed graph (the IR) and its build pass; nodegraph implementations as functions
    nodes    node implementations as data: a GLSL template and a folding evaluator per category
    passes   the passes after build, in order: reduce, fold, closures
    emit     GLSL: the vertex and fragment stages, functions, the manifest
    draw     pictures: the headless renderer, environment and lights
    pipeline, options, api
             one document through the stages; every generation setting in one object; the Python API
    apps     the command line, batch and golden, the viewer, WebGL and three.js, tools for tests

The public API (api.py; __all__ below): generate, render, Session, Shader, DocumentError, DocumentWarning,
Options; environment (draw/environment.py) prepares u_envRadiance and u_envIrradiance for any GL host.
docs/interface.md describes the shaders' application interface and the manifest.
"""

__all__ = ["generate", "render", "Session", "Shader", "Shaders", "Options", "DocumentError", "DocumentWarning",
           "Problem", "environment", "is_usd", "__version__"]

# The public API (api.py) is imported on first use: `import mtlxgen` stays cheap for mtlxgen.is_usd's callers and
# the command line's start.
_API = frozenset(("generate", "render", "Session", "Shader", "Shaders", "Options", "DocumentError", "DocumentWarning",
                  "Problem"))


def __getattr__(name):
    if name in _API:
        from mtlxgen import api
        value = getattr(api, name)
    elif name == "environment":
        import mtlxgen.draw.environment
        value = mtlxgen.draw.environment
    elif name == "__version__":
        value = _version()
    else:
        raise AttributeError("module 'mtlxgen' has no attribute %r" % name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))


def _version():
    """The installed distribution's version; where mtlxgen runs from a checkout that was never installed, the
    version pyproject.toml names."""
    try:
        from importlib.metadata import PackageNotFoundError, version
        try:
            return version("mtlxgen")
        except PackageNotFoundError:
            pass
    except ImportError:
        pass
    import os
    import re
    try:
        with open(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "pyproject.toml"),
                  encoding="utf-8") as f:
            m = re.search(r'^version\s*=\s*"([^"]+)"', f.read(), re.M)
        return m.group(1) if m else "0+unknown"
    except OSError:
        return "0+unknown"

# usdstage.USD_EXTENSIONS, here so that telling a USD stage from a .mtlx document imports nothing (usdstage's
# import costs a small generation's time); tests/read/test_library_index.py holds them equal
USD_EXTENSIONS = (".usd", ".usda", ".usdc", ".usdz")


def is_usd(path):
    """Whether `path` names a USD stage (by its extension), as usdstage.is_usd says."""
    return str(path).lower().endswith(USD_EXTENSIONS)
