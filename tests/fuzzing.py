"""Fuzzing the CLI with mutated documents: a seeded mutator of our own and the checks every input must pass.

Used by tests/read/test_fuzz.py (a few hundred cases in CI) and tools/fuzz.py (any count, any seed).
Each case is a seed document (tests/fuzz_seeds/, the bundled examples) put through one to four
mutations: byte edits (flip, insert, delete, truncate), XML edits (drop, duplicate, re-parent or deeply
nest elements; rename tags, element names and attributes; hostile attribute values) and MaterialX edits
(includes and implementation files pointing outside the document's folder, at devices or at a canary,
inline GLSL with broken template tokens, nodes wired into cycles, self-referencing nodegraphs and
structs). Every case must:
  - exit with 0 or 1 (never an internal error, 3; never a Python exception out of main),
  - print problems only as `FILE:LINE: ...` lines,
  - write shaders that link in an OpenGL context,
  - open no file outside the allowed roots (document folder, output folder, the project, the libraries,
    the Python installation, the library cache), seen through an audit hook,
  - carry no byte of the canary file (outside the document's folder) into any output,
  - finish within a time bound.
"""
import contextlib
import io
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import xml.etree.ElementTree as ET

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SEED_DIRS = [os.path.join(ROOT, "tests", "fuzz_seeds"), os.path.join(ROOT, "examples")]
CANARY = "MTLXGEN-CANARY-7f3a9c1e-never-in-output"
TIME_LIMIT_S = 30
PROBLEM_LINE = re.compile(r"^.+:\d+: \S")
WARNING_LINE = re.compile(r"^.+:\d+: warning: ")     # a slip MaterialX reads on (status 0 unless --strict)
CATEGORIES = ["add", "multiply", "image", "texcoord", "constant", "mix", "surface", "standard_surface",
              "surfacematerial", "nodegraph", "output", "input", "nodedef", "implementation", "typedef",
              "member", "dielectric_bsdf", "layer", "ifgreater", "separate3", "convert", "swizzle",
              "open_pbr_surface", "UsdPreviewSurface", "UsdUVTexture", "token", "bogus_node", "geompropdef"]
TYPES = ["float", "color3", "color4", "vector2", "vector3", "vector4", "integer", "boolean", "string",
         "filename", "matrix33", "matrix44", "BSDF", "EDF", "VDF", "surfaceshader", "lightshader", "material",
         "multioutput", "fuzz_pair", "floatarray", "", "nope"]
ATTRIBUTES = ["name", "type", "value", "nodename", "nodegraph", "output", "interfacename", "colorspace",
              "nodedef", "node", "href", "file", "function", "sourcecode", "target", "enum", "version",
              "fileprefix", "defaultgeomprop", "uniform", "unit", "unittype", "channels", "xpos"]


def seed_documents():
    """Seed paths: small, well-formed documents that generate today (sorted: the run is reproducible)."""
    out = []
    for d in SEED_DIRS:
        for name in sorted(os.listdir(d)):
            p = os.path.join(d, name)
            if name.endswith(".mtlx") and os.path.getsize(p) < 8000:
                out.append(p)
    return out


def hostile_values(case_dir):
    canary_dir = os.path.join(case_dir, "outside")
    return ["inf", "-inf", "nan", "1e999", "Infinity", "-1e308", "0x10", "1e3", "99999999999", "-2147483649",
            "", " ", "1,2", "1, 2, 3, 4, 5", "a", "true", "maybe", "2.5.0", "0.5.0, 1, 2", "1;2", "\n", "x" * 3000,
            "{{@}}", "{{$type:nope}}", "{{in", "{{nope}}", "<UDIM>", "tex.<UVTILE>.png", "../outside/canary.glsl",
            os.path.join(canary_dir, "canary.glsl"), os.path.join(canary_dir, "canary.mtlx"),
            "../outside/canary.mtlx", "/dev/zero", "/dev/stdin", "/dev/urandom", "/proc/self/environ",
            "/etc/passwd", "fifo", "fifo.mtlx", ".", "..", "/", "é∂ﬀ", "a b", "a/b", "con", "R", "T", "RT",
            "lin_rec709", "srgb_texture", "acescg", "no_such_space", "ND_add_float", "ND_nope", "genglsl",
            "essl", "out", "outx", "in1", "NG_math", "surf", "M_math"]


