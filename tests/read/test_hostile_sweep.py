"""A sweep of hostile and careless inputs the other tests do not cover, each through the command line in a
process of its own: every run ends with status 0 or 1, no traceback, one `FILE:LINE: message` line per problem.
"""
import os
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(ROOT, "examples", "unlit_checker.mtlx")
LIT = os.path.join(ROOT, "examples", "quick_start.mtlx")


def run_cli(*args, cwd, timeout=120):
    env = dict(os.environ)
    env.pop("DISPLAY", None)            # view: the offscreen framebuffer, never a window
    env.pop("WAYLAND_DISPLAY", None)
    return subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), *args], capture_output=True,
                          encoding="utf-8", errors="replace",       # (a file name not in UTF-8 is printed as is)
                          cwd=str(cwd), timeout=timeout, env=env)


def problem_lines(proc):
    """The run's stderr lines, checked: status 0 or 1, no traceback, no internal error."""
    text = proc.stdout + proc.stderr
    assert proc.returncode in (0, 1), text
    assert "Traceback" not in text and "internal error" not in text, text
    assert "pending error" not in text, text        # OpenImageIO's untaken error, printed at exit
    return [line for line in proc.stderr.splitlines() if line.strip()]


@pytest.fixture
def lit(tmp_path):
    shutil.copy(LIT, tmp_path / "lit.mtlx")
    return tmp_path / "lit.mtlx"


@pytest.fixture
def doc(tmp_path):
    shutil.copy(CHECKER, tmp_path / "doc.mtlx")
    return tmp_path / "doc.mtlx"


# ---------------------------------------------------------------- view --capture-window

@pytest.mark.parametrize("name", ["window", "window.bogus"])
def test_capture_window_to_a_name_no_image_format_takes_is_one_line(doc, tmp_path, name):
    """--capture-window FILE with no image extension: one line naming FILE (OpenImageIO's pending error on
    several lines at exit, naming the temporary file, before)."""
    proc = run_cli("view", str(doc), "--headless-frames", "1", "--no-watch", "--no-panel", "--size", "16", "16",
                   "--capture-window", name, cwd=tmp_path)
    lines = problem_lines(proc)
    assert proc.returncode == 1
    assert len(lines) == 1 and lines[0].startswith(name + ":0: "), lines
    assert ".tmp" not in proc.stdout + proc.stderr and "pending error" not in proc.stdout + proc.stderr, proc.stdout
    assert "format" in lines[0], lines
    assert not [f for f in os.listdir(tmp_path) if f.startswith(".")]


# ---------------------------------------------------------------- --env of odd images

def write_exr(path, pixels):
    import numpy as np
    import OpenImageIO as oiio
    h, w, c = pixels.shape
    buf = oiio.ImageBuf(oiio.ImageSpec(w, h, c, oiio.FLOAT))
    buf.set_pixels(oiio.ROI(), np.ascontiguousarray(pixels, dtype=np.float32))
    assert buf.write(str(path)), buf.geterror()
    return str(path)


ENV_RUNS = {"render": ("render", "-o", "out", "--size", "8"),
            "web": ("web", "-o", "out", "--size", "8"),
            "three": ("three", "-o", "out", "--size", "8"),
            "batch": ("batch", "-o", "out", "--size", "8", "-j", "1", "--no-progress"),
            "view": ("view", "--headless-frames", "1", "--no-watch", "--no-panel", "--size", "8", "8")}


@pytest.mark.parametrize("command", sorted(ENV_RUNS))
def test_two_channel_environment_is_read_as_grey(lit, tmp_path, command):
    """A grey-and-alpha environment (two channels) lights as its grey, as a one-channel one does (an internal
    error in the SH projection, and three's environment.exr written from the wrong buffer, before)."""
    import numpy as np
    env = write_exr(tmp_path / "grey_alpha.exr", np.full((8, 16, 2), 0.5))
    args = ENV_RUNS[command]
    proc = run_cli(*args[:1], str(lit), *args[1:], "--env", env, cwd=tmp_path)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr


@pytest.mark.parametrize("value", ["nan", "inf", "3e38"])
def test_environment_of_non_finite_or_huge_values_prints_no_numpy_warnings(lit, tmp_path, value):
    """NaN, infinite or float-overflowing radiance: the render is written, stderr holds no multi-line numpy
    RuntimeWarnings (a NaN pixel is written black in the PNG)."""
    import numpy as np
    env = write_exr(tmp_path / "env.exr", np.full((8, 16, 3), float(value)))
    proc = run_cli("render", str(lit), "-o", "out", "--size", "8", "--env", env, cwd=tmp_path)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr


