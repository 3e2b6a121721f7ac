"""The package as a user installs it: `python -m build` makes an sdist and a wheel (the wheel built from the sdist,
so the sdist is complete), `twine check` passes both, the wheel holds every data file the package reads, and the
README's quick start runs against the wheel installed into a fresh virtual environment, from a folder outside the
checkout, without the network: the wheel installed with `pip --no-index --no-deps`, the dependencies seen through
a .pth file naming this environment's site-packages (their own .pth files, this checkout's editable install among
them, are not run from there). The picture it draws is the golden image's.

Marked `packaging` (about 30 s on 2 cores; `-m "not packaging"` leaves it out)."""
import fcntl
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
import zipfile

import pytest

from mtlxgen.draw import compare
from mtlxgen.apps import golden

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLE = "examples/quick_start.mtlx"
ELEMENT = "M_tiles"

pytestmark = pytest.mark.packaging


def _missing_build_tools():
    try:
        import build  # noqa: F401
        import setuptools
        import twine  # noqa: F401
    except ImportError as e:
        return "%s: the packaging test builds offline with build, setuptools and twine (pip install -e '.[test]')" % e
    major = int(setuptools.__version__.split(".")[0])
    if major < 77:
        return ("setuptools %s: pyproject's build needs >= 77 and the test builds without isolation (offline): "
                "pip install -e '.[test]'" % setuptools.__version__)
    return None


def _run(cmd, **kw):
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300, **kw)
    assert r.returncode == 0, "%s exited %d:\n%s\n%s" % (" ".join(map(str, cmd)), r.returncode, r.stdout[-4000:],
                                                         r.stderr[-4000:])
    return r


def quick_start_command():
    """The first command block of the README's quick start, split at `&&`: (install part, the rest)."""
    with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
        text = f.read()
    section = re.search(r"^## Quick start.*?$(.*?)^## ", text, re.S | re.M)
    assert section, "README.md has no '## Quick start' section"
    block = re.search(r"```sh\n(.*?)```", section.group(1), re.S)
    assert block, "README.md's quick start has no sh block"
    line = " ".join(block.group(1).split())
    install, _, rest = line.partition("&&")
    return install.strip(), rest.strip()


@pytest.fixture(scope="module")
def dist(tmp_path_factory):
    reason = _missing_build_tools()
    if reason:
        pytest.skip(reason)
    # One build per session: under xdist each worker runs this fixture, and builds running at once in the same
    # checkout race on its build folders (mtlxgen-0.1.0/, build/). The first worker builds into a folder all
    # workers share (the session's temporary root); the others wait on the lock and take its result.
    shared = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        shared = shared.parent
    out = shared / "packaging-dist"
    with open(shared / "packaging-dist.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not (out / "done").exists():
            shutil.rmtree(out, ignore_errors=True)
            out.mkdir()
            # sdist first, then the wheel from the unpacked sdist (build's default); no isolation: nothing downloaded
            _run([sys.executable, "-m", "build", "--no-isolation", "--outdir", str(out), ROOT], cwd=ROOT)
            (out / "done").write_text("")
    wheels = sorted(out.glob("*.whl"))
    sdists = sorted(out.glob("*.tar.gz"))
    assert len(wheels) == 1 and len(sdists) == 1, os.listdir(out)
    return wheels[0], sdists[0]


def test_twine_check_passes(dist):
    r = _run([sys.executable, "-m", "twine", "check", "--strict", str(dist[0]), str(dist[1])])
    assert r.stdout.count("PASSED") == 2, r.stdout


def test_wheel_holds_the_package_data(dist):
    names = set(zipfile.ZipFile(dist[0]).namelist())
    want = []
    for dp, dirs, files in os.walk(os.path.join(ROOT, "glsl_lib")):
        dirs[:] = [d for d in dirs if d != "__pycache__"]
        rel = os.path.relpath(dp, ROOT).replace(os.sep, "/").replace("glsl_lib", "mtlxgen/glsl_lib", 1)
        want += ["%s/%s" % (rel, f) for f in files if not f.endswith(".pyc")]
    assert len(want) > 80
    assets = os.path.join(ROOT, "mtlxgen", "web_assets")
    want += ["mtlxgen/web_assets/" + f for f in os.listdir(assets) if f.endswith((".js", ".html"))]
    want += ["mtlxgen/" + f for f in os.listdir(os.path.join(ROOT, "mtlxgen"))
             if f.endswith(".py") or f == "py.typed"]
    for stage in ("base", "read", "graph", "nodes", "passes", "emit", "draw", "apps"):
        want += ["mtlxgen/%s/%s" % (stage, f) for f in os.listdir(os.path.join(ROOT, "mtlxgen", stage)) if f.endswith(".py")]
    missing = sorted(set(want) - names)
    assert not missing, "not in the wheel: %s" % missing
    info = [n for n in names if ".dist-info/" in n]
    for lic in ("LICENSE", "NOTICE"):
        assert any(n.endswith(".dist-info/licenses/" + lic) for n in info), (lic, info)
    meta = zipfile.ZipFile(dist[0]).read([n for n in info if n.endswith("/METADATA")][0]).decode()
    assert "License-Expression: Apache-2.0" in meta
    assert "Provides-Extra: view" in meta and "Provides-Extra: docs" in meta


def _site_packages():
    """This environment's site-packages folders (where the dependencies are)."""
    paths = {sysconfig.get_paths()[k] for k in ("purelib", "platlib")}
    paths |= {p for p in sys.path if os.path.basename(p) in ("site-packages", "dist-packages")}
    return [p for p in sorted(paths) if os.path.isdir(p)]


@pytest.fixture(scope="module")
def venv(dist, tmp_path_factory):
    """A fresh virtual environment with the wheel installed and nothing else; the dependencies through a .pth."""
    where = tmp_path_factory.mktemp("venv") / "env"
    _run([sys.executable, "-m", "venv", "--without-pip", str(where)])
    py = where / "bin" / "python"
    _run([sys.executable, "-m", "pip", "--python", str(py), "install", "--quiet", "--no-index", "--no-deps",
          "--no-cache-dir", str(dist[0])])
    site = _run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"]).stdout.strip()
    with open(os.path.join(site, "_mtlxgen_test_dependencies.pth"), "w") as f:
        f.write("\n".join(_site_packages()) + "\n")
    return where


def _env(venv, tmp):
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "VIRTUAL_ENV"))}
    env["PATH"] = str(venv / "bin") + os.pathsep + env.get("PATH", "")
    env["VIRTUAL_ENV"] = str(venv)
    env["MTLXGEN_CACHE"] = str(tmp / "cache")          # the libraries parsed afresh from the installed glsl_lib
    return env


