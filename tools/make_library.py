"""A synthetic material library to scale batch rendering and golden checks on (benchmarks/bench_cluster.py,
tests/apps/test_cluster.py): N varied materials, one .mtlx document each, and the textures they sample.

    python tools/make_library.py N OUTDIR [--seed S] [--textures T] [--texture-size PX] [--kinds K,K,...]

Materials cycle through six kinds, each with values drawn from a random generator seeded by --seed (the same
N, seed and options write the same bytes):

  standard_surface      base colour, metalness, roughness, coat, sheen; every third one textured
  open_pbr_surface      base colour, metalness, roughness, coat and fuzz weights
  gltf_pbr              base colour (every other one from a texture), metallic, roughness
  UsdPreviewSurface     diffuse colour from a UsdUVTexture (every other one) or a value, metallic, roughness
  procedural            a nodegraph: texture coordinates scaled, 2D noise, a mix of two colours, into
                        standard_surface's base colour and roughness
  checker               a nodegraph: a checkerboard of two colours through an unlit surface

--kinds keeps some of them (cycled in the order given): on a software rasterizer the lit kinds cost seconds
each to link and draw, the unlit checker a tenth of that, so tests and quick benchmarks take `--kinds checker`.

Textures (OUTDIR/textures/tex_NNN.png, --textures of them, shared as a real library shares its images) are
written with numpy and OpenImageIO: stripes, checks, rings and value noise in random colours. Documents go in
folders of 100 (OUTDIR/m000/, OUTDIR/m001/, ...) so no folder grows past what a file manager lists easily.
"""
import argparse
import os
import sys

import numpy as np

KINDS = ("standard_surface", "open_pbr_surface", "gltf_pbr", "UsdPreviewSurface", "procedural", "checker")
PER_FOLDER = 100


def _c3(rng, lo=0.05, hi=0.95):
    return ", ".join("%.4f" % v for v in rng.uniform(lo, hi, 3))


def _f(rng, lo=0.0, hi=1.0):
    return "%.4f" % rng.uniform(lo, hi)


