"""The compact library cache: a parsed Library written once, read back in a few milliseconds.

File: MAGIC, a checksum of the body (digest(): CRC-32, Adler-32 and length, zlib's, which every start has loaded
already; hashlib would load OpenSSL, 6 ms of a cold start), the body: marshal data (builtin types only: no code
runs reading it, unlike a pickle). The checksum finds a truncated or corrupted file; it authenticates nothing, nor
need it: a file is read only where it is a regular file of the user's own, in the user's own cache folder. The
body holds each nodedef and nodegraph as its own marshal blob; a loaded Library's tables (LazyTable) decode an
entry when it is first used, so a document that uses 60 of the 826 nodedefs decodes about 60. An entry decoded once is the same object in every table and every overlay that reaches it.

Name: library-KEY.mxlib, KEY (digest()) of the format, the fields of the document classes, the size and mtime of
the modules that read libraries, and the path, size and mtime of every library file (the wheel's, ours,
MATERIALX_SEARCH_PATH's, --library's): any change is another key, so a stale file is never read. A file
that is not ours (another owner), not a regular file, or whose digest does not match its body is ignored and
rewritten. Folder: MTLXGEN_CACHE, else $XDG_CACHE_HOME/mtlxgen, else ~/.cache/mtlxgen (never beside the
libraries: site-packages may be read-only or shared); where it cannot be written the library is parsed and
nothing is written. At most KEEP files are kept (the newest).
"""
import _thread
import marshal
import os
import stat
import zlib
from collections.abc import MutableMapping
from mtlxgen.base.records import fields

from mtlxgen.base import diagnostics, mxtypes
from mtlxgen.read import document

FORMAT = 2                  # 2: the zlib checksum (1: SHA-256)
MAGIC = b"MTLXGEN-LIB\0"
KEEP = 12                   # cache files kept in the folder (one per library set and code version)
_DIGEST = 16

# modules whose code decides what a parsed library holds: editing one makes another key
_READERS = ("read/document.py", "read/xmlreader.py", "base/mxtypes.py", "read/upgrade.py", "read/library.py",
            "read/library_cache.py", "base/diagnostics.py", "base/files.py")


def cache_dir():
    base = os.environ.get("MTLXGEN_CACHE")
    if base:
        return base
    xdg = os.environ.get("XDG_CACHE_HOME")
    root = xdg if xdg and os.path.isabs(xdg) else os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(root, "mtlxgen")


def digest(data):
    """16 bytes: CRC-32, Adler-32 and the length of `data` (a check against accidents, not an authentication)."""
    return zlib.crc32(data).to_bytes(4, "big") + zlib.adler32(data).to_bytes(4, "big") + len(data).to_bytes(8, "big")


def cache_key(files):
    parts = [b"format %d\n" % FORMAT]
    for cls in _CLASSES:
        parts.append(("%s(%s)\n" % (cls.__name__, ",".join(f.name for f in fields(cls)))).encode())
    from mtlxgen.base.files import PACKAGE as here
    for name in _READERS:
        st = os.stat(os.path.join(here, name))
        parts.append(("%s|%d|%d\n" % (name, st.st_size, st.st_mtime_ns)).encode())
    for f in files:
        st = os.stat(f)
        parts.append(("%s|%d|%d\n" % (f, st.st_size, st.st_mtime_ns)).encode("utf-8", "surrogateescape"))
    return digest(b"".join(parts)).hex()


def cache_path(files):
    return os.path.join(cache_dir(), "library-%s.mxlib" % cache_key(files))


def load(files, parse, Library):
    """The Library of `files`: from its cache file where that is sound, else parse(files), then cached.
    Library: library.Library, the class a cached body is decoded into (handed in: library.py imports this)."""
    try:
        path = cache_path(files)
    except OSError:             # a file vanished between listing and stat: parse (which then says which)
        return parse(files)
    body = _read(path)
    if body is not None:
        try:
            return _decode_library(marshal.loads(body), Library)
        except Exception:       # a sound digest over a body this code cannot read: rewritten below
            pass
    lib = parse(files)
    _write(path, lib)
    return lib


