#!/usr/bin/env python3
"""Developer tool: the scoreboard's measure over any folder of .mtlx documents (issue 16: documents the project
has not seen). For every renderable element MaterialX finds in each document, as the scoreboard counts them:

  mx         MaterialX's GenGlsl (with its colour-management system on, as its viewer and the scoreboard run
             it) generated a shader: elements it cannot generate are listed and not counted
  generated  ours generated a vertex/fragment pair
  compiled   ours links (OpenGL 4.x, the scoreboard's scene)
  parity     ours and MaterialX's, both drawn in the scoreboard's scene (render.Renderer.scoreboard, the same
             pixels as ../shared/tools/mxharness.py), differ by a mean <= 2/255 and <= 1% of pixels > 8/255

usage: tools/unseen_sweep.py PATH [PATH ...] [--out DIR] [--size N] [--no-color-management] [--ref-cache DIR]
                             [--json FILE] [--only SUBSTRING] [--usd] [--known DIR ...] [--by-source N]
PATH: .mtlx files or folders (searched recursively). Prints a table per document, then each element that is
not at parity with its metric and a side-by-side image (ours | MaterialX | difference x8) under --out.
--ref-cache keeps MaterialX's renders keyed by its shader text, so that a second sweep after a change of ours
draws only ours. Exit status 0 (it measures; it does not judge).

A fresh set (issue 26): --known DIR (default: ../shared/corpus and ../shared/seeds; repeatable) leaves out every
document whose text, whitespace aside, is that of a .mtlx file there (public projects copy MaterialX's examples),
so the counts are of documents not seen; --usd also sweeps USD stages (.usda, .usdc, .usd, .usdz), each
UsdShadeMaterial a row that counts generated and compiled (MaterialX draws no stage: no parity column);
--by-source N sums the table by the first N folders under the common base (one row per public project).
"""
import argparse
import hashlib
import json
import os
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
CORPUS = os.path.join(ROOT, "..", "shared", "corpus", "materialx")

import numpy as np  # noqa: E402

from mtlxgen import USD_EXTENSIONS, is_usd, pipeline
from mtlxgen.draw import compare
from mtlxgen.base import images  # noqa: E402
from mtlxgen.base.diagnostics import MtlxError  # noqa: E402
from mtlxgen.apps.reference import MaterialXReference  # noqa: E402
from mtlxgen.draw.renderer import Renderer  # noqa: E402


KNOWN = [os.path.join(ROOT, "..", "shared", "corpus"), os.path.join(ROOT, "..", "shared", "seeds")]


def documents(paths, usd=False):
    ends = (".mtlx",) + (USD_EXTENSIONS if usd else ())
    out = []
    for p in paths:
        if os.path.isdir(p):
            out += sorted(os.path.join(dp, f) for dp, _, fs in os.walk(p) for f in fs if f.lower().endswith(ends))
        else:
            out.append(p)
    return [os.path.abspath(p) for p in out]


def _text_key(path):
    """A document's text with all whitespace removed (copies re-indented or re-wrapped are the same document)."""
    try:
        with open(path, "rb") as f:
            data = f.read(8 * 2 ** 20)
    except OSError:
        return None
    return hashlib.sha256(b"".join(data.split())).hexdigest()


def known_texts(folders):
    """Keys (_text_key) of every .mtlx document under `folders`."""
    keys = set()
    for folder in folders:
        if os.path.isdir(folder):
            for dp, _, fs in os.walk(folder):
                keys.update(_text_key(os.path.join(dp, f)) for f in fs if f.endswith(".mtlx"))
    keys.discard(None)
    return keys


def fresh(files, known):
    """(documents not among the known texts, documents left out as copies of a known one)."""
    keep, seen = [], []
    for f in files:
        (seen if f.endswith(".mtlx") and _text_key(f) in known else keep).append(f)
    return keep, seen


def first_line(e, limit=110):
    text = e.lines()[0] if isinstance(e, MtlxError) else str(e).strip()
    lines = [ln for ln in text.splitlines() if ln.strip()]
    return (lines[-1] if lines else type(e).__name__)[:limit]


