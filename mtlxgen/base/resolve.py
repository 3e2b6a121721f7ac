"""Resolve file references the way MaterialX does: the document's folder, then search paths."""
import os


def search_paths(extra=()):
    env = os.environ.get("MATERIALX_SEARCH_PATH", "")
    return [p for p in env.split(os.pathsep) if p] + list(extra)


def resolve_file(name, doc_path, extra=()):
    """Absolute path of an existing file, or None. `<UDIM>`-style tokens are left to the caller."""
    if not name:
        return None
    if os.path.isabs(name):
        return name if os.path.lexists(name) else None
    for base in search_folders(doc_path, extra):
        cand = os.path.join(base, name)
        if os.path.lexists(cand):       # a dangling link or a loop too: found, and refused by whoever reads it
            return os.path.abspath(cand)
    return None


def search_folders(doc_path, extra=()):
    """The folders a relative file name is looked for in, in order: the document's, the search paths, then the
    folders above the document's."""
    doc_dir = os.path.dirname(os.path.abspath(doc_path))
    return [doc_dir] + search_paths(extra) + _ancestors(doc_dir)


def _ancestors(folder):
    """The folders above the document's: a resource tree's root (which MaterialX applications put on
    the search path, e.g. the folder holding resources/Images) is usually one of them."""
    out, cur = [], os.path.dirname(folder)
    while cur and cur != os.path.dirname(cur):
        out.append(cur)
        cur = os.path.dirname(cur)
    return out
