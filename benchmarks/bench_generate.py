#!/usr/bin/env python3
"""Generation time per element: mtlxgen vs MaterialX's GenGlsl, measured in the same process and run.

usage: bench_generate.py [FILE.mtlx ...] [--repeat N] [--materials N] [--no-big]

Default files: every document of Materials/Examples in ../shared/corpus/materialx (or $MTLXGEN_CORPUS; of
tests/data/materialx where neither is there), then two generated documents of --materials materials each: one of ONE
structure (standard_surface materials differing in their values only) and one of as many DIFFERENT structures (each
material's own nodegraph, a chain of math nodes whose categories and length spell the material's number, feeding
standard_surface, open_pbr_surface or gltf_pbr by turns).

Per document, like against like, both warm (libraries loaded, first run not timed):
  mtlxgen    pipeline.generate(FILE, ELEMENTS): read, upgrade, the library overlaid with the document's own
             definitions, each element's graph and GLSL (what `mtlxgen generate` does after its start)
  MaterialX  readFromXmlFile + setDataLibrary (the libraries referenced, not copied), then GlslShaderGenerator.generate of each element with ONE
             GenContext made at the start and reused for every element of every document (a fresh context per
             element re-reads MaterialX's source files each time and would flatter us)
ELEMENTS: the renderable elements (MaterialX's findRenderableElements) that both generate; a document or
element that fails on either side is listed and skipped, never ends the run. Prints per-document medians per
element and ratios ours / MaterialX (target <= 1.0), the overall ratio (sum of times), and the library's load
times (cold parse; warm from the compact cache). Timings only: nothing here asserts; machines are shared and noisy.
"""
import argparse
import glob
import os
import statistics
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from mtlxgen.read import library
from mtlxgen import pipeline  # noqa: E402
from mtlxgen.base.diagnostics import MtlxError  # noqa: E402

CORPUS = os.environ.get("MTLXGEN_CORPUS") or os.path.join(ROOT, "..", "shared", "corpus", "materialx")
if not os.path.isdir(CORPUS):
    CORPUS = os.path.join(ROOT, "tests", "data", "materialx")
EXAMPLES = os.path.join(CORPUS, "resources", "Materials", "Examples")


class MaterialX:
    """MaterialX's GenGlsl with its libraries loaded once and one GenContext for the whole run."""

    def __init__(self):
        import MaterialX as mx
        import MaterialX.PyMaterialXGenGlsl as mx_glsl
        import MaterialX.PyMaterialXGenShader as mx_gen
        self.mx, self.mx_gen = mx, mx_gen
        self.search = mx.getDefaultDataSearchPath()
        self.lib = mx.createDocument()
        mx.loadLibraries(mx.getDefaultDataLibraryFolders(), self.search, self.lib)
        self.gen = mx_glsl.GlslShaderGenerator.create()
        self.ctx = mx_gen.GenContext(self.gen)
        self.ctx.registerSourceCodeSearchPath(self.search)

    def load(self, path):
        doc = self.mx.createDocument()
        self.mx.readFromXmlFile(doc, path, self.search)
        doc.setDataLibrary(self.lib)      # referenced, not copied (importLibrary: +40 ms a document)
        return doc

    def elements(self, path):
        doc = self.load(path)           # held while its elements are read (they do not keep it)
        return [e.getNamePath() for e in self.mx_gen.findRenderableElements(doc)]

    def generate(self, path, elements):
        """Read the document and generate each element in the shared context; returns the pixel shaders."""
        doc = self.load(path)
        return [self.gen.generate("s", doc.getDescendant(e), self.ctx).getSourceCode(self.mx_gen.PIXEL_STAGE)
                for e in elements]


def ours(path, elements):
    shaders, _ = pipeline.generate(path, elements=elements, partial=True)
    return shaders


def common_elements(mx, path):
    """(elements both generate, [why others were skipped])."""
    skipped = []
    try:
        doc = mx.load(path)
        names = [e.getNamePath() for e in mx.mx_gen.findRenderableElements(doc)]
    except Exception as e:
        return [], ["MaterialX cannot read it: %s" % str(e).splitlines()[0][:120]]
    theirs = []
    for name in names:
        try:
            mx.gen.generate("s", doc.getDescendant(name), mx.ctx)
            theirs.append(name)
        except Exception as e:
            skipped.append("%s: MaterialX fails: %s" % (name, str(e).splitlines()[0][:100]))
    if not theirs:
        return [], skipped
    try:
        shaders, error = pipeline.generate(path, elements=theirs, partial=True)
    except Exception as e:              # the document fails (or our bug): reported, the run goes on
        shaders, error = [], e
    done = {s.element for s in shaders}
    if len(done) < len(theirs):
        lines = error.lines() if isinstance(error, MtlxError) else [repr(error)]
        skipped.append("%d element(s): mtlxgen fails: %s" % (len(theirs) - len(done), lines[0][:120] if lines else "?"))
    return [n for n in theirs if n in done], skipped


