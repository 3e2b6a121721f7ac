"""The package shows its architecture: subpackages by stage, each importing only its own stage and those below.

    base < read < graph < nodes < passes < emit < draw < (pipeline, options, api) < apps

An edge is any import in a module (module level or inside a function), read with ast as test_import_cycles reads
them; the package's own __init__ (the public face: `import mtlxgen` loads nothing) is everyone's and no one's
layer. Each stage's __init__ says what the stage does.
"""
import ast
import os

from test_import_cycles import import_graph, modules

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LAYERS = ["base", "read", "graph", "nodes", "passes", "emit", "draw", "top", "apps"]
TOP = ("pipeline", "options", "api")          # modules of mtlxgen itself: one document through the stages, the API


def layer(module):
    """The stage of a module of the package (mtlxgen.STAGE.x), "top" for mtlxgen.pipeline/options/api, None for the
    package itself."""
    parts = module.split(".")
    if parts == ["mtlxgen"]:
        return None
    if len(parts) == 2 and parts[1] in TOP:
        return "top"
    return parts[1]


def test_every_module_is_in_a_stage():
    stray = [m for m in modules() if layer(m) not in LAYERS + [None]]
    assert not stray, "modules outside the stages %s: %s" % (LAYERS, stray)


def test_imports_go_only_downward():
    edges = import_graph()
    upward = []
    for importer, names in edges.items():
        a = layer(importer)
        if a is None:
            continue
        for imported in names:
            b = layer(imported)
            if b is not None and LAYERS.index(b) > LAYERS.index(a):
                upward.append("%s (%s) imports %s (%s)" % (importer, a, imported, b))
    assert not upward, "imports going up a stage:\n" + "\n".join(sorted(upward))


def test_a_lower_stage_importing_a_higher_one_is_caught(tmp_path):
    """The check above reads what it should: a base module importing an emitter would be an upward edge."""
    assert LAYERS.index(layer("mtlxgen.emit.emitter")) > LAYERS.index(layer("mtlxgen.base.files"))
    assert layer("mtlxgen.pipeline") == "top" and layer("mtlxgen.apps.cli") == "apps" and layer("mtlxgen") is None


def test_each_stage_says_what_it_does():
    for stage in LAYERS:
        if stage == "top":
            continue
        init = os.path.join(ROOT, "mtlxgen", stage, "__init__.py")
        with open(init, encoding="utf-8") as f:
            doc = ast.get_docstring(ast.parse(f.read()))
        assert doc and len(doc.split()) >= 12, "mtlxgen/%s/__init__.py: a docstring saying the stage's job" % stage
        assert len(doc.splitlines()) <= 30, "mtlxgen/%s/__init__.py: a few lines, not a manual" % stage


def test_no_module_docstring_names_an_issue():
    """Concepts have names of their own, not issue numbers."""
    import re
    for name, path in modules().items():
        with open(path, encoding="utf-8") as f:
            doc = ast.get_docstring(ast.parse(f.read())) or ""
        assert not re.search(r"\bissue\s*#?\d+|#\d{1,3}\b", doc, re.I), "%s: docstring names an issue" % name
