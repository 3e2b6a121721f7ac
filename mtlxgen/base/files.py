"""Reading files a document names: which files may be read, and reads that cannot hang or exhaust memory.

Documents come from strangers (downloaded assets, pull requests), so two rules apply:

- Bytes copied into the output (xi:include'd documents, <implementation file=> GLSL) come only from
  files inside the *allowed roots*: the document's folder tree, the search paths (MATERIALX_SEARCH_PATH
  and --library folders) and the data libraries. Symlinks are resolved first, so a link pointing out
  of the tree is outside.
- Every file read (documents, GLSL, images, IES profiles) must be a regular file: devices, FIFOs,
  sockets and anything under /proc, /sys or /dev are refused before opening (reading /dev/zero never
  ends, /dev/stdin blocks, /proc/self/environ holds secrets), and so is a file larger than its kind's
  size cap (MAX_BYTES), checked on the file's size before any library opens it.
- A document saved directly in a shared folder anyone may write to (/tmp: world-writable with the sticky
  bit) or in / does not make that whole tree an allowed root: there, only files owned by the document's
  owner are admitted through the document's folder.

Every file we write goes through write_atomic / write_through_temp: a temporary file in the same folder,
fsync, then a rename over the target, so a reader never sees half a file, a crash leaves the old bytes, and
an existing symlink at the output path is replaced, never followed. New files get ordinary modes
(0666 less the umask); a file written over keeps its mode (and, where permitted, its owner).
"""
import errno
import os
import stat

from mtlxgen.base.diagnostics import MtlxError

MAX_TEXT_BYTES = 32 * 2 ** 20           # one .mtlx, GLSL or IES file: far above any real one
# size caps per kind of file, checked on the file's size before anything reads it (a 1 GB sparse file named
# as a texture would otherwise be read to its end by every format reader)
MAX_BYTES = {
    "text": MAX_TEXT_BYTES,             # .mtlx, GLSL, IES
    "image": 512 * 2 ** 20,             # a texture or environment file (a 16k float EXR is ~1.5 GB
                                        # uncompressed, but files that size are compressed well under this)
    "usd": 1024 * 2 ** 20,              # a USD layer or .usdz package
    "json": 64 * 2 ** 20,               # results.json, manifests, rigs
}
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


