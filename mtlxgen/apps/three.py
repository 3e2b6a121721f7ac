"""mtlxgen three: an ES module per element that gives three.js a material drawing our GLSL ES 3.00 code.

For each element, OUT/STEM.js exports createMaterial(THREE, options) -> THREE.RawShaderMaterial (the essl
shaders, every public uniform at its manifest value, every application uniform at its default, textures loaded
through three's loaders, the matrices and camera position set per draw), the element's shaders and manifest,
and the helpers of the shared runtime OUT/mtlxgen_three.js (web_assets/mtlxgen_three.js): prepareGeometry,
createSphere, createEnvironment, setEnvironment, createDisplay. OUT/STEM.html is an example page drawing the
element on render's sphere in render's scene (an import map points `three` at OUT/three/, where the user puts
the npm package's files); OUT/environment.exr is the environment it lights with (the built-in sky, or --env).

Texture files are never copied. Each file the manifest resolves (wherever the document points: textures are
decoded, not copied, as docs/documents.md says of untrusted documents) is decoded through images.read_image
and its pixels written afresh under OUT/textures/ so a page can load them (encode_texture): a PNG for 8-bit
sources of up to four channels, else a 32-bit float OpenEXR. No byte of the source file (metadata chunks,
trailing data, the encoding itself) reaches the output; a file that is missing draws its default colour,
one that does not decode is an error (one line; the element is not written), as in render. What is written is bounded as the web page bounds what it embeds. OUT/textures/ must be a
folder of its own (a symbolic link there is refused).

Text from the document is data in every file written: the module's values (element name, manifest, shaders)
are JavaScript literals through escape.json_in_script, the doc comment shows names and values only as
escape.js_comment's one-line JSON (no `*/` or line break can end the comment), and the example page's title
goes through escape.html_text. Every file goes through files.write_atomic / write_through_temp (a symlink at an
output path is replaced, never followed).
"""
import hashlib
import os
import re

import numpy as np

from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.escape import html_text, js_comment, js_string, json_in_script
from mtlxgen.base.files import check_regular, write_atomic, write_through_temp
from mtlxgen.base.images import image_header, read_image
from mtlxgen.apps.web import ASSETS, MAX_TEXTURE_PIXELS, MAX_TEXTURES_PIXELS, _too_big, fill

RUNTIME = "mtlxgen_three.js"
ENVIRONMENT = "environment.exr"
TEXTURES = "textures"
STEM = re.compile(r"[A-Za-z0-9_+][A-Za-z0-9_.+-]*\Z")     # emit.file_stem's characters


def _safe_name(name):
    stem, ext = os.path.splitext(os.path.basename(name))
    stem = re.sub(r"[^A-Za-z0-9_.+-]", "_", stem).lstrip(".-") or "texture"
    return stem[:100] + ext.lower()


def _write_oiio(path, data, channels, fmt, compression=None):
    """Write pixels (h, w, channels) as a new image file at `path` (format from its extension), through a
    temporary file and a rename."""
    import OpenImageIO as oiio
    h, w = data.shape[:2]
    spec = oiio.ImageSpec(w, h, channels, fmt)
    spec.attribute("oiio:UnassociatedAlpha", 1)         # the values as given: no division by alpha
    if compression:
        spec.attribute("compression", compression)
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray(data))

    def write(tmp):
        if not buf.write(tmp):
            raise MtlxError((Loc(path, 0), "cannot write: %s" % " ".join(buf.geterror().split())))
    write_through_temp(path, write)


def encode_texture(img, bits8, path_stem):
    """Write decoded pixels `img` ((h, w, c) float, as images.read_image returns them) as PATH_STEM.png (8-bit
    sources of up to 4 channels: the same 8-bit values) or PATH_STEM.exr (32-bit float, up to 4 channels; two
    channels, grey and alpha, as R and G with a zero B: three's EXRLoader reads Y or RGB(A), not RG alone, and
    the shader reads a 2-channel texture's r and g); returns the file's path."""
    import OpenImageIO as oiio
    c = img.shape[2]
    if bits8 and c <= 4:
        path = path_stem + ".png"
        _write_oiio(path, np.clip(np.round(img * 255.0), 0, 255).astype(np.uint8), c, oiio.UINT8)
        return path
    data = np.asarray(img[..., :4], dtype=np.float32)
    if data.shape[2] == 2:
        data = np.concatenate([data, np.zeros_like(data[..., :1])], axis=2)
    path = path_stem + ".exr"
    _write_oiio(path, np.ascontiguousarray(data), data.shape[2], oiio.FLOAT, "zip")
    return path


