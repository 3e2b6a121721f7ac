"""The public API, used only through mtlxgen.__all__: generate from a path, a string of XML and a USD stage; render;
a Session; DocumentError with every FILE:LINE problem; warnings through the warnings module; the host example's
picture equal to render's; --version, -q and a missing dependency on the command line."""
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import mtlxgen
from conftest import ROOT

QUICK_START = os.path.join(ROOT, "examples", "quick_start.mtlx")
STAGE = os.path.join(ROOT, "examples", "usd", "preview_stage.usda")
PUBLIC = {name: getattr(mtlxgen, name) for name in mtlxgen.__all__}

BROKEN = """<?xml version="1.0"?>
<materialx version="1.39">
  <nodegraph name="g">
    <frobnicate name="f" type="float" />
    <output name="out" type="float" nodename="f" />
  </nodegraph>
  <nodegraph name="h">
    <add name="a" type="float"><input name="in1" type="vector3" value="1, 2, 3" /></add>
    <output name="out" type="float" nodename="a" />
  </nodegraph>
</materialx>
"""

SLIP = """<?xml version="1.0"?>
<materialx version="1.39">
  <nodegraph name="g">
    <constant name="c" type="float"><input name="value" type="float" value="0.5abc" /></constant>
    <output name="out" type="float" nodename="c" />
  </nodegraph>
</materialx>
"""


def test_all_names_exist_and_import_is_cheap():
    assert {"generate", "render", "Session", "Shader", "DocumentError", "DocumentWarning"} <= set(PUBLIC)
    code = "import sys, mtlxgen; print(sorted(m for m in sys.modules if m.startswith(('mtlxgen.', 'numpy'))))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert out.stdout.strip() == "[]"          # the API, numpy and the pipeline load on first use
    assert isinstance(PUBLIC["__version__"], str) and PUBLIC["__version__"][0].isdigit()


def test_generate_a_path_a_string_and_a_stage():
    generate, Shader = PUBLIC["generate"], PUBLIC["Shader"]
    from_path = generate(QUICK_START)
    assert [s.name for s in from_path] == ["M_tiles"] and isinstance(from_path[0], Shader)
    s = from_path[0]
    assert s.vertex.startswith("#version 400") and "void main()" in s.fragment
    assert s.manifest["element"] == "M_tiles" and s.manifest["transparent"] is False
    with open(QUICK_START, encoding="utf-8") as f:
        from_text = generate(f.read())
    assert from_text[0].fragment.replace("from document.mtlx", "") == s.fragment.replace("from quick_start.mtlx", "")
    stage = generate(STAGE)
    assert stage and all(sh.manifest["usd"]["prim"].startswith("/") for sh in stage)
    essl = generate(QUICK_START, "M_tiles", target="essl", interface="reduced")
    assert essl[0].manifest["target"] == "essl" and essl[0].manifest["interface"] == "reduced"


def test_document_error_carries_every_problem_with_file_and_line():
    with pytest.raises(PUBLIC["DocumentError"]) as caught:
        PUBLIC["generate"](BROKEN)
    e = caught.value
    lines = [str(p) for p in e.problems]
    assert len(lines) == 2 and str(e) == "\n".join(lines)
    assert lines[0].startswith("<string>:4: ") and "frobnicate" in lines[0]
    assert lines[1].startswith("<string>:8: ") and [p.line for p in e.problems] == [4, 8]
    with pytest.raises(PUBLIC["DocumentError"]) as missing:
        PUBLIC["generate"](os.path.join(ROOT, "no", "such.mtlx"))
    assert str(missing.value).endswith("such.mtlx:0: no such file")


def test_warnings_through_the_warnings_module_and_on_the_result():
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        shaders = PUBLIC["generate"](SLIP)
    ours = [w for w in seen if issubclass(w.category, PUBLIC["DocumentWarning"])]
    assert len(ours) == 1 and str(ours[0].message).startswith("<string>:4: warning: ")
    assert shaders.warnings == [str(ours[0].message)]
    with warnings.catch_warnings():
        warnings.simplefilter("error", PUBLIC["DocumentWarning"])        # a Python user makes them errors
        with pytest.raises(PUBLIC["DocumentWarning"]):
            PUBLIC["generate"](SLIP)
    with pytest.raises(PUBLIC["DocumentError"]):                           # or asks for strict reading
        PUBLIC["generate"](SLIP, options={"strict": True})


