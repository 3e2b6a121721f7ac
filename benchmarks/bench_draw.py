#!/usr/bin/env python3
"""Draw time of our shaders over MaterialX's, for the same elements in the same harness and run.

usage: bench_draw.py [FILE.mtlx ...] [--repeat N] [--size N] [--environment fis|prefiltered] [--skip PATTERN]
Default files: the corpus Examples (StandardSurface, OpenPbr, GltfPbr, UsdPreviewSurface, ...) of
../shared/corpus, or where that is absent (a clone) the two Examples copied in tests/data/materialx.
Each element is drawn --repeat times per shader (after one warm-up draw); the median draw time of
each is kept and the totals' ratio printed. On machines without a GPU this measures Mesa's llvmpipe;
run it where a GPU is lent to measure hardware. Timings only: nothing asserts.
"""
import argparse
import glob
import os
import statistics
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from mtlxgen import pipeline  # noqa: E402
from mtlxgen.base.diagnostics import MtlxError  # noqa: E402
from mtlxgen.apps.reference import MaterialXReference  # noqa: E402
from mtlxgen.draw.renderer import Renderer  # noqa: E402

CORPUS = os.path.join(ROOT, "..", "shared", "corpus", "materialx")
if not os.path.isdir(CORPUS):
    CORPUS = os.path.join(ROOT, "tests", "data", "materialx")
DEFAULT = sorted(glob.glob(os.path.join(CORPUS, "resources", "Materials", "Examples", "*", "*.mtlx")))


def timed_draws(renderer, vs, fs, manifest, textures, repeat):
    renderer.render_timed(vs, fs, manifest, textures)          # compile + warm-up
    times = []
    for _ in range(repeat):
        _, t = renderer.render_timed(vs, fs, manifest, textures)
        times.append(t["draw_s"])
    return statistics.median(times)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--environment", choices=("fis", "prefiltered"), default="fis",
                    help="our environment method (MaterialX's is always its default, FIS)")
    ap.add_argument("--skip", action="append", default=[], metavar="PATTERN",
                    help="skip files whose path contains PATTERN (e.g. chess_set: seconds per draw on llvmpipe)")
    args = ap.parse_args()
    ref = MaterialXReference([CORPUS])
    ours_total = theirs_total = 0.0
    n = 0
    with Renderer(size=args.size) as r:
        print("renderer: %s" % r.ctx.info.get("GL_RENDERER", "?"))
        for path in [os.path.abspath(f) for f in (args.files or DEFAULT)]:
            if any(p in path for p in args.skip):
                continue
            try:
                elements = ref.elements(path)
            except Exception:
                continue
            for element in elements:
                try:
                    vs, fs, tex, _ = ref.generate(path, element)
                    shader = pipeline.generate(path, elements=[element], environment=args.environment)[0]
                    theirs = timed_draws(r, vs, fs, {}, tex, args.repeat)
                    ours = timed_draws(r, shader.vertex, shader.fragment, shader.manifest, None, args.repeat)
                except (MtlxError, Exception) as e:
                    print("%-60s skipped: %s" % (os.path.basename(path) + ":" + element,
                                                 (e.lines()[0] if isinstance(e, MtlxError) else str(e).strip().splitlines()[-1])[:90]))
                    continue
                n += 1
                ours_total += ours
                theirs_total += theirs
                print("%-60s ours %7.2f ms  MaterialX %7.2f ms  ratio %.2f" % (
                    os.path.basename(path) + ":" + element, 1e3 * ours, 1e3 * theirs, ours / theirs))
    if n:
        print("overall: %d elements, draw-time ratio (ours / MaterialX) %.2f" % (n, ours_total / theirs_total))


if __name__ == "__main__":
    main()