# ---------------------------------------------------------------- --lights rigs of wrong types

@pytest.mark.parametrize("light, member, type_, value", [
    ("directional_light", "direction", "float", "1"),
    ("directional_light", "direction", "vector4", "1, 2, 3, 4"),
    ("point_light", "position", "matrix33", "1, 0, 0, 0, 1, 0, 0, 0, 1"),
    ("point_light", "intensity", "color3", "1, 1, 1"),
    ("point_light", "intensity", "string", "bright"),
    ("point_light", "color", "filename", "x.png"),
])
@pytest.mark.parametrize("command", ["render", "view"])
def test_light_rig_input_of_another_type_is_one_line_at_the_input(lit, tmp_path, light, member, type_, value, command):
    """A rig's light input whose type no light nodedef takes: one line at the input (exit 3, an internal error
    from float() or struct.pack, before)."""
    rig = tmp_path / "rig.mtlx"
    rig.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n  <%s name="l" type="lightshader">\n'
                   '    <input name="%s" type="%s" value="%s" />\n  </%s>\n</materialx>\n'
                   % (light, member, type_, value, light))
    args = (("render", str(lit), "-o", "out", "--size", "8") if command == "render" else
            ("view", str(lit), "--headless-frames", "1", "--no-watch", "--no-panel", "--size", "8", "8"))
    proc = run_cli(*args, "--lights", str(rig), cwd=tmp_path)
    lines = problem_lines(proc)
    assert proc.returncode == 1 and len(lines) == 1, lines
    assert lines[0].startswith(str(rig) + ":4: ") and member in lines[0] and type_ in lines[0], lines


# ---------------------------------------------------------------- a golden index from a stranger

