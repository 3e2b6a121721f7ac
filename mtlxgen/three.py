"""mtlxgen three: an ES module per element that gives three.js a material drawing our GLSL ES 3.00 code.

For each element, OUT/STEM.js exports createMaterial(THREE, options) -> THREE.RawShaderMaterial (the essl
shaders, every public uniform at its manifest value, every application uniform at its default, textures loaded
through three's loaders, the matrices and camera position set per draw), the element's shaders and manifest,
and the helpers of the shared runtime OUT/mtlxgen_three.js (web_assets/mtlxgen_three.js): prepareGeometry,
createSphere, createEnvironment, setEnvironment, createDisplay. OUT/STEM.html is an example page drawing the
element on render's sphere in render's scene (an import map points `three` at OUT/three/, where the user puts
the npm package's files); OUT/environment.exr is the environment it lights with (the built-in sky, or --env).

Texture files the manifest resolves are put beside the modules (OUT/textures/) so a page can load them: files
three's loaders read (PNG, JPEG, WebP, OpenEXR, Radiance HDR) are copied when they decode as that image format,
others are decoded and written as PNG (8-bit sources) or OpenEXR; a file that is missing or does not decode
draws its default colour. What is copied is bounded as the web page bounds what it embeds.
"""
import hashlib
import json
import os
import re
import shutil

import numpy as np

from .diagnostics import Loc, MtlxError
from .images import image_header
from .web import ASSETS, MAX_TEXTURE_PIXELS, MAX_TEXTURES_PIXELS, _html_text, _too_big, fill

RUNTIME = "mtlxgen_three.js"
ENVIRONMENT = "environment.exr"
TEXTURES = "textures"
# OpenImageIO format names three's loaders read, and the extension each is written with
LOADABLE = {"png": ".png", "jpeg": ".jpg", "webp": ".webp", "openexr": ".exr", "hdr": ".hdr"}




def _safe_name(name):
    stem, ext = os.path.splitext(os.path.basename(name))
    stem = re.sub(r"[^A-Za-z0-9_.+-]", "_", stem).lstrip(".-") or "texture"
    return stem[:100] + ext.lower()


class TextureFiles:
    """Texture files put under OUT/textures/ for the modules of one run, each once (by real path)."""

    def __init__(self, out_dir):
        self.out_dir = out_dir
        self.done = {}              # real path -> url relative to out_dir, or None (draws its default)
        self.budget = MAX_TEXTURES_PIXELS

    def url(self, path):
        from .files import check_regular
        if not path or not os.path.exists(path):
            return None
        real = os.path.realpath(path)
        if real in self.done:
            return self.done[real]
        check_regular(path, Loc(path, 0), "image file")
        info = image_header(real)
        if info is None:
            self.done[real] = None
            return None
        fmt, width, height, bits8 = info
        if width * height > MAX_TEXTURE_PIXELS:
            raise _too_big(path, (width, height), MAX_TEXTURE_PIXELS, "texture")
        if width * height > self.budget:
            raise MtlxError((Loc(path, 0), "the textures of these elements add up to more than a page loads "
                                           "(%.1f megapixels)" % (MAX_TEXTURES_PIXELS / 1e6)))
        self.budget -= width * height
        folder = os.path.join(self.out_dir, TEXTURES)
        os.makedirs(folder, exist_ok=True)
        digest = hashlib.sha256(real.encode("utf-8", "surrogatepass")).hexdigest()[:8]
        if fmt in LOADABLE:
            stem = os.path.splitext(_safe_name(real))[0]
            name = "%s-%s%s" % (stem, digest, LOADABLE[fmt])
            shutil.copyfile(real, os.path.join(folder, name))
        else:           # a format three does not load: decoded here, written as one it does
            name = self._transcode(real, folder, digest, bits8)
            if name is None:
                self.done[real] = None
                return None
        self.done[real] = "%s/%s" % (TEXTURES, name)
        return self.done[real]

    @staticmethod
    def _transcode(path, folder, digest, bits8):
        import OpenImageIO as oiio
        from .images import read_image
        try:
            img = read_image(path)
        except MtlxError:
            return None
        stem = os.path.splitext(_safe_name(path))[0]
        h, w, c = img.shape
        if bits8 and c <= 4:
            name, spec = "%s-%s.png" % (stem, digest), oiio.ImageSpec(w, h, c, oiio.UINT8)
            data = np.clip(np.round(img * 255.0), 0, 255).astype(np.uint8)
        else:
            name, spec = "%s-%s.exr" % (stem, digest), oiio.ImageSpec(w, h, min(c, 4), oiio.FLOAT)
            data = np.ascontiguousarray(img[..., :4], dtype=np.float32)
        spec.attribute("oiio:UnassociatedAlpha", 1)
        buf = oiio.ImageBuf(spec)
        buf.set_pixels(oiio.ROI(), np.ascontiguousarray(data))
        if not buf.write(os.path.join(folder, name)):
            raise MtlxError((Loc(path, 0), "cannot write its copy: %s" % buf.geterror().strip()))
        return name


