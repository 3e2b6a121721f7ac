"""Folders and outputs as a careless or hostile user's file system has them.

- A folder given to `batch` or `golden check|update` holding entries that cannot be read (a dangling symbolic
  link, a link loop, FIFOs named .mtlx and .usda, folder links that loop): one `PATH:0: skipped: WHY` line each,
  the rest done, exit 1; never a traceback, an internal error or a hang.
- Outputs replace a symbolic link at their path instead of writing through it (generate's files, golden's
  images, index and results.json, batch's images, glslvalidate's stage files); new files get ordinary modes.
- An internal error in one batch document is one line naming the document; the others are drawn.
- `view --screenshot` of a document that draws nothing writes no (black) picture.
- An empty struct value (value="") is read as MaterialX reads it: a nodedef's as no value (warned), a node's
  refused on one line.
- Output folders that cannot take files: one line, exit 1.
"""
import json
import os
import re
import shutil
import stat
import subprocess
import sys

import numpy as np
import pytest

from util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CHECKER = os.path.join(ROOT, "examples", "unlit_checker.mtlx")
GOLDEN = "unlit_checker__M_checker"


def run_cli(*args, cwd, umask=None, timeout=60):
    """The command line in a process of its own (a FIFO that blocks it shows as a timeout, not a stuck run)."""
    env = dict(os.environ)
    env.pop("DISPLAY", None)            # view: the offscreen framebuffer, never a window
    env.pop("WAYLAND_DISPLAY", None)
    return subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), *args], capture_output=True, text=True,
                          cwd=str(cwd), timeout=timeout, env=env,
                          preexec_fn=None if umask is None else (lambda: os.umask(umask)))


def no_crash(proc):
    text = proc.stdout + proc.stderr
    assert "Traceback" not in text and "internal error" not in text, text


def victim(path, text="keep me\n"):
    """A file a symbolic link at an output points to: it must keep its bytes."""
    with open(path, "w") as f:
        f.write(text)
    return str(path)


def unchanged(path, text="keep me\n"):
    with open(path) as f:
        return f.read() == text


def is_regular_file(path):
    return not os.path.islink(path) and stat.S_ISREG(os.lstat(path).st_mode)


# ---------------------------------------------------------------- folders with unreadable entries

SKIPPED = ["mats/dangling.mtlx:0: skipped: a dangling symbolic link",
           "mats/fifo.mtlx:0: skipped: a FIFO",
           "mats/loop.mtlx:0: skipped: a symbolic link loop",
           "mats/stage.usda:0: skipped: a FIFO"]


def hostile_folder(root):
    """root/mats: the checker beside a dangling link, a link loop, FIFOs named .mtlx and .usda, and folder links
    that loop (to the folder itself, to its parent, and from a subfolder back up)."""
    mats = root / "mats"
    (mats / "deeper").mkdir(parents=True)
    shutil.copy(CHECKER, mats / "unlit_checker.mtlx")
    os.symlink("nowhere.mtlx", mats / "dangling.mtlx")
    os.symlink("loop.mtlx", mats / "loop.mtlx")
    os.mkfifo(mats / "fifo.mtlx")
    os.mkfifo(mats / "stage.usda")
    os.symlink(".", mats / "same")
    os.symlink("..", mats / "up")
    os.symlink("..", mats / "deeper" / "back")
    return mats