class Sweep:
    def __init__(self, size=None, color_management=True, ref_cache=None, out=None):
        self.ref = MaterialXReference([CORPUS] if os.path.isdir(CORPUS) else [], color_management=color_management)
        self.harness = Renderer.scoreboard(**({"size": size} if size else {}))
        self.ref_cache = ref_cache
        self.out = out
        if ref_cache:
            os.makedirs(ref_cache, exist_ok=True)

    def theirs(self, vs, fs, tex):
        key = hashlib.sha256(json.dumps([vs, fs, sorted(tex.items()), self.harness.size]).encode()).hexdigest()
        cached = os.path.join(self.ref_cache, key + ".npy") if self.ref_cache else None
        if cached and os.path.exists(cached):
            return np.load(cached)
        img, _ = self.harness.render_timed(vs, fs, None, tex)
        if cached:
            np.save(cached, img)
        return img

    def stage(self, path, report=None):
        """(rows, note) for a USD stage: one row per UsdShadeMaterial, generated and compiled (MaterialX draws no
        stage: `usd` rows are counted apart). note: the stage's own problems (composition), which are no row."""
        try:
            session = pipeline.Session(path)
        except MtlxError as e:
            return [], "cannot read it: %s" % first_line(e)
        rows = []
        for element in session.elements:
            row = {"file": path, "element": element, "usd": True, "mx": False, "generated": False,
                   "compiled": False, "parity": False}
            rows.append(row)
            try:
                shader = session.shader(element)
                row["generated"] = True
                self.harness.render_timed(shader.vertex, shader.fragment, None,
                                          {t["uniform"]: t["file"] for t in shader.manifest["textures"]})
                row["compiled"] = True
            except MtlxError as e:
                row["error"] = first_line(e)
            except Exception as e:
                row["error"] = ("does not compile: " if row["generated"] else "") + first_line(e)
            if report:
                report(row)
        notes = session.notes()
        return rows, ("; ".join(first_line(MtlxError([n])) for n in notes[:2]) if notes else
                      "" if rows else "no material")

    def document(self, path, report=None):
        """(rows, note): one row per element MaterialX finds renderable; note says why there are none.
        report(row) is called as each row is done."""
        if is_usd(path):
            return self.stage(path, report)
        try:
            doc = self.ref.load(path)
            elements = [e.getNamePath() for e in self.ref.mx_gen.findRenderableElements(doc)]
        except Exception as e:
            return [], "MaterialX cannot read it: %s" % first_line(e)
        try:
            shaders, problems = pipeline.generate(path, elements=elements, partial=True)
        except MtlxError as e:
            shaders, problems = [], e
        except Exception as e:   # a bug of ours: every element fails alike
            shaders, problems = [], e
        ours = {s.element: s for s in shaders}
        problem_text = first_line(problems) if problems is not None else ""
        rows = []
        for element in elements:
            row = {"file": path, "element": element, "mx": False, "generated": False, "compiled": False,
                   "parity": False}
            rows.append(row)
            self.measure(path, doc, element, ours.get(element), problem_text, row)
            if report:
                report(row)
        return rows, "" if elements else "no renderable element"

    def measure(self, path, doc, element, shader, problem_text, row):
        """Fill one row: MaterialX generates it, ours is generated, compiles, and at parity."""
        try:
            vs, fs, tex, _ = self.ref.generate(path, element, doc)
            row["mx"] = True
        except Exception as e:
            row["mx_error"] = first_line(e)
            return
        if shader is None:
            try:                # MaterialX generates it: does its shader compile (else it is not counted)?
                self.theirs(vs, fs, tex)
            except Exception as e:
                row["mx"] = False
                row["mx_error"] = "MaterialX's shader does not compile: " + first_line(e)
                return
            row["error"] = problem_text or "not generated"
            return
        row["generated"] = True
        try:
            mine, _ = self.harness.render_timed(shader.vertex, shader.fragment, None,
                                                {t["uniform"]: t["file"] for t in shader.manifest["textures"]})
            row["compiled"] = True
        except Exception as e:
            row["error"] = "does not compile: " + first_line(e)
            return
        try:
            theirs = self.theirs(vs, fs, tex)
        except Exception as e:
            row["mx"] = False
            row["mx_error"] = "MaterialX's shader does not compile: " + first_line(e)
            return
        p = compare.parity(mine, theirs)
        row.update(parity=p.passes, mean=round(p.mean, 3), fraction=round(p.fraction, 5), max=p.max)
        if self.out and not p.passes:
            a, b = images.to_srgb8(mine)[..., :3], images.to_srgb8(theirs)[..., :3]
            d = np.abs(a.astype(np.int16) - b.astype(np.int16)).max(-1)
            heat = np.repeat(np.clip(d * 8, 0, 255)[..., None], 3, -1).astype(np.uint8)
            name = os.path.splitext(os.path.basename(path))[0] + "__" + element.replace("/", "_") + ".png"
            row["image"] = os.path.join(self.out, name)
            images.write_image(row["image"], np.concatenate([a, b, heat], axis=1))


def _counts(rows):
    counted = [r for r in rows if r["mx"]]
    return [len(rows), len(counted), sum(r["generated"] for r in counted), sum(r["compiled"] for r in counted),
            sum(r["parity"] for r in counted)]


def table(results, base):
    """The per-document table (markdown) and the totals (of .mtlx documents; stages: usd_table)."""
    lines = ["| document | elements | MaterialX generates | generated | compiled | parity |",
             "|---|---|---|---|---|---|"]
    tot = [0] * 5
    results = [r for r in results if not is_usd(r[0])]
    for path, rows, note in results:
        n = _counts(rows)
        tot = [a + b for a, b in zip(tot, n)]
        name = os.path.relpath(path, base) if base else path
        lines.append("| %s | %d | %d | %d | %d | %d |%s" % ((name,) + tuple(n) + ((" " + note) if note else "",)))
    lines.append("| **all (%d documents)** | %d | %d | %d | %d | %d |" % ((len(results),) + tuple(tot)))
    return "\n".join(lines), tot