class Mutator:
    """Seeded mutations of MaterialX documents (text in, text out); deterministic for one seed."""

    def __init__(self, seed, case_dir):
        self.rng = random.Random(seed)
        self.values = hostile_values(case_dir)

    def mutate(self, text):
        rng = self.rng
        for _ in range(rng.choice([1, 1, 1, 2, 2, 3, 4])):
            op = rng.random()
            try:
                if op < 0.08:
                    text = self.bytes_edit(text)
                elif op < 0.7:
                    text = self.tree_edit(text)
                else:
                    text = self.materialx_edit(text)
            except RecursionError:      # ElementTree recurses per level on a deeply nested document
                text = self.bytes_edit(text)
        return text

    # ---- bytes
    def bytes_edit(self, text):
        rng = self.rng
        data = bytearray(text.encode("utf-8", "surrogatepass"))
        if not data:
            return text
        k = rng.randrange(len(data))
        choice = rng.randrange(5)
        if choice == 0:
            data[k] = rng.randrange(256)
        elif choice == 1:
            data[k:k] = bytes(rng.choice([b"<", b">", b"&", b'"', b"\x00", b"\xff\xfe", b"<!--", b"]]>", b"&amp;"]))
        elif choice == 2:
            del data[k:k + rng.randint(1, 40)]
        elif choice == 3:
            del data[k:]
        else:
            data[0:0] = rng.choice([b'<?xml version="1.0" encoding="utf-7"?>\n', b"\xef\xbb\xbf",
                                    b'<?xml version="1.0" encoding="latin-1"?>\n',
                                    b'<!DOCTYPE x [<!ENTITY a "aaaaaaaaaa">]>\n'])
        return data.decode("utf-8", "surrogateescape")

    # ---- XML tree
    def _parse(self, text):
        try:
            return ET.fromstring(text.encode("utf-8", "surrogateescape"))
        except (ET.ParseError, ValueError, LookupError):   # malformed, or an encoding ET cannot read
            return None

    def tree_edit(self, text):
        root = self._parse(text)
        if root is None:
            return self.bytes_edit(text)
        rng = self.rng
        elements = list(root.iter())
        parents = {c: p for p in elements for c in p}
        el = rng.choice(elements)
        choice = rng.choice([0, 1, 2, 3, 3, 3, 4, 4, 4, 5, 6, 7, 8, 8])
        if choice == 0 and el is not root:
            parents[el].remove(el)
        elif choice == 1 and el is not root:
            parents[el].append(ET.fromstring(ET.tostring(el)))       # duplicate: same name twice
        elif choice == 2:
            el.tag = rng.choice(CATEGORIES)
        elif choice == 3:
            el.set(rng.choice(ATTRIBUTES), rng.choice(self.values))
        elif choice == 4 and el.attrib:
            key = rng.choice(sorted(el.attrib))
            el.set(key, rng.choice(self.values + TYPES))
        elif choice == 5 and el.attrib:
            del el.attrib[rng.choice(sorted(el.attrib))]
        elif choice == 6 and el is not root:
            other = rng.choice(elements)
            if other is not el and el not in other.iter() and el in parents:
                parents[el].remove(el)
                other.append(el)                                      # re-parent
        elif choice == 7:                                             # deep nesting, written as text
            depth, tag = rng.choice([50, 300, 1200]), rng.choice(["nodegraph", "input", "add"])
            deep = "".join('<%s name="deep%d">' % (tag, i) for i in range(depth)) + "</%s>" % tag * depth
            return text.replace("</materialx>", deep + "</materialx>", 1)
        else:
            names = [e.get("name") for e in elements if e.get("name")]
            inputs = [e for e in elements if e.tag == "input"]
            if names and inputs:
                rng.choice(inputs).set("nodename", rng.choice(names))  # rewire: cycles, wrong types
        return self._text(root, text)

    def _text(self, root, fallback):
        try:
            return ET.tostring(root, encoding="unicode")
        except RecursionError:          # a deeply nested document from an earlier edit: edit its bytes
            return self.bytes_edit(fallback)

    # ---- MaterialX-level
    def materialx_edit(self, text):
        root = self._parse(text)
        if root is None:
            return self.bytes_edit(text)
        rng = self.rng
        target = rng.choice(self.values[26:36] + ["missing.mtlx", "sub/../custom_node.mtlx", "included.mtlx"])
        choice = rng.randrange(8)
        if choice == 0:
            ET.SubElement(root, rng.choice(["xi:include", "include", "foo:include"]), href=target)
        elif choice == 1:
            nd = ET.SubElement(root, "nodedef", name="ND_ext", node="ext_node")
            ET.SubElement(nd, "input", name="in", type="float", value="1")
            ET.SubElement(nd, "output", name="out", type="float")
            ET.SubElement(root, "implementation", name="IM_ext", nodedef="ND_ext", target="genglsl",
                          file=target, function=rng.choice(["ext_fn", "main", "x y", ""]))
            node = ET.SubElement(root, "ext_node", name="use_ext", type="float")
            ET.SubElement(node, "input", name="in", type="float", value="0.5")
            ET.SubElement(root, "output", name="ext_out", type="float", nodename="use_ext")
        elif choice == 2:
            nd = ET.SubElement(root, "nodedef", name="ND_src", node="src_node")
            ET.SubElement(nd, "input", name="in", type="float", value="1")
            ET.SubElement(nd, "output", name="out", type="float")
            ET.SubElement(root, "implementation", name="IM_src", nodedef="ND_src", target="genglsl",
                          sourcecode=rng.choice(["{{@}}", "{{$type:nope}}", "{{in", "{{nope}} + 1.0",
                                                 "{{in}} + {{in}}", "{{in}}; }", "*/ {{in}}", "\n#version 100\n",
                                                 "{{in}} // \\", "sin({{in}})"]))
            node = ET.SubElement(root, "src_node", name="use_src", type="float")
            ET.SubElement(node, "input", name="in", type="float", value=rng.choice(["0.5", "inf", "x"]))
            ET.SubElement(root, "output", name="src_out", type="float", nodename="use_src")
        elif choice == 3:
            a = ET.SubElement(root, "typedef", name="loop_a")
            ET.SubElement(a, "member", name="m", type=rng.choice(["loop_b", "loop_a", "lightshader", "BSDF", "nope"]))
            b = ET.SubElement(root, "typedef", name="loop_b")
            ET.SubElement(b, "member", name="n", type="loop_a")
        elif choice == 4:
            g = ET.SubElement(root, "nodegraph", name="NG_self")
            ET.SubElement(g, "input", name="i", type="float", nodegraph="NG_self", output="out")
            n = ET.SubElement(g, "add", name="n", type="float")
            ET.SubElement(n, "input", name="in1", type="float", interfacename="i")
            ET.SubElement(g, "output", name="out", type="float", nodename="n")
        elif choice == 5:
            img = ET.SubElement(root, "image", name="img_fuzz", type="color3")
            ET.SubElement(img, "input", name="file", type="filename", value=target)
            ET.SubElement(root, "output", name="img_out", type="color3", nodename="img_fuzz")
        elif choice == 6:
            named = [e for e in root.iter() if e.get("name")]
            if named:
                rng.choice(named).set("name", rng.choice(["a\nb", "x" * 300, "../up", "a/b", "*/", "con",
                                                          "\u00e9t\u00e9", "main", "out", "gl_Position", "a b"]))
        else:
            named = [e for e in root.iter() if e.get("name")]
            if named:
                el = rng.choice(named)
                el.set("type", rng.choice(TYPES))
        return self._text(root, text)


