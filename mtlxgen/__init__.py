"""mtlxgen: MaterialX documents to GLSL shaders.

The pipeline, one module a stage, plain data between them:

    xmlreader  .mtlx text         -> element tree with file/line      (xml + xi:include)
    document   element tree       -> Document of typed dataclasses    (values parsed, prefixes applied)
    library    data libraries     -> Library: nodedefs indexed by category and signature
    graph      Document + Library -> Graph: resolved, type-checked, flattened, ordered nodes
                                     (graphtypes: the Graph's data and naming rules; the target's
                                     graph.BuildRules handed in by pipeline: nodes.RULES, nodes/usd.SeedRules)
    emit       Graph              -> Shader: vertex and fragment GLSL plus interface manifest
                                     (closureplan: when closures are needed; template: inline templates;
                                     stagewriter: main's lines; nodes/: the node table and pure handlers)
    render     Shader             -> linear RGBA pixels (moderngl, headless)

    view       a document, live   -> a window redrawn as the files change (render's drawing path, hot reload,
                                     progressive sampling, property panel: geometry, docedit, viewpanel)

The public API (api.py; __all__ below): generate, render, Session, Shader, DocumentError, DocumentWarning,
Options; environment (environment.py) prepares u_envRadiance and u_envIrradiance for any GL host.
docs/interface.md describes the shaders' application interface and the manifest.
"""
import sys

__all__ = ["generate", "render", "Session", "Shader", "Shaders", "Options", "DocumentError", "DocumentWarning",
           "Problem", "environment", "is_usd", "__version__"]

# The public API (api.py) is imported on first use: `import mtlxgen` stays cheap for mtlxgen.is_usd's callers and
# the command line's start.
# mtlxgen.render is the renderer's module (render.py), made callable: mtlxgen.render(shader_or_source, ...) is
# api.render (a function of that name would be replaced by the module as soon as anything imports it).
_API = frozenset(("generate", "Session", "Shader", "Shaders", "Options", "DocumentError", "DocumentWarning",
                  "Problem"))


def __getattr__(name):
    if name in _API:
        from . import api
        value = getattr(api, name)
    elif name in ("environment", "render"):
        # `from . import render` would ask this function again; importing a name from the module imports it, and
        # the import system sets it here
        if name == "render":
            from .render import Renderer  # noqa: F401
        else:
            from .environment import prepare  # noqa: F401
        value = sys.modules[__name__ + "." + name]
    elif name == "__version__":
        value = _version()
    else:
        raise AttributeError("module 'mtlxgen' has no attribute %r" % name)
    globals()[name] = value
    return value


class _CallableModule(type(sys)):
    """The class of the module mtlxgen.render: calling it is calling api.render (render.py sets it)."""

    def __call__(self, *args, **kwargs):
        from .api import render
        return render(*args, **kwargs)

    @property
    def __wrapped__(self):          # help() and inspect.signature show api.render's
        from .api import render
        return render


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
# import costs a small generation's time); tests/test_library_index.py holds them equal
USD_EXTENSIONS = (".usd", ".usda", ".usdc", ".usdz")


def is_usd(path):
    """Whether `path` names a USD stage (by its extension), as usdstage.is_usd says."""
    return str(path).lower().endswith(USD_EXTENSIONS)