def timed(fn, *args):
    t = time.perf_counter()
    fn(*args)
    return time.perf_counter() - t


def measure(mx, path, repeat):
    """(elements, ours seconds, MaterialX seconds, skipped): medians over `repeat` runs, runs taking turns."""
    elements, skipped = common_elements(mx, path)
    if not elements:
        return elements, None, None, skipped
    a, b = [], []
    for _ in range(repeat):
        a.append(timed(ours, path, elements))
        b.append(timed(mx.generate, path, elements))
    return elements, statistics.median(a), statistics.median(b), skipped


MATERIAL = {
    0: """<standard_surface name="ss{i}" type="surfaceshader">
  <input name="base_color" type="color3" value="{r:.3f}, {g:.3f}, 0.2" />
  <input name="specular_roughness" type="float" value="{s:.3f}" />
  <input name="metalness" type="float" value="{m:.3f}" />
</standard_surface>
<surfacematerial name="M{i}" type="material"><input name="surfaceshader" type="surfaceshader" nodename="ss{i}" /></surfacematerial>""",
    1: """<open_pbr_surface name="op{i}" type="surfaceshader">
  <input name="base_color" type="color3" value="{r:.3f}, {g:.3f}, 0.5" />
  <input name="specular_roughness" type="float" value="{s:.3f}" />
  <input name="coat_weight" type="float" value="{m:.3f}" />
</open_pbr_surface>
<surfacematerial name="M{i}" type="material"><input name="surfaceshader" type="surfaceshader" nodename="op{i}" /></surfacematerial>""",
    2: """<nodegraph name="NG{i}">
  <position name="p" type="vector3" />
  <noise3d name="n" type="float"><input name="position" type="vector3" nodename="p" />
    <input name="amplitude" type="float" value="{s:.3f}" /></noise3d>
  <mix name="c" type="color3"><input name="fg" type="color3" value="{r:.3f}, {g:.3f}, 0.1" />
    <input name="bg" type="color3" value="0.1, 0.2, 0.3" /><input name="mix" type="float" nodename="n" /></mix>
  <output name="out" type="color3" nodename="c" />
</nodegraph>
<gltf_pbr name="gl{i}" type="surfaceshader">
  <input name="base_color" type="color3" nodegraph="NG{i}" output="out" />
  <input name="roughness" type="float" value="{m:.3f}" />
</gltf_pbr>
<surfacematerial name="M{i}" type="material"><input name="surfaceshader" type="surfaceshader" nodename="gl{i}" /></surfacematerial>""",
}


def many_materials(path, n):
    """A document of n standard_surface materials of one structure (their values differ)."""
    parts = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for i in range(n):
        parts.append(MATERIAL[0].format(i=i, r=(i % 10) / 10, g=(i % 7) / 7, s=0.1 + (i % 9) / 10, m=(i % 5) / 5))
    parts.append("</materialx>")
    with open(path, "w") as f:
        f.write("\n".join(parts) + "\n")
    return path


CHAIN_OPS = ("multiply", "add", "subtract", "max", "min")
SHADERS = (("standard_surface", "base_color", "specular_roughness"), ("open_pbr_surface", "base_color",
                                                                         "specular_roughness"),
           ("gltf_pbr", "base_color", "roughness"))


