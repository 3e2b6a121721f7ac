"""glsl_lib files split into items (glsldeps.split), kept on disk between processes.

A process that generates its first shader splits the 20-40 glsl_lib files it pastes (9-10 ms of a cold
`mtlxgen generate` of standard_surface, docs/measuring.md); the split of a text only depends on the text and on the
splitter's code. This file keeps the splits of the texts met before: one marshal file in the library cache's folder
(read.library_cache.cache_dir(), read and written with its rules: a regular file of the user's own, its body
checked by digest, written atomically), named after the splitter's code (glsldeps.py's size and modification time:
an edited splitter reads another file). An entry is found by its text's digest and length and its file name, and
is used only where every offset it holds falls inside the text; anything else is split again. Entries are added by
`remember` (glsldeps.used_code: once for each new set of files, not once per file) and the file is written when
something was added; at most MAX_ENTRIES are kept (the file starts again from those of this process beyond that).
"""
import _thread
import marshal
import os

from mtlxgen.read import library_cache

FORMAT = 1
MAX_ENTRIES = 4096
_PREFIX = "glsl-split-"

_entries = None             # key -> entry, as read from the file (None: not read yet)
_added = {}                 # entries this process made, not yet written
_lock = _thread.allocate_lock()     # the viewer generates on two threads: one of them reads or writes these at once


# the splitter, whose code decides what a split holds (beside this module; not imported: it imports this one)
_SPLITTER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "glsldeps.py")


def _path():
    st = os.stat(_SPLITTER)
    name = "%d|%s|%d|%d" % (FORMAT, _SPLITTER, st.st_size, st.st_mtime_ns)
    return os.path.join(library_cache.cache_dir(),
                        "%s%s.bin" % (_PREFIX, library_cache.digest(name.encode("utf-8", "surrogateescape")).hex()))


def key(rel, text):
    data = text.encode("utf-8", "surrogateescape")
    return rel + "|" + library_cache.digest(data).hex()


def _loaded():
    global _entries
    if _entries is None:
        _entries = {}
        try:
            body = library_cache._read(_path())
            data = marshal.loads(body) if body is not None else None
        except (OSError, ValueError, EOFError, TypeError):
            data = None
        if isinstance(data, dict):
            _entries = data
    return _entries


def find(rel, text):
    """The stored split of `text` (glsl_lib file `rel`): (header end, ((kind, names, uses, code_start, code_end,
    line, start, end), ...)) with every offset inside the text, or None."""
    k = key(rel, text)
    with _lock:
        entry = _added.get(k) or _loaded().get(k)
    if not _sound(entry, len(text)):
        return None
    return entry


def _sound(entry, n):
    try:
        header_end, items = entry
        if not (type(header_end) is int and 0 <= header_end <= n):
            return False
        for kind, names, uses, code_start, code_end, line, start, end in items:
            if not (type(kind) is str and isinstance(names, tuple) and isinstance(uses, tuple)
                    and all(type(v) is int and 0 <= v <= n for v in (code_start, code_end, start, end))
                    and type(line) is int and all(type(x) is str for x in names + uses)):
                return False
        return True
    except (TypeError, ValueError):
        return False


def add(rel, text, lib_file):
    """Keep the split `lib_file` (a glsldeps.LibFile) of `text` until the next save()."""
    items = tuple((it.kind, tuple(sorted(it.names)), tuple(sorted(it.uses)), it.code_start, it.code_end, it.line,
                   it.start, it.end) for it in lib_file.items)
    with _lock:
        _added[key(rel, text)] = (len(lib_file.header), items)


def save():
    """Write the entries added since the last save (with those of the file, up to MAX_ENTRIES); nothing where the
    cache folder cannot be written. Saves run one at a time, so the last one written holds every entry saved."""
    with _lock:
        if not _added:
            return
        entries = dict(_loaded())
        if len(entries) + len(_added) > MAX_ENTRIES:
            entries = {}
        entries.update(_added)
        _added.clear()
        _loaded().update(entries)
        _write(entries)


def _write(entries):
    path = _path()
    if library_cache.store(path, marshal.dumps(entries, 4)):
        # the files of earlier splitter versions removed (all but the four newest)
        library_cache.prune(os.path.dirname(path), _PREFIX, (".bin", ".tmp"), 4, keep=path)
