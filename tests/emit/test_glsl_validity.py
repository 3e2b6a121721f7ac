"""Generated shaders are valid to Khronos' reference compiler for every target, not only to Mesa (which accepts
more: a struct defined twice, backslash line continuations in GLSL 4.00, `#version 300 es` features ES lacks).

- glsl and essl: both stages compile with `glslangValidator`.
- vulkan: both stages become SPIR-V (`glslangValidator -V`) that `spirv-val` accepts, and the two stages
  linked give glslang's reflection, whose block offsets, array strides and sampler bindings must be the ones
  the manifest tells a renderer (targets.std140 computes them independently).

Every shader of the bundled examples, the tests' documents and the fuzz seeds, for every target; with
../shared, every element of the scoreboard's corpus too (marked corpus)."""
import glob
import os

import pytest

from conftest import CORPUS, DATA, ROOT, corpus_params
from mtlxgen import pipeline
from mtlxgen.base import targets
from mtlxgen.apps.glslvalidate import (GLSLANG, SPIRV_VAL, reflection_mismatches, run_tool, validate,
                                       validate_documents)

pytestmark = pytest.mark.skipif(GLSLANG is None, reason="glslangValidator not installed (Debian glslang-tools; "
                                                        ".ci/run installs it)")
OWN_DATA = os.path.join(ROOT, "tests", "data", "targets")


def documents(*roots):
    return sorted(p for r in roots for p in glob.glob(os.path.join(r, "**", "*.mtlx"), recursive=True))


def check_documents(paths, tmp_path, target="glsl"):
    count, errors = validate_documents(paths, str(tmp_path), target)
    return count, [os.path.relpath(e.split(": ", 1)[0], ROOT) + ": " + e.split(": ", 1)[1] for e in errors]


@pytest.mark.parametrize("target", targets.NAMES)
@pytest.mark.parametrize("root", ["examples", os.path.join("tests", "fuzz_seeds"), "data", "targets"])
def test_project_documents_generate_shaders_the_reference_compiler_accepts(root, target, tmp_path):
    paths = documents({"data": DATA, "targets": OWN_DATA}.get(root) or os.path.join(ROOT, root))
    count, errors = check_documents(paths, tmp_path, target)
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


def test_validator_rejects_what_es_lacks(tmp_path):
    """The essl check is not vacuous either: GLSL 4.00's bitfieldReverse and uniform initializers fail ES 3.00."""
    class S:
        stem = "probe_es"
        vertex = "#version 300 es\nvoid main() { gl_Position = vec4(0.0); }\n"
        fragment = ("#version 300 es\nprecision highp float;\nuniform float k = 1.0;\nout vec4 c;\n"
                    "void main() { c = vec4(float(bitfieldReverse(7u)) * k); }\n")
    assert validate(S, str(tmp_path), "essl")


@pytest.mark.skipif(SPIRV_VAL is None, reason="spirv-val not installed (Debian spirv-tools; .ci/run installs it)")
def test_reflection_check_sees_a_wrong_offset(tmp_path):
    """An offset the manifest gets wrong is caught: the check compares every member with glslang's."""
    s = pipeline.generate(os.path.join(OWN_DATA, "interface_types.mtlx"), target="vulkan")[0]
    assert not validate(s, str(tmp_path), "vulkan")
    for m in s.manifest["uniform_block"]["members"]:
        if m["name"] == "u_viewPosition":
            m["offset"] += 4
    errors = validate(s, str(tmp_path), "vulkan")
    assert any("u_viewPosition" in e for e in errors), errors


def test_reflection_covers_every_block_member_and_sampler(tmp_path):
    """glslang reflects every member the shader reads, struct fields and samplers included, so the offset
    check above is not silently skipping names."""
    s = pipeline.generate(os.path.join(OWN_DATA, "struct_uniform.mtlx"), target="vulkan")[0]
    path = {}
    for stage, text in (("vert", s.vertex), ("frag", s.fragment)):
        path[stage] = os.path.join(str(tmp_path), "s.%s" % stage)
        with open(path[stage], "w") as f:
            f.write(text)
    r = run_tool([GLSLANG, "-V", "-l", "-q", path["vert"], path["frag"], "-o", os.path.join(str(tmp_path), "l.spv")])
    mismatches, seen = reflection_mismatches(s, r.stdout)
    assert not mismatches
    assert {"t_pair.weight", "t_pair.tint", "t_pair.offset", "u_viewProjectionMatrix", "u_worldMatrix"} <= seen


def _corpus_groups():
    top = os.path.join(CORPUS, "resources", "Materials")
    return [pytest.param(d, id=d) for d in sorted(os.listdir(top)) if os.path.isdir(os.path.join(top, d))]


@pytest.mark.corpus
@pytest.mark.parametrize("target", targets.NAMES)
@pytest.mark.parametrize("group", corpus_params(_corpus_groups))
def test_corpus_generates_shaders_the_reference_compiler_accepts(group, target, tmp_path):
    paths = documents(os.path.join(CORPUS, "resources", "Materials", group))
    count, errors = check_documents(paths, tmp_path, target)
    assert count > 0
    assert not errors, "%d of %d shaders invalid:\n%s" % (len(errors), count, "\n".join(errors[:20]))
