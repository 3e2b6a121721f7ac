"""The package's modules import each other without a cycle, function-level imports included.

Every mtlxgen/**/*.py is parsed with ast (nothing is imported); an edge A -> B is any `import` or
`from ... import` in A, at module level or inside a function, naming package module B. Importing a.b.c
also runs the packages a.b and a that A is not already inside, so those count too; a package whose
__init__ calls importlib.import_module imports its modules by name at run time (nodes/: the node tables),
so it counts as importing every module of its folder.
"""
import ast
import os

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PACKAGE = "mtlxgen"


def modules():
    """{module name: path} of every .py file of the package."""
    found = {}
    for folder, _, files in os.walk(os.path.join(ROOT, PACKAGE)):
        for f in files:
            if f.endswith(".py"):
                rel = os.path.relpath(os.path.join(folder, f), ROOT)[:-3].split(os.sep)
                if rel[-1] == "__init__":
                    rel = rel[:-1]
                found[".".join(rel)] = os.path.join(folder, f)
    return found


def _resolve(importer, is_package, level, name):
    """Absolute name of a (possibly relative) import in module `importer`."""
    if level == 0:
        return name
    base = importer.split(".")
    if not is_package:
        base = base[:-1]
    base = base[:len(base) - (level - 1)]
    return ".".join(base + ([name] if name else []))


def imported_names(module, path):
    """Absolute dotted names a module's import statements name (a `from X import y` names X and X.y)."""
    with open(path, encoding="utf-8") as f:
        tree = ast.parse(f.read(), path)
    is_package = path.endswith("__init__.py")
    names, dynamic = [], False
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = _resolve(module, is_package, node.level, node.module)
            names.append(base)
            names += ["%s.%s" % (base, a.name) for a in node.names]
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                and node.func.attr == "import_module":
            dynamic = True
    return names, dynamic


def import_graph():
    mods = modules()
    edges = {m: set() for m in mods}
    for m, path in mods.items():
        names, dynamic = imported_names(m, path)
        for name in names:
            parts = name.split(".")
            for k in range(1, len(parts) + 1):
                target = ".".join(parts[:k])
                # a module runs inside its own packages: only the packages it is not in are run by its import
                if target in mods and target != m and not (m + ".").startswith(target + "."):
                    edges[m].add(target)
        if dynamic and path.endswith("__init__.py"):
            edges[m].update(o for o in mods if o.rsplit(".", 1)[0] == m and o != m)
    return edges


def find_cycle(edges):
    """One import cycle as a list of modules (first == last), or None."""
    state, stack = {}, []

    def visit(m):
        state[m] = "open"
        stack.append(m)
        for n in sorted(edges[m]):
            if state.get(n) == "open":
                return stack[stack.index(n):] + [n]
            if n not in state:
                found = visit(n)
                if found:
                    return found
        stack.pop()
        state[m] = "done"
        return None

    for m in sorted(edges):
        if m not in state:
            found = visit(m)
            if found:
                return found
    return None


def test_the_package_has_no_import_cycle():
    edges = import_graph()
    assert len(edges) > 40 and "mtlxgen.graph.build" in edges and "mtlxgen.nodes.usd" in edges
    cycle = find_cycle(edges)
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_the_graph_side_imports_nothing_of_the_emit_side():
    """graph/build.py and its data types know no target: nothing of nodes/, emit or the writers."""
    edges = import_graph()
    for m in ("mtlxgen.graph.build", "mtlxgen.graph.graphtypes"):
        emit_side = sorted(n for n in edges[m] if n.startswith("mtlxgen.nodes") or n == "mtlxgen.emit.emitter")
        assert not emit_side, "%s imports %s" % (m, emit_side)


def test_the_graph_data_types_are_a_leaf():
    edges = import_graph()
    assert all(n.startswith("mtlxgen.base") for n in edges["mtlxgen.graph.graphtypes"]), edges["mtlxgen.graph.graphtypes"]


@pytest.mark.parametrize("edges, cycle", [
    ({"a": {"b"}, "b": {"c"}, "c": {"a"}}, ["a", "b", "c", "a"]),
    ({"a": {"b"}, "b": set(), "c": {"b"}}, None),
])
def test_the_cycle_finder_finds_a_cycle(edges, cycle):
    assert find_cycle(edges) == cycle


def test_function_level_and_package_imports_are_edges(tmp_path):
    """An import inside a function counts, and so does the package a `from .pkg.mod import x` runs."""
    p = tmp_path / "m.py"
    p.write_text("def f():\n    from .nodes.usd import seed\n    import json\n")
    names, _ = imported_names("mtlxgen.m", str(p))
    assert "mtlxgen.nodes.usd" in names and "json" in names
    assert _resolve("mtlxgen.nodes.usd", False, 2, "graph") == "mtlxgen.graph"
    assert _resolve("mtlxgen.nodes", True, 1, "cmlib") == "mtlxgen.nodes.cmlib"
