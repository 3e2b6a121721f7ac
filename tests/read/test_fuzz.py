"""Mutated documents never break the CLI (tests/fuzzing.py has the mutator and the checks).

Each case must exit 0 or 1 with only `FILE:LINE:` problem lines, write shaders that link, open nothing
outside the allowed roots and copy no byte of the canary into its output, within a time bound.
MTLXGEN_FUZZ_COUNT (default 320) and MTLXGEN_FUZZ_SEED (default 17) set the run; tools/fuzz.py runs
any count outside pytest.
"""
import os

import pytest

import fuzzing

COUNT = int(os.environ.get("MTLXGEN_FUZZ_COUNT", "320"))
SEED = int(os.environ.get("MTLXGEN_FUZZ_SEED", "17"))
CHUNKS = 8          # spread over pytest-xdist's workers


@pytest.fixture(scope="module")
def case_dir(tmp_path_factory):
    d = str(tmp_path_factory.mktemp("fuzz"))
    fuzzing.prepare_case_dir(d)
    return d


@pytest.mark.parametrize("chunk", range(CHUNKS))
def test_mutated_documents_exit_cleanly_and_leak_nothing(chunk, case_dir, renderer):
    roots = fuzzing.allowed_roots(case_dir)

    def compile_program(vs, fs):
        renderer.ctx.__enter__()
        renderer.ctx.program(vertex_shader=vs, fragment_shader=fs).release()

    failures = []
    for i, seed_path, text in fuzzing.cases(SEED, COUNT, case_dir):
        if i % CHUNKS != chunk:
            continue
        problems = fuzzing.run_case(text, case_dir, compile_program, roots)
        if problems:
            failures.append("case %d (seed %d, from %s): %s" % (i, SEED, os.path.basename(seed_path),
                                                                 "; ".join(problems)))
    assert not failures, "\n".join(failures[:10])


def test_the_checks_catch_what_they_are_for(case_dir, renderer):
    """The checker itself can fail: a leak of the canary, a problem line without FILE:LINE and a shader
    that does not compile are each reported (the checks are not vacuous)."""
    roots = fuzzing.allowed_roots(case_dir)
    compiled = []

    def compile_program(vs, fs):
        compiled.append(fs)
        renderer.ctx.__enter__()
        renderer.ctx.program(vertex_shader=vs, fragment_shader=fs).release()

    with open(os.path.join(fuzzing.SEED_DIRS[0], "custom_node.mtlx")) as f:     # outputs, no material
        clean = f.read()
    assert fuzzing.run_case(clean, case_dir, compile_program, roots) == [] and compiled
    # a GLSL file inside the document's folder is allowed into the output: carrying the canary, the bytes
    # check sees it
    inside = os.path.join(case_dir, "doc", "inside_canary.glsl")
    with open(os.path.join(case_dir, "outside", "canary.glsl")) as src, open(inside, "w") as dst:
        dst.write(src.read())
    leak = clean.replace("</materialx>", '<nodedef name="ND_ext" node="ext"><input name="in" type="float" value="1" />'
                         '<output name="out" type="float" /></nodedef><implementation name="IM_ext" nodedef="ND_ext" '
                         'target="genglsl" file="inside_canary.glsl" function="ext_fn" /><ext name="e" type="float" />'
                         '<output name="eo" type="float" nodename="e" /></materialx>')
    try:
        problems = fuzzing.run_case(leak, case_dir, compile_program, roots)
    finally:
        os.remove(inside)
    assert any("canary bytes" in p for p in problems), problems
    doc_dir = os.path.realpath(os.path.join(case_dir, "doc"))
    problems = fuzzing.run_case(clean, case_dir, compile_program, [r for r in roots if r != doc_dir])
    assert any("opened outside the allowed roots" in p and "case.mtlx" in p for p in problems), problems
    # the generator now refuses a document whose own GLSL does not compile, so a driver that rejects what
    # was written stands in for a broken shader
    def rejecting(vs, fs):
        raise RuntimeError("0:1(1): error: syntax error")
    problems = fuzzing.run_case(clean, case_dir, rejecting, roots)
    assert any("does not compile" in p for p in problems), problems
