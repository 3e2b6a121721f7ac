"""A texture file a .mtlx document names that cannot be read (not found, no UDIM tiles, a FIFO, a dangling link) is
reported as a USD stage's is: one FILE:LINE line at the input naming it. generate writes the shader (it is valid:
the image's default stands in) and warns; --strict makes it an error; everything that draws (render, web, three,
batch, golden) reports it as a problem, exit 1."""
import os
import re
import subprocess
import sys

import pytest

from mtlxgen import pipeline
from mtlxgen.base.diagnostics import Warnings

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  <image name="img" type="color3">
    <input name="default" type="color3" value="0.2, 0.4, 0.6" />
    <input name="file" type="filename" value="{file}" />
  </image>
  <standard_surface name="ss" type="surfaceshader">
    <input name="base_color" type="color3" nodename="img" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="ss" />
  </surfacematerial>
</materialx>
"""
FILE_LINE = 5       # the file input's line in DOC


def _doc(tmp_path, file):
    folder = tmp_path / "doc"
    folder.mkdir(exist_ok=True)
    path = folder / "m.mtlx"
    path.write_text(DOC.format(file=file))
    return str(path)


def _cli(*args, timeout=240):
    proc = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), *args], capture_output=True, text=True,
                          timeout=timeout, cwd=ROOT)
    assert "Traceback" not in proc.stderr, proc.stderr
    return proc.returncode, proc.stderr.splitlines()


def _missing_line(path, rest):
    return re.compile(r"^%s:%d: %s" % (re.escape(path), FILE_LINE, rest))


def test_generate_warns_and_writes_strict_refuses(tmp_path):
    path = _doc(tmp_path, "textures/gone.png")
    rc, err = _cli("generate", path, "-o", str(tmp_path / "out"))
    assert rc == 0
    assert len(err) == 1 and _missing_line(path, r"warning: texture 'textures/gone\.png' not found \(looked for "
                                            + re.escape(os.path.join(os.path.dirname(path), "textures", "gone.png"))
                                            ).match(err[0]), err
    assert os.path.isfile(tmp_path / "out" / "M.frag")
    rc, err = _cli("generate", path, "-o", str(tmp_path / "strict"), "--strict")
    assert rc == 1
    assert len(err) == 1 and _missing_line(path, "texture 'textures/gone.png' not found").match(err[0]) \
        and err[0].endswith("(a warning; an error with --strict)"), err


@pytest.mark.parametrize("command", ["render", "web", "three"])
def test_commands_that_draw_report_it(tmp_path, command):
    path = _doc(tmp_path, "textures/gone.png")
    extra = ["--size", "32"] if command == "render" else []
    rc, err = _cli(command, path, "-o", str(tmp_path / "out"), *extra)
    assert rc == 1
    assert len(err) == 1 and _missing_line(path, "texture 'textures/gone.png' not found").match(err[0]), err


def test_batch_and_golden_report_it(tmp_path):
    path = _doc(tmp_path, "gone.png")
    rc, err = _cli("batch", path, "-o", str(tmp_path / "b"), "-j", "1", "--size", "16", "--no-progress")
    assert rc == 1
    assert any(_missing_line(path, "texture 'gone.png' not found").search(line) for line in err), err


def test_present_texture_says_nothing(tmp_path):
    from mtlxgen.base.images import write_image
    import numpy as np
    path = _doc(tmp_path, "tex.png")
    write_image(os.path.join(os.path.dirname(path), "tex.png"), np.full((4, 4, 3), 0.5, np.float32))
    warnings = Warnings()
    shaders = pipeline.generate(path, warnings=warnings)
    assert len(shaders) == 1 and not warnings.items
    assert pipeline.generate(path, partial=True, unreadable_textures="error")[1] is None


def test_udim_tiles_said_once(tmp_path):
    """A tile pattern is emission's to resolve: no tiles is its one problem (not a second note), a tile enough."""
    path = _doc(tmp_path, "tiles/t.<UDIM>.png")
    shaders, error = pipeline.generate(path, partial=True, unreadable_textures="error")
    assert not shaders and len(error.problems) == 1 and "no tiles of 'tiles/t.<UDIM>.png' found" in error.lines()[0]
    from mtlxgen.base.images import write_image
    import numpy as np
    write_image(os.path.join(os.path.dirname(path), "tiles", "t.1001.png"), np.ones((2, 2, 3), np.float32))
    warnings = Warnings()
    assert len(pipeline.generate(path, warnings=warnings, unreadable_textures="error")) == 1
    assert warnings.items == []


