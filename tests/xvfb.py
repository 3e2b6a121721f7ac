"""An Xvfb display for the viewer's tests (Debian package `xvfb`; .ci/run installs it). Tests that need one
skip, saying so, where Xvfb is not installed."""
import os
import shutil
import subprocess
import time

import pytest


class Display:
    def __init__(self, proc, name):
        self.proc, self.name = proc, name

    def env(self, **extra):
        """os.environ with DISPLAY set to this display (for a subprocess)."""
        env = dict(os.environ, DISPLAY=self.name, **extra)
        env.pop("WAYLAND_DISPLAY", None)
        return env


def start_xvfb(width=1024, height=768):
    """Start Xvfb on a free display (it picks the number and writes it to a pipe); the Display, or a skip."""
    binary = shutil.which("Xvfb")
    if binary is None:
        pytest.skip("Xvfb is not installed (Debian: apt-get install xvfb): the viewer's window tests need a display")
    read, write = os.pipe()
    proc = subprocess.Popen([binary, "-displayfd", str(write), "-screen", "0", "%dx%dx24" % (width, height),
                             "-nolisten", "tcp"], pass_fds=(write,), stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    os.close(write)
    number = b""
    deadline = time.time() + 20
    while not number.endswith(b"\n") and time.time() < deadline:
        chunk = os.read(read, 16)
        if not chunk:
            break
        number += chunk
    os.close(read)
    if not number.strip():
        proc.kill()
        pytest.skip("Xvfb did not start")
    return Display(proc, ":" + number.decode().strip())


def stop_xvfb(display):
    display.proc.terminate()
    try:
        display.proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        display.proc.kill()
