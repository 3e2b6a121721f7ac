#!/usr/bin/env python3
"""Edit-to-pixel latency of `mtlxgen view`: from a document's write to the end of the first frame that shows the
change, for mtlxgen's generator and for MaterialX's Python GenGlsl driven the same way (the same Viewer, window,
file watcher, reload thread, text comparison, frames and driver; only the generator differs).

usage: bench_latency.py [--edits N] [--size N] [--kind value|connection|both] [--edit-samples N] [--offscreen]

Two kinds of edit of a standard_surface material, N each (default 10), each giving text not seen before:
  value       its base_color value;
  connection  its base_color fed by a node of a new name (a multiply of a checkerboard, then a constant, in
              turn): new text, linked anew.
What is measured: perf_counter from just before the file is written to ctx.finish() after the first frame drawn
with the edit's result (the viewer's generation advanced, that frame drew it, no problems shown); the picture is
still and converged before each write. That first frame is the viewer's quick frame after a change: EDIT_SAMPLES
environment samples a lobe (1; --edit-samples N to draw it with N), the same for every row; the following
frames accumulate 16 samples each (not measured). The window is 256x256 with the environment behind the sphere.

Rows:
  mtlxgen                   the viewer as `mtlxgen view` runs it, with two things only our generator gives it:
                            a value edit compares the document's XML with the one the drawn shader came from and,
                            where only input values of the shader's public uniforms changed, sets them on the
                            linked program without generating (Viewer._value_edit; the generator's manifest and
                            input locations say which uniform each input sets); and the zero-weight
                            specialization (OurGenerator.specialize: inputs at zero are constants, their lobes
                            left out of the code: a smaller shader that compiles and draws faster);
  mtlxgen, complete         our generator with the complete interface (no specialization; value edits still skip
                            the generator);
  MaterialX                 MaterialX's GenGlsl in the same viewer: a value edit regenerates on the reload thread,
                            the text compared with the drawn one differs only in initial values, so the program
                            is kept and the values set (the viewer's shortcut, which MaterialXView lacks);
  MaterialX, relink always  MaterialX's GenGlsl relinking on every change, as MaterialXView does.
The runs take turns, edit by edit, so the machine's load falls on them alike. The medians are printed with the
time to the edit's result applied (values set, or the program linked; the first frame then also JIT-compiles a
new program on llvmpipe) and the ratios of ours to each. Mesa's shader cache is turned off
(MESA_SHADER_CACHE_DISABLE) so that a link is a compile, as for an edit never seen before. A glfw window where a
display is (run it under `xvfb-run -a` on machines without one), else an offscreen framebuffer (--offscreen
forces it). On machines without a GPU this measures Mesa's llvmpipe; run it where a GPU is lent for the hardware
figure. Timings only.
"""
import argparse
import os
import statistics
import sys
import tempfile
import time

os.environ.setdefault("MESA_SHADER_CACHE_DISABLE", "true")     # before any GL context: every link compiles
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from mtlxgen.emit import emitter as emit
from mtlxgen.apps import view  # noqa: E402
from mtlxgen.base.diagnostics import Loc, MtlxError  # noqa: E402
from mtlxgen.apps.view import Generated, GlfwWindow, OffscreenWindow, OurGenerator, Viewer  # noqa: E402

DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  <checkerboard name="chk" type="color3">
    <input name="color1" type="color3" value="0.9, 0.5, 0.1" />
    <input name="uvtiling" type="vector2" value="8, 8" />
  </checkerboard>
  {node}
  <standard_surface name="SR" type="surfaceshader">
    <input name="base_color" type="color3" {base_color} />
    <input name="specular_roughness" type="float" value="0.3" />
    <input name="metalness" type="float" value="0.2" />
    <input name="coat" type="float" value="0.4" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
