#!/usr/bin/env python3
"""Developer tool: each float and colour input of a shader set outside its usual range, ours against MaterialX's
(issue 16: documents written by converters carry such values, e.g. a base colour fed from a world position).

For every float, color3 and vector2 input of each nodedef named, a document of one shader node (a BSDF node: under a
surface, layered over an Oren-Nayar base) with that input alone set to each of --floats (a float), --colors (a
colour) or --vectors (a vector2), drawn by us and by MaterialX (colour management on) in the
scoreboard's scene. Prints the inputs off parity, with a side-by-side image (ours | MaterialX | difference x8)
under --out. It measures; what is off is judged elsewhere (docs/differences/README.md: a mix factor outside
[0, 1] is one of ours on purpose).

usage: tools/range_sweep.py [ND_standard_surface_surfaceshader ND_dielectric_bsdf ...] [--floats -0.5,2.5]
                            [--colors "-0.5, 0.3, 1.5;2.5, 2.5, 2.5"] [--vectors "-0.5, 0.3;2.5, 2.5"] [--out DIR]
"""
import argparse
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import numpy as np  # noqa: E402

from mtlxgen.draw import compare
from mtlxgen.base import images
from mtlxgen import pipeline  # noqa: E402
from mtlxgen.apps.reference import MaterialXReference  # noqa: E402
from mtlxgen.draw.renderer import Renderer  # noqa: E402

SHADERS = ["ND_standard_surface_surfaceshader", "ND_gltf_pbr_surfaceshader", "ND_open_pbr_surface_surfaceshader",
           "ND_UsdPreviewSurface_surfaceshader"]
DOC = ('<?xml version="1.0"?>\n<materialx version="1.39">\n<%(node)s name="s" type="surfaceshader">'
       '<input name="%(input)s" type="%(type)s" value="%(value)s" /></%(node)s>'
       '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" />'
       '</surfacematerial>\n</materialx>\n')
# a BSDF nodedef: its node under a surface, over an Oren-Nayar base (so that what a lobe lets through shows)
BSDF_DOC = ('<?xml version="1.0"?>\n<materialx version="1.39">\n<%(node)s name="b" type="BSDF">'
            '<input name="%(input)s" type="%(type)s" value="%(value)s" /></%(node)s>'
            '<oren_nayar_diffuse_bsdf name="d" type="BSDF"><input name="color" type="color3" value="0.5, 0.4, 0.3" />'
            '</oren_nayar_diffuse_bsdf><layer name="l" type="BSDF"><input name="top" type="BSDF" nodename="b" />'
            '<input name="base" type="BSDF" nodename="d" /></layer>'
            '<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="l" /></surface>'
            '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" />'
            '</surfacematerial>\n</materialx>\n')


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("nodedefs", nargs="*", default=SHADERS)
    ap.add_argument("--floats", default="-0.5,2.5")
    ap.add_argument("--colors", default="-0.5, 0.3, 1.5;2.5, 2.5, 2.5")
    ap.add_argument("--vectors", default="-0.5, 0.3;2.5, 2.5", help="vector2 values (BSDF roughness)")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    values = {"float": args.floats.split(","), "color3": args.colors.split(";"), "vector2": args.vectors.split(";")}
    out = args.out or tempfile.mkdtemp(prefix="range-")
    os.makedirs(out, exist_ok=True)
    ref = MaterialXReference(color_management=True)
    mx = ref.mx
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    off = total = 0
    with tempfile.TemporaryDirectory() as tmp, Renderer.scoreboard() as harness:
        for name in args.nodedefs:
            nd = lib.getNodeDef(name)
            if nd is None:
                print("%s: no such nodedef in MaterialX's libraries" % name)
                continue
            for inp in nd.getActiveInputs():
                for value in values.get(inp.getType(), ()):
                    path = os.path.join(tmp, "doc.mtlx")
                    doc = BSDF_DOC if nd.getType() == "BSDF" else DOC
                    with open(path, "w") as f:
                        f.write(doc % {"node": nd.getNodeString(), "input": inp.getName(), "type": inp.getType(),
                                       "value": value.strip()})
                    total += 1
                    try:
                        shader = pipeline.generate(path, elements=["m"])[0]
                        ours, _ = harness.render_timed(shader.vertex, shader.fragment, None, {})
                        vs, fs, tex, _ = ref.generate(path, "m")
                        theirs, _ = harness.render_timed(vs, fs, None, tex)
                    except Exception as e:             # noqa: BLE001 (a tool: report and go on)
                        print("%s %s = %s: %s" % (nd.getNodeString(), inp.getName(), value, str(e).splitlines()[-1]))
                        continue
                    p = compare.parity(ours, theirs)
                    if p.passes:
                        continue
                    off += 1
                    a, b = images.to_srgb8(ours)[..., :3], images.to_srgb8(theirs)[..., :3]
                    d = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(-1)
                    heat = np.repeat(np.clip(d * 8, 0, 255)[..., None], 3, -1).astype(np.uint8)
                    image = os.path.join(out, "%s_%s_%s.png" % (nd.getNodeString(), inp.getName(),
                                                                value.replace(",", "_").replace(" ", "")))
                    images.write_image(image, np.concatenate([a, b, heat], axis=1))
                    print("%s %s = %s: %s  %s" % (nd.getNodeString(), inp.getName(), value.strip(), p, image),
                          flush=True)
    print("%d of %d off parity; images in %s" % (off, total, out))


if __name__ == "__main__":
    main()
