"""Reading files a document names: which files may be read, and reads that cannot hang or exhaust memory.

Documents come from strangers (downloaded assets, pull requests), so two rules apply:

- Bytes copied into the output (xi:include'd documents, <implementation file=> GLSL) come only from
  files inside the *allowed roots*: the document's folder tree, the search paths (MATERIALX_SEARCH_PATH
  and --library folders) and the data libraries. Symlinks are resolved first, so a link pointing out
  of the tree is outside.
- Every file read (documents, GLSL, images, IES profiles) must be a regular file: devices, FIFOs,
  sockets and anything under /proc, /sys or /dev are refused before opening (reading /dev/zero never
  ends, /dev/stdin blocks, /proc/self/environ holds secrets). Text reads take at most a fixed size.
"""
import os
import stat

from .diagnostics import MtlxError

MAX_TEXT_BYTES = 32 * 2 ** 20           # one .mtlx, GLSL or IES file: far above any real one
SYSTEM_FOLDERS = ("/proc", "/sys", "/dev")

_KINDS = ((stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO"),
          (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a folder"))


def quoted(name):
    """A name from a document as problem lines show it: quoted, control characters escaped (one line)."""
    return repr(name)


def _kind(mode):
    for test, name in _KINDS:
        if test(mode):
            return name
    return "not a regular file"


def _under(path, root):
    return path == root or path.startswith(root.rstrip(os.sep) + os.sep)


def regular_file_problem(path):
    """Why `path` may not be read as a file (a short phrase), or None when it is a regular file."""
    real = os.path.realpath(path)
    for folder in SYSTEM_FOLDERS:
        if _under(real, folder):
            return "a system file (under %s)" % folder
    try:
        st = os.stat(real)
    except OSError as e:
        return "unreadable (%s)" % (e.strerror or e)
    if not stat.S_ISREG(st.st_mode):
        return _kind(st.st_mode)
    return None


def check_regular(path, loc, what):
    """Raise MtlxError at `loc` unless `path` is a regular file outside /proc, /sys and /dev."""
    problem = regular_file_problem(path)
    if problem is not None:
        raise MtlxError((loc, "%s is %s" % (what, problem)))


def read_bounded(path, loc, what, limit=None):
    """The bytes of a regular file of at most `limit` (MAX_TEXT_BYTES) bytes; MtlxError at `loc` otherwise."""
    limit = MAX_TEXT_BYTES if limit is None else limit
    check_regular(path, loc, what)
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags)
    except OSError as e:
        raise MtlxError((loc, "cannot read %s: %s" % (what, e.strerror or e))) from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):       # swapped for something else between the check and the open
            raise MtlxError((loc, "%s is %s" % (what, _kind(st.st_mode))))
        chunks, size = [], 0
        while size <= limit:
            chunk = os.read(fd, min(1 << 20, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as e:
        raise MtlxError((loc, "cannot read %s: %s" % (what, e.strerror or e))) from None
    finally:
        os.close(fd)
    if size > limit:
        raise MtlxError((loc, "%s is larger than %d MB" % (what, limit // 2 ** 20)))
    return b"".join(chunks)


def materialx_library_root():
    """MaterialX/libraries of the installed wheel, or None."""
    try:
        import importlib.util
        spec = importlib.util.find_spec("MaterialX")
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    for loc in spec.submodule_search_locations:
        cand = os.path.join(loc, "libraries")
        if os.path.isdir(cand):
            return cand
    return None


def glsl_lib_root():
    """Our GLSL library: glsl_lib/ beside the package in a checkout, or installed as package data."""
    here = os.path.dirname(os.path.abspath(__file__))
    for cand in (os.path.join(os.path.dirname(here), "glsl_lib"), os.path.join(here, "glsl_lib")):
        if os.path.isdir(cand):
            return cand
    raise RuntimeError("glsl_lib not found next to the mtlxgen package")


def library_roots():
    """The folders of the data libraries (the materialx wheel's and ours)."""
    roots = [materialx_library_root()]
    try:
        roots.append(glsl_lib_root())
    except RuntimeError:
        pass
    return [r for r in roots if r]


def allowed_roots(doc_path, search_paths=(), extra=()):
    """Real paths of the folders whose files may be copied into output for the document at doc_path."""
    roots = [os.path.dirname(os.path.abspath(doc_path)), *search_paths, *library_roots(), *extra]
    out = []
    for r in roots:
        real = os.path.realpath(r)
        if os.path.isfile(real):       # a --library entry naming one file: that file's folder
            real = os.path.dirname(real)
        if real not in out:
            out.append(real)
    return out


def is_inside(path, roots):
    real = os.path.realpath(path)
    return any(_under(real, root) for root in roots)


def check_inside(path, roots, loc, what):
    """Raise MtlxError at `loc` unless `path` (symlinks resolved) lies inside one of `roots`."""
    if not is_inside(path, roots):
        raise MtlxError((loc, "%s is outside the document's folder and the search paths" % what))


GLSL_EXTENSIONS = (".glsl", ".frag", ".vert")


def read_implementation(full, name, loc, doc_path):
    """Text of an <implementation file=> GLSL source, which goes verbatim into the shader: only a GLSL
    file inside the document's folder, the search paths, the data libraries, or the folder of the
    (already admitted) file declaring it."""
    from .resolve import search_paths
    what = "implementation file %s" % quoted(name)
    if not full.lower().endswith(GLSL_EXTENSIONS):
        raise MtlxError((loc, "%s is not a GLSL source (%s)" % (what, ", ".join(GLSL_EXTENSIONS))))
    roots = allowed_roots(doc_path, search_paths(), extra=[os.path.dirname(os.path.abspath(loc.file))])
    if not os.path.lexists(full):
        raise MtlxError((loc, "%s: no such file" % what))
    check_inside(full, roots, loc, what)
    data = read_bounded(full, loc, what)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = None
    if text is None or "\0" in text:
        raise MtlxError((loc, "%s is not UTF-8 text" % what))
    return text