def _megabytes(n):
    return "%d MB" % (n // 2 ** 20) if n >= 2 ** 20 and n % 2 ** 20 == 0 else "{:,} bytes".format(n)


def regular_file_problem(path, max_bytes=None):
    """Why `path` may not be read as a file (a short phrase), or None when it is a regular file (of at most
    `max_bytes` bytes, where given: a key of MAX_BYTES or a number)."""
    if isinstance(max_bytes, str):
        max_bytes = MAX_BYTES[max_bytes]
    try:
        os.lstat(path)
    except OSError as e:
        return "missing (no such file)" if isinstance(e, FileNotFoundError) else "unreadable (%s)" % (e.strerror or e)
    try:
        real = os.path.realpath(path, strict=True)
    except OSError as e:
        if isinstance(e, FileNotFoundError):
            return "a dangling symbolic link"
        if e.errno == 40:           # ELOOP
            return "a symbolic link loop"
        return "unreadable (%s)" % (e.strerror or e)
    for folder in SYSTEM_FOLDERS:
        if _under(real, folder):
            return "a system file (under %s)" % folder
    try:
        st = os.stat(real)
    except OSError as e:
        return "unreadable (%s)" % (e.strerror or e)
    if not stat.S_ISREG(st.st_mode):
        return _kind(st.st_mode)
    if max_bytes is not None and st.st_size > max_bytes:
        return "larger than %s (%s)" % (_megabytes(max_bytes), _megabytes(st.st_size))
    return None


def check_regular(path, loc, what, max_bytes=None):
    """Raise MtlxError at `loc` unless `path` is a regular file outside /proc, /sys and /dev (and of at most
    `max_bytes` bytes: a MAX_BYTES key or a number)."""
    problem = regular_file_problem(path, max_bytes)
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


# the mtlxgen package's folder (its stages are subpackages of it)
PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def glsl_lib_root():
    """Our GLSL library: glsl_lib/ beside the package in a checkout, or installed as package data."""
    here = PACKAGE
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


class SharedRoot(str):
    """An allowed root that is a shared folder (world-writable with the sticky bit, like /tmp, or /): only
    files owned by `owner` (the document's owner) are inside it."""

    def __new__(cls, path, owner):
        obj = super().__new__(cls, path)
        obj.owner = owner
        return obj


def is_shared_folder(folder):
    """True for / and for a folder anyone may write to (world-writable, as /tmp and /var/tmp are)."""
    try:
        st = os.stat(folder)
    except OSError:
        return False
    return os.path.realpath(folder) == os.sep or bool(st.st_mode & stat.S_IWOTH)


def allowed_roots(doc_path, search_paths=(), extra=()):
    """Real paths of the folders whose files may be copied into output for the document at doc_path. The
    document's own folder, where it is a shared folder (/tmp, /), is a SharedRoot: only files of the
    document's owner count as inside it."""
    doc_folder = os.path.realpath(os.path.dirname(os.path.abspath(doc_path)))
    roots = [doc_folder, *search_paths, *library_roots(), *extra]
    out = []
    for r in roots:
        real = os.path.realpath(r)
        if os.path.isfile(real):       # a --library entry naming one file: that file's folder
            real = os.path.dirname(real)
        if is_shared_folder(real):
            if real != doc_folder:
                continue               # a search path or declaring file's folder in /tmp admits nothing more
            try:
                real = SharedRoot(real, os.stat(doc_path).st_uid)
            except OSError:
                continue
        if real not in out:
            out.append(real)
    return out


def _inside_root(real, root):
    if not _under(real, root):
        return False
    owner = getattr(root, "owner", None)
    if owner is None:
        return True
    try:
        return os.stat(real).st_uid == owner
    except OSError:
        return False


def is_inside(path, roots):
    real = os.path.realpath(path)
    return any(_inside_root(real, root) for root in roots)


def check_inside(path, roots, loc, what):
    """Raise MtlxError at `loc` unless `path` (symlinks resolved) lies inside one of `roots`."""
    if not is_inside(path, roots):
        raise MtlxError((loc, "%s is outside the document's folder and the search paths" % what))


GLSL_EXTENSIONS = (".glsl", ".frag", ".vert")


def read_implementation(full, name, loc, doc_path):
    """Text of an <implementation file=> GLSL source, which goes verbatim into the shader: only a GLSL
    file inside the document's folder, the search paths, the data libraries, or the folder of the
    (already admitted) file declaring it."""
    from mtlxgen.base.resolve import search_paths
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


# ------------------------------------------------------------------ writing

def _new_file_mode():
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


# how _temp_beside opens its file: created here or not at all (O_EXCL), never through a link, not inherited
_TEMP_FLAGS = (os.O_RDWR | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_CLOEXEC", 0)
               | getattr(os, "O_BINARY", 0))


def _temp_beside(path, suffix=""):
    """(fd, temp path) of a new, empty file in path's folder (O_EXCL: never an existing file or link), mode 0600
    until _finish gives it its own: what tempfile.mkstemp does, without importing tempfile (and shutil, bz2, lzma
    and random with it: 12 ms of every command's start)."""
    folder = os.path.dirname(os.path.abspath(path)) or "."
    stem = os.path.join(folder, "." + os.path.basename(path)[:80] + ".")
    for _ in range(100):
        name = stem + os.urandom(6).hex() + (suffix or ".tmp")
        try:
            return os.open(name, _TEMP_FLAGS, 0o600), name
        except FileExistsError:         # another writer's name (48 random bits): another one
            continue
    raise FileExistsError(errno.EEXIST, "no unused temporary file name", folder)


def _finish(tmp, path, mode, durable=True):
    """Give the temp file its mode (and the replaced file's owner), then rename it over `path`."""
    try:
        old = os.lstat(path)
    except OSError:
        old = None
    keep = old is not None and stat.S_ISREG(old.st_mode)
    os.chmod(tmp, stat.S_IMODE(old.st_mode) if keep and mode is None else
             (_new_file_mode() if mode is None else mode))
    if keep and hasattr(os, "chown"):
        try:
            os.chown(tmp, old.st_uid, old.st_gid)
        except OSError:
            pass                        # not permitted (not root): the writer's own, as any editor leaves it
    os.replace(tmp, path)               # a symlink at `path` is replaced, not followed
    if not durable:
        return
    try:
        dfd = os.open(os.path.dirname(os.path.abspath(path)) or ".", os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(dfd)
    except OSError:
        pass
    finally:
        os.close(dfd)


def _named(error, path):
    """An OSError of a write about `path` (not the temporary file beside it), so its line names the output."""
    if isinstance(error, OSError) and error.filename is not None and error.filename != path:
        return OSError(error.errno, error.strerror or str(error), path)
    return error


def write_atomic(path, data, mode=None, durable=True):
    """Write `data` (bytes, or str as UTF-8) to `path` all at once: a temporary file beside it, fsync, rename.
    A crash leaves the old file whole; a symlink at `path` is replaced by the file, never followed. `mode`:
    permission bits; default: the replaced regular file's, else 0666 less the umask. durable=False skips the
    fsyncs (a reader still never sees half a file): for scratch files and outputs made again by running the
    command again, where thousands of fsyncs would cost more than the work (glslvalidate's stage files)."""
    if isinstance(data, str):
        data = data.encode("utf-8")

    def write(tmp):
        with open(tmp, "wb") as f:
            f.write(data)
    return write_through_temp(path, write, mode, durable)


def write_through_temp(path, writer, mode=None, durable=True):
    """write_atomic for a writer of files (OpenImageIO, or write_atomic's own): writer(temp path) writes a file
    whose name ends as `path` does (the format follows the extension); then it is flushed to disk (durable) and
    renamed over `path`."""
    try:
        fd, tmp = _temp_beside(path, suffix=".tmp" + os.path.splitext(path)[1])
    except OSError as e:
        raise _named(e, path) from None
    os.close(fd)
    try:
        writer(tmp)
        if durable:
            with open(tmp, "rb") as f:
                os.fsync(f.fileno())
        _finish(tmp, path, mode, durable)
    except BaseException as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise _named(e, path) from None
    return path
