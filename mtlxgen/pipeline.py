"""The whole pipeline for one document: read, resolve, build each element's graph, emit GLSL."""
import os

from . import document, emit, graph, library
from .diagnostics import Loc, MtlxError, Problems
from .resolve import search_paths


def load_document(path, library_dirs=()):
    if not os.path.exists(path):
        raise MtlxError((Loc(path, 0), "no such file"))
    doc = document.load(path, search_paths(library_dirs))
    from .upgrade import upgrade
    return upgrade(doc)


def generate(path, elements=None, library_dirs=(), partial=False, usd_seed_rules=None):
    """Shaders for the renderable elements of a .mtlx file (or the named ones).

    usd_seed_rules: resolve USD's preview nodes by the UsdPreviewSurface seed's rules (nodes/usd.py)
    rather than MaterialX's nodegraphs; None (the default) turns them on for documents from USD.

    Returns [Shader]. Problems in any element are collected and raised together as one MtlxError;
    with partial=True returns (shaders that worked, MtlxError or None) instead.
    """
    lib = library.load_library(library_dirs)
    doc = load_document(path, library_dirs)
    names = elements or graph.renderable_elements(doc)
    if usd_seed_rules is None:
        from .nodes.usd import comes_from_usd
        usd_seed_rules = comes_from_usd(doc)
    if not names:
        raise MtlxError((Loc(path, 1), "nothing to render: no material, shader or output elements"))
    problems, shaders = Problems(), []
    for name in names:
        try:
            g = graph.build_graph(doc, lib, name, usd_seed_rules=usd_seed_rules)
            shaders.append(emit.emit(g))
        except MtlxError as e:
            problems.extend(e)
    if partial:
        return shaders, (MtlxError(problems.items) if problems else None)
    problems.raise_if_any()
    return shaders
