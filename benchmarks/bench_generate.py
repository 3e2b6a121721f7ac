#!/usr/bin/env python3
"""Generation time per element: mtlxgen vs MaterialX's GenGlsl, measured in the same process.

usage: bench_generate.py [FILE.mtlx ...] [--repeat N]
Default files: the TestSuite stdlib math documents of ../shared/corpus (of tests/data/materialx where
../shared is absent). Prints per-file medians and the overall ratio (ours / MaterialX); also library
load times (cold parse and warm cache; target < 0.2 s warm). Timings only: nothing here asserts, machines are shared and noisy.
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

from mtlxgen import document, emit, graph, library  # noqa: E402
from mtlxgen.diagnostics import MtlxError  # noqa: E402
from mtlxgen.reference import MaterialXReference  # noqa: E402

CORPUS = os.path.join(ROOT, "..", "shared", "corpus", "materialx")
if not os.path.isdir(CORPUS):
    CORPUS = os.path.join(ROOT, "tests", "data", "materialx")
DEFAULT = sorted(glob.glob(os.path.join(CORPUS, "resources", "Materials", "TestSuite", "stdlib", "math", "*.mtlx")))


def library_load_times():
    files = library.library_files()
    t = time.perf_counter()
    lib = library.Library(files=files)
    for f in files:
        lib.add_document(document.load(f))
    lib.flatten_inheritance()
    cold = time.perf_counter() - t
    with tempfile.TemporaryDirectory() as cache:
        os.environ["MTLXGEN_CACHE"] = cache
        library._MEMO.clear()
        library.load_library()                 # writes the cache
        library._MEMO.clear()
        t = time.perf_counter()
        library.load_library()
        warm = time.perf_counter() - t
        del os.environ["MTLXGEN_CACHE"]
    library._MEMO.clear()
    return cold, warm, len(files)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    files = [os.path.abspath(f) for f in (args.files or DEFAULT)]
    cold, warm, n = library_load_times()
    print("library load: %d files, cold parse %.3f s, warm (cache) %.3f s (target < 0.2 s)" % (n, cold, warm))
    lib = library.load_library()
    ref = MaterialXReference()
    ours_total = theirs_total = 0.0
    count = 0
    for path in files:
        doc = document.load(path)
        mx_doc = ref.load(path)
        ours, theirs = [], []
        for element in ref.elements(path):
            try:
                ref.generate(path, element, mx_doc)
                graph.build_graph(doc, lib, element)
            except (MtlxError, Exception):
                continue
            t_ours, t_theirs = [], []
            for _ in range(args.repeat):
                t = time.perf_counter()
                emit.emit(graph.build_graph(doc, lib, element))
                t_ours.append(time.perf_counter() - t)
                t_theirs.append(ref.generate(path, element, mx_doc)[3])
            ours.append(statistics.median(t_ours))
            theirs.append(statistics.median(t_theirs))
        if not ours:
            continue
        count += len(ours)
        ours_total += sum(ours)
        theirs_total += sum(theirs)
        print("%-28s %3d elements  mtlxgen %.2f ms  MaterialX %.2f ms  ratio %.2f" % (
            os.path.basename(path), len(ours), 1e3 * statistics.median(ours), 1e3 * statistics.median(theirs),
            sum(ours) / sum(theirs)))
    if count:
        print("overall: %d elements, mtlxgen %.2f ms/element, MaterialX %.2f ms/element, ratio %.2f" % (
            count, 1e3 * ours_total / count, 1e3 * theirs_total / count, ours_total / theirs_total))


if __name__ == "__main__":
    main()
