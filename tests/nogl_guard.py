"""The guard behind the test markers: a test not marked `gl` that creates a GL context or runs a GLSL compiler
fails, saying "test uses GL but is not marked gl", instead of passing in a full run and slowing (or breaking,
on a machine without Mesa) the fast subset `pytest -m "not gl"`.

What counts as GL use (the things the `gl` marker stands for):
- a GL context: moderngl's create_standalone_context / create_context / init_context (which EGL, OSMesa, X11,
  mtlxgen.glcontext, render.Renderer, the viewer and glslcheck all go through);
- a GLSL compiler or validator run as a program: glslangValidator, spirv-val, or anything under
  ../shared/tools/gpu_proxy (mtlxgen.glslvalidate.run_tool and tests calling subprocess directly alike).

In the test process the guard raises pytest's Failed (a BaseException, so `except Exception` fallbacks such as
glcontext's backend loop cannot swallow it). Python subprocesses (the CLI run as a program) inherit it through
tests/_nogl_site/sitecustomize.py on PYTHONPATH: there it prints the same message, writes it to the report file
named by MTLXGEN_TEST_NOGL_REPORT and exits 97; the test's fixture reads that file at teardown and fails the
test, so a subprocess that was expected to fail anyway cannot hide it.
"""
import os
import subprocess
import sys

ENV_REPORT = "MTLXGEN_TEST_NOGL_REPORT"
SITE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_nogl_site")
MESSAGE = "test uses GL but is not marked gl: %s (mark it gl: the fixture or module table in tests/conftest.py)"
COMPILERS = ("glslangValidator", "spirv-val", "spirv-opt", "spirv-link")
CONTEXT_FACTORIES = ("create_standalone_context", "create_context", "init_context")


def compiler_in(args):
    """The GLSL compiler a subprocess command runs, or None."""
    if isinstance(args, (str, bytes, os.PathLike)):
        argv0 = os.fsdecode(args).split()[0] if os.fsdecode(args).split() else ""
    else:
        args = list(args)
        argv0 = os.fsdecode(args[0]) if args else ""
    name = os.path.basename(argv0)
    if name in COMPILERS or (os.sep + "gpu_proxy" + os.sep) in argv0:
        return name
    return None


def guard_contexts(moderngl, refuse, undo):
    """moderngl's context factories call refuse(what) (which raises or exits) instead."""
    for name in CONTEXT_FACTORIES:
        if hasattr(moderngl, name):
            undo.append((moderngl, name, getattr(moderngl, name)))
            setattr(moderngl, name, lambda *a, _name=name, **k: refuse("moderngl.%s()" % _name))


def guard_compilers(refuse, undo):
    """subprocess.Popen (under run, check_output, call alike) calls refuse(what) for a GLSL compiler."""
    original_popen = subprocess.Popen

    class GuardedPopen(original_popen):
        def __init__(self, args, *a, **k):
            compiler = compiler_in(args)
            if compiler is not None:
                refuse("ran %s" % compiler)
            super().__init__(args, *a, **k)

    undo.append((subprocess, "Popen", original_popen))
    subprocess.Popen = GuardedPopen


def install(refuse):
    """Both guards in this process; returns a function undoing them."""
    import moderngl
    undo = []
    guard_contexts(moderngl, refuse, undo)
    guard_compilers(refuse, undo)

    def restore():
        for owner, name, original in reversed(undo):
            setattr(owner, name, original)
    return restore


def child_env_changes(report):
    """The environment variables that carry the guard into Python subprocesses."""
    path = os.environ.get("PYTHONPATH")
    return {"PYTHONPATH": SITE + (os.pathsep + path if path else ""), ENV_REPORT: report}


def child_refuse(what):
    """The guard's refusal in a subprocess: the message on stderr and in the report file, exit 97."""
    line = MESSAGE % ("subprocess %s %s" % (os.path.basename(sys.argv[0] or sys.executable), what))
    report = os.environ.get(ENV_REPORT)
    if report:
        with open(report, "a", encoding="utf-8") as f:
            f.write(line + "\n")
    sys.stderr.write(line + "\n")
    sys.stderr.flush()
    os._exit(97)