def test_installed_package_is_the_wheel(venv, tmp_path):
    """From outside the checkout the venv imports the wheel's mtlxgen and reads the wheel's glsl_lib."""
    r = _run([str(venv / "bin" / "python"), "-c",
              "import mtlxgen, mtlxgen.base.files as f; print(mtlxgen.__file__); print(f.glsl_lib_root())"],
             cwd=tmp_path, env=_env(venv, tmp_path))
    module, lib = r.stdout.split()
    for p in (module, lib):
        assert os.path.realpath(p).startswith(os.path.realpath(str(venv)) + os.sep), (p, venv)
        assert not os.path.realpath(p).startswith(ROOT + os.sep), p


def test_readme_quick_start_runs_from_the_wheel(venv, tmp_path):
    install, command = quick_start_command()
    # the install half is the wheel's install above (pip install . from a checkout builds this wheel)
    assert re.fullmatch(r"python3? -m pip install \.", install), install
    assert EXAMPLE in command, command
    work = tmp_path / "work"
    (work / "examples").mkdir(parents=True)
    shutil.copy(os.path.join(ROOT, EXAMPLE), work / EXAMPLE)   # procedural: the document alone is the example
    env = _env(venv, tmp_path)
    assert shutil.which("mtlxgen", path=env["PATH"]) == str(venv / "bin" / "mtlxgen")
    r = subprocess.run(command, shell=True, cwd=work, env=env, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, (command, r.stdout, r.stderr)
    out = work / shlex.split(command)[shlex.split(command).index("-o") + 1]
    png, exr = out / (ELEMENT + ".png"), out / (ELEMENT + ".exr")
    assert png.is_file() and exr.is_file(), sorted(os.listdir(out))
    assert golden.read_png8(str(png)).shape[:2] == (256, 256)     # render's default size

    # the installed package draws the golden image (golden check's metric, at the golden's size)
    with open(os.path.join(ROOT, "golden_images", "index.json")) as f:
        settings = json.load(f)["goldens"]["quick_start__" + ELEMENT]["settings"]
    assert settings["environment"] == "builtin_sky" and not settings["lights"], settings
    small = tmp_path / "small"
    _run(["mtlxgen", "render", EXAMPLE, "-o", str(small), "--size", str(settings["size"])], cwd=work, env=env)
    new8 = golden.read_png8(str(small / (ELEMENT + ".png")))
    gold8 = golden.read_png8(os.path.join(ROOT, "golden_images", "quick_start__%s.png" % ELEMENT))
    assert new8.shape == gold8.shape
    d = compare.diff_map(new8, gold8, min(new8.shape[-1], gold8.shape[-1]))
    tol = golden.Tolerance()
    over = float((d > tol.threshold).mean())
    assert over <= tol.max_fraction, "%.4f%% of pixels over %d/255 (max %d)" % (100 * over, tol.threshold, d.max())
