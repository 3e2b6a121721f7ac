"""Generated GLSL is valid to Khronos' reference compiler, not only to Mesa (which accepts more: a struct
defined twice, backslash line continuations in GLSL 4.00). Every shader of the bundled examples, the
tests' MaterialX documents and the fuzz seeds passes `glslangValidator`; with ../shared, every element
of the scoreboard's corpus too."""
import glob
import os
import shutil
import subprocess

import pytest

from conftest import CORPUS, DATA, ROOT, corpus_params
from mtlxgen import pipeline
from mtlxgen.diagnostics import MtlxError

GLSLANG = shutil.which("glslangValidator")
pytestmark = pytest.mark.skipif(GLSLANG is None, reason="glslangValidator not installed (Debian glslang-tools; "
                                                        ".ci/run installs it)")


def documents(*roots):
    return sorted(p for r in roots for p in glob.glob(os.path.join(r, "**", "*.mtlx"), recursive=True))


def validate(shader, tmp_dir):
    """glslangValidator's ERROR lines for both stages of one shader (empty when valid)."""
    errors = []
    for stage, text in (("vert", shader.vertex), ("frag", shader.fragment)):
        path = os.path.join(tmp_dir, "%s.%s" % (shader.stem, stage))
        with open(path, "w") as f:
            f.write(text)
        r = subprocess.run([GLSLANG, path], capture_output=True, text=True, timeout=120)
        if r.returncode:
            errors += ["%s.%s: %s" % (shader.stem, stage, line) for line in r.stdout.splitlines()
                       if line.startswith("ERROR")][:3] or ["%s.%s: exit %d" % (shader.stem, stage, r.returncode)]
    return errors


def check_documents(paths, tmp_path):
    errors, count = [], 0
    for path in paths:
        try:
            shaders, _ = pipeline.generate(path, partial=True)
        except MtlxError:        # nothing renderable, or a document refused whole: other tests pin those
            continue
        for s in shaders:
            count += 1
            errors += ["%s: %s" % (os.path.relpath(path, ROOT), e) for e in validate(s, str(tmp_path))]
    return count, errors


@pytest.mark.parametrize("root", ["examples", os.path.join("tests", "fuzz_seeds"), "data"])
def test_project_documents_generate_glsl_the_reference_compiler_accepts(root, tmp_path):
    paths = documents(DATA if root == "data" else os.path.join(ROOT, root))
    count, errors = check_documents(paths, tmp_path)
    assert count >= len(paths) > 0
    assert not errors, "\n".join(errors[:20])


def test_validator_rejects_what_mesa_accepts(tmp_path):
    """The check is not vacuous: a struct defined twice and a backslash continuation fail it."""
    class S:
        stem = "probe"
        vertex = "#version 400\nvoid main() { gl_Position = vec4(0.0); }\n"
        fragment = ("#version 400\nstruct A { float x; };\nstruct A { float x; };\n#define F(x) \\\n (x)\n"
                    "out vec4 c;\nvoid main() { c = vec4(F(1.0)); }\n")
    assert any("redefinition" in e for e in validate(S, str(tmp_path)))


def _corpus_groups():
    top = os.path.join(CORPUS, "resources", "Materials")
    return [pytest.param(d, id=d) for d in sorted(os.listdir(top)) if os.path.isdir(os.path.join(top, d))]


@pytest.mark.corpus
@pytest.mark.parametrize("group", corpus_params(_corpus_groups))
def test_corpus_generates_glsl_the_reference_compiler_accepts(group, tmp_path):
    paths = documents(os.path.join(CORPUS, "resources", "Materials", group))
    count, errors = check_documents(paths, tmp_path)
    assert count > 0
    assert not errors, "%d of %d shaders invalid:\n%s" % (len(errors), count, "\n".join(errors[:20]))