def _read(path):
    """The body of a cache file, or None where there is none, it is not a regular file of ours, or its digest
    does not match (truncated, corrupted, written by something else)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0))
    except OSError:
        return None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode) or (hasattr(os, "getuid") and st.st_uid != os.getuid()):
            return None
        with os.fdopen(fd, "rb") as f:
            fd = None
            data = f.read()
    except OSError:
        return None
    finally:
        if fd is not None:
            os.close(fd)
    head = len(MAGIC) + _DIGEST
    if len(data) < head or not data.startswith(MAGIC):
        return None
    body = data[head:]
    if digest(body) != data[len(MAGIC):head]:
        return None
    return body


def _write(path, lib):
    """Write `lib` to `path` (atomically: a reader sees the old file or the whole new one); nothing where the
    folder cannot be written or the library holds a value the format cannot carry."""
    try:
        body = marshal.dumps(_encode_library(lib), 4)
    except (ValueError, TypeError, AttributeError):
        return
    if store(path, body):
        prune(os.path.dirname(path), "library-", (".mxlib", ".pickle", ".tmp"), KEEP, keep=path)


def store(path, body):
    """Write a cache file: MAGIC, digest(body), body (atomically: a reader sees the old file or the whole new one;
    each writer, process or thread, its own temporary file). False where the folder cannot be written."""
    folder = os.path.dirname(path)
    tmp = "%s.%d.%d.tmp" % (path, os.getpid(), _thread.get_ident())
    try:
        os.makedirs(folder, mode=0o700, exist_ok=True)
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | getattr(os, "O_NOFOLLOW", 0), 0o600)
        with os.fdopen(fd, "wb") as f:
            f.write(MAGIC + digest(body) + body)
        os.replace(tmp, path)
    except OSError:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        return False
    return True


def prune(folder, prefix, suffixes, count, keep):
    """Remove all but the `count` newest files of `folder` named prefix...suffix (never `keep`)."""
    try:
        entries = []
        for n in os.listdir(folder):
            if n.startswith(prefix) and n.endswith(suffixes):
                p = os.path.join(folder, n)
                try:
                    entries.append((os.lstat(p).st_mtime, p))
                except OSError:
                    pass
        entries.sort(reverse=True)
        for _, p in entries[count:]:
            if p != keep:
                os.unlink(p)
    except OSError:
        pass


# ---------------------------------------------------------------- encoding
# Each class a tuple of its fields in declaration order; Locs (file, line, where); port dicts
# ((key, port), ...); a nodegraph's nodes ((key, node), ...); values as they are (marshal keeps tuples,
# floats, booleans and strings exactly).

_CLASSES = (document.Port, document.Node, document.NodeDef, document.NodeGraph, document.Implementation,
            document.GeomPropDef, mxtypes.StructType, diagnostics.Loc)
_PORT_DICTS = ("inputs", "outputs", "tokens")


def _plan(cls):
    """[(field name, kind)] of a class: 'loc', 'ports', 'nodes' or None (the value as it is)."""
    out = []
    for f in fields(cls):
        kind = "loc" if f.name == "loc" else "ports" if f.name in _PORT_DICTS else \
            "nodes" if (cls is document.NodeGraph and f.name == "nodes") else None
        out.append((f.name, kind))
    return out


_PLANS = {cls: _plan(cls) for cls in _CLASSES if cls is not diagnostics.Loc}


def _enc_loc(loc):
    if loc is None:
        return None
    if type(loc) is not diagnostics.Loc:
        raise TypeError("not a Loc")
    return (loc.file, loc.line, loc.where)


def _enc(obj):
    if type(obj) not in _PLANS:
        raise TypeError("cannot cache a %s" % type(obj).__name__)
    out = []
    for name, kind in _PLANS[type(obj)]:
        v = getattr(obj, name)
        if kind == "loc":
            v = _enc_loc(v)
        elif kind == "ports":
            v = tuple((k, _enc(p)) for k, p in v.items())
        elif kind == "nodes":
            v = tuple((k, _enc(n)) for k, n in v.items())
        out.append(v)
    if len(vars(obj)) != len(out):      # an attribute beyond the fields: the format cannot carry it
        raise TypeError("%s has attributes beyond its fields" % type(obj).__name__)
    return tuple(out)


def _decoder(cls):
    plan = _PLANS[cls]
    loc_at = [i for i, (_, kind) in enumerate(plan) if kind == "loc"]
    ports_at = [i for i, (_, kind) in enumerate(plan) if kind == "ports"]
    nodes_at = [i for i, (_, kind) in enumerate(plan) if kind == "nodes"]
    Loc = diagnostics.Loc

    def decode(t):
        v = list(t)
        for i in loc_at:
            if v[i] is not None:
                v[i] = Loc(*v[i])
        for i in ports_at:
            v[i] = {k: _dec_port(p) for k, p in v[i]}
        for i in nodes_at:
            v[i] = {k: _dec_node(n) for k, n in v[i]}
        return cls(*v)
    return decode


_dec_port = _decoder(document.Port)
_dec_node = _decoder(document.Node)
_dec_nodedef = _decoder(document.NodeDef)
_dec_nodegraph = _decoder(document.NodeGraph)
_dec_impl = _decoder(document.Implementation)
_dec_geomprop = _decoder(document.GeomPropDef)
_dec_struct = _decoder(mxtypes.StructType)


def _blobs(table, blobs, index):
    """{key: blob number} of a table, each distinct object one blob (shared objects stay shared)."""
    out = {}
    for k, obj in table.items():
        n = index.get(id(obj))
        if n is None:
            n = index[id(obj)] = len(blobs)
            blobs.append(marshal.dumps(_enc(obj), 4))
        out[k] = n
    return out


def _encode_library(lib):
    nd_blobs, nd_index, ng_blobs, ng_index = [], {}, [], {}
    nodedefs = _blobs(lib.nodedefs, nd_blobs, nd_index)
    by_category = {}
    for cat, lst in lib.by_category.items():
        by_category[cat] = tuple(_blobs({i: nd for i, nd in enumerate(lst)}, nd_blobs, nd_index).values())
    nodegraphs = _blobs(lib.nodegraphs, ng_blobs, ng_index)
    graph_impls = _blobs(lib.graph_impls, ng_blobs, ng_index)
    return {
        "format": FORMAT,
        "files": tuple(lib.files),
        "nodedef_blobs": tuple(nd_blobs), "nodegraph_blobs": tuple(ng_blobs),
        "nodedefs": nodedefs, "by_category": by_category, "nodegraphs": nodegraphs, "graph_impls": graph_impls,
        "implementations": {k: _enc(v) for k, v in lib.implementations.items()},
        "geompropdefs": {k: _enc(v) for k, v in lib.geompropdefs.items()},
        "unitdefs": {k: dict(v) for k, v in lib.unitdefs.items()},
        "structs": {k: _enc(v) for k, v in lib.structs.items()},
    }


class _Store:
    """The decoded entries of one cache file, shared by every table (and every copy) reading from it."""

    def __init__(self, nodedef_blobs, nodegraph_blobs):
        self.nodedef_blobs, self.nodegraph_blobs = nodedef_blobs, nodegraph_blobs
        self.nodedef_objs, self.nodegraph_objs = {}, {}

    def nodedef(self, n):
        obj = self.nodedef_objs.get(n)
        if obj is None:
            obj = self.nodedef_objs[n] = _dec_nodedef(marshal.loads(self.nodedef_blobs[n]))
        return obj

    def nodegraph(self, n):
        obj = self.nodegraph_objs.get(n)
        if obj is None:
            obj = self.nodegraph_objs[n] = _dec_nodegraph(marshal.loads(self.nodegraph_blobs[n]))
        return obj

    def category(self, numbers):
        return [self.nodedef(n) for n in numbers]


def _decode_library(body, Library):
    if body.get("format") != FORMAT:
        raise ValueError("another format")
    store = _Store(body["nodedef_blobs"], body["nodegraph_blobs"])
    return Library(
        nodedefs=LazyTable(body["nodedefs"], store.nodedef),
        by_category=LazyTable(body["by_category"], store.category),
        graph_impls=LazyTable(body["graph_impls"], store.nodegraph),
        nodegraphs=LazyTable(body["nodegraphs"], store.nodegraph),
        implementations={k: _dec_impl(v) for k, v in body["implementations"].items()},
        geompropdefs={k: _dec_geomprop(v) for k, v in body["geompropdefs"].items()},
        unitdefs={k: dict(v) for k, v in body["unitdefs"].items()},
        structs={k: _dec_struct(v) for k, v in body["structs"].items()},
        files=list(body["files"]))


class LazyTable(MutableMapping):
    """A dict-like table whose values are decoded on first use: `raw` maps each key (in order) to what
    `decode` turns into its value. Assigned values replace the raw ones; copies share the decoder (and so
    the objects it has decoded) but not their assignments."""
    __slots__ = ("_raw", "_done", "_decode")

    def __init__(self, raw, decode, done=None):
        self._raw = raw             # key -> raw entry (None once a value was assigned): the keys, in order
        self._done = done if done is not None else {}      # key -> value
        self._decode = decode

    def __getitem__(self, key):
        try:
            return self._done[key]
        except KeyError:
            raw = self._raw[key]            # KeyError: not a key
            value = self._done[key] = self._decode(raw)
            return value

    def get(self, key, default=None):
        try:
            return self._done[key]
        except KeyError:
            if key not in self._raw:
                return default
            return self[key]

    def __contains__(self, key):
        return key in self._raw

    def __setitem__(self, key, value):
        if key not in self._raw:
            self._raw[key] = None
        self._done[key] = value

    def __delitem__(self, key):
        del self._raw[key]
        self._done.pop(key, None)

    def __iter__(self):
        return iter(self._raw)

    def __len__(self):
        return len(self._raw)

    def __repr__(self):
        return "LazyTable(%d entries, %d decoded)" % (len(self._raw), len(self._done))

    def loaded_values(self):
        """The values decoded or assigned so far (what a flattening pass must see; the others are cached flat)."""
        return list(self._done.values())

    def copy(self, each=None):
        done = {k: each(v) for k, v in self._done.items()} if each else dict(self._done)
        return LazyTable(dict(self._raw), self._decode, done)

    def __reduce__(self):           # pickled (a worker process): as the plain dict it stands for
        return (dict, (dict(self.items()),))