class TextureFiles:
    """Texture files written under OUT/textures/ for the modules of one run, each source once (by real path):
    decoded and re-encoded, never copied."""

    def __init__(self, out_dir):
        self.out_dir = out_dir
        self.done = {}              # real path -> url relative to out_dir, or None (draws its default)
        self.budget = MAX_TEXTURES_PIXELS

    def folder(self):
        folder = os.path.join(self.out_dir, TEXTURES)
        if os.path.islink(folder) or (os.path.lexists(folder) and not os.path.isdir(folder)):
            raise MtlxError((Loc(folder, 0), "is a symbolic link or not a folder: textures are written only into a "
                                             "folder of their own (remove it)"))
        os.makedirs(folder, exist_ok=True)
        return folder

    def url(self, path):
        if not path or not os.path.exists(path):
            return None
        real = os.path.realpath(path)
        if real in self.done:
            return self.done[real]
        check_regular(path, Loc(path, 0), "image file", max_bytes="image")
        info = image_header(real)
        if info is None:        # not an image: read_image says why, one line (render refuses it the same way)
            read_image(real)
        _, width, height, bits8 = info
        if width * height > MAX_TEXTURE_PIXELS:
            raise _too_big(path, (width, height), MAX_TEXTURE_PIXELS, "texture")
        if width * height > self.budget:
            raise MtlxError((Loc(path, 0), "the textures of these elements add up to more than a page loads "
                                           "(%.1f megapixels)" % (MAX_TEXTURES_PIXELS / 1e6)))
        img = read_image(real)      # a file that does not decode: one line, the element not written (as render)
        self.budget -= width * height
        digest = hashlib.sha256(real.encode("utf-8", "surrogatepass")).hexdigest()[:8]
        stem = "%s-%s" % (os.path.splitext(_safe_name(real))[0], digest)
        written = encode_texture(img, bits8, os.path.join(self.folder(), stem))
        self.done[real] = "%s/%s" % (TEXTURES, os.path.basename(written))
        return self.done[real]


def write_environment(out_dir, environment=None):
    """OUT/environment.exr: the lat-long radiance (32-bit float RGB) the example pages light with."""
    import OpenImageIO as oiio
    from mtlxgen.draw import renderer as render
    env = render.builtin_sky() if environment is None else np.asarray(environment, dtype=np.float32)[..., :3]
    path = os.path.join(out_dir, ENVIRONMENT)
    _write_oiio(path, np.ascontiguousarray(env, dtype=np.float32), 3, oiio.FLOAT, "zip")
    return path


def _js(obj):
    """A JavaScript literal of a JSON-able value, safe in a module and inside an HTML <script> element."""
    return json_in_script(obj, separators=(", ", ": "))


