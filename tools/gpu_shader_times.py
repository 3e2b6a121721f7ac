#!/usr/bin/env python3
"""Developer tool for a session with a GPU lent (the device tool): compile-to-first-pixel and draw time of shader
pairs on that machine's driver, each pair in its own process (a fresh context: nothing cached in the driver's
process), several at a time.

usage: tools/gpu_shader_times.py DIR [--parallel N] [--limit SECONDS] [--size N]
DIR holds NAME.vert / NAME.frag pairs (e.g. `mtlxgen generate` output, ours and MaterialX's side by side). Each is
drawn in the scoreboard's scene (render.Renderer.scoreboard: a sphere, the procedural sky, 64 environment samples,
a NAME.json manifest bound where there is one): link, the first draw (glFinish), then the median of 15 draws of the
linked program. One JSON line per pair, and a
parity line (mean / share over 8 / max, in sRGB 8-bit steps) for every pair NAME_x against NAME_y of one stem where
the names end in _ours and _mx. Set __GL_SHADER_DISK_CACHE=0 (NVIDIA) or MESA_SHADER_CACHE_DISABLE=true so that
every link compiles. Timings only; the pixels are compared, nothing asserts.
"""
import argparse
import glob
import json
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def one(base, size):
    sys.path.insert(0, ROOT)
    import numpy as np
    from mtlxgen.draw.renderer import Renderer
    r = Renderer.scoreboard(size=size)
    vs, fs = open(base + ".vert").read(), open(base + ".frag").read()
    manifest = json.load(open(base + ".json")) if os.path.exists(base + ".json") else None
    if manifest is not None:        # texture files are relative to the manifest's folder
        from mtlxgen.base.interface import absolute_textures
        manifest = absolute_textures(manifest, os.path.dirname(os.path.abspath(base)))
    t0 = time.perf_counter()
    prepared = r.prepare(vs, fs, manifest)
    t1 = time.perf_counter()
    r.draw(prepared)
    r.ctx.finish()
    t2 = time.perf_counter()
    img = np.frombuffer(r.fbo.read(components=4, dtype="f4"), dtype="f4").reshape(size, size, 4)[::-1]
    draws = []
    for _ in range(15):
        r.ctx.finish()
        a = time.perf_counter()
        r.draw(prepared)
        r.ctx.finish()
        draws.append(time.perf_counter() - a)
    np.save(base + ".npy", img)
    print(json.dumps({"case": os.path.basename(base), "renderer": r.ctx.info.get("GL_RENDERER", "?"),
                      "link_ms": round(1e3 * (t1 - t0), 1), "first_draw_ms": round(1e3 * (t2 - t1), 1),
                      "draw_ms": round(1e3 * statistics.median(draws), 3)}), flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--parallel", type=int, default=4)
    ap.add_argument("--limit", type=float, default=300.0)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--one", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.one:
        return one(args.one, args.size)
    pairs = sorted(f[:-5] for f in glob.glob(os.path.join(args.dir, "*.frag")))
    pending, running, t0 = list(pairs), [], time.time()
    while pending or running:
        while pending and len(running) < args.parallel:
            p = pending.pop(0)
            running.append((p, subprocess.Popen([sys.executable, __file__, args.dir, "--one", p, "--size",
                                                 str(args.size)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                                text=True)))
        for p, proc in list(running):
            if proc.poll() is not None:
                out = proc.stdout.read().strip()
                print(out.splitlines()[-1] if out else os.path.basename(p) + ": no output", flush=True)
                if proc.returncode:
                    print("  failed: %s: %s" % (os.path.basename(p), out[-800:]), flush=True)
                running.remove((p, proc))
        if time.time() - t0 > args.limit:
            for p, proc in running:
                proc.kill()
                print("timed out: %s" % os.path.basename(p), flush=True)
            break
        time.sleep(0.1)
    import numpy as np
    sys.path.insert(0, ROOT)
    from mtlxgen.draw import compare
    for ours in sorted(glob.glob(os.path.join(args.dir, "*_ours.npy"))):
        theirs = ours[:-len("_ours.npy")] + "_mx.npy"
        if os.path.exists(theirs):
            print("parity %s: %s" % (os.path.basename(ours)[:-9],
                                     compare.parity(np.load(ours), np.load(theirs))), flush=True)


if __name__ == "__main__":
    main()
