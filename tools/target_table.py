"""The table of targets in docs/commands.md ("Shader targets"): for each group of documents, how many elements
generate and how many of them compile with Khronos' reference compiler in each target (glsl, essl:
glslangValidator; vulkan: SPIR-V that spirv-val accepts, with the block offsets glslang reflects).

    python tools/target_table.py [--corpus] [--out FILE]

Groups: the project's documents (examples/, tests/data/, tests/fuzz_seeds/), and with --corpus the
scoreboard's corpus (../shared/corpus/materialx: Examples and each TestSuite library)."""
import argparse
import datetime
import glob
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from mtlxgen.base import targets  # noqa: E402
from mtlxgen.apps.glslvalidate import GLSLANG, validate_documents  # noqa: E402


def documents(root):
    return sorted(glob.glob(os.path.join(root, "**", "*.mtlx"), recursive=True))


def groups(corpus):
    out = [("examples/", documents(os.path.join(ROOT, "examples"))),
           ("tests/data/", documents(os.path.join(ROOT, "tests", "data"))),
           ("tests/fuzz_seeds/", documents(os.path.join(ROOT, "tests", "fuzz_seeds")))]
    if corpus:
        top = os.path.join(ROOT, "..", "shared", "corpus", "materialx", "resources", "Materials")
        out.append(("corpus Examples", documents(os.path.join(top, "Examples"))))
        suite = os.path.join(top, "TestSuite")
        for lib in sorted(os.listdir(suite)):
            if os.path.isdir(os.path.join(suite, lib)):
                out.append(("corpus TestSuite/" + lib, documents(os.path.join(suite, lib))))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--corpus", action="store_true", help="also the scoreboard's corpus in ../shared")
    ap.add_argument("--out", help="write the markdown table here too")
    args = ap.parse_args(argv)
    if GLSLANG is None:
        sys.exit("glslangValidator not found (Debian glslang-tools)")
    rows, failures = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for name, paths in groups(args.corpus):
            cells = []
            for target in targets.NAMES:
                count, errors = validate_documents(paths, tmp, target)
                bad = {e.split(": ")[1].split(".")[0] for e in errors}      # shader stems with a problem
                cells.append("%d / %d" % (count - len(bad), count))
                failures += ["%s %s" % (target, e) for e in errors]
            rows.append("| %s | %d | %s |" % (name, len(paths), " | ".join(cells)))
            print(rows[-1], flush=True)
    table = ["Elements compiled / generated, per target (%s):" % datetime.date.today().isoformat(), "",
             "| documents | files | %s |" % " | ".join(targets.NAMES), "|---|---|%s" % ("---|" * len(targets.NAMES))]
    table += rows
    text = "\n".join(table) + "\n"
    print(text)
    for f in failures[:50]:
        print(f)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
