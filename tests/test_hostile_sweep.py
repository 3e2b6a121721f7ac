"""A sweep of hostile and careless inputs the other tests do not cover, each through the command line in a
process of its own: every run ends with status 0 or 1, no traceback, one `FILE:LINE: message` line per problem.
"""
import os
import shutil
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHECKER = os.path.join(ROOT, "examples", "unlit_checker.mtlx")


def run_cli(*args, cwd, timeout=120):
    env = dict(os.environ)
    env.pop("DISPLAY", None)            # view: the offscreen framebuffer, never a window
    env.pop("WAYLAND_DISPLAY", None)
    return subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), *args], capture_output=True, text=True,
                          cwd=str(cwd), timeout=timeout, env=env)


def problem_lines(proc):
    """The run's stderr lines, checked: status 0 or 1, no traceback, no internal error."""
    text = proc.stdout + proc.stderr
    assert proc.returncode in (0, 1), text
    assert "Traceback" not in text and "internal error" not in text, text
    return [line for line in proc.stderr.splitlines() if line.strip()]


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