def test_render_a_shader_and_a_source_and_a_session():
    render, Session = PUBLIC["render"], PUBLIC["Session"]
    shader = PUBLIC["generate"](QUICK_START)[0]
    img = render(shader, size=32)
    assert img.shape == (32, 32, 4) and img.dtype == np.float32
    assert img[0, 0, 3] == 0.0 and img[16, 16, 3] == 1.0 and img[16, 16, :3].max() > 0.05   # sphere on clear
    assert np.array_equal(render(QUICK_START, size=32), img)
    with Session(size=32) as session:
        again = session.render(session.generate(QUICK_START)[0])
        brighter = session.render(shader, environment=np.full((16, 32, 3), 4.0, np.float32))
    assert np.array_equal(again, img) and brighter[16, 16, :3].mean() > img[16, 16, :3].mean()
    with pytest.raises(PUBLIC["DocumentError"]):
        render(BROKEN, size=8)


def test_the_host_example_draws_what_render_draws(tmp_path):
    """examples/host_moderngl.py, headless: its own GL bound from the manifest, equal to render within the golden
    tolerance (2 sRGB steps, no pixel over), a textured document too."""
    from mtlxgen.draw.compare import diff_map
    from mtlxgen.apps.golden import Tolerance
    for doc in (QUICK_START, os.path.join(ROOT, "tests", "data", "web", "textured.mtlx")):
        out = tmp_path / "host.npy"
        r = subprocess.run([sys.executable, os.path.join(ROOT, "examples", "host_moderngl.py"), doc, "--headless",
                            "--size", "64", "--out", str(out)], capture_output=True, text=True, cwd=ROOT, timeout=300)
        assert r.returncode == 0, r.stderr
        host, ours = np.load(out), PUBLIC["render"](doc, size=64)
        assert host[32, 32, 3] == 1.0 and host[0, 0, 3] == 0.0
        assert diff_map(host, ours).max() <= Tolerance().threshold
    with open(os.path.join(ROOT, "examples", "host_moderngl.py"), encoding="utf-8") as f:
        assert len(f.read().splitlines()) < 150


# ---------------------------------------------------------------- the command line

def _cli(*args, pre=""):
    code = pre + "import sys; from mtlxgen.apps.cli import main; sys.exit(main(sys.argv[1:]))"
    return subprocess.run([sys.executable, "-c", code] + list(args), capture_output=True, text=True, cwd=ROOT,
                          timeout=300)


def test_version():
    r = _cli("--version")
    assert r.returncode == 0 and r.stdout == "mtlxgen %s\n" % PUBLIC["__version__"]


def test_generate_says_what_it_wrote_unless_quiet(tmp_path):
    r = _cli("generate", QUICK_START, "-o", str(tmp_path / "o"))
    assert r.returncode == 0 and r.stdout == "wrote %s.{vert,frag,json}\n" % os.path.join(str(tmp_path / "o"), "M_tiles")
    assert sorted(os.listdir(tmp_path / "o")) == ["M_tiles.frag", "M_tiles.json", "M_tiles.vert"]
    r = _cli("generate", QUICK_START, "-o", str(tmp_path / "q"), "-q")
    assert r.returncode == 0 and r.stdout == "" and len(os.listdir(tmp_path / "q")) == 3


@pytest.mark.parametrize("module, package", [("moderngl", "moderngl"), ("OpenImageIO", "OpenImageIO"),
                                             ("MaterialX", "materialx"), ("numpy", "numpy")])
def test_a_missing_dependency_is_one_line_naming_the_package(tmp_path, module, package):
    r = _cli("render", QUICK_START, "-o", str(tmp_path), "--size", "8", pre="import sys; sys.modules[%r] = None; " % module)
    assert r.returncode == 1 and r.stdout == ""
    assert r.stderr == "mtlxgen render: error: the Python package %s is not installed (pip install %s)\n" % (
        package, package)
