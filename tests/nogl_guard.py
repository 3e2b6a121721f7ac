"""The guard behind the test markers: a test not marked `gl` that creates a GL context or runs a GLSL compiler
fails, saying "test uses GL but is not marked gl", instead of passing in a full run and slowing (or breaking,
on a machine without Mesa) the fast subset `pytest -m "not gl"`.

What counts as GL use (the things the `gl` marker stands for):
- a GL context: moderngl's create_standalone_context / create_context / init_context (which EGL, OSMesa, X11,
  mtlxgen.draw.glcontext, render.Renderer, the viewer and glslcheck all go through);
- a GLSL compiler or validator run as a program: glslangValidator, spirv-val, or anything under
  ../shared/tools/gpu_proxy (mtlxgen.apps.glslvalidate.run_tool and tests calling subprocess directly alike).

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
ENV_KINDS = "MTLXGEN_TEST_GUARD"            # which guards a subprocess installs: "gl", "browser" or "gl,browser"
SITE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "_nogl_site")
MESSAGES = {
    "gl": "test uses GL but is not marked gl: %s (mark it gl: the fixture or module table in tests/conftest.py)",
    "browser": "test uses a browser but is not marked browser: %s (mark it browser: the fixture or module table "
               "in tests/conftest.py)"}
MESSAGE = MESSAGES["gl"]
COMPILERS = ("glslangValidator", "spirv-val", "spirv-opt", "spirv-link")
BROWSERS = ("chromium", "chromium-browser", "chrome", "google-chrome", "headless_shell", "node", "npm", "npx")
CONTEXT_FACTORIES = ("create_standalone_context", "create_context", "init_context")


def _argv0(args):
    if isinstance(args, (str, bytes, os.PathLike)):
        argv0 = os.fsdecode(args).split()[0] if os.fsdecode(args).split() else ""
    else:
        args = list(args)
        argv0 = os.fsdecode(args[0]) if args else ""
    return argv0


def compiler_in(args):
    """The GLSL compiler a subprocess command runs, or None."""
    argv0 = _argv0(args)
    name = os.path.basename(argv0)
    return name if name in COMPILERS or (os.sep + "gpu_proxy" + os.sep) in argv0 else None


def browser_in(args):
    """The browser or Node a subprocess command runs (playwright's driver is a node), or None."""
    name = os.path.basename(_argv0(args))
    return name if name in BROWSERS else None


def guard_contexts(moderngl, refuse, undo):
    """moderngl's context factories call refuse(what) (which raises or exits) instead."""
    for name in CONTEXT_FACTORIES:
        if hasattr(moderngl, name):
            undo.append((moderngl, name, getattr(moderngl, name)))
            setattr(moderngl, name, lambda *a, _name=name, **k: refuse("moderngl.%s()" % _name))


def guard_programs(refuse, undo, kinds=("gl",)):
    """subprocess.Popen (under run, check_output, call and asyncio alike) calls refuse(what, kind) for a GLSL
    compiler (kind "gl") or a browser or Node (kind "browser"), for the kinds given."""
    original_popen = subprocess.Popen
    finders = [(kind, find) for kind, find in (("gl", compiler_in), ("browser", browser_in)) if kind in kinds]

    class GuardedPopen(original_popen):
        def __init__(self, args, *a, **k):
            for kind, find in finders:
                program = find(args)
                if program is not None:
                    refuse("ran %s" % program, kind)
            super().__init__(args, *a, **k)

    undo.append((subprocess, "Popen", original_popen))
    subprocess.Popen = GuardedPopen


def install(refuse, kinds=("gl",)):
    """The guards of `kinds` ("gl": contexts and compilers; "browser": Chromium and Node) in this process;
    refuse(what, kind) must raise. Returns a function undoing them."""
    undo = []
    if "gl" in kinds:
        import moderngl
        guard_contexts(moderngl, lambda what: refuse(what, "gl"), undo)
    guard_programs(refuse, undo, kinds)

    def restore():
        for owner, name, original in reversed(undo):
            setattr(owner, name, original)
    return restore


def child_env_changes(report, kinds=("gl",)):
    """The environment variables that carry the guards into Python subprocesses."""
    path = os.environ.get("PYTHONPATH")
    return {"PYTHONPATH": SITE + (os.pathsep + path if path else ""), ENV_REPORT: report,
            ENV_KINDS: ",".join(kinds)}


def child_refuse(what, kind="gl"):
    """The guard's refusal in a subprocess: the message on stderr and in the report file, exit 97."""
    line = MESSAGES[kind] % ("subprocess %s %s" % (os.path.basename(sys.argv[0] or sys.executable), what))
    report = os.environ.get(ENV_REPORT)
    if report:
        with open(report, "a", encoding="utf-8") as f:
            f.write(line + "\n")
    sys.stderr.write(line + "\n")
    sys.stderr.flush()
    os._exit(97)
