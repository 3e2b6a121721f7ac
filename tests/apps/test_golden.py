"""Golden-image regression: goldens of the bundled examples (and of everything in golden_images/),
proof that the check can fail, determinism, reference parity, and the HTML report in a browser.

`pytest --update-goldens` rewrites the goldens from the current renders instead of checking them.
"""
import hashlib
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import DATA_TESTSUITE, ROOT
from util import FAILURES, assert_parity_with_materialx

from mtlxgen.apps import batch, golden, report
from mtlxgen.base import images
from mtlxgen.apps.batch import RenderSettings
from mtlxgen.base.diagnostics import MtlxError

GOLDEN_DIR = os.path.join(ROOT, "golden_images")
EXAMPLES = os.path.join(ROOT, "examples")
CHECKER = "unlit_checker.mtlx"


def _golden_params():
    """Every golden in the index plus every renderable element of examples/ (a new example without a
    golden fails until `mtlxgen golden update` or `pytest --update-goldens` creates it)."""
    found = {}
    try:
        index = golden.Index(GOLDEN_DIR)
        for t in golden.targets(index, None):
            found[t.name] = (t.path, t.element)
        for t in golden.targets(index, [EXAMPLES]):
            found.setdefault(t.name, (t.path, t.element))
    except Exception as e:  # reported by the test itself, not as a collection error
        found["<index or examples unreadable>"] = ("", str(e))
    return [pytest.param(path, element, id=name) for name, (path, element) in sorted(found.items())]


def _keep_failure(run):
    """Copy a failing check's new/golden/diff images to tests/_failures/golden; message naming them."""
    dest = os.path.join(FAILURES, "golden")
    os.makedirs(dest, exist_ok=True)
    lines = []
    for r in run.results:
        if r["status"] == "pass":
            continue
        lines.append("%s %s (%s:%s): %s" % (r["status"].upper(), r["name"], r["source"], r["element"],
                                            "; ".join(r["message"])))
        kept = []
        for key in ("new", "golden", "diff", "flip"):
            if key in r["files"]:
                shutil.copyfile(os.path.join(run.out_dir, r["files"][key]), os.path.join(dest, r["files"][key]))
                kept.append(os.path.join(dest, r["files"][key]))
        if kept:
            lines.append("  images side by side: " + "  ".join(kept))
    return "\n".join(lines + ["(if the change is intended: pytest --update-goldens, or mtlxgen golden update)"])


# ---------------------------------------------------------------- the goldens themselves

@pytest.mark.parametrize("path,element", _golden_params())
def test_golden(path, element, update_goldens, tmp_path):
    assert path, "cannot list goldens: %s" % element
    spec = "%s:%s" % (path, element) if element else path
    if update_goldens:
        done = golden.update([spec], GOLDEN_DIR, workers=1, progress=False)
        errors = [line for _, status, lines in done if status == "error" for line in lines]
        assert not errors, "\n".join(errors)
        return
    run = golden.check([spec], GOLDEN_DIR, str(tmp_path), workers=1, progress=False)
    assert run.results, "nothing checked for %s" % spec
    assert run.ok, _keep_failure(run)


def test_index_records_render_settings():
    index = golden.Index(GOLDEN_DIR)
    assert index.goldens, "golden_images/index.json is empty: run mtlxgen golden update examples"
    for name, entry in index.goldens.items():
        assert os.path.exists(index.file(entry["png"])), name
        s = entry["settings"]
        assert {"size", "environment", "samples", "lights", "geometry", "camera"} <= set(s), name
        assert os.path.exists(index.source(entry)), "%s: source %s is gone" % (name, entry["source"])
    # at least one bundled example keeps a linear EXR because its render leaves [0, 1]
    assert any(e.get("exr") for e in index.goldens.values())


# ---------------------------------------------------------------- the check can fail

@pytest.fixture(scope="module")
def project(tmp_path_factory):
    """A scratch project: a copy of examples/ with fresh goldens for the checker and the HDR rim."""
    root = tmp_path_factory.mktemp("golden_project")
    shutil.copytree(EXAMPLES, root / "examples")
    gdir = str(root / "golden_images")
    done = golden.update([str(root / "examples" / CHECKER), str(root / "examples" / "unlit_hdr_rim.mtlx")],
                         gdir, workers=1, progress=False)
    assert [s for _, s, _ in done] == ["created", "created"], done
    return root