def test_batch_reports_each_unreadable_entry_and_draws_the_rest(tmp_path):
    hostile_folder(tmp_path)
    (tmp_path / "out").mkdir()
    os.symlink(victim(tmp_path / "victim.png"), tmp_path / "out" / (GOLDEN + ".png"))
    proc = run_cli("batch", "mats", "-o", "out", "--size", "8", "-j", "1", "--no-progress", cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 1, proc.stderr
    assert sorted(proc.stderr.splitlines()) == SKIPPED, proc.stderr
    assert "1 materials" in proc.stdout, proc.stdout
    png = tmp_path / "out" / (GOLDEN + ".png")
    assert is_regular_file(png) and unchanged(tmp_path / "victim.png")      # the link replaced, not written through


def test_golden_update_and_check_report_unreadable_entries_and_fail(tmp_path):
    hostile_folder(tmp_path)
    update = run_cli("golden", "update", "mats", "--goldens", "g", "--size", "8", "-j", "1", "--no-progress",
                     cwd=tmp_path)
    no_crash(update)
    assert update.returncode == 1, update.stdout + update.stderr
    lines = [line.strip() for line in update.stdout.splitlines()]
    assert "created   %s" % GOLDEN in lines and all(s in lines for s in SKIPPED), update.stdout
    assert "1 created, 4 error" in update.stdout
    with open(tmp_path / "g" / "index.json") as f:
        assert list(json.load(f)["goldens"]) == [GOLDEN]

    check = run_cli("golden", "check", "mats", "--goldens", "g", "-o", "out", "-j", "1", "--no-progress",
                    "--no-flip", cwd=tmp_path)
    no_crash(check)
    assert check.returncode == 1, check.stdout + check.stderr    # a document that cannot be read is no pass
    assert "1 passed, 0 failed, 0 missing, 4 errors" in check.stdout, check.stdout
    lines = [line.strip() for line in check.stdout.splitlines()]
    assert all(s in lines for s in SKIPPED), check.stdout
    with open(tmp_path / "out" / "results.json") as f:
        results = json.load(f)["results"]
    assert sorted(r["status"] for r in results) == ["error"] * 4 + ["pass"]

    # the index's own source turned into a FIFO: named as such, no reader opens it
    os.remove(tmp_path / "mats" / "unlit_checker.mtlx")
    os.mkfifo(tmp_path / "mats" / "unlit_checker.mtlx")
    check = run_cli("golden", "check", "--goldens", "g", "-o", "out", "-j", "1", "--no-progress", "--no-flip",
                    cwd=tmp_path)
    no_crash(check)
    assert check.returncode == 1
    assert "mats/unlit_checker.mtlx:0: the source of golden %s is a FIFO" % GOLDEN in check.stdout, check.stdout


def test_dangling_links_and_loops_alone_are_reported_not_a_crash(tmp_path, monkeypatch, capsys):
    # (without a FIFO in the folder: dangling entries made batch die of an IndexError, golden of a ValueError)
    from mtlxgen.apps.cli import main
    mats = tmp_path / "mats"
    mats.mkdir()
    shutil.copy(CHECKER, mats / "unlit_checker.mtlx")
    os.symlink("nowhere.mtlx", mats / "dangling.mtlx")
    os.symlink("loop.mtlx", mats / "loop.mtlx")
    monkeypatch.chdir(tmp_path)
    assert main(["batch", "mats", "-o", "out", "--size", "8", "-j", "1", "--no-progress"]) == 1
    assert sorted(capsys.readouterr().err.splitlines()) == [SKIPPED[0], SKIPPED[2]]
    assert os.listdir("out") == [GOLDEN + ".png"]
    assert main(["golden", "update", "mats", "--goldens", "g", "--size", "8", "-j", "1", "--no-progress"]) == 1
    out = [line.strip() for line in capsys.readouterr().out.splitlines()]
    assert SKIPPED[0] in out and SKIPPED[2] in out and "created   %s" % GOLDEN in out, out


@pytest.mark.parametrize("make,why", [(os.mkfifo, "a FIFO"), (lambda p: os.symlink("gone.json", p),
                                                               "a dangling symbolic link")], ids=["fifo", "dangling"])
def test_a_golden_index_that_is_not_a_regular_file_is_one_line(tmp_path, make, why):
    from mtlxgen.apps import golden
    from mtlxgen.base.diagnostics import MtlxError
    from base.test_security import deadline
    make(str(tmp_path / "index.json"))
    with deadline(10), pytest.raises(MtlxError) as e:        # (a FIFO opened for reading blocks)
        golden.Index(str(tmp_path))
    assert e.value.lines() == ["%s:1: golden index is %s" % (tmp_path / "index.json", why)]


# ---------------------------------------------------------------- outputs replace symbolic links

def test_generate_replaces_symlinks_at_its_outputs_and_gives_ordinary_modes(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    os.symlink(victim(tmp_path / "victim.txt"), out / "M_checker.frag")
    os.symlink(str(tmp_path / "made_elsewhere.txt"), out / "M_checker.vert")        # dangling: not created there
    proc = run_cli("generate", CHECKER, "-o", "out", cwd=tmp_path, umask=0o027)
    no_crash(proc)
    assert proc.returncode == 0, proc.stderr
    assert unchanged(tmp_path / "victim.txt") and not os.path.lexists(tmp_path / "made_elsewhere.txt")
    for ext in (".frag", ".vert", ".json"):
        path = out / ("M_checker" + ext)
        assert is_regular_file(path) and stat.S_IMODE(os.stat(path).st_mode) == 0o640, ext
    assert (out / "M_checker.frag").read_text().startswith("#version")
    assert sorted(os.listdir(out)) == ["M_checker.frag", "M_checker.json", "M_checker.vert"]   # no temp files


def test_golden_outputs_replace_symlinks_and_the_index_keeps_ordinary_modes(tmp_path):
    from mtlxgen.base import images
    (tmp_path / "m").mkdir()
    shutil.copy(CHECKER, tmp_path / "m" / "unlit_checker.mtlx")
    g = tmp_path / "g"
    g.mkdir()
    os.symlink(victim(tmp_path / "victim_golden.png"), g / (GOLDEN + ".png"))
    proc = run_cli("golden", "update", "m", "--goldens", "g", "--size", "8", "-j", "1", "--no-progress",
                   cwd=tmp_path, umask=0o027)
    no_crash(proc)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert unchanged(tmp_path / "victim_golden.png") and is_regular_file(g / (GOLDEN + ".png"))
    assert stat.S_IMODE(os.stat(g / "index.json").st_mode) == 0o640          # 0666 less the umask, not 0600

    os.chmod(g / "index.json", 0o604)          # an index written over keeps its mode
    proc = run_cli("golden", "update", "m", "--goldens", "g", "--size", "9", "-j", "1", "--no-progress",
                   cwd=tmp_path, umask=0o077)
    assert proc.returncode == 0 and "updated   %s" % GOLDEN in proc.stdout, proc.stdout + proc.stderr
    assert stat.S_IMODE(os.stat(g / "index.json").st_mode) == 0o604

    # a failing check writes results.json and the golden's copy beside the new image: links there are replaced
    images.write_image(str(g / (GOLDEN + ".png")), np.zeros((9, 9, 4), np.uint8))
    out = tmp_path / "out"
    out.mkdir()
    os.symlink(victim(tmp_path / "victim_results.txt"), out / "results.json")
    os.symlink(victim(tmp_path / "victim_copy.txt"), out / (GOLDEN + ".golden.png"))
    proc = run_cli("golden", "check", "m", "--goldens", "g", "-o", "out", "-j", "1", "--no-progress", "--no-flip",
                   cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 1 and "0 passed, 1 failed" in proc.stdout, proc.stdout + proc.stderr
    assert unchanged(tmp_path / "victim_results.txt") and unchanged(tmp_path / "victim_copy.txt")
    assert is_regular_file(out / "results.json") and is_regular_file(out / (GOLDEN + ".golden.png"))
    with open(out / "results.json") as f:
        assert json.load(f)["results"][0]["status"] == "fail"
    assert (out / (GOLDEN + ".golden.png")).read_bytes() == (g / (GOLDEN + ".png")).read_bytes()


def test_golden_outputs_the_file_system_refuses_are_named_not_their_temporary_files(tmp_path):
    (tmp_path / "m").mkdir()
    shutil.copy(CHECKER, tmp_path / "m" / "unlit_checker.mtlx")
    (tmp_path / "g" / (GOLDEN + ".png")).mkdir(parents=True)          # a folder where the golden goes
    proc = run_cli("golden", "update", "m", "--goldens", "g", "--size", "8", "-j", "1", "--no-progress", cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 1 and ".tmp" not in proc.stdout + proc.stderr, proc.stdout + proc.stderr
    assert "g/%s.png:0: cannot write image: Is a directory" % GOLDEN in proc.stdout, proc.stdout
    assert not os.path.exists(tmp_path / "g" / "index.json")          # nothing recorded for it

    os.rmdir(tmp_path / "g" / (GOLDEN + ".png"))
    assert run_cli("golden", "update", "m", "--goldens", "g", "--size", "8", "-j", "1", "--no-progress",
                   cwd=tmp_path).returncode == 0
    (tmp_path / "out" / "results.json").mkdir(parents=True)
    proc = run_cli("golden", "check", "m", "--goldens", "g", "-o", "out", "-j", "1", "--no-progress", "--no-flip",
                   cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 1
    assert proc.stderr.splitlines() == ["out/results.json:0: cannot write: Is a directory"], proc.stderr


def test_glslvalidate_replaces_a_symlink_at_its_stage_file(tmp_path):
    from mtlxgen.apps import glslvalidate
    from mtlxgen import pipeline
    if not glslvalidate.GLSLANG:
        pytest.skip("glslangValidator is not installed")
    shader = pipeline.generate(CHECKER)[0]
    os.symlink(victim(tmp_path / "victim.txt"), tmp_path / ("%s.glsl.frag" % shader.stem))
    assert glslvalidate.validate(shader, str(tmp_path)) == []
    assert unchanged(tmp_path / "victim.txt") and is_regular_file(tmp_path / ("%s.glsl.frag" % shader.stem))


# ---------------------------------------------------------------- an internal error in one batch document

def test_an_internal_error_in_one_batch_document_is_one_line_naming_it(tmp_path, monkeypatch, capsys):
    from mtlxgen import pipeline
    from mtlxgen.apps.cli import main
    folder = tmp_path / "docs"
    folder.mkdir()
    for name in ("a.mtlx", "b.mtlx"):
        shutil.copy(CHECKER, folder / name)
    shader = pipeline.Session.shader

    def broken(self, name):             # a bug of ours, met in one document only
        if self.path.endswith("a.mtlx"):
            raise ZeroDivisionError("boom\nand a second line")
        return shader(self, name)

    monkeypatch.setattr(pipeline.Session, "shader", broken)
    status = main(["batch", str(folder), "-o", str(tmp_path / "out"), "--size", "8", "-j", "1", "--no-progress"])
    err = capsys.readouterr().err.splitlines()
    assert status == 1
    assert err == ["%s:0: M_checker: internal error: ZeroDivisionError: boom and a second line (set MTLXGEN_DEBUG=1 "
                   "for details)" % (folder / "a.mtlx")], err
    assert os.listdir(tmp_path / "out") == ["b__M_checker.png"]           # the other document still drawn


# ---------------------------------------------------------------- view: no picture of nothing

def test_view_screenshot_of_a_document_that_draws_nothing_is_not_written(tmp_path):
    path = write_doc(tmp_path, '<nosuchnode name="n" type="color3" />\n'
                               '<output name="o" type="color3" nodename="n" />', name="broken.mtlx")
    proc = run_cli("view", path, "--headless-frames", "2", "--size", "8", "8", "--screenshot", "shot.png",
                   "--capture-window", "window.png", "--no-watch", "--no-panel", cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 1
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and re.match(r".*broken\.mtlx:3: unknown node category 'nosuchnode'", lines[0]), lines
    assert not [n for n in os.listdir(tmp_path) if n.startswith(("shot", "window"))]


def test_screenshot_key_in_the_window_says_why_nothing_is_written(tmp_path):
    import io
    from mtlxgen.apps.view import OffscreenWindow, Viewer, handle_key
    path = write_doc(tmp_path, '<nosuchnode name="n" type="color3" />\n'
                               '<output name="o" type="color3" nodename="n" />', name="broken.mtlx")
    window, log = OffscreenWindow((8, 8)), io.StringIO()
    v = Viewer(window.ctx, path, size=(8, 8), samples=1, frame_samples=1, output_dir=str(tmp_path / "shots"),
               watch=False, out=log)
    try:
        v.frame(window.screen)
        handle_key(v, "c")
    finally:
        v.close()
        window.close()
    lines = log.getvalue().splitlines()
    assert len(lines) == 2 and "unknown node category 'nosuchnode'" in lines[0], lines      # the problem, shown
    assert lines[1] == "%s:0: no screenshot: nothing is drawn (the document has problems)" % path
    assert not os.path.exists(tmp_path / "shots")


# ---------------------------------------------------------------- value="" of a struct type

def struct_doc(tmp_path, members, nodedef_value='', node_input=''):
    return write_doc(tmp_path, '\n'.join([
        '<typedef name="S">%s</typedef>' % members,                                           # line 3
        '<nodedef name="ND_ex" node="ex">',
        '  <input name="in" type="S"%s />' % nodedef_value,                                   # line 5
        '  <output name="out" type="float" />',
        '</nodedef>',
        '<implementation name="IM_ex" nodedef="ND_ex" sourcecode="{{in}}.a" />',
        '<ex name="m" type="float">%s</ex>' % node_input,                                     # line 9
        '<output name="o" type="float" nodename="m" />']), name="struct.mtlx")


ONE = '<member name="a" type="float" value="0.5" />'
TWO = ONE + '<member name="b" type="color3" value="0, 1, 0" />'
EMPTY_WARNING = "warning: input 'in' of type S: the value is empty: read as no value (its default)"


@pytest.mark.parametrize("members,initializer", [(ONE, "S(0.5)"), (TWO, "S(0.5, vec3(0.0, 1.0, 0.0))")],
                         ids=["one member", "two members"])
def test_empty_struct_default_of_a_nodedef_reads_as_no_value_with_a_warning(tmp_path, members, initializer):
    # MaterialX's generator reads on there (its uniform gets no value); one member was an internal error, two
    # a refusal ("struct S has 2 members, value '' has 1")
    proc = run_cli("generate", struct_doc(tmp_path, members, nodedef_value=' value=""'), "-o", "out", cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and re.match(r".*struct\.mtlx:5: " + re.escape(EMPTY_WARNING), lines[0]), lines
    assert "uniform S m_in = %s;" % initializer in (tmp_path / "out" / "o.frag").read_text()


@pytest.mark.parametrize("members", [ONE, TWO], ids=["one member", "two members"])
def test_empty_struct_value_on_a_node_is_refused_on_one_line(tmp_path, members):
    # MaterialX stops there ("Wrong number of initializers")
    path = struct_doc(tmp_path, members, node_input='<input name="in" type="S" value="" />')
    proc = run_cli("generate", path, "-o", "out", cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 1
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and re.match(r".*struct\.mtlx:9: input 'in' of type S: the value is empty, which "
                                        r"MaterialX cannot read for a struct", lines[0]), lines


def test_empty_member_default_reads_as_the_member_types_zero(tmp_path):
    path = struct_doc(tmp_path, '<member name="a" type="float" value="" /><member name="b" type="color3" />')
    proc = run_cli("generate", path, "-o", "out", cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and re.match(r".*struct\.mtlx:3: warning: member 'a' of struct 'S': the value is empty",
                                        lines[0]), lines
    assert "uniform S m_in = S(0.0, vec3(0.0, 0.0, 0.0));" in (tmp_path / "out" / "o.frag").read_text()


def test_an_empty_member_inside_a_struct_value_is_refused_on_one_line(tmp_path):
    proc = run_cli("generate", struct_doc(tmp_path, TWO, nodedef_value=' value="{0.5; }"'), "-o", "out",
                   cwd=tmp_path)
    no_crash(proc)
    assert proc.returncode == 1
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and re.match(r".*struct\.mtlx:5: input 'in' of type S: member 'b' of struct S is empty",
                                        lines[0]), lines


# ---------------------------------------------------------------- output folders that cannot take the files

def _read_only(folder):
    """Make `folder` refuse new files even to root (chmod does not stop root: the immutable flag does);
    returns how to undo it, or None where neither works here."""
    os.chmod(folder, 0o555)
    if not os.access(folder, os.W_OK):
        return lambda: os.chmod(folder, 0o755)
    if shutil.which("chattr") and subprocess.run(["chattr", "+i", str(folder)], capture_output=True).returncode == 0:
        return lambda: (subprocess.run(["chattr", "-i", str(folder)], capture_output=True), os.chmod(folder, 0o755))
    os.chmod(folder, 0o755)
    return None


@pytest.mark.parametrize("kind", ["a file", "a dangling link", "a read-only folder", "a folder at an output file"])
def test_generate_into_an_output_that_cannot_take_the_files_is_one_line(tmp_path, kind):
    out, undo, named = tmp_path / "out", None, "out"
    if kind == "a file":
        out.write_text("not a folder\n")
    elif kind == "a dangling link":
        os.symlink(str(tmp_path / "nowhere"), out)
    elif kind == "a read-only folder":
        out.mkdir()
        undo = _read_only(out)
        if undo is None:
            pytest.skip("no way to make a folder read-only for this user here")
    else:
        (out / "M_checker.frag").mkdir(parents=True)
        named = "out/M_checker.frag"
    try:
        proc = run_cli("generate", CHECKER, "-o", "out", cwd=tmp_path)
    finally:
        if undo is not None:
            undo()
    no_crash(proc)
    assert proc.returncode == 1
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and named in lines[0], lines
    if kind == "a folder at an output file":
        assert not [n for n in os.listdir(out) if n.startswith(".")]          # no temporary file left behind


def test_batch_never_writes_one_documents_image_over_anothers(tmp_path):
    """a/x.mtlx and b/x.mtlx make the same image name: the second is refused with one line naming both."""
    doc = ('<?xml version="1.0"?>\n<materialx version="1.39">\n  <constant name="c" type="color3">\n'
           '    <input name="value" type="color3" value="%s" />\n  </constant>\n'
           '  <output name="out" type="color3" nodename="c" />\n</materialx>\n')
    for sub, colour in (("a", "1, 0, 0"), ("b", "0, 0, 1")):
        (tmp_path / sub).mkdir()
        (tmp_path / sub / "x.mtlx").write_text(doc % colour)
    proc = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "batch", str(tmp_path / "a"),
                           str(tmp_path / "b"), "-o", str(tmp_path / "out"), "-j", "1", "--size", "8",
                           "--no-progress"], capture_output=True, text=True, timeout=240)
    assert proc.returncode == 1 and "Traceback" not in proc.stderr
    err = proc.stderr.splitlines()
    assert err == ["%s:1: image x__out.png is also drawn from %s; not written (rename one of the files)"
                   % (tmp_path / "b" / "x.mtlx", tmp_path / "a" / "x.mtlx")], err
    from mtlxgen.base.images import read_image
    centre = read_image(str(tmp_path / "out" / "x__out.png"))[4, 4]
    assert centre[0] > 0.5 and centre[2] < 0.1, centre          # a's red on the sphere, not b's blue
