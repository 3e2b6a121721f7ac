#!/usr/bin/env python3
"""Our shaders against MaterialX's GenGlsl on real GPU shader compilers, with no GPU: Mesa 25's hardware drivers
compiling through no-op DRM shims and RADV's null winsys (../shared/tools/gpu_proxy, README there). Installs
nothing: the drivers come from `bash ../shared/tools/gpu_proxy/setup.sh` (once, ~1 min, into /opt/gpuproxy;
GPUPROXY_PREFIX names another place), and this script says so when they are missing.

usage: bench_gpu_compilers.py [FILE.mtlx ...] [--backends radv-aco,nouveau] [--only TEXT] [-n N] [--modes ...]
                              [--baseline CHECKOUT]

Default files: bench_shaders.py's eight elements plus MaterialX's OpenPbr Examples (../shared/corpus). For each
element, interface (complete against complete, reduced against reduced: MaterialX's SHADER_INTERFACE_REDUCED) and
backend, both shaders are compiled n times and reported as ours / MaterialX's:
  cpu       compile process-CPU seconds, median of n (robust to the machine's load; compare ratios of one run).
            Vulkan rows: vkCreateGraphicsPipelines of the SPIR-V (glslangValidator -V) with RADV's cache off;
            GL rows: compile + link + first draw in a fresh process
  instr     the backend's instruction count of the fragment shader
  regs      VGPRs (RADV) or GPRs (nouveau) the fragment shader takes
  spill     RADV: spilled VGPRs + SGPRs; nouveau: bytes of local memory (spills and indexed arrays)
  br        ACO's branch instructions (RADV; nouveau's codegen reports none: '-')
  loops     loops left in the final NIR (RADV; '-' elsewhere)
Backends (measure.py's): radv-aco (AMD RDNA2, Vulkan), nouveau (NVIDIA ISA, NV192/AD102, GL 4.3), radv-llvm,
radeonsi-aco, radeonsi-llvm, nouveau-kepler, llvmpipe. The last line holds the ratios of the totals over all
elements, per backend and interface. Shaders are generated as the scoreboard does (colour management on both
sides; ours with its defaults: FIS environment, no light loop). Timings only: nothing asserts.

--baseline CHECKOUT: a change's before and after in one run: the other side is not MaterialX's but ours as another
copy of the project generates it (a folder holding mtlxgen/ and glsl_lib/, e.g. `git archive HEAD mtlxgen glsl_lib`
unpacked, or a `git worktree`); the columns then read ours / the baseline's.
"""
import argparse
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))

PREFIX = os.environ.get("GPUPROXY_PREFIX", "/opt/gpuproxy")
GPU_PROXY = os.path.normpath(os.path.join(ROOT, "..", "shared", "tools", "gpu_proxy"))
SETUP = "bash ../shared/tools/gpu_proxy/setup.sh"
OPENPBR = "OpenPbr"
COLUMNS = ("cpu", "instr", "regs", "spill", "br", "loops")


def missing_tools():
    """Why the benchmark cannot run here (one line), or None."""
    if not os.path.exists(os.path.join(GPU_PROXY, "measure.py")):
        return "the GPU compiler proxies' tools are missing (%s/measure.py): the benchmark needs ../shared" % GPU_PROXY
    absent = [t for t in ("vkpipe", "glpipe") if not os.access(os.path.join(PREFIX, t), os.X_OK)]
    if absent:
        return ("the GPU compiler proxies are not installed (no %s in %s): run `%s` once from the project root "
                "(~1 min)" % (", ".join(absent), PREFIX, SETUP))
    if not shutil.which("glslangValidator"):
        return "glslangValidator is not on PATH (Vulkan rows compile SPIR-V): apt-get install glslang-tools"
    return None


