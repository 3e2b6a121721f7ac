#!/usr/bin/env python3
"""Fuzz `mtlxgen generate` with seeded mutations of the fuzz seeds (tests/fuzzing.py): any count, any seed.

    python tools/fuzz.py --count 10000 --seed 1234 [--keep DIR]

Prints one line per failing case (and writes the failing document to --keep, default a fresh temporary
folder), then a summary; exits 1 when any case failed. The same checks run in the test suite on a few
hundred cases (tests/read/test_fuzz.py).
"""
import argparse
import os
import shutil
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))
sys.path.insert(0, ROOT)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=17)
    ap.add_argument("--keep", metavar="DIR", help="where failing documents go (default: a fresh temporary folder)")
    args = ap.parse_args()
    import fuzzing
    from mtlxgen.draw.renderer import create_context
    ctx = create_context()

    def compile_program(vs, fs):
        ctx.program(vertex_shader=vs, fragment_shader=fs).release()

    work = tempfile.mkdtemp(prefix="mtlxgen-fuzz-")
    keep = args.keep or tempfile.mkdtemp(prefix="mtlxgen-fuzz-failures-")
    os.makedirs(keep, exist_ok=True)
    fuzzing.prepare_case_dir(work)
    roots = fuzzing.allowed_roots(work)
    failed, t0 = 0, time.time()
    for i, seed_path, text in fuzzing.cases(args.seed, args.count, work):
        problems = fuzzing.run_case(text, work, compile_program, roots)
        if problems:
            failed += 1
            kept = os.path.join(keep, "case_%05d.mtlx" % i)
            with open(kept, "w", encoding="utf-8", errors="surrogateescape") as f:
                f.write(text)
            print("FAIL case %d (from %s, kept %s): %s" % (i, os.path.basename(seed_path), kept, "; ".join(problems)),
                  flush=True)
    shutil.rmtree(work, ignore_errors=True)
    print("fuzz: %d cases, seed %d: %d passed, %d failed in %.0f s" % (args.count, args.seed, args.count - failed,
                                                                         failed, time.time() - t0))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