@pytest.fixture
def golden_tree(tmp_path, doc):
    """tmp_path/doc.mtlx with its golden in tmp_path/g (made by golden update)."""
    proc = run_cli("golden", "update", str(doc), "--goldens", "g", "-j", "1", "--no-progress", cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return tmp_path


def _edit_index(tree, edit):
    import json
    path = tree / "g" / "index.json"
    index = json.loads(path.read_text())
    (name, entry), = index["goldens"].items()
    name = edit(index["goldens"], name, entry) or name
    path.write_text(json.dumps(index))
    return name


def _rename(key):
    def edit(goldens, name, entry):
        entry["settings"]["lights"] = [{"type": 1}]         # and the check fails: images are written
        goldens[key] = goldens.pop(name)
    return edit


def _set(field, value, where=None):
    def edit(goldens, name, entry):
        (entry if where is None else entry[where])[field] = value
    return edit


INDEX_EDITS = {
    "name climbing out": (_rename("../../evil"), "goldens['../../evil']: not a file name"),
    "absolute name": (_rename("/tmp/evil"), "goldens['/tmp/evil']: not a file name"),
    "png absolute": (_set("png", "/etc/passwd"), ".png: '/etc/passwd' is not a file name in the golden folder"),
    "png climbing out": (_set("png", "../secret.png"), ".png: '../secret.png' is not a file name"),
    "png a number": (_set("png", 5), ".png: 5 is not a non-empty text"),
    "exr a list": (_set("exr", [1]), ".exr: [1] is not a text or null"),
    "source an object": (_set("source", {}), ".source: {} is not a non-empty text"),
    "element gone": (lambda goldens, name, entry: entry.pop("element") and None, ".element: None is not a text"),
    "size a billion": (_set("size", 10 ** 9, "settings"), ".settings.size: 1000000000 is not a whole number"),
    "size negative": (_set("size", -5, "settings"), ".settings.size: -5 is not a whole number"),
    "size true": (_set("size", True, "settings"), ".settings.size: True is not a whole number"),
    "lights a text": (_set("lights", "x", "settings"), ".settings.lights: 'x' is not a list"),
    "tolerance a text": (_set("tolerance", {"threshold": "abc"}), ".tolerance.threshold: 'abc' is not a number"),
    "tolerance a list": (_set("tolerance", [1]), ".tolerance: [1] is not an object"),
    "entry a list": (lambda goldens, name, entry: goldens.__setitem__(name, [1]), "]: [1] is not an object"),
}


@pytest.mark.parametrize("verb", ["check", "update"])
@pytest.mark.parametrize("case", sorted(INDEX_EDITS))
def test_golden_index_entry_outside_the_shape_update_writes_is_one_line(golden_tree, case, verb):
    """golden check/update of an index a pull request brought: a name or image path that would read or write
    outside the golden and output folders (a check wrote NAME.new.png at out/../../evil.new.png, or /tmp/evil.*;
    copied any PNG the index named into the output), a size that aborted the process (stack smashing), values of
    other types (internal errors): one line naming the index and the field, exit 1, nothing written."""
    shutil.copy(golden_tree / "g" / "doc__M_checker.png", golden_tree.parent / "secret.png")
    edit, message = INDEX_EDITS[case]
    _edit_index(golden_tree, edit)
    before = sorted(os.listdir(golden_tree.parent)), sorted(os.listdir(golden_tree / "g"))
    args = ("-o", "out") if verb == "check" else ()
    proc = run_cli("golden", verb, "--goldens", "g", "-j", "1", "--no-progress", *args, cwd=golden_tree)
    lines = problem_lines(proc)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert len(lines) == 1 and lines[0].startswith("%s:0: goldens[" % (golden_tree / "g" / "index.json")), lines
    assert message in lines[0], lines
    assert (sorted(os.listdir(golden_tree.parent)), sorted(os.listdir(golden_tree / "g"))) == before
    assert not os.path.exists("/tmp/evil.new.png") and not (golden_tree / "out").exists()


def test_golden_image_linked_from_outside_the_golden_folder_is_not_copied(golden_tree):
    """A golden PNG that is a symbolic link out of the golden folder (git stores links): a failing check wrote
    the linked file's bytes (any metadata in them) as out/NAME.golden.png; now its decoded pixels are written."""
    import numpy as np
    import OpenImageIO as oiio
    outside = golden_tree.parent / "private.png"
    red = np.zeros((128, 128, 4), np.uint8)
    red[..., 0], red[..., 3] = 200, 255
    spec = oiio.ImageSpec(128, 128, 4, oiio.UINT8)
    spec.attribute("Comment", "private words")
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), red)
    assert buf.write(str(outside))
    golden = golden_tree / "g" / "doc__M_checker.png"
    golden.unlink()
    os.symlink(outside, golden)
    proc = run_cli("golden", "check", "--goldens", "g", "-o", "out", "-j", "1", "--no-progress", cwd=golden_tree)
    problem_lines(proc)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    copy = golden_tree / "out" / "doc__M_checker.golden.png"
    assert b"private words" not in copy.read_bytes() and copy.read_bytes() != outside.read_bytes()
    assert np.array_equal(oiio.ImageBuf(str(copy)).get_pixels(oiio.UINT8), red)


# ---------------------------------------------------------------- report

def test_results_json_with_a_lone_surrogate_is_reported(golden_tree):
    """JSON may spell a lone UTF-16 surrogate (\\ud800), which is no Unicode text: the page could not be written
    as UTF-8 (an internal error, exit 3); now the text is shown with U+FFFD in its place."""
    import json
    _edit_index(golden_tree, _set("lights", [{"type": 1}], "settings"))      # the check fails: images written
    run_cli("golden", "check", "--goldens", "g", "-o", "out", "-j", "1", "--no-progress", cwd=golden_tree)
    results = golden_tree / "out" / "results.json"
    data = json.loads(results.read_text())
    data["results"][0]["message"] = ["\ud800</script>"]
    results.write_text(json.dumps(data))
    proc = run_cli("report", "out", cwd=golden_tree)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr
    page = (golden_tree / "out" / "report.html").read_bytes().decode("utf-8")
    assert "\ufffd&lt;/script&gt;" in page and "\ufffd</script>" not in page


# ---------------------------------------------------------------- file names that are not UTF-8

@pytest.fixture
def latin1_named(tmp_path):
    """tmp_path/mats/caf\\xe9.mtlx: a file name in Latin-1, not UTF-8 (Python holds it with a surrogate)."""
    (tmp_path / "mats").mkdir()
    name = os.path.join(os.fsencode(str(tmp_path / "mats")), b"caf\xe9.mtlx")
    shutil.copy(CHECKER, name)
    return tmp_path