def different_materials(path, n):
    """A document of n materials of n different structures: material i's nodegraph is a chain of math nodes, one per
    base-5 digit of i (the digit picks the category), from a noise of the position to a mix of two colours."""
    parts = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for i in range(n):
        digits, k = [], i
        while True:
            digits.append(k % len(CHAIN_OPS))
            k //= len(CHAIN_OPS)
            if not k:
                break
        chain = ['  <position name="p" type="vector3" />',
                 '  <noise3d name="n0" type="float"><input name="position" type="vector3" nodename="p" /></noise3d>']
        for j, d in enumerate(digits):
            chain.append('  <%s name="n%d" type="float"><input name="in1" type="float" nodename="n%d" />'
                         '<input name="in2" type="float" value="%.3f" /></%s>' % (CHAIN_OPS[d], j + 1, j, 0.1 + d / 10,
                                                                                   CHAIN_OPS[d]))
        last = len(digits)
        chain.append('  <mix name="c" type="color3"><input name="fg" type="color3" value="0.8, 0.3, 0.1" />'
                     '<input name="bg" type="color3" value="0.1, 0.2, 0.6" /><input name="mix" type="float" '
                     'nodename="n%d" /></mix>' % last)
        chain.append('  <output name="out" type="color3" nodename="c" />')
        category, color, rough = SHADERS[i % 3]
        parts.append('<nodegraph name="NG%d">\n%s\n</nodegraph>' % (i, "\n".join(chain)))
        parts.append('<%s name="s%d" type="surfaceshader"><input name="%s" type="color3" nodegraph="NG%d" output="out" />'
                     '<input name="%s" type="float" value="%.3f" /></%s>' % (category, i, color, i, rough,
                                                                             0.1 + (i % 9) / 10, category))
        parts.append('<surfacematerial name="M%d" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="s%d" /></surfacematerial>' % (i, i))
    parts.append("</materialx>")
    with open(path, "w") as f:
        f.write("\n".join(parts) + "\n")
    return path


def library_load_times():
    files = library.library_files()
    library._MEMO.clear()
    t = time.perf_counter()
    library.load_library(use_cache=False)
    cold = time.perf_counter() - t
    saved = os.environ.get("MTLXGEN_CACHE")
    with tempfile.TemporaryDirectory() as cache:
        os.environ["MTLXGEN_CACHE"] = cache
        library._MEMO.clear()
        library.load_library()                 # writes the cache
        warm = []
        for _ in range(5):
            library._MEMO.clear()
            t = time.perf_counter()
            library.load_library()
            warm.append(time.perf_counter() - t)
    if saved is None:
        del os.environ["MTLXGEN_CACHE"]
    else:
        os.environ["MTLXGEN_CACHE"] = saved
    library._MEMO.clear()
    return cold, statistics.median(warm), len(files)


def row(name, n, a, b):
    print("%-46s %4d elements  mtlxgen %7.2f ms  MaterialX %7.2f ms  ratio %.2f" % (
        name[:46], n, 1e3 * a / n, 1e3 * b / n, a / b))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*")
    ap.add_argument("--repeat", type=int, default=5, help="runs per document (medians; the big document: 1)")
    ap.add_argument("--materials", type=int, default=1000, help="materials of the generated document")
    ap.add_argument("--no-big", action="store_true", help="without the generated document")
    args = ap.parse_args()
    files = [os.path.abspath(f) for f in args.files] or sorted(
        glob.glob(os.path.join(EXAMPLES, "**", "*.mtlx"), recursive=True))
    cold, warm, n = library_load_times()
    print("library load: %d files, cold parse %.0f ms, warm (compact cache) %.1f ms" % (n, 1e3 * cold, 1e3 * warm))
    library.load_library()
    mx = MaterialX()
    total_a = total_b = 0.0
    count = 0
    for path in files:
        name = os.path.relpath(path, EXAMPLES) if path.startswith(EXAMPLES) else os.path.basename(path)
        try:
            elements, a, b, skipped = measure(mx, path, args.repeat)
        except Exception as e:          # never stops the run
            print("%-46s failed: %s" % (name[:46], str(e).splitlines()[0][:100]))
            continue
        for s in skipped:
            print("%-46s skipped %s" % (name[:46], s))
        if not elements:
            continue
        row(name, len(elements), a, b)
        total_a += a
        total_b += b
        count += len(elements)
    if count:
        print("overall: %d elements, mtlxgen %.2f ms/element, MaterialX %.2f ms/element, ratio %.2f (target <= 1.0)"
              % (count, 1e3 * total_a / count, 1e3 * total_b / count, total_a / total_b))
    if not args.no_big:
        with tempfile.TemporaryDirectory() as tmp:
            for label, make in (("one structure", many_materials), ("different structures", different_materials)):
                path = make(os.path.join(tmp, "materials_%d.mtlx" % args.materials), args.materials)
                elements, a, b, skipped = measure(mx, path, 1)
                for s in skipped[:5]:
                    print("%s: skipped %s" % (label, s))
                if elements:
                    row("%d materials, %s" % (args.materials, label), len(elements), a, b)

if __name__ == "__main__":
    main()