def test_not_a_regular_file_is_named(tmp_path):
    path = _doc(tmp_path, "pipe.png")
    os.mkfifo(os.path.join(os.path.dirname(path), "pipe.png"))
    shaders, error = pipeline.generate(path, partial=True, unreadable_textures="error")
    assert len(shaders) == 1
    assert [str(loc) for loc, _ in error.problems] == ["%s:%d" % (path, FILE_LINE)]
    assert error.problems[0][1] == "texture 'pipe.png' is a FIFO; the image's default is drawn"
    path = _doc(tmp_path, "dangling.png")
    os.symlink(str(tmp_path / "nowhere.png"), os.path.join(os.path.dirname(path), "dangling.png"))
    shaders, error = pipeline.generate(path, partial=True, unreadable_textures="error")
    assert error.problems[0][1] == "texture 'dangling.png' is a dangling symbolic link; the image's default is drawn"


def test_materials_of_one_structure_each_name_their_texture(tmp_path):
    """Six materials of one structure (one function called by each): each names its missing texture at its own
    input's line."""
    parts = ['<?xml version="1.0"?>\n<materialx version="1.39">']
    for k in range(6):
        parts += ['  <image name="img%d" type="color3">' % k,
                  '    <input name="file" type="filename" value="gone.png" />',
                  '  </image>',
                  '  <standard_surface name="ss%d" type="surfaceshader">' % k,
                  '    <input name="base_color" type="color3" nodename="img%d" />' % k,
                  '    <input name="base" type="float" value="0.%d" />' % (k + 1),
                  '  </standard_surface>',
                  '  <surfacematerial name="M%d" type="material">' % k,
                  '    <input name="surfaceshader" type="surfaceshader" nodename="ss%d" />' % k,
                  '  </surfacematerial>']
    parts.append('</materialx>\n')
    path = tmp_path / "six.mtlx"
    path.write_text("\n".join(parts))
    shaders, error = pipeline.generate(str(path), partial=True, unreadable_textures="error")
    assert len(shaders) == 6
    assert sorted(loc.line for loc, _ in error.problems) == [4 + 10 * k for k in range(6)]


def test_a_texture_that_does_not_decode_is_one_line_at_its_input(tmp_path):
    """A truncated PNG: the decoder's message (libpng's, captured) in one line at the input naming the file, for
    render and batch alike; generate says nothing (it reads no pixels)."""
    import numpy as np
    from mtlxgen.base.images import write_image
    path = _doc(tmp_path, "cut.png")
    whole = str(tmp_path / "whole.png")
    write_image(whole, np.random.default_rng(1).random((64, 64, 3)).astype(np.float32))
    data = open(whole, "rb").read()
    with open(os.path.join(os.path.dirname(path), "cut.png"), "wb") as f:
        f.write(data[:len(data) // 2])
    cut = os.path.join(os.path.dirname(path), "cut.png")
    for args in (["render", path, "-o", str(tmp_path / "r"), "--size", "16"],
                 ["batch", path, "-o", str(tmp_path / "b"), "-j", "1", "--size", "16", "--no-progress"]):
        rc, err = _cli(*args)
        lines = [line for line in err if "cut.png" in line]
        assert rc == 1 and len(lines) == 1 and lines[0].startswith("%s:%d: texture '%s': " % (path, FILE_LINE, cut)), err
        assert not any("libpng" in line and not line.startswith(path) for line in err), err
    rc, err = _cli("generate", path, "-o", str(tmp_path / "g"))
    assert rc == 0 and err == []


def test_view_says_it_and_draws_the_default(tmp_path):
    """The viewer draws the element (the image's default) and shows the line as a problem: headless, exit 1."""
    path = _doc(tmp_path, "gone.png")
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    env.pop("WAYLAND_DISPLAY", None)
    proc = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "view", path, "--headless-frames", "2",
                           "--screenshot", str(tmp_path / "shot.png"), "--no-watch"], capture_output=True, text=True,
                          timeout=240, env=env)
    assert proc.returncode == 1 and "Traceback" not in proc.stderr
    assert [line for line in proc.stderr.splitlines() if "gone.png" in line] == [
        "%s:%d: texture 'gone.png' not found (looked for %s and in the search paths); the image's default is drawn"
        % (path, FILE_LINE, os.path.join(os.path.dirname(path), "gone.png"))], proc.stderr
    from mtlxgen.base.images import read_image
    centre = read_image(str(tmp_path / "shot.png"))[240, 320]     # drawn: the sphere, not an empty frame
    assert centre[:3].max() > 0.05, centre