def source_of(path, base, depth):
    parts = os.path.relpath(path, base).split(os.sep)
    return "/".join(parts[:min(depth, len(parts) - 1)]) or parts[0]


def source_table(results, base, depth):
    """The table summed by source (the first `depth` folders under base): documents, elements, MaterialX
    generates, generated, compiled, parity; .mtlx documents only."""
    groups = {}
    for path, rows, _ in results:
        if is_usd(path):
            continue
        g = groups.setdefault(source_of(path, base, depth), [0] * 6)
        for i, v in enumerate([1] + _counts(rows)):
            g[i] += v
    lines = ["| source | documents | elements | MaterialX generates | generated | compiled | parity |",
             "|---|---|---|---|---|---|---|"]
    lines += ["| %s | %d | %d | %d | %d | %d | %d |" % ((name,) + tuple(n)) for name, n in sorted(groups.items())]
    tot = [sum(n[i] for n in groups.values()) for i in range(6)]
    lines.append("| **all** | %d | %d | %d | %d | %d | %d |" % tuple(tot))
    return "\n".join(lines), tot


def usd_table(results, base):
    """Stages: materials found, generated, compiled."""
    stages = [(p, rows) for p, rows, _ in results if is_usd(p)]
    lines = ["| stage | materials | generated | compiled |", "|---|---|---|---|"]
    tot = [0, 0, 0]
    for path, rows in stages:
        n = [len(rows), sum(r["generated"] for r in rows), sum(r["compiled"] for r in rows)]
        tot = [a + b for a, b in zip(tot, n)]
        lines.append("| %s | %d | %d | %d |" % ((os.path.relpath(path, base),) + tuple(n)))
    lines.append("| **all (%d stages)** | %d | %d | %d |" % ((len(stages),) + tuple(tot)))
    return "\n".join(lines), tot


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("paths", nargs="+")
    ap.add_argument("--out", default=None, help="folder for side-by-side images of the elements not at parity "
                                                "(default: a new temporary folder)")
    ap.add_argument("--size", type=int, default=None, help="render size (default: the scoreboard's)")
    ap.add_argument("--no-color-management", action="store_true",
                    help="MaterialX without its colour-management system (the scoreboard runs with it)")
    ap.add_argument("--ref-cache", default=None, help="folder of MaterialX's renders, keyed by its shader text")
    ap.add_argument("--json", default=None, help="write every row here")
    ap.add_argument("--only", default=None, help="only documents whose path contains this")
    ap.add_argument("--usd", action="store_true", help="sweep USD stages too (generated and compiled)")
    ap.add_argument("--known", action="append", default=None,
                    help="leave out copies of the .mtlx documents in this folder (default: ../shared/corpus and "
                         "../shared/seeds; --known none: leave out nothing)")
    ap.add_argument("--by-source", type=int, default=0, help="also sum the table by the first N folders")
    args = ap.parse_args()
    files = documents(args.paths, args.usd)
    if args.only:
        files = [f for f in files if args.only in f]
    known = [] if args.known == ["none"] else (args.known or KNOWN)
    files, copies = fresh(files, known_texts(known))
    if copies:
        print("left out %d copies of known documents (%s)" % (len(copies), ", ".join(known)), flush=True)
    out = args.out or tempfile.mkdtemp(prefix="unseen-")
    os.makedirs(out, exist_ok=True)
    base = os.path.commonpath([os.path.dirname(f) for f in files]) if files else ""
    sweep = Sweep(args.size, not args.no_color_management, args.ref_cache, out)
    results, t0 = [], time.time()

    def report(r):
        if r.get("usd"):
            status = ("PASS  generated, compiled" if r["compiled"] else "FAIL  " + r.get("error", ""))
        elif not r["mx"]:
            status = "MaterialX cannot generate it: " + r.get("mx_error", "")
        elif r["parity"]:
            status = "PASS  mean %.2f, %.2f%% > 8/255" % (r["mean"], 100 * r["fraction"])
        elif "mean" in r:
            status = "FAIL  mean %.2f, %.2f%% > 8/255, max %d  %s" % (r["mean"], 100 * r["fraction"], r["max"],
                                                                     r.get("image", ""))
        else:
            status = "FAIL  " + r.get("error", "")
        print("%-70s %s" % ((os.path.relpath(r["file"], base) + " " + r["element"])[-70:], status), flush=True)

    for path in files:
        rows, note = sweep.document(path, report)
        results.append((path, rows, note))
        if note:
            print("%-70s %s" % (os.path.relpath(path, base)[-70:], note), flush=True)
    text, tot = table(results, base)
    print()
    print(text)
    if args.by_source:
        print()
        print(source_table(results, base, args.by_source)[0])
    if args.usd:
        print()
        print(usd_table(results, base)[0])
    print("\n%d elements MaterialX generates: generated %d, compiled %d, parity %d (%.0f s); images in %s"
          % (tot[1], tot[2], tot[3], tot[4], time.time() - t0, out))
    if args.json:
        with open(args.json, "w") as f:
            json.dump([r for _, rows, _ in results for r in rows], f, indent=1)


if __name__ == "__main__":
    main()
