"""`mtlxgen view` (issue 12): --headless-frames N --screenshot FILE draws N frames and writes the last, in a glfw
window under Xvfb and in an offscreen context without a display; the screenshot is at parity with `mtlxgen
render` of the same element, camera and samples (and pixel-identical where one frame takes all the samples)."""
import os
import subprocess
import sys

import numpy as np
import pytest

from mtlxgen.draw import compare
from mtlxgen.base import images

from xvfb import start_xvfb, stop_xvfb

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
QUICK_START = os.path.join(ROOT, "examples", "quick_start.mtlx")
SIZE = 64


def run_cli(args, env=None, timeout=300):
    env = dict(env if env is not None else os.environ)
    return subprocess.run([sys.executable, os.path.join(ROOT, "cli.py")] + args, capture_output=True, text=True,
                          env=env, timeout=timeout, cwd=ROOT)


def no_display():
    env = dict(os.environ)
    env.pop("DISPLAY", None)
    env.pop("WAYLAND_DISPLAY", None)
    return env


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    out = tmp_path_factory.mktemp("render")
    r = run_cli(["render", QUICK_START, "-o", str(out), "--size", str(SIZE)])
    assert r.returncode == 0, r.stderr
    return images.read_image(str(out / "M_tiles.exr"))


@pytest.fixture(scope="module")
def display():
    pytest.importorskip("glfw", reason="the viewer's window needs glfw (pip install 'mtlxgen[view]')")
    d = start_xvfb()
    yield d
    stop_xvfb(d)


def view(tmp_path, env, *extra, frames=4):
    shot = tmp_path / "shot.png"
    r = run_cli(["view", QUICK_START, "--size", str(SIZE), str(SIZE), "--headless-frames", str(frames),
                 "--screenshot", str(shot), "--no-background", "--no-watch"] + list(extra), env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == [str(shot), str(tmp_path / "shot.exr")]
    return images.read_image(str(tmp_path / "shot.exr"))


def test_offscreen_one_frame_of_all_samples_is_render(tmp_path, rendered):
    """Without a display, offscreen: 64 samples in one frame is render's estimate, pixel for pixel, with the
    complete interface (render's shader); the viewer's own zero-weight specialization (the default: inputs at
    zero folded, their lobes left out of the code) draws the same picture but for float rounding."""
    img = view(tmp_path, no_display(), "--samples", "64", "--frame-samples", "64", "--interface", "complete",
               frames=2)
    assert np.array_equal(img, rendered)
    special = view(tmp_path, no_display(), "--samples", "64", "--frame-samples", "64", frames=2)
    assert np.abs(special - rendered).max() <= 1e-3
    p = compare.parity(special, rendered)
    assert p.mean <= 0.01 and p.passes, p


def test_window_progressive_screenshot_at_parity_with_render(tmp_path, rendered, display):
    """A glfw window under Xvfb, 4 still frames of 16 samples accumulated: parity with render's 64."""
    img = view(tmp_path, display.env(), "--samples", "64", "--frame-samples", "16", frames=4)
    p = compare.parity(img, rendered)
    assert p.mean <= compare.MEAN_LIMIT and p.passes, p
    few = view(tmp_path, display.env(), "--samples", "64", "--frame-samples", "16", frames=1)   # one frame of 4
    assert compare.parity(few, rendered).mean > p.mean


def test_window_capture_shows_background_and_keys_in_title(tmp_path, display):
    cap = tmp_path / "window.png"
    r = run_cli(["view", QUICK_START, "--size", "96", "72", "--headless-frames", "2", "--capture-window", str(cap),
                 "--no-watch", "--no-panel", "--geometry", "plane"], env=display.env())
    assert r.returncode == 0, r.stderr
    img = images.read_image(str(cap))
    assert img.shape[:2] == (72, 96)
    corner = img[0, 0, :3]                 # the sky above the plane: blue, not the grey of no background
    assert corner[2] > corner[0] + 0.1, corner


@pytest.mark.parametrize("args, message", [
    (["--screenshot", "x.png"], "--screenshot and --capture-window go with --headless-frames N"),
    (["--samples", "48"], "argument --samples: 48 is not a power of two"),
    (["--geometry", "no_such_mesh.obj"], "argument --geometry: no_such_mesh.obj: no such file"),
    (["--element", "nope", "--headless-frames", "1"], "no renderable element 'nope' (elements: M_tiles)"),
])
def test_bad_options_are_one_line(args, message):
    r = run_cli(["view", QUICK_START, "--size", "8", "8", "--no-watch"] + args, env=no_display())
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], r.stderr
