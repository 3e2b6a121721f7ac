"""Draw time of the prefiltered environment against 64-sample FIS (issue 27: prefiltered <= 0.2x on llvmpipe),
and the prefilter pass's own time. For each of the seven materials of docs/measuring.md: the median of --runs draws
of the fis shader at 64 samples and of the prefiltered one (same renderer, the prefiltered map made beforehand);
the ratio of the totals on the last line.

    python benchmarks/bench_environment.py [--size 256] [--runs 5]
"""
import argparse
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "tests"))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args(argv)
    import numpy as np
    from mtlxgen.draw import environment, renderer as render
    from mtlxgen import pipeline
    from test_environment_prefilter import SEVEN

    def median_draw(r, prepared):
        times = []
        for _ in range(args.runs):
            t0 = time.perf_counter()
            r.draw(prepared)
            r.ctx.finish()
            times.append(time.perf_counter() - t0)
        return float(np.median(times))

    with render.Renderer(size=args.size) as r:
        t0 = time.perf_counter()
        r.prefiltered_env()
        r.ctx.finish()
        print("prefilter pass (%dx%d, %d samples a texel): %.0f ms" % (
            *r.env.size, environment.PREFILTER_SAMPLES, 1000 * (time.perf_counter() - t0)))
        totals = [0.0, 0.0]
        for rel, el in SEVEN:
            path = os.path.join(ROOT, "examples", rel)
            times = []
            for method in ("fis", "prefiltered"):
                (s,) = pipeline.generate(path, elements=[el], environment=method)
                p = r.prepare(s.vertex, s.fragment, s.manifest)
                try:
                    r.draw(p)                   # first draw: compile, bind
                    r.ctx.finish()
                    times.append(median_draw(r, p))
                finally:
                    p.release()
            totals[0] += times[0]
            totals[1] += times[1]
            print("%-18s fis64 %7.1f ms  prefiltered %6.1f ms  ratio %.3f" % (el, 1000 * times[0], 1000 * times[1],
                                                                               times[1] / times[0]))
        print("all: fis64 %.1f ms, prefiltered %.1f ms, ratio %.3f" % (1000 * totals[0], 1000 * totals[1],
                                                                       totals[1] / totals[0]))


if __name__ == "__main__":
    main()
