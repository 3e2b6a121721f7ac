"""Image files through OpenImageIO: linear float arrays in, PNG (sRGB 8-bit) and EXR (linear) out.

Image files come from strangers, so a read is bounded before anything is decoded:

- the file must be a regular file of at most files.MAX_BYTES["image"] bytes (files.check_regular, before
  OpenImageIO opens it: a FIFO would block, a 1 GB sparse file would be read to its end);
- its header must describe one 2-D image of at most MAX_IMAGE_PIXELS pixels (16384 x 8192, a lat-long
  environment) in tiles (if tiled) of at most MAX_TILE_BYTES decoded;
- only the first MAX_CHANNELS (4) channels are decoded, into 32-bit floats, band by band (a band of rows at a
  time, never the whole file at once), and what is decoded, pixels x channels x 4 bytes, must fit a budget
  (MAX_DECODED_BYTES unless the caller gives one). A reader that may reduce (the renderer's textures and
  environments) box-filters the image by the smallest power of two that fits instead, band by band as it is read,
  as a renderer with a texture memory budget binds a lower level of detail;
- whatever a decoder writes on stderr itself (libpng does) is caught: a file that does not read is one line
  naming it, with the decoder's first meaningful message.
"""
import os
import tempfile
import threading
from contextlib import contextmanager

import numpy as np

from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.files import check_regular, regular_file_problem, write_through_temp

MAX_IMAGE_PIXELS = 2 ** 27      # 16384 x 8192: a lat-long environment; a bigger header is a decompression bomb
MAX_CHANNELS = 4                # channels decoded (RGBA); any others are not read
MAX_DECODED_BYTES = 2 ** 29     # 512 MB of float32: 8192 x 4096 RGBA, or 8192 x 5461 RGB
MAX_TILE_BYTES = 2 ** 28        # one tile of all its channels as float32: decoded whole by the reader
BAND_BYTES = 2 ** 25            # a read call: rows (or tiles) of at most this many bytes of all channels as float32


def srgb_encode(linear):
    c = np.clip(linear, 0.0, None)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def to_srgb8(img):
    """Linear RGB(A) float image -> sRGB 8-bit RGB(A) (alpha stays linear); NaN is written as 0."""
    out = np.array(img, dtype=np.float64, copy=True)
    out[..., :3] = srgb_encode(out[..., :3])
    return (np.nan_to_num(np.clip(out, 0.0, 1.0), nan=0.0) * 255.0 + 0.5).astype(np.uint8)


# ---------------------------------------------------------------- decoder messages

_STDERR_LOCK = threading.Lock()
_STDERR = {"depth": 0, "saved": None, "scratch": None}


@contextmanager
def captured_stderr():
    """Whatever is written to file descriptor 2 inside the block (libraries write there themselves: libpng's
    "libpng error: ...", USD's warnings), kept out of the process's stderr; the list yielded receives the lines
    written meanwhile at the end. Blocks may nest and overlap across threads: the first one in sends fd 2 to a
    scratch file, the last one out puts it back."""
    import sys
    lines = []
    with _STDERR_LOCK:
        if _STDERR["depth"] == 0:
            try:
                sys.stderr.flush()
                saved = os.dup(2)
            except (OSError, ValueError):
                saved = None
            if saved is not None:
                scratch = tempfile.TemporaryFile()
                os.dup2(scratch.fileno(), 2)
                _STDERR.update(saved=saved, scratch=scratch)
        _STDERR["depth"] += 1
        scratch = _STDERR["scratch"]
        start = os.fstat(scratch.fileno()).st_size if scratch is not None else 0
    try:
        yield lines
    finally:
        with _STDERR_LOCK:
            if scratch is not None:
                end = os.fstat(scratch.fileno()).st_size
                data = os.pread(scratch.fileno(), min(end - start, 1 << 16), start) if end > start else b""
                lines.extend(data.decode("utf-8", "replace").splitlines())
            _STDERR["depth"] -= 1
            if _STDERR["depth"] == 0 and _STDERR["saved"] is not None:
                os.dup2(_STDERR["saved"], 2)
                os.close(_STDERR["saved"])
                _STDERR["scratch"].close()
                _STDERR.update(saved=None, scratch=None)