def texture(rng, size):
    """An RGB float image in [0, 1]: one of four patterns in two random colours."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    a, b = rng.uniform(0.05, 0.95, 3), rng.uniform(0.05, 0.95, 3)
    kind = rng.integers(4)
    f = rng.uniform(2, 9)
    if kind == 0:
        t = (np.sin(2 * np.pi * f * (x * np.cos(f) + y * np.sin(f))) > 0).astype(np.float32)
    elif kind == 1:
        t = ((np.floor(x * f) + np.floor(y * f)) % 2).astype(np.float32)
    elif kind == 2:
        t = 0.5 + 0.5 * np.cos(2 * np.pi * f * np.hypot(x - 0.5, y - 0.5))
    else:
        cells = rng.uniform(0, 1, (int(f) + 2, int(f) + 2))
        ix, iy = x * f, y * f
        x0, y0 = ix.astype(int), iy.astype(int)
        fx, fy = ix - x0, iy - y0
        fx, fy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
        t = ((cells[y0, x0] * (1 - fx) + cells[y0, x0 + 1] * fx) * (1 - fy)
             + (cells[y0 + 1, x0] * (1 - fx) + cells[y0 + 1, x0 + 1] * fx) * fy)
    return (a * (1 - t[..., None]) + b * t[..., None]).astype(np.float32)


def write_png(path, img):
    import OpenImageIO as oiio
    h, w, c = img.shape
    buf = oiio.ImageBuf(oiio.ImageSpec(w, h, c, oiio.UINT8))
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray((np.clip(img, 0, 1) * 255 + 0.5).astype(np.uint8)))
    if not buf.write(path):
        raise OSError("cannot write %s: %s" % (path, buf.geterror()))


def _image(name, tex, kind="color3"):
    return ('  <image name="%s" type="%s">\n    <input name="file" type="filename" value="%s" />\n  </image>\n'
            % (name, kind, tex))


def _base_textured(kind, srf, rng, tex, textured, floats):
    """A `kind` surface whose base_color is the texture `tex` (textured) or a random colour, and whose float
    inputs `floats` ((name, low, high) each) are random: the image node (where textured) and the surface."""
    body = _image("base_tex", tex) if textured else ""
    base = ('<input name="base_color" type="color3" nodename="base_tex" />' if textured else
            '<input name="base_color" type="color3" value="%s" />' % _c3(rng))
    body += '  <%s name="%s" type="surfaceshader">\n    %s\n' % (kind, srf, base)
    for name, lo, hi in floats:
        body += '    <input name="%s" type="float" value="%s" />\n' % (name, _f(rng, lo, hi))
    return body + "  </%s>\n" % kind


def material(kind, i, rng, tex):
    """The body of material i's document (between <materialx> and </materialx>) and its material's name."""
    m = "M_%05d" % i
    srf = "SR_%05d" % i
    if kind == "standard_surface":
        floats = (("metalness", 0, 1), ("specular_roughness", 0.05, 0.9), ("coat", 0, 0.6), ("sheen", 0, 0.5))
        body = _base_textured(kind, srf, rng, tex, i % 3 == 0, floats)
    elif kind == "open_pbr_surface":
        body = ('  <open_pbr_surface name="%s" type="surfaceshader">\n'
                '    <input name="base_color" type="color3" value="%s" />\n'
                '    <input name="base_metalness" type="float" value="%s" />\n'
                '    <input name="specular_roughness" type="float" value="%s" />\n'
                '    <input name="coat_weight" type="float" value="%s" />\n'
                '    <input name="fuzz_weight" type="float" value="%s" />\n  </open_pbr_surface>\n'
                % (srf, _c3(rng), _f(rng), _f(rng, 0.05, 0.9), _f(rng, 0, 0.7), _f(rng, 0, 0.4)))
    elif kind == "gltf_pbr":
        body = _base_textured(kind, srf, rng, tex, i % 2 == 0, (("metallic", 0, 1), ("roughness", 0.05, 0.9)))
    elif kind == "UsdPreviewSurface":
        textured = i % 2 == 0
        body = ('  <UsdUVTexture name="diffuse_tex" type="multioutput">\n'
                '    <input name="file" type="filename" value="%s" />\n'
                '    <input name="sourceColorSpace" type="string" value="sRGB" />\n  </UsdUVTexture>\n'
                % tex) if textured else ""
        base = ('<input name="diffuseColor" type="color3" nodename="diffuse_tex" output="rgb" />' if textured else
                '<input name="diffuseColor" type="color3" value="%s" />' % _c3(rng))
        body += ('  <UsdPreviewSurface name="%s" type="surfaceshader">\n    %s\n'
                 '    <input name="metallic" type="float" value="%s" />\n'
                 '    <input name="roughness" type="float" value="%s" />\n'
                 '    <input name="clearcoat" type="float" value="%s" />\n  </UsdPreviewSurface>\n'
                 % (srf, base, _f(rng), _f(rng, 0.05, 0.9), _f(rng, 0, 0.5)))
    elif kind == "procedural":
        body = ('  <nodegraph name="NG_%05d">\n'
                '    <texcoord name="uv" type="vector2" />\n'
                '    <multiply name="scaled" type="vector2">\n'
                '      <input name="in1" type="vector2" nodename="uv" />\n'
                '      <input name="in2" type="vector2" value="%s, %s" />\n    </multiply>\n'
                '    <noise2d name="noise" type="float">\n'
                '      <input name="texcoord" type="vector2" nodename="scaled" />\n'
                '      <input name="amplitude" type="float" value="0.5" />\n'
                '      <input name="pivot" type="float" value="0.5" />\n    </noise2d>\n'
                '    <mix name="blend" type="color3">\n'
                '      <input name="fg" type="color3" value="%s" />\n'
                '      <input name="bg" type="color3" value="%s" />\n'
                '      <input name="mix" type="float" nodename="noise" />\n    </mix>\n'
                '    <output name="color_out" type="color3" nodename="blend" />\n'
                '    <output name="rough_out" type="float" nodename="noise" />\n'
                '  </nodegraph>\n'
                '  <standard_surface name="%s" type="surfaceshader">\n'
                '    <input name="base_color" type="color3" nodegraph="NG_%05d" output="color_out" />\n'
                '    <input name="specular_roughness" type="float" nodegraph="NG_%05d" output="rough_out" />\n'
                '    <input name="metalness" type="float" value="%s" />\n  </standard_surface>\n'
                % (i, _f(rng, 2, 12), _f(rng, 2, 12), _c3(rng), _c3(rng), srf, i, i, _f(rng, 0, 0.3)))
    else:
        body = ('  <nodegraph name="NG_%05d">\n'
                '    <checkerboard name="checks" type="color3">\n'
                '      <input name="color1" type="color3" value="%s" />\n'
                '      <input name="color2" type="color3" value="%s" />\n'
                '      <input name="uvtiling" type="vector2" value="%d, %d" />\n    </checkerboard>\n'
                '    <output name="out" type="color3" nodename="checks" />\n  </nodegraph>\n'
                '  <surface_unlit name="%s" type="surfaceshader">\n'
                '    <input name="emission_color" type="color3" nodegraph="NG_%05d" output="out" />\n'
                '  </surface_unlit>\n' % (i, _c3(rng), _c3(rng), rng.integers(2, 16), rng.integers(2, 10), srf, i))
    body += ('  <surfacematerial name="%s" type="material">\n'
             '    <input name="surfaceshader" type="surfaceshader" nodename="%s" />\n  </surfacematerial>\n'
             % (m, srf))
    return m, body


def make_library(n, out_dir, seed=1, textures=8, texture_size=64, kinds=KINDS):
    """Write the library; returns the documents' paths (in order)."""
    rng = np.random.default_rng(seed)
    tex_dir = os.path.join(out_dir, "textures")
    os.makedirs(tex_dir, exist_ok=True)
    tex_names = []
    for t in range(textures):
        name = "tex_%03d.png" % t
        write_png(os.path.join(tex_dir, name), texture(rng, texture_size))
        tex_names.append(name)
    paths = []
    for i in range(n):
        kind = kinds[i % len(kinds)]
        folder = os.path.join(out_dir, "m%03d" % (i // PER_FOLDER))
        os.makedirs(folder, exist_ok=True)
        tex = "../textures/" + tex_names[rng.integers(len(tex_names))]
        name, body = material(kind, i, rng, tex)
        path = os.path.join(folder, "%s_%05d.mtlx" % (kind.lower(), i))
        text = ('<?xml version="1.0"?>\n<!-- tools/make_library.py: material %d of %d (%s), seed %d -->\n'
                '<materialx version="1.39" colorspace="lin_rec709">\n%s</materialx>\n' % (i, n, kind, seed, body))
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        paths.append(path)
    return paths


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("n", type=int, help="number of materials")
    ap.add_argument("out_dir", metavar="OUTDIR")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--textures", type=int, default=8, help="distinct texture images (default: 8)")
    ap.add_argument("--texture-size", type=int, default=64, metavar="PX", help="texture width and height (64)")
    ap.add_argument("--kinds", default=",".join(KINDS), help="comma-separated, of: %s" % ", ".join(KINDS))
    args = ap.parse_args(argv)
    kinds = tuple(k.strip() for k in args.kinds.split(",") if k.strip())
    unknown = [k for k in kinds if k not in KINDS]
    if unknown or not kinds:
        ap.error("--kinds: %s is not one of %s" % (", ".join(unknown) or "nothing", ", ".join(KINDS)))
    if args.n < 1 or args.textures < 1 or args.texture_size < 2:
        ap.error("N and --textures must be at least 1, --texture-size at least 2")
    paths = make_library(args.n, args.out_dir, args.seed, args.textures, args.texture_size, kinds)
    print("%d materials in %s (%d textures)" % (len(paths), args.out_dir, args.textures))
    return 0


if __name__ == "__main__":
    sys.exit(main())
