"""Documents generated from the libraries' own nodedefs (hypothesis), a fuzzer independent of the mutator in
tests/fuzzing.py: where that one edits known-good documents, this one writes new ones — random nodes of
any nodedef, wired to each other by name (matching types or not, forwards and backwards, so cycles too),
with valid and hostile values — so that many cases get through to the emitter and the compiler.

Every document must pass fuzzing.run_case's checks (exit 0/1, FILE:LINE lines, shaders that link and
that glslangValidator accepts, nothing read outside the allowed roots, no canary bytes, a time bound).
MTLXGEN_FUZZ_EXAMPLES (default 60) sets how many; runs are derandomized (reproducible in CI) unless
MTLXGEN_FUZZ_SEED is set, which seeds hypothesis instead.
"""
import functools
import os
from xml.sax.saxutils import quoteattr

import pytest

hypothesis = pytest.importorskip("hypothesis", reason="hypothesis is a test dependency (pip install -e '.[test]')")
from hypothesis import HealthCheck, given, seed, settings, strategies as st  # noqa: E402

import fuzzing  # noqa: E402

EXAMPLES = int(os.environ.get("MTLXGEN_FUZZ_EXAMPLES", "60"))
SEED = os.environ.get("MTLXGEN_FUZZ_SEED")
VALUE_TYPES = {"float": 1, "integer": 1, "boolean": 1, "vector2": 2, "vector3": 3, "vector4": 4, "color3": 3,
               "color4": 4, "matrix33": 9, "matrix44": 16}


@functools.lru_cache(maxsize=1)
def nodedefs():
    """(name, category, [(input, type, enum values)], output type or 'multioutput') of every library nodedef
    whose inputs and outputs a document can spell (no struct-typed ports), sorted for reproducibility."""
    from mtlxgen.read.library import load_library
    out = []
    for nd in sorted(load_library().nodedefs.values(), key=lambda n: n.name):
        ports = list(nd.inputs.values()) + list(nd.outputs.values())
        if not nd.outputs or any(p.type not in VALUE_TYPES and p.type not in (
                "string", "filename", "BSDF", "EDF", "VDF", "surfaceshader", "volumeshader", "displacementshader",
                "lightshader", "material") for p in ports):
            continue
        inputs = [(i.name, i.type, [v.strip() for v in (i.enum or "").split(",") if v.strip()])
                  for i in nd.inputs.values()]
        otype = next(iter(nd.outputs.values())).type if len(nd.outputs) == 1 else "multioutput"
        out.append((nd.name, nd.category, inputs, otype, [(o.name, o.type) for o in nd.outputs.values()]))
    return out


def number(draw):
    return draw(st.one_of(st.floats(-1e6, 1e6, allow_nan=False, width=32).map(lambda x: "%g" % x),
                          st.sampled_from(["0", "1", "0.5", "-1", "inf", "nan", "1e999", "", "x", "1,2"])))


@st.composite
def value_text(draw, type_name, enum):
    if type_name in VALUE_TYPES:
        n = VALUE_TYPES[type_name]
        if type_name == "integer":
            return draw(st.one_of(st.integers(-5, 20).map(str), st.sampled_from(["99999999999", "1.5", "Infinity"])))
        if type_name == "boolean":
            return draw(st.sampled_from(["true", "false", "maybe"]))
        k = draw(st.sampled_from([n, n, n, 1, n + 1]))
        return ", ".join(number(draw) for _ in range(k))
    if type_name == "string":
        return draw(st.sampled_from(enum + ["", "bogus", "world", "object", "model"]) if enum else
                    st.sampled_from(["", "world", "st", "UVMap", "a\tb"]))
    if type_name == "filename":
        return draw(st.sampled_from(["texture.png", "missing.png", "../outside/canary.glsl", "/dev/zero", "fifo",
                                     "tex.<UDIM>.png", ""]))
    return None


@st.composite
def documents(draw):
    defs = nodedefs()
    count = draw(st.integers(1, 6))
    nodes = []
    for k in range(count):
        name, category, inputs, otype, outputs = draw(st.sampled_from(defs))
        nodes.append(("n%d" % k, name, category, inputs, otype, outputs))
    lines = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for k, (node, ndname, category, inputs, otype, outputs) in enumerate(nodes):
        attrs = ' nodedef="%s"' % ndname if draw(st.booleans()) else ""
        lines.append('  <%s name="%s" type="%s"%s>' % (category, node, otype, attrs))
        for iname, itype, enum in inputs:
            how = draw(st.sampled_from(["default", "default", "value", "connect", "connect_any"]))
            if how == "value":
                text = draw(value_text(itype, enum))
                if text is not None:
                    lines.append('    <input name="%s" type="%s" value=%s />' % (iname, itype, quoteattr(text)))
            elif how.startswith("connect"):
                # same-typed producers only (earlier first), or any node at all: wrong types and cycles
                producers = [n for n in nodes if n[4] == itype and n[0] != node] if how == "connect" else nodes
                if producers:
                    src = draw(st.sampled_from(producers))
                    out = (' output="%s"' % draw(st.sampled_from(src[5]))[0]) if src[4] == "multioutput" else ""
                    lines.append('    <input name="%s" type="%s" nodename="%s"%s />' % (iname, itype, src[0], out))
        lines.append('  </%s>' % category)
    last = nodes[-1]
    if last[4] == "surfaceshader":
        lines.append('  <surfacematerial name="M" type="material">'
                     '<input name="surfaceshader" type="surfaceshader" nodename="%s" /></surfacematerial>' % last[0])
    elif last[4] == "multioutput":
        oname, otype = draw(st.sampled_from(last[5]))
        lines.append('  <output name="out" type="%s" nodename="%s" output="%s" />' % (otype, last[0], oname))
    else:
        lines.append('  <output name="out" type="%s" nodename="%s" />' % (last[4], last[0]))
    lines.append("</materialx>")
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def case_dir(tmp_path_factory):
    d = str(tmp_path_factory.mktemp("fuzzgen"))
    fuzzing.prepare_case_dir(d)
    return d


def _settings(f):
    s = settings(max_examples=EXAMPLES, deadline=None, database=None, derandomize=SEED is None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                        HealthCheck.function_scoped_fixture])
    f = s(f)
    return seed(int(SEED))(f) if SEED is not None else f


def test_generated_documents_exit_cleanly_and_compile(case_dir, renderer):
    roots = fuzzing.allowed_roots(case_dir)
    stats = {"cases": 0, "written": 0}

    def compile_program(vs, fs):
        stats["written"] += 1
        renderer.ctx.__enter__()
        renderer.ctx.program(vertex_shader=vs, fragment_shader=fs).release()

    @_settings
    @given(text=documents())
    def run(text):
        stats["cases"] += 1
        problems = fuzzing.run_case(text, case_dir, compile_program, roots)
        assert not problems, "%s\n--- document:\n%s" % ("\n".join(problems), text)

    run()
    print("generated documents: %(cases)d, shader pairs written and compiled: %(written)d" % stats)
    # the generator reaches the emitter and the compiler, not only the error paths
    assert stats["cases"] >= min(EXAMPLES, 20) and stats["written"] >= stats["cases"] // 5, stats
