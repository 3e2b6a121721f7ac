#!/usr/bin/env python3
"""Developer tool: our render vs MaterialX's for elements of one document, both drawn in the scoreboard's
scene (mtlxgen.draw.renderer.Renderer.scoreboard), with side-by-side images (ours | MaterialX | diff x8).

usage: tools/parity.py FILE.mtlx [ELEMENT ...] [--out DIR] [--color-management]
Images go to --out, or else to a fresh temporary directory (printed).
--color-management turns MaterialX's colour-management system on (the scoreboard runs without one).
"""
import argparse
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
# MaterialX resolves resources/... file names against the scoreboard's corpus where it exists
CORPUS = os.path.join(ROOT, "..", "shared", "corpus", "materialx")

import numpy as np  # noqa: E402

from mtlxgen.draw import compare
from mtlxgen.base import images
from mtlxgen import pipeline  # noqa: E402
from mtlxgen.base.diagnostics import MtlxError  # noqa: E402
from mtlxgen.apps.reference import MaterialXReference  # noqa: E402
from mtlxgen.draw.renderer import Renderer  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file")
    ap.add_argument("elements", nargs="*")
    ap.add_argument("--out", default=None, help="folder for the images (default: a new temporary folder)")
    ap.add_argument("--color-management", action="store_true")
    args = ap.parse_args()
    ref = MaterialXReference([CORPUS] if os.path.isdir(CORPUS) else [], color_management=args.color_management)
    harness = Renderer.scoreboard()
    path = os.path.abspath(args.file)
    out_dir = args.out or tempfile.mkdtemp(prefix="parity-")
    os.makedirs(out_dir, exist_ok=True)
    print("images in %s" % out_dir)
    passed = total = 0
    for element in args.elements or ref.elements(path):
        total += 1
        try:
            vs, fs, tex, _ = ref.generate(path, element)
            theirs, _ = harness.render_timed(vs, fs, None, tex)
        except Exception as e:
            print("%-40s MaterialX cannot render it: %s" % (element, str(e).splitlines()[0][:80]))
            continue
        try:
            shader = pipeline.generate(path, elements=[element])[0]
            mine, _ = harness.render_timed(shader.vertex, shader.fragment, None,
                                           {t["uniform"]: t["file"] for t in shader.manifest["textures"]})
        except MtlxError as e:
            print("%-40s ours: %s" % (element, e.lines()[0]))
            continue
        except Exception as e:
            print("%-40s ours does not compile: %s" % (element, str(e).strip().splitlines()[-1][:100]))
            continue
        p = compare.parity(mine, theirs)
        passed += p.passes
        a, b = images.to_srgb8(mine)[..., :3], images.to_srgb8(theirs)[..., :3]
        d = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(-1)
        heat = np.repeat(np.clip(d * 8, 0, 255)[..., None], 3, -1).astype(np.uint8)
        out = os.path.join(out_dir, element.replace("/", "_") + ".png")
        images.write_image(out, np.concatenate([a, b, heat], axis=1))
        print("%-40s %s  %s  %s" % (element, "PASS" if p.passes else "FAIL", p, out))
    print("%d / %d at parity" % (passed, total))


if __name__ == "__main__":
    main()