_GENERIC = ("png library error", "png read error", "error", "")


def first_message(*texts):
    """The first meaningful line of decoder messages (OpenImageIO's are often several lines, the last ones
    generic): its first sentence, without the library prefix libpng gives it."""
    for text in texts:
        for line in (text or "").splitlines():
            line = " ".join(line.split())
            for prefix in ("libpng error:", "libpng warning:"):
                if line.lower().startswith(prefix):
                    line = line[len(prefix):].strip()
            if line.lower().rstrip(".:") in _GENERIC:
                continue
            head, sep, tail = line.partition(". ")
            return head.rstrip(".") if sep and tail[:1].isupper() else line.rstrip(".")
    return "unknown error"


def _oiio_errors(*objects):
    """Pending error text of OpenImageIO objects and of the library (reading it clears it, so that nothing is
    left pending when the process exits)."""
    import OpenImageIO as oiio
    texts = []
    for obj in objects:
        if obj is not None:
            try:
                texts.append(obj.geterror())
            except Exception:
                pass
    texts.append(oiio.geterror())
    return "\n".join(t for t in texts if t)


# ---------------------------------------------------------------- headers

def _config(associated):
    import OpenImageIO as oiio
    config = oiio.ImageSpec()
    if not associated:      # colour as stored: straight (unassociated) alpha, as texture files mean it
        config.attribute("oiio:UnassociatedAlpha", 1)
    return config


NOT_UTF8 = "named by a path that is not UTF-8 text (OpenImageIO opens no such path: rename it)"


def _utf8(path):
    """Whether OpenImageIO can take `path`: a name in another encoding is held with surrogates, no UTF-8 text."""
    try:
        path.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _open(path, associated, lines):
    """(ImageInput, its spec), or (None, why: "not an image (...)") where the file does not read as one."""
    import OpenImageIO as oiio
    if not _utf8(path):
        return None, NOT_UTF8
    inp = oiio.ImageInput.open(path, _config(associated))
    if inp is None:
        return None, "not an image (%s)" % first_message(_oiio_errors(), "\n".join(lines))
    return inp, inp.spec()