def load_measure():
    os.environ.setdefault("GPUPROXY_PREFIX", PREFIX)
    spec = importlib.util.spec_from_file_location("gpu_proxy_measure", os.path.join(GPU_PROXY, "measure.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def default_files(examples):
    from bench_shaders import DEFAULT
    files = [os.path.join(examples, f) for f in DEFAULT]
    folder = os.path.join(examples, OPENPBR)
    if os.path.isdir(folder):
        files += [os.path.join(folder, f) for f in sorted(os.listdir(folder)) if f.endswith(".mtlx")]
    return [f for f in dict.fromkeys(files) if os.path.exists(f)]


def write_ours(path, element, mode, target, stem):
    from mtlxgen import pipeline
    s = pipeline.generate(path, elements=[element], interface=mode, target=target)[0]
    _write(stem, s.vertex, s.fragment)


def write_theirs(ref, path, element, mode, target, stem):
    """MaterialX's GenGlsl (GlslShaderGenerator, or VkShaderGenerator for Vulkan) as gen_shaders.py and the
    scoreboard make it: colour management on, the reduced interface for mode 'reduced'."""
    mx_gen = ref.mx_gen
    doc = ref.load(path)
    gen = (ref.mx_glsl.VkShaderGenerator if target == "vulkan" else ref.mx_glsl.GlslShaderGenerator).create()
    cms = mx_gen.DefaultColorManagementSystem.create(gen.getTarget())
    cms.loadLibrary(ref.lib)
    gen.setColorManagementSystem(cms)
    ctx = mx_gen.GenContext(gen)
    if mode == "reduced":
        ctx.getOptions().shaderInterfaceType = mx_gen.ShaderInterfaceType.SHADER_INTERFACE_REDUCED
    ctx.registerSourceCodeSearchPath(ref.search)
    shader = gen.generate("s", doc.getDescendant(element), ctx)
    _write(stem, shader.getSourceCode(mx_gen.VERTEX_STAGE), shader.getSourceCode(mx_gen.PIXEL_STAGE))


_BASELINE = """
import sys
sys.path.insert(0, sys.argv[1])
from mtlxgen import pipeline
s = pipeline.generate(sys.argv[2], elements=[sys.argv[3]], interface=sys.argv[4], target=sys.argv[5])[0]
open(sys.argv[6] + ".vert", "w").write(s.vertex)
open(sys.argv[6] + ".frag", "w").write(s.fragment)
"""


def write_baseline(checkout, path, element, mode, target, stem):
    """Ours as the project copy in `checkout` generates it (its own mtlxgen and glsl_lib, in a fresh process)."""
    p = subprocess.run([sys.executable, "-c", _BASELINE, checkout, path, element, mode, target, stem],
                       capture_output=True, text=True, cwd=checkout)
    if p.returncode:
        raise RuntimeError("baseline %s: %s" % (checkout, (p.stdout + p.stderr).strip().splitlines()[-1]))


def _write(stem, vertex, fragment):
    with open(stem + ".vert", "w") as f:
        f.write(vertex)
    with open(stem + ".frag", "w") as f:
        f.write(fragment)


def spirv(stem):
    for stage in ("vert", "frag"):
        p = subprocess.run(["glslangValidator", "-V", "-o", "%s.%s.spv" % (stem, stage), "%s.%s" % (stem, stage)],
                           capture_output=True, text=True)
        if p.returncode:
            raise RuntimeError("glslangValidator: %s" % (p.stdout + p.stderr).strip().splitlines()[-1])


def figures(res):
    """The row's six figures from measure.py's result (None where the backend does not report one)."""
    if "error" in res:
        return None
    spill = None
    if res.get("spill_vgprs") is not None or res.get("spill_sgprs") is not None:
        spill = (res.get("spill_vgprs") or 0) + (res.get("spill_sgprs") or 0)
    elif res.get("local_bytes") is not None:
        spill = res["local_bytes"]
    regs = res.get("vgprs") if res.get("vgprs") is not None else res.get("gprs")
    return {"cpu": res.get("cpu_s"), "instr": res.get("instructions"), "regs": regs, "spill": spill,
            "br": res.get("branches"), "loops": res.get("nir_loops")}


def compile_one(measure, backend, stem, n, tmp):
    kind, extra = measure.BACKENDS[backend]
    if kind == "vk":
        row = {"vert_spv": stem + ".vert.spv", "frag_spv": stem + ".frag.spv"}
        irdir = os.path.join(tmp, "ir_%s_%s" % (backend, os.path.basename(stem)))
        shutil.rmtree(irdir, ignore_errors=True)
        return measure.run_vk(backend, extra, row, n, irdir)
    return measure.run_gl(backend, extra, {"vert": stem + ".vert", "frag": stem + ".frag"}, n)


def fmt(v, key):
    if v is None:
        return "-"
    return "%.2f" % v if key == "cpu" else "%d" % v


def ratio(a, b):
    """a / b; '-' where a backend reports no figure or b is 0 (both 0: 'same')."""
    if a is None or b is None or b == 0:
        return "same" if a == 0 and b == 0 else "-"
    return "%.2f" % (a / b)


def cell(o, m, c):
    r = ratio(o, m)
    if r == "same":
        return "%s/%s" % (fmt(o, c), fmt(m, c))
    if o is None and m is None:
        return "-"
    return "%s/%s=%s" % (fmt(o, c), fmt(m, c), r)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*")
    ap.add_argument("--backends", default="radv-aco,nouveau", help="comma-separated (default radv-aco,nouveau)")
    ap.add_argument("--only", help="elements whose file name or element path contains this text")
    ap.add_argument("-n", type=int, default=1, help="compiles per shader and backend (median; default 1)")
    ap.add_argument("--modes", default="complete,reduced")
    ap.add_argument("--keep", help="write the shaders into this folder (default: a temporary one)")
    ap.add_argument("--baseline", metavar="CHECKOUT", help="compare with ours from this copy of the project instead "
                    "of MaterialX's (a change's before and after in one run)")
    args = ap.parse_args()
    if args.baseline and not os.path.isdir(os.path.join(args.baseline, "mtlxgen")):
        print("bench_gpu_compilers: --baseline %s: no mtlxgen/ there (a copy of the project is needed)" % args.baseline)
        return 1
    other = "base" if args.baseline else "MX"

    why = missing_tools()
    if why:
        print("bench_gpu_compilers: %s" % why)
        return 1
    measure = load_measure()
    backends = args.backends.split(",")
    unknown = [b for b in backends if b not in measure.BACKENDS]
    if unknown:
        print("bench_gpu_compilers: unknown backend %s (known: %s)" % (", ".join(unknown), ", ".join(measure.BACKENDS)))
        return 1
    modes = args.modes.split(",")
    from bench_shaders import CORPUS, EXAMPLES
    from mtlxgen.apps.reference import MaterialXReference, ReferenceUnavailable
    try:
        ref = MaterialXReference([CORPUS], color_management=True)
    except ReferenceUnavailable as e:
        print("bench_gpu_compilers: %s" % e)
        return 1
    files = [os.path.abspath(f) for f in args.files] or default_files(EXAMPLES)
    targets = sorted({"vulkan" if measure.BACKENDS[b][0] == "vk" else "glsl" for b in backends})
    tmp = args.keep or tempfile.mkdtemp(prefix="bench_gpu_")
    os.makedirs(tmp, exist_ok=True)
    print("gpu_proxy: %s (Mesa 25 drivers), backends %s, %d compile%s each, load average %.1f %.1f %.1f" % (
        PREFIX, ",".join(backends), args.n, "s" if args.n > 1 else "", *os.getloadavg()))
    head = "%-40s %-12s %-8s" % ("element", "backend", "mode")
    for c in COLUMNS:
        head += " %18s" % ("%s ours/%s=ratio" % (c, other) if c == "cpu" else c)
    print(head)
    totals = {}          # (backend, mode) -> {column: [ours, theirs]}
    count = 0
    t_start = time.time()
    try:
        for path in files:
            only_file = args.only and args.only in os.path.basename(path)
            for element in ref.elements(path):
                label = "%s:%s" % (os.path.basename(path)[:-5], element)
                if args.only and not only_file and args.only not in element:
                    continue
                count += 1
                for mode in modes:
                    stems = {}
                    try:
                        for target in targets:
                            for who in ("ours", "mx"):
                                stem = os.path.join(tmp, "%d_%s_%s_%s" % (count, target, mode, who))
                                if who == "ours":
                                    write_ours(path, element, mode, target, stem)
                                elif args.baseline:
                                    write_baseline(os.path.abspath(args.baseline), path, element, mode, target, stem)
                                else:
                                    write_theirs(ref, path, element, mode, target, stem)
                                if target == "vulkan":
                                    spirv(stem)
                                stems[target, who] = stem
                    except Exception as e:     # a document either side cannot do: reported, the run goes on
                        print("%-40s %-12s %-8s skipped: %s" % (label[:40], "", mode,
                                                               str(e).strip().splitlines()[-1][:90]))
                        continue
                    for backend in backends:
                        target = "vulkan" if measure.BACKENDS[backend][0] == "vk" else "glsl"
                        res = [compile_one(measure, backend, stems[target, who], args.n, tmp) for who in ("ours", "mx")]
                        figs = [figures(r) for r in res]
                        if None in figs:
                            bad = res[figs.index(None)]["error"].strip().splitlines()
                            print("%-40s %-12s %-8s failed (%s): %s" % (
                                label[:40], backend, mode, "ours" if figs[0] is None else other,
                                bad[-1][:90] if bad else "?"))
                            continue
                        line = "%-40s %-12s %-8s" % (label[:40], backend, mode)
                        t = totals.setdefault((backend, mode), {c: [0, 0] for c in COLUMNS})
                        for c in COLUMNS:
                            o, m = figs[0][c], figs[1][c]
                            line += " %18s" % cell(o, m, c)
                            for i, v in enumerate((o, m)):
                                t[c][i] = None if v is None or t[c][i] is None else t[c][i] + v
                        print(line, flush=True)
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)
    if not totals:
        print("bench_gpu_compilers: no element measured")
        return 1
    for (backend, mode), t in totals.items():
        line = "%-40s %-12s %-8s" % ("total", backend, mode)
        for c in COLUMNS:
            o, m = t[c]
            line += " %18s" % cell(o, m, c)
        print(line)
    print("# %d elements in %.0f s, load average %.1f %.1f %.1f" % (count, time.time() - t_start, *os.getloadavg()))
    parts = []
    for (backend, mode), t in totals.items():
        parts.append("%s %s: %s" % (backend, mode, ", ".join(
            "%s %s" % (c, ratio(*t[c])) for c in COLUMNS if ratio(*t[c]) != "-") or "-"))
    print("overall ours / %s (totals): " % ("baseline" if args.baseline else "MaterialX") + "; ".join(parts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