# ---------------------------------------------------------------- checking one case

class _Opens:
    """Paths opened while recording (sys.audit 'open' events). An audit hook cannot be removed, so one
    hook per process serves every case."""
    recording = None
    installed = False

    @classmethod
    def install(cls):
        if not cls.installed:
            sys.addaudithook(cls._hook)
            cls.installed = True

    @classmethod
    def _hook(cls, event, args):
        if cls.recording is not None and event == "open" and args and isinstance(args[0], (str, bytes)):
            path = args[0].decode("utf-8", "replace") if isinstance(args[0], bytes) else args[0]
            cls.recording.append(path)


def allowed_roots(case_dir):
    import MaterialX
    cache = os.environ.get("MTLXGEN_CACHE") or os.path.join(os.path.expanduser("~"), ".cache", "mtlxgen")
    roots = [os.path.join(case_dir, "doc"), os.path.join(case_dir, "out"), ROOT,
             os.path.dirname(os.path.abspath(MaterialX.__file__)), cache, sys.prefix, sys.base_prefix,
             sys.exec_prefix]
    roots += [p for p in sys.path if p and os.path.isdir(p) and os.path.abspath(p) != "/"]
    return [os.path.realpath(r) for r in roots]


def _inside(path, roots):
    real = os.path.realpath(path)
    return any(real == r or real.startswith(r.rstrip(os.sep) + os.sep) for r in roots)


class _Timeout(Exception):
    pass


def prepare_case_dir(case_dir):
    """The folder layout every case uses: doc/ (the seeds' neighbours, a FIFO), outside/ (the canary)."""
    import shutil
    doc, outside = os.path.join(case_dir, "doc"), os.path.join(case_dir, "outside")
    os.makedirs(doc, exist_ok=True)
    os.makedirs(outside, exist_ok=True)
    for d in SEED_DIRS[:1]:
        for name in os.listdir(d):
            shutil.copy(os.path.join(d, name), os.path.join(doc, name))
    for name in ("canary.glsl", "canary.mtlx"):
        with open(os.path.join(outside, name), "w") as f:
            body = "void ext_fn(float x, out float r) { r = x; } // %s\n" % CANARY
            f.write(body if name.endswith(".glsl") else
                    '<?xml version="1.0"?>\n<materialx version="1.39">\n<!-- %s -->\n'
                    '<constant name="leak" type="float"><input name="value" type="float" value="1" /></constant>\n'
                    '<output name="leak_out" type="float" nodename="leak" />\n</materialx>\n' % CANARY)
    for fifo in ("fifo", "fifo.mtlx"):
        path = os.path.join(doc, fifo)
        if not os.path.exists(path):
            os.mkfifo(path)