def _header_problem(spec):
    """Why an image of this spec is not read (a phrase), or None."""
    if spec.deep:
        return "a deep image (samples per pixel): only flat images are read"
    if spec.depth > 1:
        return "a volume image (%d slices): only 2-D images are read" % spec.depth
    if spec.width < 1 or spec.height < 1 or spec.nchannels < 1:
        return "an image of %dx%d pixels, %d channels: nothing to read" % (spec.width, spec.height, spec.nchannels)
    if spec.width * spec.height > MAX_IMAGE_PIXELS:
        return "an image of %dx%d pixels, larger than %d megapixels" % (spec.width, spec.height,
                                                                       MAX_IMAGE_PIXELS // 10 ** 6)
    if spec.tile_width and spec.tile_width * spec.tile_height * spec.nchannels * 4 > MAX_TILE_BYTES:
        return "an image in tiles of %dx%d pixels, %d channels: a tile larger than %d MB decoded" % (
            spec.tile_width, spec.tile_height, spec.nchannels, MAX_TILE_BYTES // 2 ** 20)
    return None


def image_header(path):
    """(format name, width, height, 8-bit) from an image file's header, without decoding it; None where the file
    is not a regular file (of at most the image size cap) or does not read as an image."""
    if regular_file_problem(path, "image") is not None or not _utf8(path):
        return None
    import OpenImageIO as oiio
    with captured_stderr():
        inp = oiio.ImageInput.open(path)
        if inp is None:
            _oiio_errors()
            return None
        try:
            spec = inp.spec()
            return inp.format_name(), spec.width, spec.height, spec.format == oiio.UINT8
        finally:
            inp.close()
            _oiio_errors(inp)


def image_problem(path):
    """Why the file at `path` cannot be bound as an image (a phrase: "a FIFO", "not an image (...)"), or None.
    Reads the header only: a file whose pixels are damaged still fails when it is decoded."""
    why = regular_file_problem(path, "image")
    if why is not None:
        return why
    with captured_stderr() as lines:
        inp, spec = _open(path, False, lines)
        if inp is None:
            return spec
        try:
            return _header_problem(spec)
        finally:
            inp.close()
            _oiio_errors(inp)


# ---------------------------------------------------------------- reading

def reduction(width, height, channels, budget):
    """The smallest power of two f for which a width x height image of `channels` float32 channels, box-filtered
    f x f (edges averaged over what is there), fits `budget` bytes."""
    f = 1
    while -(-width // f) * -(-height // f) * channels * 4 > budget and (f < width or f < height):
        f *= 2
    return f


def _box(block, f):
    """block (n, w, c) averaged over f x f squares (those at the far edges over the pixels they hold): sums of f
    strided views along each axis (a pass over the band per step, no reduction over a strided axis)."""
    for axis in (0, 1):
        n = block.shape[axis]
        count = np.minimum(f, n - np.arange(0, n, f)).astype(np.float32)
        take = lambda k: block[k::f] if axis == 0 else block[:, k::f]
        total = take(0).copy()
        for k in range(1, f):
            part = take(k)
            if axis == 0:
                total[:len(part)] += part
            else:
                total[:, :part.shape[1]] += part
        block = total / (count[:, None, None] if axis == 0 else count[None, :, None])
    return block


def read_image(path, loc=None, what=None, budget=None, reduce=False, associated=False):
    """Image file -> float32 array (rows top first, channels last: at most MAX_CHANNELS, the file's first ones).

    loc, what: where and as what a problem is reported (default: the file itself, as "image file" or "file").
    budget: bytes the decoded array may take (MAX_DECODED_BYTES). reduce: an image over the budget is box-filtered
    down by a power of two as it is read, rather than refused. associated: colour multiplied by alpha, as
    OpenImageIO reads files unless told otherwise (default: straight alpha, as texture files store it). Raises
    MtlxError, one line."""
    loc = loc or Loc(path, 0)
    budget = MAX_DECODED_BYTES if budget is None else budget
    # textures are decoded, never copied, so any regular file will do; devices, FIFOs and /proc would hang or
    # leak, and a huge (or sparse) file would be read to its end before any format reader gives up
    check_regular(path, loc, what or "image file", "image")
    said = what
    what = what or "file"
    with captured_stderr() as lines:
        inp, spec = _open(path, associated, lines)
        if inp is None:
            raise MtlxError((loc, "%s is %s" % (what, spec)))
        try:
            problem = _header_problem(spec)
            if problem is not None:     # "FILE:0: image of WxH pixels, ..." where the file is the subject
                raise MtlxError((loc, "%s is %s" % (said, problem) if said else problem.split(" ", 1)[1]))
            channels = min(spec.nchannels, MAX_CHANNELS)
            f = reduction(spec.width, spec.height, channels, budget) if reduce else 1
            if f == 1 and spec.width * spec.height * channels * 4 > budget:
                raise MtlxError((loc, "%s is an image of %dx%d pixels, %d channels: %d MB decoded, more than the "
                                      "%d MB a read may take" % (what, spec.width, spec.height, channels,
                                                                 spec.width * spec.height * channels * 4 // 2 ** 20,
                                                                 budget // 2 ** 20)))
            out = _decode(inp, spec, channels, f)
            if out is None:
                raise MtlxError((loc, "%s does not decode as an image (%s)"
                                 % (what, first_message(_oiio_errors(inp), "\n".join(lines)))))
        finally:
            inp.close()
            _oiio_errors(inp)
    return out


def _decode(inp, spec, channels, f):
    """The image's first `channels` channels as float32 (h/f, w/f, channels), band by band; None where a read
    fails (the reader's error is pending)."""
    w, h = spec.width, spec.height
    tw, th = (spec.tile_width, spec.tile_height) if spec.tile_width else (0, 0)
    if tw:          # whole tiles: a band of tile rows, as many tile columns a read as fit BAND_BYTES
        unit_x = _lcm(tw, f)
        band = _lcm(th, f)
        span = max(unit_x, BAND_BYTES // (band * spec.nchannels * 4) // unit_x * unit_x)
    else:           # scanlines: as many rows a read as fit BAND_BYTES, whole rows
        band = max(f, BAND_BYTES // (w * spec.nchannels * 4) // f * f)
        span = w
    fmt, scale = _stored_as(spec)
    out = np.empty((-(-h // f), -(-w // f), channels), dtype=np.float32)
    for y0 in range(0, h, band):
        y1 = min(h, y0 + band)
        for x0 in range(0, w, span):
            x1 = min(w, x0 + span)
            if tw:
                px = inp.read_tiles(0, 0, spec.x + x0, spec.x + x1, spec.y + y0, spec.y + y1, spec.z, spec.z + 1,
                                    0, channels, fmt)
            else:
                px = inp.read_scanlines(0, 0, spec.y + y0, spec.y + y1, spec.z, 0, channels, fmt)
            if px is None or inp.has_error:
                return None
            px = np.asarray(px).reshape(y1 - y0, x1 - x0, channels)
            if px.dtype != np.float32:      # 8-bit, 16-bit or half, as stored: to float as OpenImageIO converts
                px = px.astype(np.float32)
                if scale != 1.0:
                    px *= scale
            if f == 1:
                out[y0:y1, x0:x1] = px
            else:
                out[y0 // f:-(-y1 // f), x0 // f:-(-x1 // f)] = _box(px, f)
            del px
    return out


def _stored_as(spec):
    """(format to read in, float32 factor to floats): 8-bit, 16-bit and half channels (all of one format) are read
    as stored and made floats here, as OpenImageIO makes them (x * float32(1 / 255)); others as floats."""
    import OpenImageIO as oiio
    if not list(spec.channelformats or ()):
        for fmt, scale in ((oiio.UINT8, 1.0 / 255.0), (oiio.UINT16, 1.0 / 65535.0), (oiio.HALF, 1.0)):
            if spec.format == fmt:
                return fmt, np.float32(scale)
    return oiio.FLOAT, 1.0


def _lcm(a, b):
    import math
    return a * b // math.gcd(a, b)


def write_image(path, img):
    """Write a linear float image: .png/.jpg as sRGB 8-bit, .exr/.hdr as linear half/float."""
    import OpenImageIO as oiio
    if not _utf8(os.path.abspath(path)):
        raise MtlxError((Loc(path, 0), "cannot write image: %s" % NOT_UTF8.replace("opens", "writes")))
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    img = np.ascontiguousarray(img)
    h, w, c = img.shape
    ext = os.path.splitext(path)[1].lower()
    if ext in (".exr", ".hdr"):
        spec = oiio.ImageSpec(w, h, c, oiio.HALF if ext == ".exr" else oiio.FLOAT)
        data = img.astype(np.float32)
    else:
        spec = oiio.ImageSpec(w, h, c, oiio.UINT8)
        spec.attribute("oiio:UnassociatedAlpha", 1)     # write the bytes as given: no division by alpha
        data = img if img.dtype == np.uint8 else to_srgb8(img)
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray(data))

    def write(tmp):         # through a temporary file and a rename: a symlink at `path` is replaced, not followed
        if not buf.write(tmp, fileformat=ext.lstrip(".")):
            # a name no format takes leaves OpenImageIO's global error (printed at exit unless taken), naming tmp
            why = " ".join((buf.geterror() or oiio.geterror()).replace(tmp, path).split())
            raise MtlxError((Loc(path, 0), "cannot write image: %s" % why))
    write_through_temp(path, write)
    return path
