"""Offline validation of generated shaders with Khronos' tools, the judges of validity for every target
(Mesa accepts GLSL that other drivers reject): glslangValidator for glsl and essl, and for vulkan SPIR-V
(`glslangValidator -V`) checked by spirv-val, the two stages linked, and glslang's reflection of the block
compared with the manifest's offsets, array strides and sampler bindings. Used by the tests and by
tools/target_table.py (the table in docs/commands.md)."""
import os
import re
import shutil
import subprocess

from mtlxgen.base.files import write_atomic

GLSLANG = shutil.which("glslangValidator")
SPIRV_VAL = shutil.which("spirv-val")


def run_tool(args):
    """A Khronos tool's completed process (output captured, bounded in time)."""
    return subprocess.run(args, capture_output=True, text=True, timeout=300)


def _errors(label, r):
    lines = [line for line in (r.stdout + r.stderr).splitlines() if line.startswith(("ERROR", "error"))]
    return ["%s: %s" % (label, line) for line in lines[:3]] or ["%s: exit %d" % (label, r.returncode)]


REFLECTED = re.compile(r"^(\S+): offset (-?\d+), type \w+, size \d+, index -?\d+, binding (-?\d+)[^\n]*?"
                       r"(?:topLevelArrayStride (\d+))?$", re.M)


def reflection_mismatches(shader, reflection):
    """Where glslang's reflection of the linked vulkan stages disagrees with the manifest's offsets/bindings."""
    block = shader.manifest["uniform_block"]
    expected = {}
    for m in block["members"]:
        if m.get("members"):        # a struct (array): glslang lists its fields as NAME.FIELD
            for f in m["members"]:
                expected["%s.%s" % (m["name"], f["name"])] = (m["offset"] + f["offset"], -1, m.get("stride"))
        else:
            expected[m["name"]] = (m["offset"], -1, None)
    for s in shader.manifest["samplers"]:
        expected[s["name"]] = (-1, s["binding"], None)
    seen, out = set(), []
    for name, offset, binding, stride in REFLECTED.findall(reflection):
        name = name.split("[")[0] if name.endswith("]") else name
        if name not in expected:
            continue
        seen.add(name)
        want = expected[name]
        got = (int(offset), int(binding), int(stride) if stride else None)
        if got[:2] != want[:2] or (want[2] is not None and got[2] != want[2]):
            out.append("%s: %s: manifest (offset, binding, stride) %s, glslang %s" % (shader.stem, name, want, got))
    return out, seen


def validate(shader, tmp_dir, target="glsl"):
    """The reference compiler's complaints about one shader (empty when valid)."""
    errors, paths = [], {}
    for stage, text in (("vert", shader.vertex), ("frag", shader.fragment)):
        path = paths[stage] = os.path.join(tmp_dir, "%s.%s.%s" % (shader.stem, target, stage))
        write_atomic(path, text, durable=False)     # a scratch file: a symlink there replaced, no fsync
        if target != "vulkan":
            r = run_tool([GLSLANG, path])
            if r.returncode:
                errors += _errors("%s.%s" % (shader.stem, stage), r)
            continue
        spv = path + ".spv"
        r = run_tool([GLSLANG, "-V", path, "-o", spv])
        if r.returncode:
            errors += _errors("%s.%s" % (shader.stem, stage), r)
        elif SPIRV_VAL:
            r = run_tool([SPIRV_VAL, spv])
            if r.returncode:
                errors += _errors("%s.%s.spv (spirv-val)" % (shader.stem, stage), r)
    if target == "vulkan" and not errors:
        r = run_tool([GLSLANG, "-V", "-l", "-q", paths["vert"], paths["frag"], "-o", os.path.join(tmp_dir, "linked.spv")])
        if r.returncode:
            errors += _errors("%s (linked)" % shader.stem, r)
        else:
            errors += reflection_mismatches(shader, r.stdout)[0]
    return errors


def validate_documents(paths, tmp_dir, target="glsl", workers=2):
    """(shaders generated, [problem lines]) for every renderable element of the documents at `paths`; a
    document refused whole (nothing renderable, bad input) counts nothing: the CLI reports those."""
    import concurrent.futures
    from mtlxgen import pipeline
    from mtlxgen.base.diagnostics import MtlxError
    shaders = []
    for path in paths:
        try:
            made, _ = pipeline.generate(path, partial=True, target=target)
        except MtlxError:
            continue
        shaders += [(path, s) for s in made]
    with concurrent.futures.ThreadPoolExecutor(workers) as pool:      # the tools run as processes
        found = list(pool.map(lambda ps: ["%s: %s" % (ps[0], e) for e in validate(ps[1], tmp_dir, target)],
                              shaders))
    return len(shaders), [e for errs in found for e in errs]