def test_batch_of_a_file_name_that_is_not_utf8(latin1_named):
    """batch drew the document and failed to write its image: OpenImageIO takes no such name (exit 3, an internal
    error on several lines)."""
    proc = run_cli("batch", "mats", "-o", "out", "-j", "1", "--no-progress", cwd=latin1_named)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr
    assert [f for f in os.listdir(latin1_named / "out") if f.endswith(".png")]


def test_golden_update_check_and_report_of_a_file_name_that_is_not_utf8(latin1_named):
    proc = run_cli("golden", "update", "mats", "--goldens", "g", "-j", "1", "--no-progress", cwd=latin1_named)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr
    proc = run_cli("golden", "check", "mats", "--goldens", "g", "-o", "out", "-j", "1", "--no-progress",
                   cwd=latin1_named)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr
    proc = run_cli("report", "out", "--goldens", "g", cwd=latin1_named)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr


@pytest.mark.parametrize("command", ["generate", "render", "info", "batch"])
def test_usd_stage_whose_file_name_is_not_utf8_is_one_line(tmp_path, command):
    """USD takes paths as UTF-8 text: a stage named in Latin-1 was an internal error (UnicodeEncodeError)."""
    src = os.path.join(ROOT, "examples", "usd")
    name = os.path.join(os.fsencode(str(tmp_path)), b"st\xe9.usda")
    shutil.copy(os.path.join(src, "preview_stage.usda"), name)
    for f in os.listdir(src):
        if f.endswith(".png"):
            shutil.copy(os.path.join(src, f), tmp_path / f)
    stage = os.fsdecode(name)
    args = {"generate": ("generate", stage, "-o", "out"), "render": ("render", stage, "-o", "out", "--size", "8"),
            "info": ("info", stage), "batch": ("batch", str(tmp_path), "-o", "out", "-j", "1", "--no-progress")}
    proc = run_cli(*args[command], cwd=tmp_path)
    lines = problem_lines(proc)
    assert proc.returncode == 1 and len(lines) == 1 and "not UTF-8" in lines[0], lines
    assert lines[0].startswith(os.path.join(str(tmp_path), "st\\udce9.usda:0: ")), lines


@pytest.fixture
def latin1_folder(tmp_path):
    """tmp_path/d\\xfe (a folder named in Latin-1) holding doc.mtlx, which names its texture t.png beside it,
    t.png and env.png."""
    import numpy as np
    folder = os.path.join(os.fsencode(str(tmp_path)), b"d\xfe")
    os.mkdir(folder)
    png = str(tmp_path / "one.png")
    from mtlxgen.base.images import write_image
    write_image(png, np.ones((2, 2, 3), np.float32))
    for name in (b"t.png", b"env.png"):
        shutil.copy(png, os.path.join(folder, name))
    with open(os.path.join(folder, b"doc.mtlx"), "w") as f:
        f.write('<?xml version="1.0"?>\n<materialx version="1.39">\n'
                '  <image name="c" type="color3"><input name="file" type="filename" value="t.png" /></image>\n'
                '  <standard_surface name="S" type="surfaceshader">\n'
                '    <input name="base_color" type="color3" nodename="c" />\n  </standard_surface>\n'
                '  <surfacematerial name="M" type="material">\n'
                '    <input name="surfaceshader" type="surfaceshader" nodename="S" />\n  </surfacematerial>\n'
                '</materialx>\n')
    return os.fsdecode(folder)


@pytest.mark.parametrize("command", ["render", "web", "three", "batch", "view", "env", "output"])
def test_images_under_a_folder_name_that_is_not_utf8_are_one_line(latin1_folder, tmp_path, lit, command):
    """OpenImageIO takes paths as UTF-8 text: a texture, an environment or an output under a folder named in
    Latin-1 was an internal error (a TypeError from the binding, on several lines)."""
    doc = os.path.join(latin1_folder, "doc.mtlx")
    args = {"render": ("render", doc, "-o", "out", "--size", "8"),
            "web": ("web", doc, "-o", "out", "--size", "8"),
            "three": ("three", doc, "-o", "out"),
            "batch": ("batch", latin1_folder, "-o", "out", "-j", "1", "--no-progress"),
            "view": ("view", doc, "--headless-frames", "1", "--no-watch", "--no-panel", "--size", "8", "8"),
            "env": ("render", str(lit), "-o", "out", "--size", "8", "--env", os.path.join(latin1_folder, "env.png")),
            "output": ("render", str(lit), "-o", os.path.join(latin1_folder, "out"), "--size", "8")}[command]
    proc = run_cli(*args, cwd=tmp_path)
    lines = problem_lines(proc)
    assert proc.returncode == 1 and len(lines) == 1 and "not UTF-8" in lines[0], lines


