"""The markers that say what a test needs (gl, browser, window; tests/conftest.py) and the guard that makes a
mislabelled test fail (tests/nogl_guard.py): a test not marked gl that creates a GL context or runs a GLSL
compiler, in this process or in a Python subprocess, fails with "test uses GL but is not marked gl"."""
import ast
import glob
import os
import subprocess
import sys

import pytest

import conftest
import nogl_guard

TESTS = os.path.dirname(os.path.abspath(__file__))


class Refused(Exception):
    pass


def _refuse(what, kind="gl"):
    raise Refused("%s: %s" % (kind, what))


def test_this_module_is_not_marked_gl(request):
    assert request.node.get_closest_marker("gl") is None


@pytest.mark.parametrize("factory", nogl_guard.CONTEXT_FACTORIES)
def test_context_factories_are_refused_then_restored(factory):
    import moderngl
    guarded = getattr(moderngl, factory)        # the autouse guard's (this test is not marked gl)
    restore = nogl_guard.install(_refuse)
    try:
        with pytest.raises(Refused, match=factory):
            getattr(moderngl, factory)()
    finally:
        restore()
    assert getattr(moderngl, factory) is guarded


def test_the_context_factory_of_the_package_is_refused_with_the_message():
    """What a mislabelled test meets: glcontext's fallback loop catches Exception, the guard's failure passes
    through it (pytest's Failed is a BaseException) and names the marker."""
    from mtlxgen.draw import glcontext
    with pytest.raises(BaseException) as caught:
        glcontext.create_context()
    assert "test uses GL but is not marked gl" in str(caught.value)
    assert not isinstance(caught.value, Exception)


@pytest.fixture(scope="module")
def module_context_attempt():
    """What a module's fixture creating a context meets for a test not marked gl (caught here to be read)."""
    import moderngl
    try:
        ctx = moderngl.create_standalone_context()
    except BaseException as e:      # the guard's failure (pytest's Failed)
        return str(e)
    ctx.release()
    return None


def test_a_module_fixture_creating_a_context_is_refused_naming_it(module_context_attempt):
    """A module's fixture is set up before the test's own guard: conftest.pytest_fixture_setup guards it too."""
    assert module_context_attempt is not None, "a module-scoped fixture created a context for a test not marked gl"
    assert "test uses GL but is not marked gl" in module_context_attempt
    assert "module-scoped fixture 'module_context_attempt'" in module_context_attempt


@pytest.mark.parametrize("args, refused", [
    (["glslangValidator", "--version"], "glslangValidator"),
    (["/usr/bin/spirv-val", "x.spv"], "spirv-val"),
    ("glslangValidator -V a.frag", "glslangValidator"),
    ([os.path.join("..", "shared", "tools", "gpu_proxy", "run"), "x"], "run"),
    ([sys.executable, "-c", "pass"], None),
    (["git", "--version"], None),
])
def test_compiler_runs_are_told_from_other_programs(args, refused):
    assert nogl_guard.compiler_in(args) == refused


@pytest.mark.parametrize("args, refused", [
    (["/usr/bin/chromium", "--headless"], "chromium"),
    (["node", "--check", "m.js"], "node"),
    (["/x/site-packages/playwright/driver/node", "cli.js"], "node"),
    (["nodejs-tool"], None),
    (["glslangValidator", "a.frag"], None),
])
def test_browser_runs_are_told_from_other_programs(args, refused):
    assert nogl_guard.browser_in(args) == refused


def test_browser_runs_are_refused_only_where_asked():
    restore = nogl_guard.install(_refuse, kinds=("browser",))
    try:
        with pytest.raises(Refused, match="browser: ran node"):
            subprocess.run(["node", "--version"], capture_output=True)
    finally:
        restore()


def test_a_compiler_run_through_subprocess_is_refused():
    restore = nogl_guard.install(_refuse)
    try:
        with pytest.raises(Refused, match="glslangValidator"):
            subprocess.run(["glslangValidator", "--version"], capture_output=True)
        assert subprocess.run([sys.executable, "-c", "print(6 * 7)"], capture_output=True,
                              text=True).stdout.strip() == "42"
    finally:
        restore()


@pytest.mark.parametrize("code, what", [
    ("import moderngl; moderngl.create_standalone_context()", "moderngl.create_standalone_context()"),
    ("from mtlxgen.draw import glcontext; glcontext.create_context()", "moderngl.create_standalone_context()"),
    ("import subprocess; subprocess.run(['spirv-val', 'x.spv'])", "ran spirv-val"),
    ("import subprocess; subprocess.run(['chromium', '--version'])", "not marked browser: subprocess -c ran chromium"),
])
def test_a_python_subprocess_reports_its_gl_use(tmp_path, code, what):
    """The guard reaches subprocesses through PYTHONPATH; the report file tells the parent even where the
    subprocess's exit status was expected to be a failure."""
    report = str(tmp_path / "report.txt")
    env = dict(os.environ, **nogl_guard.child_env_changes(report, ("gl", "browser")))
    env["PYTHONPATH"] = os.pathsep.join([env["PYTHONPATH"], os.path.dirname(TESTS)])
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 97, r.stderr
    with open(report, encoding="utf-8") as f:
        lines = f.read().splitlines()
    assert len(lines) == 1 and what in lines[0], lines
    assert ("not marked browser" if "chromium" in code else "test uses GL but is not marked gl") in lines[0]
    assert lines[0] in r.stderr


def test_a_python_subprocess_without_gl_is_left_alone(tmp_path):
    report = str(tmp_path / "report.txt")
    env = dict(os.environ, **nogl_guard.child_env_changes(report))
    r = subprocess.run([sys.executable, "-c", "import moderngl, subprocess; print(moderngl.__name__)"], env=env,
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and r.stdout.strip() == "moderngl", r.stderr
    assert not os.path.exists(report)


def _module_path(module):
    """tests/STAGE/MODULE.py (the tests mirror the package's stages), or None."""
    found = glob.glob(os.path.join(TESTS, "**", module + ".py"), recursive=True)
    return found[0] if found else None


def _test_functions(module):
    with open(_module_path(module), encoding="utf-8") as f:
        tree = ast.parse(f.read())
    return {n.name for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}


def test_every_table_entry_names_a_test_that_exists():
    """A renamed or deleted test leaves no stale entry behind (which would hide nothing, but mislead)."""
    stale = []
    for key, marks in conftest.MODULE_MARKS.items():
        module, _, function = key.partition("::")
        assert set(marks) <= {"gl", "browser", "window"}, key
        if _module_path(module) is None:
            stale.append(key)
        elif function and function not in _test_functions(module):
            stale.append(key)
    assert not stale, "MODULE_MARKS entries naming no test: %s" % stale


def test_a_window_implies_gl():
    """A window is a GL context: a window test must leave the fast subset `-m "not gl"` too."""
    for key, marks in list(conftest.MODULE_MARKS.items()) + list(conftest.FIXTURE_MARKS.items()):
        if "window" in marks:
            assert "gl" in marks, key


def test_markers_are_registered(pytestconfig):
    registered = {line.split(":")[0] for line in pytestconfig.getini("markers")}
    assert {"gl", "browser", "window", "corpus"} <= registered
