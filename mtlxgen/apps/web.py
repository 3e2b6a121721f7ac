"""mtlxgen web: a self-contained WebGL2 page per element that draws what `mtlxgen render` draws.

The page holds everything it needs, so it works opened from file:// with no network: the element's GLSL ES
3.00 shaders (generate --target essl) and manifest, render's sphere, the environment's full mip chain and its
irradiance map, and each texture's decoded pixels with their mip chains, base64 in a JSON block; the viewer
(web_assets/viewer.js) is inlined. The page draws like render.Renderer: linear radiance into a float
framebuffer (EXT_color_buffer_float), cleared to transparent black, depth-tested, no culling or blending; then
an encode pass writes sRGB 8-bit with alpha as is into the canvas (images.to_srgb8), so the canvas holds the
bytes render's PNG holds. Textures and the environment carry the mip chain render's GL build_mipmaps makes
(mip_chain: bilinear at each texel's centre, a 2x2 box where sizes are even), wrap repeat, trilinear.
Drag orbits, the wheel zooms, a double click returns to render's camera.

Documents come from strangers: only files the manifest resolves are read, through images.read_image (regular
files only, decoded, never copied: the page holds pixels, no byte of the file itself), and what a page embeds
is bounded (MAX_TEXTURE_PIXELS, MAX_ENV_PIXELS). Text from the document (the element's name, a texture's file
name, uniform names, the shaders' comments) is data: HTML text through escape.html_text, the data block JSON
through escape.json_in_script (valid JSON that no `</script>` or `<!--` in a string can break out of). The page
is written through files.write_atomic.
"""
import base64
import os
import re

import numpy as np

from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.draw.environment import mip_chain  # environment.py's recipe: what render's GL mips hold
from mtlxgen.base.escape import html_text, json_in_script

ASSETS = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "web_assets")
MAX_TEXTURE_PIXELS = 2 ** 22            # 2048 x 2048: one texture a page embeds
MAX_TEXTURES_PIXELS = 2 ** 24           # all of a page's textures together
MAX_ENV_PIXELS = 2 ** 21                # a 2048 x 1024 lat-long environment


# ---------------------------------------------------------------- images as the page receives them

HALF_MAX = 65504.0


def _b64(array):
    return base64.b64encode(np.ascontiguousarray(array).tobytes()).decode("ascii")


def encode_image(levels, precision="auto"):
    """{width, height, channels, type, levels: [base64]} of a mip chain. type f16 (RGB16F etc.: ample for
    textures) where every value fits a half float, else f32; precision "f32" forces 32-bit floats."""
    h, w, c = levels[0].shape
    fits_half = all(np.isfinite(lv).all() and np.abs(lv).max(initial=0.0) <= HALF_MAX for lv in levels)
    kind = "f16" if precision == "auto" and fits_half else "f32"
    dtype = "<f2" if kind == "f16" else "<f4"
    return {"width": int(w), "height": int(h), "channels": int(c), "type": kind,
            "levels": [_b64(lv.astype(dtype)) for lv in levels]}


def image_size(path):
    """(width, height) from an image file's header, without decoding it; None where it does not read."""
    from mtlxgen.base.images import image_header
    header = image_header(path)
    return None if header is None else header[1:3]


def _too_big(path, size, limit, what):
    return MtlxError((Loc(path, 0), "%s of %dx%d pixels is larger than a web page embeds (at most %.1f "
                                    "megapixels); use a smaller image" % (what, size[0], size[1], limit / 1e6)))


