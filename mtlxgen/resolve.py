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
        return name if os.path.exists(name) else None
    for base in [os.path.dirname(os.path.abspath(doc_path))] + search_paths(extra):
        cand = os.path.join(base, name)
        if os.path.exists(cand):
            return os.path.abspath(cand)
    return None