def run_case(text, case_dir, compile_program, roots):
    """Generate one mutated document through the CLI in this process; returns a list of failures (empty when
    the case is clean). compile_program(vertex, fragment) raises on a shader that does not link."""
    from mtlxgen.apps import cli
    import shutil
    doc = os.path.join(case_dir, "doc", "case.mtlx")
    out = os.path.join(case_dir, "out")
    shutil.rmtree(out, ignore_errors=True)
    with open(doc, "w", encoding="utf-8", errors="surrogateescape") as f:
        f.write(text)
    failures = []
    err, opened = io.StringIO(), []
    _Opens.install()

    def on_alarm(signum, frame):
        raise _Timeout()
    old = signal.signal(signal.SIGALRM, on_alarm)
    signal.alarm(TIME_LIMIT_S)
    from mtlxgen.draw import glslcheck
    glslcheck.context()         # the compile context for document GLSL opens the driver's files: made beforehand
    _Opens.recording = opened
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            rc = cli.main(["generate", doc, "-o", out])
    except _Timeout:
        rc = "timeout"
        failures.append("did not finish within %d s" % TIME_LIMIT_S)
    except BaseException as e:    # noqa: B036 (anything escaping main is a failure, SystemExit included)
        rc = "exception"
        failures.append("exception out of main: %s: %s" % (type(e).__name__, e))
    finally:
        _Opens.recording = None
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)
    if rc not in (0, 1, "timeout", "exception"):
        failures.append("exit status %s" % rc)
    lines = err.getvalue().splitlines()
    bad = [line for line in lines if not PROBLEM_LINE.match(line)]
    if bad:
        failures.append("stderr lines without FILE:LINE: %r" % bad[:3])
    if any("internal error" in line for line in lines):
        failures.append("internal error: %r" % [l for l in lines if "internal error" in l][:1])
    if rc == 1 and not [line for line in lines if not WARNING_LINE.match(line)]:
        failures.append("exit 1 without a problem line (warnings alone never fail a run)")
    outside = sorted({p for p in opened if not _inside(p, roots)})
    if outside:
        failures.append("opened outside the allowed roots: %r" % outside[:5])
    for dirpath, _, files in os.walk(out) if os.path.isdir(out) else ():
        for name in files:
            path = os.path.join(dirpath, name)
            with open(path, "rb") as f:
                data = f.read()
            if CANARY.encode() in data or b"root:x:0:0" in data:
                failures.append("canary bytes in %s" % name)
    if os.path.isdir(out):
        stems = {n[:-5] for n in os.listdir(out) if n.endswith(".frag")}
        for stem in sorted(stems):
            try:
                with open(os.path.join(out, stem + ".vert")) as f:
                    vs = f.read()
                with open(os.path.join(out, stem + ".frag")) as f:
                    fs = f.read()
                compile_program(vs, fs)
            except Exception as e:
                failures.append("%s does not compile: %s" % (stem, str(e).strip().splitlines()[-1:]))
                continue
            for ext in (".vert", ".frag"):
                error = reference_compiler_error(os.path.join(out, stem + ext))
                if error:
                    failures.append("%s%s is not valid to glslangValidator: %s" % (stem, ext, error))
    return failures


GLSLANG = shutil.which("glslangValidator")


def reference_compiler_error(path):
    """glslangValidator's first ERROR line for a .vert/.frag file, or None (also when it is not installed:
    Mesa's link above still runs; .ci/run installs glslang-tools)."""
    if GLSLANG is None:
        return None
    r = subprocess.run([GLSLANG, path], capture_output=True, text=True, timeout=60)
    if r.returncode == 0:
        return None
    return next((l for l in r.stdout.splitlines() if l.startswith("ERROR")), "exit %d" % r.returncode)


def cases(seed, count, case_dir):
    """(index, seed document, mutated text) for `count` cases from one seed."""
    seeds = seed_documents()
    rng = random.Random(seed)
    for i in range(count):
        path = rng.choice(seeds)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        yield i, path, Mutator(rng.randrange(2 ** 32), case_dir).mutate(text)