def _one_pixel_changed(project, name="unlit_checker__M_checker"):
    """Copy the project's goldens with one visible pixel of one golden recoloured; returns (dir, (y, x))."""
    gdir = str(project / ("golden_images_%s" % name))
    if os.path.exists(gdir):
        shutil.rmtree(gdir)
    shutil.copytree(str(project / "golden_images"), gdir)
    png = os.path.join(gdir, name + ".png")
    img = golden.read_png8(png)
    y, x = img.shape[0] // 2 + 5, img.shape[1] // 2 + 7
    assert img[y, x, 3] == 255, "expected the sphere at the chosen pixel"
    img[y, x, :3] = 255 - img[y, x, :3]
    images.write_image(png, img)
    return gdir, (y, x)


def test_unchanged_goldens_pass(project, tmp_path):
    run = golden.check(None, str(project / "golden_images"), str(tmp_path), workers=1, progress=False)
    assert [r["status"] for r in run.results] == ["pass", "pass"], _keep_failure(run)
    assert all(r["metrics"]["max"] == 0 and r["metrics"]["flip"] == 0.0 for r in run.results)


def test_passing_materials_leave_no_images(project, tmp_path):
    out = tmp_path / "out"
    run = golden.check(None, str(project / "golden_images"), str(out), workers=1, progress=False)
    assert run.ok and len(run.results) == 2, _keep_failure(run)
    assert os.listdir(out) == ["results.json"]
    assert all(r["files"] == {} for r in run.results)


def test_images_of_an_earlier_failure_are_removed_when_it_passes(project, tmp_path):
    gdir, _ = _one_pixel_changed(project)
    out = str(tmp_path / "out")
    failed = golden.check(None, gdir, out, workers=1, progress=False)
    bad = [r for r in failed.results if r["status"] == "fail"]
    assert len(bad) == 1 and all(os.path.exists(os.path.join(out, f)) for f in bad[0]["files"].values())
    passed = golden.check(None, str(project / "golden_images"), out, workers=1, progress=False)
    assert passed.ok, _keep_failure(passed)
    assert os.listdir(out) == ["results.json"]


def test_check_outside_the_project_is_an_error_saying_where_it_looked(tmp_path, monkeypatch, capsys):
    from mtlxgen.apps.cli import main
    monkeypatch.chdir(tmp_path)
    assert main(["golden", "check", "--no-progress"]) == 1
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(str(tmp_path / "golden_images" / "index.json") + ":0: nothing to check"), lines[0]
    assert "0 passed" not in captured.out
    assert not (tmp_path / "out").exists(), "checking nothing must write nothing"


def test_check_of_an_empty_index_or_a_folder_without_materials_is_an_error(project, tmp_path):
    empty = tmp_path / "goldens"
    empty.mkdir()
    (empty / "index.json").write_text('{"version": 1, "goldens": {}}\n')
    with pytest.raises(MtlxError, match=r"index\.json:0: nothing to check: the index lists no goldens"):
        golden.check(None, str(empty), str(tmp_path / "out"), workers=1, progress=False)
    folder = tmp_path / "no_materials"
    folder.mkdir()
    with pytest.raises(MtlxError, match=r"no_materials:0: nothing to check: no \.mtlx file"):
        golden.check([str(folder)], str(project / "golden_images"), str(tmp_path / "out"), workers=1, progress=False)
    with pytest.raises(MtlxError, match=r"nothing to update"):
        golden.update(None, str(empty), workers=1, progress=False)


def test_one_pixel_colour_change_is_caught(project, tmp_path):
    gdir, (y, x) = _one_pixel_changed(project)
    run = golden.check(None, gdir, str(tmp_path), workers=1, progress=False)
    by_name = {r["name"]: r for r in run.results}
    bad = by_name["unlit_checker__M_checker"]
    assert not run.ok and bad["status"] == "fail"
    assert by_name["unlit_hdr_rim__M_hdr_rim"]["status"] == "pass"
    assert bad["metrics"]["failing_pixels"] == 1 and bad["metrics"]["max"] > 100
    assert "1 pixel differs" in bad["message"][0]
    # new image, golden and diff are written next to each other
    for key in ("new", "golden", "diff"):
        assert os.path.exists(os.path.join(run.out_dir, bad["files"][key])), key
    diff = golden.read_png8(os.path.join(run.out_dir, bad["files"]["diff"]))
    assert tuple(diff[y, x, :3]) != (0, 0, 0) and diff[y, x, 0] == 255
    mod, _ = golden.flip_module()
    if mod is not None:
        assert bad["metrics"]["flip"] > 0.0 and "flip" in bad["files"]