def load_texture(path, budget):
    """The (h, w, c) float image render binds for a manifest texture file, rows bottom first (as render
    uploads images), or None where render draws the sampler's default instead (a missing file). A file that
    does not decode, a device, FIFO or system file is an error, as in render; so is an image past the page's
    bounds.
    budget: [pixels left for this page's textures], decreased."""
    from mtlxgen.base.files import check_regular
    from mtlxgen.base.images import read_image
    if not os.path.exists(path):
        return None
    check_regular(path, Loc(path, 0), "image file")
    if path.lower().endswith(".ies"):          # measured_edf's profile, as render binds it (top row first)
        from mtlxgen.draw.ies import load_texture as ies_texture
        try:
            return np.asarray(ies_texture(path), dtype=np.float32)
        except Exception:
            return None
    size = image_size(path)
    if size is None:            # not an image: read_image says why, one line (render refuses it the same way)
        read_image(path)
    if size[0] * size[1] > MAX_TEXTURE_PIXELS:
        raise _too_big(path, size, MAX_TEXTURE_PIXELS, "texture")
    if size[0] * size[1] > budget[0]:
        raise MtlxError((Loc(path, 0), "the textures of this element add up to more than a web page embeds "
                                       "(%.1f megapixels)" % (MAX_TEXTURES_PIXELS / 1e6)))
    img = read_image(path)      # a file that does not decode: one line, the element not written (as render)
    budget[0] -= size[0] * size[1]
    return np.ascontiguousarray(img[::-1])


def constant_image(value):
    """render.Renderer.constant_texture's 1x1 RGBA of an image node's default colour."""
    v = [float(x) for x in (value if isinstance(value, (list, tuple)) else [value])]
    rgba = {1: v * 3 + [1.0], 2: v + [0.0, 1.0], 3: v + [1.0]}.get(len(v), v[:4])
    return np.array(rgba, dtype=np.float32).reshape(1, 1, 4)


def texture_payload(manifest):
    """{"images": [...], "samplers": {uniform: image index}} for the manifest's textures, bound as
    render.Renderer.bind binds them: the file's pixels with their mip chain, else its default colour
    (1x1, no mips), else nothing (the page binds transparent black, as render does)."""
    images, samplers, by_key = [], {}, {}
    budget = [MAX_TEXTURES_PIXELS]
    for tex in sorted(manifest.get("textures", []), key=lambda t: t["uniform"]):
        path, default = tex.get("file"), tex.get("default")
        key = img = None
        if path:
            key = ("file", os.path.realpath(path))
            if key not in by_key:
                img = load_texture(path, budget)
                if img is None:
                    key = None
        if key is None and default is not None:
            key = ("constant",) + tuple(constant_image(default).ravel().tolist())
            if key not in by_key:
                img = constant_image(default)
        if key is None:
            continue
        if key not in by_key:
            mips = key[0] == "file" and not path.lower().endswith(".ies")
            entry = encode_image(mip_chain(img) if mips else [img])
            entry["mipmaps"] = mips
            entry["source"] = os.path.basename(path) if key[0] == "file" else "default colour"
            by_key[key] = len(images)
            images.append(entry)
        samplers[tex["uniform"]] = by_key[key]
    return {"images": images, "samplers": samplers}


def environment_payload(environment=None):
    """The radiance map's mip chain (32-bit float, top row first) and its SH irradiance map, as render binds
    them for this environment (None: the built-in sky)."""
    from mtlxgen.draw.environment import prepare
    env = prepare(environment)          # environment.py: the recipe every host binds
    radiance = encode_image(env.radiance, "f32")
    radiance["mipmaps"] = True
    irradiance = encode_image([env.irradiance], "f32")
    irradiance["mipmaps"] = False
    return {"radiance": radiance, "irradiance": irradiance,
            "mips": env.uniforms["u_envRadianceMips"], "matrix": env.uniforms["u_envMatrix"]}


def read_environment(path):
    """A --env file as render reads it, bounded for a page."""
    from mtlxgen.draw import renderer as render
    size = image_size(path)
    if size is not None and size[0] * size[1] > MAX_ENV_PIXELS:
        raise _too_big(path, size, MAX_ENV_PIXELS, "environment")
    return render.load_environment(path)


