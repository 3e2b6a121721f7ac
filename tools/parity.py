#!/usr/bin/env python3
"""Developer tool: our render vs MaterialX's for elements of one document, in the scoreboard's own
harness (../shared/tools/mxharness.py), with side-by-side images (ours | MaterialX | diff x8).

usage: tools/parity.py FILE.mtlx [ELEMENT ...] [--out DIR] [--color-management]
--color-management turns MaterialX's colour-management system on (the scoreboard runs without one).
"""
import argparse
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "..", "shared", "tools"))

import numpy as np  # noqa: E402

from mtlxgen import compare, images, pipeline  # noqa: E402
from mtlxgen.diagnostics import MtlxError  # noqa: E402
from mtlxgen.reference import MaterialXReference  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file")
    ap.add_argument("elements", nargs="*")
    ap.add_argument("--out", default="/tmp/parity")
    ap.add_argument("--color-management", action="store_true")
    args = ap.parse_args()
    import mxharness
    ref = MaterialXReference([os.path.join(ROOT, "..", "shared", "corpus", "materialx")],
                             color_management=args.color_management)
    harness = mxharness.Harness()
    path = os.path.abspath(args.file)
    os.makedirs(args.out, exist_ok=True)
    passed = total = 0
    for element in args.elements or ref.elements(path):
        total += 1
        try:
            vs, fs, tex, _ = ref.generate(path, element)
            theirs, _ = harness.render(vs, fs, tex)
        except Exception as e:
            print("%-40s MaterialX cannot render it: %s" % (element, str(e).splitlines()[0][:80]))
            continue
        try:
            shader = pipeline.generate(path, [element])[0]
            mine, _ = harness.render(shader.vertex, shader.fragment,
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
        out = os.path.join(args.out, element.replace("/", "_") + ".png")
        images.write_image(out, np.concatenate([a, b, heat], axis=1))
        print("%-40s %s  %s  %s" % (element, "PASS" if p.passes else "FAIL", p, out))
    print("%d / %d at parity" % (passed, total))


if __name__ == "__main__":
    main()