def write_environment(out_dir, environment=None):
    """OUT/environment.exr: the lat-long radiance (32-bit float RGB) the example pages light with."""
    import OpenImageIO as oiio
    from . import render
    env = render.builtin_sky() if environment is None else np.asarray(environment, dtype=np.float32)[..., :3]
    h, w, _ = env.shape
    spec = oiio.ImageSpec(w, h, 3, oiio.FLOAT)
    spec.attribute("compression", "zip")
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray(env, dtype=np.float32))
    path = os.path.join(out_dir, ENVIRONMENT)
    if not buf.write(path):
        raise MtlxError((Loc(path, 0), "cannot write the environment: %s" % buf.geterror().strip()))
    return path


def _js(obj):
    """A JavaScript literal of a JSON-able value (JSON is JavaScript; ASCII so no line separator breaks it)."""
    return json.dumps(obj, ensure_ascii=True, indent=None, separators=(", ", ": "))


def _doc_line(text):
    return text.replace("*/", "* /")


def module_text(shader, textures):
    """The ES module of one element. textures: TextureFiles of the run."""
    m = shader.manifest
    if m.get("target") != "essl":
        raise ValueError("three modules carry essl shaders (generate with target='essl')")
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
    env_lines = ["%s %s: %s (default %s)" % (a["name"], a["type"], a.get("meaning", ""),
                                             "none" if a.get("default") is None else _js(a["default"]))
                 for a in m.get("application", [])]
    doc = ["/**",
           " * %s: a three.js material generated by mtlxgen from MaterialX (GLSL ES 3.00)." % _doc_line(shader.element),
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
           ] + [" *   %s %s = %s" % (u["name"], u["type"], _doc_line(_js(u["value"]))) for u in m.get("uniforms", [])] + [
           " * Textures (raw colour: the shader converts from the colorspace itself; wrap and filter as listed):",
           ] + [" *   %s: %s (%s, %s/%s, %s)" % (t["uniform"], _doc_line(t["source"] or "no file"), t.get("colorspace") or "raw",
                                             t.get("uaddressmode"), t.get("vaddressmode"), t.get("filtertype"))
                for t in tex_entries] + [
           " * Application uniforms (set by createMaterial's onBeforeRender: the matrices from the object and",
           " * camera, u_viewPosition; by setEnvironment: the environment; the others keep these defaults):",
           ] + [" *   " + _doc_line(line) for line in env_lines] + [
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
        ""])


def example_html(shader, size, samples):
    with open(os.path.join(ASSETS, "three_example.html"), encoding="utf-8") as f:
        text = f.read()
    return fill(text, {"TITLE": _html_text(shader.element), "MODULE": "./%s.js" % shader.stem, "SIZE": str(int(size)),
                       "SAMPLES": str(int(samples)), "ENVIRONMENT": ENVIRONMENT})


def write_runtime(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, RUNTIME)
    shutil.copyfile(os.path.join(ASSETS, RUNTIME), path)
    return path


def write_element(shader, out_dir, textures, size, samples):
    """OUT/STEM.js and OUT/STEM.html; returns their paths."""
    js = os.path.join(out_dir, shader.stem + ".js")
    text = module_text(shader, textures)
    with open(js, "w", encoding="utf-8") as f:
        f.write(text)
    html = os.path.join(out_dir, shader.stem + ".html")
    with open(html, "w", encoding="utf-8") as f:
        f.write(example_html(shader, size, samples))
    return js, html