# ---------------------------------------------------------------- .usdz packages

USDZ_MATERIAL = '''#usda 1.0
def Scope "Looks"
{
    def Material "M"
    {
        token outputs:surface.connect = </Looks/M/Surface.outputs:surface>
        def Shader "Surface"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor.connect = </Looks/M/Texture.outputs:rgb>
            token outputs:surface
        }
        def Shader "Texture"
        {
            uniform token info:id = "UsdUVTexture"
            asset inputs:file = @%s@
            float3 outputs:rgb
        }
    }
}
'''


def _usdz(path, texture):
    import zipfile
    with zipfile.ZipFile(path, "w", zipfile.ZIP_STORED) as z:
        z.writestr("root.usda", USDZ_MATERIAL % texture)
    return str(path)


@pytest.mark.parametrize("command", ["generate", "render", "three"])
def test_usdz_texture_climbing_out_of_its_package_is_not_read(tmp_path, command):
    """A packaged layer naming '../outside.png', which is not in the package: the stage said 'not found,
    drawing the fallback', then the renderer bound outside.png beside the package's folder (three re-encoded it
    into its output); and a name reaching a file that is no image left OpenImageIO's error pending, printed on
    several lines at exit."""
    import numpy as np
    from mtlxgen.base.images import write_image
    (tmp_path / "pkg").mkdir()
    write_image(str(tmp_path / "outside.png"), np.full((4, 4, 3), 0.5, np.float32))
    (tmp_path / "notes.txt").write_text("private\n")
    for texture in ("../outside.png", "../notes.txt"):
        stage = _usdz(tmp_path / "pkg" / "s.usdz", texture)
        args = ("-o", "out") + (("--size", "8") if command == "render" else ())
        proc = run_cli(command, stage, *args, cwd=tmp_path)
        lines = problem_lines(proc)
        assert lines and all(line.startswith(stage + ":/Looks/M/Texture.inputs:file: ") for line in lines), lines
        assert "not found" in lines[0] and len(lines) == 1, lines
        if command == "three":
            assert not [f for _, _, files in os.walk(tmp_path / "out") for f in files
                        if f.endswith((".png", ".exr")) and not f.startswith("environment")], texture


def test_golden_of_a_file_name_with_a_line_break_is_checked(tmp_path):
    """A document named 'a\\nb.mtlx': golden update wrote an index entry 'a\\nb__M_checker' that the index's own
    check refuses (a golden's name is a plain file name), so golden check of it failed on the index."""
    (tmp_path / "mats").mkdir()
    shutil.copy(CHECKER, tmp_path / "mats" / "a\nb.mtlx")
    proc = run_cli("golden", "update", "mats", "--goldens", "g", "-j", "1", "--no-progress", cwd=tmp_path)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr
    proc = run_cli("golden", "check", "--goldens", "g", "-o", "out", "-j", "1", "--no-progress", cwd=tmp_path)
    assert problem_lines(proc) == [] and proc.returncode == 0, proc.stdout + proc.stderr
    assert all(name.isprintable() for name in os.listdir(tmp_path / "g"))


# ---------------------------------------------------------------- --keep-file

@pytest.mark.parametrize("text, message", [
    ('{"uniforms": 5}', 'a JSON keep file is a list of names'),
    ('{"uniforms": "abc"}', 'a JSON keep file is a list of names'),
    ("[" * 100000 + "]" * 100000, "nested too deeply"),
])
def test_keep_file_of_another_shape_is_one_line_naming_it(doc, tmp_path, text, message):
    """A keep file whose "uniforms" is no list (an internal error iterating an int), or JSON nested past Python's
    recursion limit (a line blaming the document, with no line number)."""
    keep = tmp_path / "keep.json"
    keep.write_text(text)
    proc = run_cli("generate", str(doc), "-o", "out", "--interface", "reduced", "--keep-file", str(keep),
                   cwd=tmp_path)
    lines = problem_lines(proc)
    assert proc.returncode == 1 and len(lines) == 1 and lines[0].startswith(str(keep) + ":1: "), lines
    assert message in lines[0], lines
