#!/usr/bin/env python3
"""Our shaders against MaterialX's GenGlsl, like against like, in one run: complete interfaces against each other
and reduced ones against each other (ours: --interface reduced; MaterialX's: GenOptions.shaderInterfaceType =
SHADER_INTERFACE_REDUCED, as the scoreboard's --mx-interface reduced).

usage: bench_shaders.py [FILE.mtlx ...] [--repeat N] [--modes complete,reduced]
Default files: MaterialX's Examples StandardSurface (default, marble, brick, glass), OpenPbr (default, velvet),
GltfPbr and UsdPreviewSurface defaults from ../shared/corpus (where that is absent, the Examples in tests/data).

For each element and mode, each shader is compiled and drawn --repeat times in the scoreboard's harness
(../shared/tools/mxharness.py: 256², 64 environment samples; our Renderer.scoreboard() where ../shared is absent), with
Mesa's shader cache off so that every link compiles; the two generators take turns. Reported, as ours / MaterialX's:
  draw       the second draw's time (a drawn frame), median over the repeats
  first px   compile-to-first-pixel: link + the first draw (Mesa JIT-compiles on the first draw), median
  frag       the fragment shader's size in bytes
and per mode the ratio of the totals. Timings only: nothing asserts. On a GPU this measures the GPU's driver.
"""
import argparse
import os
import statistics
import sys

os.environ.setdefault("MESA_SHADER_CACHE_DISABLE", "true")      # before any GL library loads

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from mtlxgen import pipeline  # noqa: E402
from mtlxgen.apps.reference import MaterialXReference  # noqa: E402

SHARED_TOOLS = os.path.join(ROOT, "..", "shared", "tools")
CORPUS = os.path.join(ROOT, "..", "shared", "corpus", "materialx")
if not os.path.isdir(CORPUS):
    CORPUS = os.path.join(ROOT, "tests", "data", "materialx")
EXAMPLES = os.path.join(CORPUS, "resources", "Materials", "Examples")
DEFAULT = ["StandardSurface/standard_surface_default.mtlx", "StandardSurface/standard_surface_marble_solid.mtlx",
           "StandardSurface/standard_surface_brick_procedural.mtlx", "StandardSurface/standard_surface_glass.mtlx",
           "OpenPbr/open_pbr_default.mtlx", "OpenPbr/open_pbr_velvet.mtlx", "GltfPbr/gltf_pbr_default.mtlx",
           "UsdPreviewSurface/usd_preview_surface_default.mtlx"]


class Harness:
    """The scoreboard's harness where ../shared has it, else ours in the scoreboard's scene: render(vs, fs, textures)
    -> (image, {"link_s", "first_draw_s", "draw_s"})."""

    def __init__(self):
        if os.path.exists(os.path.join(SHARED_TOOLS, "mxharness.py")):
            sys.path.insert(0, SHARED_TOOLS)
            import mxharness
            self.impl, self.name = mxharness.Harness(), "../shared/tools/mxharness.py"
            self.render = self.impl.render
            self.gl_renderer = self.impl.ctx.info.get("GL_RENDERER", "?")
        else:
            from mtlxgen.draw.renderer import Renderer
            self.impl, self.name = Renderer.scoreboard(size=256), "mtlxgen Renderer.scoreboard()"
            self.render = lambda vs, fs, tex: self.impl.render_timed(vs, fs, None, tex)
            self.gl_renderer = self.impl.ctx.info.get("GL_RENDERER", "?")


def ours_shader(path, element, mode):
    s = pipeline.generate(path, elements=[element], interface=mode)[0]
    tex = {}
    for t in s.manifest.get("textures", []):
        f = t.get("file", "")
        if f and not os.path.isabs(f):
            f = os.path.join(os.path.dirname(path), f)
        tex[t["uniform"]] = f
    return s.vertex, s.fragment, tex


def measure(harness, shader, repeat):
    vs, fs, tex = shader
    draws, firsts = [], []
    for _ in range(repeat):
        _, t = harness.render(vs, fs, tex)
        draws.append(t["draw_s"])
        firsts.append(t["link_s"] + t["first_draw_s"])
    return statistics.median(draws), statistics.median(firsts), len(fs.encode("utf-8"))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--modes", default="complete,reduced")
    args = ap.parse_args()
    files = [os.path.abspath(f) for f in args.files] or [
        os.path.join(EXAMPLES, f) for f in DEFAULT if os.path.exists(os.path.join(EXAMPLES, f))]
    modes = args.modes.split(",")
    refs = {m: MaterialXReference([CORPUS], color_management=True, reduced=(m == "reduced")) for m in modes}
    harness = Harness()
    print("harness: %s; renderer: %s; %d repeats, Mesa shader cache %s" % (
        harness.name, harness.gl_renderer, args.repeat,
        "off" if os.environ.get("MESA_SHADER_CACHE_DISABLE") == "true" else "on"))
    totals = {m: [0.0] * 6 for m in modes}
    print("%-44s %-8s %9s %9s %6s %10s %10s %6s %8s %8s %6s" % (
        "element", "mode", "draw ms", "MX ms", "ratio", "1st px ms", "MX ms", "ratio", "frag KB", "MX KB", "ratio"))
    for path in files:
        try:
            elements = refs[modes[0]].elements(path)
        except Exception as e:                  # a document MaterialX cannot read (a missing include): said, skipped
            print("%-44s skipped: %s" % (os.path.basename(path)[:44], str(e).strip().splitlines()[-1][:80]))
            continue
        for element in elements:
            label = "%s:%s" % (os.path.basename(path), element)
            for mode in modes:
                try:
                    ours = ours_shader(path, element, mode)
                    vs, fs, tex, _ = refs[mode].generate(path, element)
                    theirs = (vs, fs, tex)
                    o = measure(harness, ours, args.repeat)
                    m = measure(harness, theirs, args.repeat)
                except Exception as e:          # a document either side cannot do: reported, the run goes on
                    print("%-44s %-8s skipped: %s" % (label[:44], mode, str(e).strip().splitlines()[-1][:80]))
                    continue
                t = totals[mode]
                for i, v in enumerate(o + m):
                    t[i] += v
                print("%-44s %-8s %9.1f %9.1f %6.2f %10.0f %10.0f %6.2f %8.1f %8.1f %6.2f" % (
                    label[:44], mode, 1e3 * o[0], 1e3 * m[0], o[0] / m[0], 1e3 * o[1], 1e3 * m[1], o[1] / m[1],
                    o[2] / 1024, m[2] / 1024, o[2] / m[2]))
    for mode in modes:
        t = totals[mode]
        if t[3]:
            print("overall %-8s ours / MaterialX: draw %.2f, compile-to-first-pixel %.2f, fragment bytes %.2f" % (
                mode, t[0] / t[3], t[1] / t[4], t[2] / t[5]))


if __name__ == "__main__":
    main()