def test_metric_threshold_and_fraction():
    new = np.zeros((16, 16, 4), np.float32)
    new[..., 3] = 1.0
    new[..., :3] = 0.5
    golden8 = images.to_srgb8(new)
    tol = golden.Tolerance()
    shifted = golden8.copy()
    shifted[3, 4, 1] += tol.threshold                       # at the threshold: passes
    m, _, _ = golden.measure(new, shifted, tolerance=tol, flip=False)
    assert golden.verdict(m, tol)[0] and m["max"] == tol.threshold
    shifted[3, 4, 1] += 1                                   # one step over, one pixel: fails
    m, _, _ = golden.measure(new, shifted, tolerance=tol, flip=False)
    assert not golden.verdict(m, tol)[0] and m["failing_pixels"] == 1
    loose = golden.Tolerance(max_fraction=0.01)             # 1 of 256 pixels is 0.4%: allowed
    assert golden.verdict(m, loose)[0]
    alpha = golden8.copy()
    alpha[0, 0, 3] = 0                                      # alpha counts too
    m, _, _ = golden.measure(new, alpha, tolerance=tol, flip=False)
    assert m["failing_pixels"] == 1


def test_hdr_golden_catches_change_the_png_clips(project, tmp_path):
    index = golden.Index(str(project / "golden_images"))
    entry = index.goldens["unlit_hdr_rim__M_hdr_rim"]
    assert entry["exr"], "the HDR example should keep a linear EXR"
    exr = images.read_image(index.file(entry["exr"]))
    assert exr[..., :3].max() > 2.0
    brighter = exr.copy()
    brighter[..., :3] = np.where(exr[..., :3] > 1.5, exr[..., :3] * 1.5, exr[..., :3])   # clipped in the PNG
    golden8 = golden.read_png8(index.file(entry["png"]))
    m, _, _ = golden.measure(brighter, golden8, exr, flip=False)
    assert m["failing_pixels"] == 0 and m["hdr_fraction"] > 0
    assert not golden.verdict(m, golden.Tolerance())[0]


def test_flip_missing_degrades_with_a_message(monkeypatch):
    monkeypatch.setitem(sys.modules, "flip_evaluator", None)     # import flip_evaluator -> ImportError
    mod, why = golden.flip_module()
    assert mod is None and "pip install flip-evaluator" in why
    img = np.full((8, 8, 4), 0.5, np.float32)
    g8 = images.to_srgb8(img)
    g8[2, 2, 0] = 0
    m, _, heat = golden.measure(img, g8)
    assert m["flip"] is None and heat is None and m["failing_pixels"] == 1


def test_missing_golden_is_a_failure(project, tmp_path):
    run = golden.check([str(project / "examples" / "unlit_normal_bands.mtlx")], str(project / "golden_images"),
                       str(tmp_path), workers=1, progress=False)
    assert [r["status"] for r in run.results] == ["missing"]
    assert "golden update" in run.results[0]["message"][0]


def test_update_is_idempotent(project):
    done = golden.update(None, str(project / "golden_images"), workers=1, progress=False)
    assert [s for _, s, _ in done] == ["unchanged", "unchanged"]


