#!/usr/bin/env python3
"""Generation time against graph size: mtlxgen and MaterialX's GenGlsl, chains and fan-ins, in the same run.

usage: bench_scale.py [--sizes 100,1000,10000,100000] [--shapes chain,fan_in,fan_out] [--timeout S] [--repeat N]

Shapes of N float nodes (tests/graph/test_generate_scale.py builds the same):
  chain    n_i = add(n_{i-1}, 0.001)
  fan_in   N/2 leaves summed by a balanced add tree (many nodes feeding one)
  fan_out  one node read by N/2 multiplies, their results summed by an add tree (one node read by many)
Each measurement runs in a process of its own (a crash or a stack overflow on one side is reported, not
fatal) and times only generation, libraries loaded: ours pipeline.generate (read, graph, GLSL); MaterialX
readFromXmlFile + setDataLibrary + GlslShaderGenerator.generate of the output in a GenContext. Each is the fastest
of --repeat runs (default 3; ours and MaterialX's taking turns; a run over 2 s is not repeated: single short runs
on a shared machine move by 30%, which made the linearity below say yes or no by chance). Prints seconds,
microseconds per node, the ratio ours / MaterialX, and whether ours is linear: its time per node at the largest
size within 1.5x of that at 1,000 nodes. Timings only: nothing asserts.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests"))

OURS = r"""
import json, sys, time
sys.path.insert(0, %r)
from mtlxgen.read import library
from mtlxgen import pipeline
library.load_library()
t = time.perf_counter()
shader, = pipeline.generate(sys.argv[1])
print(json.dumps({"seconds": time.perf_counter() - t, "bytes": len(shader.fragment)}))
""" % ROOT

MATERIALX = r"""
import json, sys, time
import MaterialX as mx
import MaterialX.PyMaterialXGenShader as mx_gen
import MaterialX.PyMaterialXGenGlsl as mx_glsl
search = mx.getDefaultDataSearchPath()
lib = mx.createDocument()
mx.loadLibraries(mx.getDefaultDataLibraryFolders(), search, lib)
gen = mx_glsl.GlslShaderGenerator.create()
ctx = mx_gen.GenContext(gen)
ctx.registerSourceCodeSearchPath(search)
t = time.perf_counter()
doc = mx.createDocument()
mx.readFromXmlFile(doc, sys.argv[1], search)
doc.setDataLibrary(lib)
shader = gen.generate("s", doc.getDescendant("out"), ctx)
code = shader.getSourceCode(mx_gen.PIXEL_STAGE)
print(json.dumps({"seconds": time.perf_counter() - t, "bytes": len(code)}))
"""


def write(path, shape, n):
    from test_generate_scale import chain, fan_in, fan_out
    lines, root = {"chain": chain, "fan_in": fan_in, "fan_out": fan_out}[shape](n)
    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<materialx version="1.39">\n%s\n<output name="out" type="float" '
                'nodename="%s" />\n</materialx>\n' % ("\n".join(lines), root))


def run(code, path, timeout):
    try:
        r = subprocess.run([sys.executable, "-c", code, path], capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, "over %d s" % timeout
    if r.returncode != 0:
        return None, "exit %d: %s" % (r.returncode, (r.stderr.strip().splitlines() or ["?"])[-1][:80])
    return json.loads(r.stdout.strip().splitlines()[-1])["seconds"], None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", default="100,1000,10000,100000")
    ap.add_argument("--shapes", default="chain,fan_in,fan_out")
    ap.add_argument("--timeout", type=int, default=600)
    ap.add_argument("--repeat", type=int, default=3, help="runs per measurement, the fastest kept (default 3)")
    args = ap.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    print("%-8s %7s  %10s %8s  %10s %8s  %6s" % ("shape", "nodes", "mtlxgen s", "us/node", "MaterialX s",
                                                  "us/node", "ratio"))
    with tempfile.TemporaryDirectory() as tmp:
        for shape in args.shapes.split(","):
            per_node = {}
            for n in sizes:
                path = os.path.join(tmp, "%s_%d.mtlx" % (shape, n))
                write(path, shape, n)
                a, why_a = run(OURS, path, args.timeout)
                b, why_b = run(MATERIALX, path, args.timeout)
                for _ in range(args.repeat - 1):
                    if a is None or b is None or max(a, b) > 2.0:
                        break
                    a = min(a, run(OURS, path, args.timeout)[0] or a)
                    b = min(b, run(MATERIALX, path, args.timeout)[0] or b)
                if a is not None:
                    per_node[n] = a / n
                print("%-8s %7d  %10s %8s  %10s %8s  %6s" % (
                    shape, n, "%.3f" % a if a is not None else why_a, "%.1f" % (1e6 * a / n) if a else "-",
                    "%.3f" % b if b is not None else why_b, "%.1f" % (1e6 * b / n) if b else "-",
                    "%.2f" % (a / b) if a and b else "-"))
            base = per_node.get(1000)
            top = max(per_node) if per_node else None
            if base and top and top > 1000:
                growth = per_node[top] / base
                print("%-8s linear: %s (time per node at %d nodes: %.2fx that at 1,000)"
                      % (shape, "yes" if growth <= 1.5 else "no", top, growth))


if __name__ == "__main__":
    main()