</materialx>
"""


class MaterialXGenerator:
    """MaterialX's GenGlsl (the `materialx` wheel) behind the viewer's generator interface."""

    def __init__(self):
        from mtlxgen.apps.reference import MaterialXReference
        self.ref = MaterialXReference()

    def open(self, path, environment):
        try:
            return path, self.ref.load(path)
        except Exception as e:
            raise MtlxError((Loc(path, 0), "MaterialX could not read it: %s" % e)) from None

    def elements(self, handle):
        return [e.getNamePath() for e in self.ref.mx_gen.findRenderableElements(handle[1])]

    def shader(self, handle, name):
        path, doc = handle
        vs, fs, textures, _ = self.ref.generate(path, name, doc=doc)
        manifest = {"textures": [{"uniform": k, "file": v} for k, v in sorted(textures.items())]}
        return Generated(name, emit.file_stem(name), vs, fs, manifest)

    def files(self, handle):
        return {os.path.abspath(handle[0])}


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def state(kind, i):
    """The document of edit i: a value not used before, or base_color fed by a node of a name not used before."""
    if kind == "value":
        return DOC.format(node="", base_color='value="%.3f, 0.3, 0.2"' % (0.1 + 0.01 * i))
    if i % 2:
        node = ('<constant name="c%d" type="color3"><input name="value" type="color3" value="0.2, 0.3, 0.2" />'
                '</constant>' % i)
    else:
        node = ('<multiply name="m%d" type="color3"><input name="in1" type="color3" nodename="chk" />'
                '<input name="in2" type="float" value="0.8" /></multiply>' % i)
    return DOC.format(node=node, base_color='nodename="%s%d"' % ("c" if i % 2 else "m", i))


def one_edit(viewer, window, path, text, timeout=120.0):
    """(seconds from writing `text` to `path` to the end of the first frame drawn with its result (the values set,
    or the shader linked, with no problems shown), seconds to the result applied)."""
    deadline = time.time() + timeout
    while (not viewer.converged() or viewer.reloader.busy()) and time.time() < deadline:    # still, nothing pending
        window.poll()
        viewer.frame(window.screen)
        window.swap()
    time.sleep(0.05)
    generation = viewer.generation
    applied = None
    t0 = time.perf_counter()
    write(path, text)
    while time.time() < deadline:          # the viewer's own loop (view.run): poll, frame, swap
        window.poll()
        viewer.poll()                      # what frame() does first, here to time it apart
        if applied is None and viewer.generation > generation:
            applied = time.perf_counter()
        viewer.frame(window.screen)
        if viewer.generation > generation and viewer.shown_generation == viewer.generation \
                and not viewer.problems:
            window.ctx.finish()
            t1 = time.perf_counter()
            window.swap()
            break
        window.swap()
    else:
        raise RuntimeError("no reload within %.0f s (problems: %s)" % (timeout, viewer.problems))
    return t1 - t0, (applied or t1) - t0


def measure(runs, window, size, kind, edits):
    """{run name: [(latency, to applied) of each edit]}; the runs take turns edit by edit (the machine's load
    shared alike)."""
    viewers = []
    for name, generator, keep in runs:
        folder = tempfile.mkdtemp(prefix="mtlxgen_latency_")
        path = os.path.join(folder, "latency.mtlx")
        write(path, state(kind, 0))
        viewer = Viewer(window.ctx, path, size=(size, size), generator=generator, background=True,
                        out=open(os.devnull, "w"), keep_program=keep, samples=16)      # converged in a frame
        viewers.append((name, viewer, path))
    out = {name: [] for name, _, _ in viewers}
    try:
        for i in range(1, edits + 2):           # the first edit warms up (Python's caches, the driver)
            for name, viewer, path in viewers:
                t = one_edit(viewer, window, path, state(kind, i))
                if i > 1:
                    out[name].append(t)
    finally:
        for _, viewer, _ in viewers:
            viewer.close()
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--edits", type=int, default=10)
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--kind", choices=("value", "connection", "both"), default="both")
    ap.add_argument("--edit-samples", type=int, default=view.EDIT_SAMPLES,
                    help="environment samples of the first frame after an edit (default: the viewer's, %d)"
                         % view.EDIT_SAMPLES)
    ap.add_argument("--offscreen", action="store_true", help="an offscreen framebuffer even where a display is")
    args = ap.parse_args()
    view.EDIT_SAMPLES = args.edit_samples
    window = OffscreenWindow((args.size, args.size)) if args.offscreen or not os.environ.get("DISPLAY") \
        else GlfwWindow((args.size, args.size))
    print("renderer: %s (%s); first frame after an edit: %d sample%s a lobe" % (
        window.ctx.info.get("GL_RENDERER", "?"), type(window).__name__, view.EDIT_SAMPLES,
        "" if view.EDIT_SAMPLES == 1 else "s"))
    kinds = ("value", "connection") if args.kind == "both" else (args.kind,)
    try:
        mx = MaterialXGenerator()
        runs = [("mtlxgen", OurGenerator(), True), ("mtlxgen, complete", OurGenerator(specialize=False), True),
                ("MaterialX", mx, True), ("MaterialX, relink always", mx, False)]
        print("%-11s %-26s %10s %11s %10s %10s" % ("edit", "generator", "median ms", "applied ms", "min ms",
                                                   "max ms"))
        for kind in kinds:
            times = measure(runs, window, args.size, kind, args.edits)
            medians = {name: statistics.median(x for x, _ in t) for name, t in times.items()}
            for name, t in times.items():
                print("%-11s %-26s %10.1f %11.1f %10.1f %10.1f" % (
                    kind, name, 1000 * medians[name], 1000 * statistics.median(a for _, a in t),
                    1000 * min(x for x, _ in t), 1000 * max(x for x, _ in t)))
            for name, _, _ in runs[1:]:
                print("%-11s ratio mtlxgen / %s: %.2f" % (kind, name, medians["mtlxgen"] / medians[name]))
    finally:
        window.close()


if __name__ == "__main__":
    main()
