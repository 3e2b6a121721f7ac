"""Image files through OpenImageIO: linear float arrays in, PNG (sRGB 8-bit) and EXR (linear) out."""
import os

import numpy as np

from .diagnostics import Loc, MtlxError
from .files import check_regular, write_through_temp

MAX_IMAGE_PIXELS = 2 ** 27      # 16384 x 8192: a lat-long environment; a bigger header is a decompression bomb


def srgb_encode(linear):
    c = np.clip(linear, 0.0, None)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def to_srgb8(img):
    """Linear RGB(A) float image -> sRGB 8-bit RGB(A) (alpha stays linear)."""
    out = np.array(img, dtype=np.float64, copy=True)
    out[..., :3] = srgb_encode(out[..., :3])
    return (np.clip(out, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)


def image_header(path):
    """(format name, width, height, 8-bit) from an image file's header, without decoding it; None where the file
    does not read as an image."""
    import OpenImageIO as oiio
    inp = oiio.ImageInput.open(path)
    if inp is None:
        oiio.geterror()
        return None
    try:
        spec = inp.spec()
        return inp.format_name(), spec.width, spec.height, spec.format == oiio.UINT8
    finally:
        inp.close()


def read_image(path):
    """Image file -> float32 array (rows top first, channels last). Raises MtlxError if unreadable."""
    import OpenImageIO as oiio
    # textures are decoded, never copied, so any regular file will do; devices and /proc would hang or leak
    check_regular(path, Loc(path, 0), "image file")
    # colour as stored: straight (unassociated) alpha, as texture files mean it and as USD's rules read it
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    buf = oiio.ImageBuf(path, 0, 0, config)
    if buf.has_error:
        raise MtlxError((Loc(path, 0), "cannot read image: %s" % buf.geterror().strip()))
    spec = buf.spec()       # the header only: refuse sizes that would exhaust memory before decoding
    if spec.width * spec.height * max(spec.depth, 1) > MAX_IMAGE_PIXELS or spec.nchannels > 64:
        raise MtlxError((Loc(path, 0), "image of %dx%d pixels, %d channels is larger than %d megapixels"
                                      % (spec.width, spec.height, spec.nchannels, MAX_IMAGE_PIXELS // 10 ** 6)))
    px = buf.get_pixels(oiio.FLOAT)
    if px is None or buf.has_error:
        raise MtlxError((Loc(path, 0), "cannot read image: %s" % buf.geterror().strip()))
    px = np.asarray(px, dtype=np.float32)
    if px.ndim == 2:
        px = px[..., None]
    return px


def write_image(path, img):
    """Write a linear float image: .png/.jpg as sRGB 8-bit, .exr/.hdr as linear half/float."""
    import OpenImageIO as oiio
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
            raise MtlxError((Loc(path, 0), "cannot write image: %s" % " ".join(buf.geterror().split())))
    write_through_temp(path, write)
    return path