def module_text(shader, textures):
    """The ES module of one element. textures: TextureFiles of the run."""
    m = shader.manifest
    if m.get("target") != "essl":
        raise ValueError("three modules carry essl shaders (generate with target='essl')")
    if not STEM.match(shader.stem):
        raise ValueError("file stem %r is not one emit.file_stem makes" % shader.stem)
    tex_entries = []
    for t in m.get("textures", []):
        entry = {k: v for k, v in t.items() if k != "file"}
        entry["url"] = textures.url(t.get("file"))
        entry["source"] = os.path.basename(t.get("file") or "")
        tex_entries.append(entry)
    manifest = {"element": m.get("element", shader.element), "target": "essl", "uniforms": m.get("uniforms", []),
                "textures": tex_entries, "application": m.get("application", []),
                "attributes": m.get("attributes", {})}
    for key in ("environment", "primvars"):
        if key in m:
            manifest[key] = m[key]
    # names and values from the document appear in the comment only as js_comment's one-line JSON
    doc = ["/**",
           " * A three.js material generated by mtlxgen from MaterialX (GLSL ES 3.00): element %s."
           % js_comment(shader.element),
           " *",
           " * import * as THREE from 'three';",
           " * import { createMaterial, createSphere, prepareGeometry, createEnvironment, setEnvironment, createDisplay }",
           " *   from './%s.js';" % shader.stem,
           " * const material = createMaterial(THREE, { envSamples: 64 });  // a THREE.RawShaderMaterial",
           " * setEnvironment(material, createEnvironment(THREE, await new EXRLoader().setDataType(THREE.FloatType)",
           " *   .loadAsync('environment.exr')));",
           " * const mesh = new THREE.Mesh(prepareGeometry(THREE, geometry), material);",
           " * // draw through createDisplay(THREE, renderer, w, h).render(scene, camera): the shader writes linear",
           " * // radiance, which the display encodes to sRGB",
           " *",
           " * @param THREE the three.js namespace (`import * as THREE from 'three'`)",
           " * @param options {envSamples, envIntensity, envMatrix, environment: createEnvironment(...),",
           " *   textures: {uniform: THREE.Texture or url}, EXRLoader, HDRLoader (classes from three/addons; else",
           " *   imported from 'three/addons/loaders/'), hdrType: THREE.FloatType (default) or THREE.HalfFloatType}",
           " * @returns THREE.RawShaderMaterial; material.userData.ready resolves when its textures are loaded",
           " *",
           " * Public uniforms (material.uniforms[name].value, from the document's values):",
           ] + [" *   " + js_comment({"name": u.get("name"), "type": u.get("type"), "value": u.get("value")})
                for u in m.get("uniforms", [])] + [
           " * Textures (raw colour: the shader converts from the colorspace itself; wrap and filter as listed):",
           ] + [" *   " + js_comment({k: t.get(k) for k in ("uniform", "source", "colorspace", "uaddressmode",
                                                           "vaddressmode", "filtertype")})
                for t in tex_entries] + [
           " * Application uniforms (set by createMaterial's onBeforeRender: the matrices from the object and",
           " * camera, u_viewPosition; by setEnvironment: the environment; the others keep these defaults):",
           ] + [" *   " + js_comment({k: a.get(k) for k in ("name", "type", "meaning", "default")})
                for a in m.get("application", [])] + [
           " */"]
    return "\n".join(doc) + "\n" + "\n".join([
        "import * as runtime from './%s';" % RUNTIME,
        "export { prepareGeometry, createSphere, createEnvironment, setEnvironment, createDisplay, loadTexture,",
        "         constantTexture } from './%s';" % RUNTIME,
        "",
        "export const element = %s;" % _js(shader.element),
        "export const manifest = %s;" % _js(manifest),
        "export const vertexShader = %s;" % _js(shader.vertex),
        "export const fragmentShader = %s;" % _js(shader.fragment),
        "",
        "export function createMaterial(THREE, options = {}) {",
        "  return runtime.createMaterial(THREE, { manifest, vertexShader, fragmentShader, baseUrl: import.meta.url },",
        "                                options);",
        "}",
        "",
        "export default createMaterial;",
        ""] + (_prefilter_lines() if m.get("environment") == "prefiltered" else []))


def _prefilter_lines():
    """A prefiltered element's module: the prefilter pass (environment.prefilter_sources("essl"), GGX samples per
    texel) and prefilterEnvironment(THREE, renderer, environment), which the material's environment goes through
    before setEnvironment (runtime prefilterEnvironment: render's environment.Prefilter recipe)."""
    from mtlxgen.apps.web import prefilter_payload
    return ["// the GGX-prefiltered environment this material's method reads (manifest environment: prefiltered)",
            "export const prefilter = %s;" % _js(prefilter_payload()),
            "",
            "export function prefilterEnvironment(THREE, renderer, environment) {",
            "  return runtime.prefilterEnvironment(THREE, renderer, environment, prefilter);",
            "}",
            ""]


ENV_LINE = "  const environment = element.createEnvironment(THREE, sky);\n"
PREFILTERED_ENV_LINE = ("  const environment = element.prefilterEnvironment(THREE, renderer, "
                        "element.createEnvironment(THREE, sky));\n")


def example_html(shader, size, samples):
    """The example page; a prefiltered element's prefilters the environment first (other pages are as before)."""
    with open(os.path.join(ASSETS, "three_example.html"), encoding="utf-8") as f:
        text = f.read()
    if shader.manifest.get("environment") == "prefiltered":
        if ENV_LINE not in text:
            raise RuntimeError("web_assets/three_example.html lost its environment line")
        text = text.replace(ENV_LINE, PREFILTERED_ENV_LINE)
    return fill(text, {"TITLE": html_text(shader.element), "MODULE": js_string("./%s.js" % shader.stem),
                       "SIZE": str(int(size)), "SAMPLES": str(int(samples)), "ENVIRONMENT": js_string(ENVIRONMENT)})


def write_runtime(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, RUNTIME)
    with open(os.path.join(ASSETS, RUNTIME), "rb") as f:
        write_atomic(path, f.read())
    return path


def write_element(shader, out_dir, textures, size, samples):
    """OUT/STEM.js and OUT/STEM.html; returns their paths."""
    js = os.path.join(out_dir, shader.stem + ".js")
    text = module_text(shader, textures)
    html = os.path.join(out_dir, shader.stem + ".html")
    page = example_html(shader, size, samples)
    write_atomic(js, text)
    write_atomic(html, page)
    return js, html