def geometry_payload(attributes):
    """render's sphere: the attributes the shader reads (of those render binds) and the index."""
    from mtlxgen.draw import renderer as render
    attrs, index = render.sphere()
    out = {name: {"size": int(a.shape[1]), "data": _b64(a.astype("<f4"))}
           for name, a in attrs.items() if name in attributes}
    small = index.max() < 65536
    return {"attributes": out, "index": _b64(index.astype("<u2" if small else "<u4")),
            "index_type": "u16" if small else "u32", "count": int(index.size)}


def camera_payload():
    from mtlxgen.draw import renderer as render
    c = render.DEFAULT_CAMERA
    return {"eye": list(c.eye), "target": list(c.target), "up": list(c.up), "fov_y": c.fov_y, "near": c.near,
            "far": c.far}


# ---------------------------------------------------------------- the page

def page_data(shader, environment, size, samples):
    """Everything the viewer reads, as one JSON-able dict. environment: an environment_payload()."""
    m = shader.manifest
    if m.get("target") != "essl":
        raise ValueError("the web page draws essl shaders (generate with target='essl')")
    data = {
        "element": shader.element, "stem": shader.stem, "vertex": shader.vertex,
        "fragment": shader.fragment,
        "uniforms": m.get("uniforms", []), "application": m.get("application", []),
        "size": int(size), "samples": int(samples), "camera": camera_payload(), "environment": environment,
        "geometry": geometry_payload(m.get("attributes", {})), "textures": texture_payload(m),
    }
    if m.get("environment") == "prefiltered":
        data["prefilter"] = prefilter_payload()
    return data


def prefilter_payload():
    """What the page's prefilter pass runs (web_assets/prefilter.js; environment.Prefilter's recipe): the
    prefilter shaders in GLSL ES 3.00 and the GGX samples per texel."""
    from mtlxgen.draw.environment import PREFILTER_SAMPLES, prefilter_sources
    vertex, fragment = prefilter_sources("essl")
    return {"vertex": vertex, "fragment": fragment, "samples": int(PREFILTER_SAMPLES)}


def _asset(name):
    with open(os.path.join(ASSETS, name), encoding="utf-8") as f:
        return f.read()


def fill(template, values):
    """The template with each {{NAME}} replaced by values[NAME], in one pass (a value holding "{{...}}", such as
    an element's name, stays as it is)."""
    return re.sub(r"\{\{([A-Z]+)\}\}", lambda m: values[m.group(1)], template)


def page_html(data):
    """The page: the element's name as HTML text (escape.html_text), the data as JSON safe inside its <script>
    element (escape.json_in_script), the viewer inlined."""
    return fill(_asset("page.html"), {"TITLE": html_text(data["element"]), "SIZE": str(int(data["size"])),
                                      "DATA": json_in_script(data),
                                      "VIEWER": _viewer_script("prefilter" in data)})


PREFILTER_MARK = "    /*PREFILTER*/\n"     # viewer.js's line where a prefiltered page's pass goes (else nothing)


def _viewer_script(prefilter=False):
    """viewer.js as the text of an inline <script>: our own file, checked to hold nothing that ends the
    element or opens an HTML comment. prefilter: with web_assets/prefilter.js at its mark (pages of
    prefiltered shaders); else the mark's line is dropped (fis pages hold no prefilter code)."""
    text = _asset("viewer.js").replace(PREFILTER_MARK, _asset("prefilter.js") if prefilter else "")
    if re.search(r"</script|<!--", text, re.I):
        raise RuntimeError("web_assets/viewer.js holds '</script' or '<!--', which would end its inline script")
    return text


def write_page(shader, out_dir, environment, size, samples):
    """Write OUT_DIR/STEM.html (files.write_atomic: a symlink there is replaced, never followed); returns its
    path."""
    from mtlxgen.base.files import write_atomic
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, shader.stem + ".html")
    write_atomic(path, page_html(page_data(shader, environment, size, samples)))
    return path