def test_cli_check_prints_where_the_images_are(project, tmp_path, capsys):
    from mtlxgen.apps.cli import main
    gdir, _ = _one_pixel_changed(project)
    out = str(tmp_path / "out")
    rc = main(["golden", "check", "--goldens", gdir, "-o", out, "-j", "1", "--no-progress"])
    text = capsys.readouterr().out
    assert rc == 1
    assert "FAIL    unlit_checker__M_checker" in text and "1 passed, 1 failed" in text
    for key in ("new", "golden", "diff"):
        m = re.search(r"%s: (\S+)" % key, text)
        assert m and os.path.exists(m.group(1)), (key, text)
    assert os.path.exists(os.path.join(out, "report.html"))
    assert main(["golden", "check", "--goldens", str(project / "golden_images"), "-o", out, "-j", "1",
                 "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "2 passed, 0 failed" in text and "images of failures" not in text      # none were written
    assert sorted(os.listdir(out)) == ["report.html", "results.json"]


# ---------------------------------------------------------------- determinism

DETERMINISM_SCRIPT = r"""
import hashlib, sys
sys.path.insert(0, sys.argv[1])
from mtlxgen.apps import batch
items = batch.render_jobs([batch.Job(p) for p in sys.argv[2:]], workers=1, progress=False)
print(hashlib.sha256(b"".join(it.image.tobytes() for it in items)).hexdigest())
"""


def _examples(*names):
    return [os.path.join(EXAMPLES, n) for n in names]


def test_same_material_twice_gives_identical_bytes(renderer):
    from mtlxgen import pipeline
    for path in _examples(CHECKER, "unlit_hdr_rim.mtlx"):
        shader = pipeline.generate(path)[0]
        a, b = renderer.render(shader), renderer.render(shader)
        c = batch.run_job(batch.Job(path, (shader.element,), RenderSettings(size=renderer.size)))[0].image
        assert a.tobytes() == b.tobytes() == c.tobytes(), path


def test_two_processes_give_identical_bytes():
    paths = _examples(CHECKER, "unlit_hdr_rim.mtlx", "math_outputs.mtlx")
    here = batch.render_jobs([batch.Job(p) for p in paths], workers=1, progress=False)
    expect = hashlib.sha256(b"".join(it.image.tobytes() for it in here)).hexdigest()
    procs = [subprocess.Popen([sys.executable, "-c", DETERMINISM_SCRIPT, ROOT] + paths, stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True) for _ in range(2)]
    outs = [p.communicate(timeout=120) for p in procs]
    for p, (out, err) in zip(procs, outs):
        assert p.returncode == 0, err
    assert [o.strip() for o, _ in outs] == [expect, expect]


def test_process_pool_matches_in_process():
    jobs = [batch.Job(p) for p in _examples(CHECKER, "unlit_normal_bands.mtlx", "math_outputs.mtlx")]
    pooled = batch.render_jobs(jobs, workers=2, progress=False)
    local = batch.render_jobs(jobs, workers=1, progress=False)
    assert [(it.path, it.element) for it in pooled] == [(it.path, it.element) for it in local]
    for a, b in zip(pooled, local):
        assert a.ok and a.image.tobytes() == b.image.tobytes(), a.element
        assert {"generate_s", "link_s", "draw_s", "total_s"} <= set(a.timings)
    assert any(it.pid != os.getpid() for it in pooled)


# ---------------------------------------------------------------- reference parity

PARITY_FILES = [os.path.join(DATA_TESTSUITE, "stdlib", "math", "transform.mtlx")] + \
    _examples(CHECKER, "unlit_normal_bands.mtlx", "unlit_hdr_rim.mtlx", "math_outputs.mtlx")


@pytest.mark.parametrize("path", PARITY_FILES, ids=os.path.basename)
def test_reference_parity(path, renderer, reference):
    """MaterialX's GLSL and ours, both drawn by our harness, within the scoreboard's thresholds.
    (math, trig, vector_math and math_operators are covered by test_parity_stdlib_math.py.)"""
    assert os.path.exists(path), "corpus missing: %s" % path
    elements = reference.elements(path)
    assert elements, "MaterialX finds nothing renderable in %s" % path
    failures = []
    for element in elements:
        try:
            assert_parity_with_materialx(renderer, reference, path, element)
        except Exception as e:
            failures.append("%s: %s" % (element, str(e).splitlines()[0] if str(e) else type(e).__name__))
    assert not failures, "\n".join(failures)


# ---------------------------------------------------------------- the HTML report

def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


@pytest.fixture(scope="module")
def report_run(project, tmp_path_factory):
    gdir, _ = _one_pixel_changed(project)
    out = str(tmp_path_factory.mktemp("report_out"))
    run = golden.check(None, gdir, out, workers=1, progress=False)
    return run, report.write_report(out)


def test_report_is_self_contained_and_sorted(report_run):
    run, html_path = report_run
    with open(html_path, encoding="utf-8") as f:
        text = f.read()
    sections = re.findall(r'<section class="material (\w+)" id="([^"]+)"', text)
    assert [name for _, name in sections] == ["unlit_checker__M_checker", "unlit_hdr_rim__M_hdr_rim"]
    assert sections[0][0] == "fail"
    assert not re.search(r'(src|href)="(?!data:)', text), "the report must not reference external files"
    for status, body in zip([s for s, _ in sections], text.split('<section class="material')[1:]):
        shown = len(re.findall(r'<img class="(?:golden|new|diff)"[^>]*src="data:image/png;base64,', body))
        assert shown == (0 if status == "pass" else 3), (status, shown)      # passes keep no images


def test_report_when_everything_passed_lists_them_without_images(project, tmp_path):
    out = str(tmp_path / "out")
    run = golden.check(None, str(project / "golden_images"), out, workers=1, progress=False)
    assert run.ok, _keep_failure(run)
    with open(report.write_report(out), encoding="utf-8") as f:
        text = f.read()
    assert '<span class="count-pass">2 pass</span>' in text and '<span class="count-fail">0 fail</span>' in text
    assert re.findall(r'<section class="material (\w+)"', text) == ["pass", "pass"]
    assert "<img" not in text and "not rendered" not in text
    assert "FLIP (mean)" in text and "failing pixels" in text                # the metrics are still there


def test_report_opens_in_headless_chromium(report_run, tmp_path):
    exe = _chromium()
    if exe is None:
        pytest.skip("no chromium binary on PATH (Debian: apt-get install -y chromium); "
                    "the report is not opened in a browser")
    run, html_path = report_run
    args = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
            "--disable-component-update", "--disable-sync", "--no-first-run", "--hide-scrollbars",
            "--user-data-dir=%s" % (tmp_path / "profile"), "--window-size=1280,1600"]
    url = "file://" + os.path.abspath(html_path)
    dom = subprocess.run(args + ["--dump-dom", url], capture_output=True, text=True, timeout=120)
    assert dom.returncode == 0, dom.stderr[-2000:]
    body = re.search(r"<body([^>]*)>", dom.stdout)
    assert body, dom.stdout[:500]
    n = len(run.results)
    failing = sum(r["status"] != "pass" for r in run.results)
    assert n == 2 and failing == 1
    assert 'data-materials="%d"' % n in body.group(1), body.group(1)
    assert 'data-not-passing="%d"' % failing in body.group(1), body.group(1)
    assert 'data-materials-with-image="%d"' % failing in body.group(1), body.group(1)   # every failure's images load
    assert dom.stdout.count('data-image-shown="yes"') == failing
    shot = tmp_path / "report.png"
    subprocess.run(args + ["--screenshot=%s" % shot, url], capture_output=True, timeout=120)
    assert shot.exists() and shot.stat().st_size > 10000
    keep = os.path.join(FAILURES, "golden_report_screenshot.png")
    os.makedirs(FAILURES, exist_ok=True)
    shutil.copyfile(str(shot), keep)                  # for a human to look at (tests/_failures is ignored)


def test_progress_bar_on_terminal_and_in_logs():
    import io

    class Tty(io.StringIO):
        def isatty(self):
            return True

    tty, log = Tty(), io.StringIO()
    for stream in (tty, log):
        bar = batch.Progress(40, "render", stream=stream)
        for _ in range(40):
            bar.advance(1, "x.mtlx")
        bar.close()
    assert "\r" in tty.getvalue() and "40/40" in tty.getvalue() and tty.getvalue().endswith("\n")
    assert "\r" not in log.getvalue() and len(log.getvalue().splitlines()) <= 11
    quiet = io.StringIO()
    bar = batch.Progress(3, "render", stream=quiet)          # short runs stay quiet
    bar.advance(3)
    assert quiet.getvalue() == ""


def test_environment_files_are_recorded_relative_to_the_project():
    import os
    from mtlxgen.apps import golden
    index = golden.Index()
    env = os.path.join(index.root, "examples", "enterprise", "white_furnace.hdr")
    recorded = index.portable_settings({"size": 64, "environment": env})
    assert recorded["environment"] == "examples/enterprise/white_furnace.hdr"
    assert index.settings({"settings": recorded}).environment == os.path.normpath(env)
    for entry in index.goldens.values():       # the committed index holds in any checkout
        assert not os.path.isabs(entry.get("settings", {}).get("environment") or "")
