"""mtlxgen report reads a results.json it did not write itself (a CI artefact, a folder from elsewhere): it is
read as a bounded regular file, checked against the schema golden check writes, and every text in it is
escaped; only PNG images inside the results folder are embedded. Anything else is one `results.json:...`
line and status 1, never a traceback or status 3, and no report is written."""
import base64
import copy
import json
import os
import re

import numpy as np
import pytest

from mtlxgen.apps import cli, report
from mtlxgen.base import images

HOSTILE = "<img src=x onerror=alert(1)></script><!--'\"&"


def result(name="doc__M", status="fail", files=None, **extra):
    r = {"name": name, "source": "examples/doc.mtlx", "element": "M", "status": status,
         "message": ["1 of 4 pixels (25.000%) over 2/255"],
         "metrics": {"mean": 0.5, "max": 9, "failing_pixels": 1, "fraction": 0.25, "pixels": 4, "threshold": 2,
                     "parity": "mean 0.5", "parity_passes": True, "flip": 0.01},
         "timings": {"render_s": 0.01}, "files": files if files is not None else {},
         "settings": {"size": 2, "environment": "builtin_sky", "samples": 4, "lights": []}}
    r.update(extra)
    return r


def write_png(path, value=128):
    images.write_image(str(path), np.full((2, 2, 4), value, np.uint8))
    return path


@pytest.fixture
def results_dir(tmp_path):
    """A results folder as golden check leaves it: one failure with its three images, one pass."""
    out = tmp_path / "results"
    out.mkdir()
    files = {"new": "doc__M.new.png", "golden": "doc__M.golden.png", "diff": "doc__M.diff.png"}
    for i, name in enumerate(files.values()):
        write_png(out / name, 40 * i)
    data = {"golden_dir": "/g", "tolerance": {"threshold": 2, "max_fraction": 0.0, "hdr_relative": 0.01, "flip": None},
            "notes": ["a note"], "results": [result(files=files), result("doc__P", "pass")]}
    write_results(out, data)
    return out, data


def write_results(out, data):
    (out / "results.json").write_text(json.dumps(data, indent=1))


def run_report(capsys, out, *extra):
    rc = cli.main(["report", str(out), *extra])
    captured = capsys.readouterr()
    return rc, captured.err.strip().splitlines(), captured.out


def assert_refused(capsys, out, *fragments):
    rc, err, _ = run_report(capsys, out)
    assert rc == 1 and len(err) == 1, (rc, err)
    assert err[0].startswith(str(out / "results.json") + ":"), err
    for f in fragments:
        assert f in err[0], err
    assert not (out / "report.html").exists()
    return err[0]


def test_a_valid_results_folder_is_reported_with_its_images(results_dir, capsys):
    out, data = results_dir
    rc, err, stdout = run_report(capsys, out)
    assert rc == 0 and err == [], err
    text = (out / "report.html").read_text(encoding="utf-8")
    assert len(re.findall(r'<img class="(?:golden|new|diff)"[^>]*src="data:image/png;base64,', text)) == 3
    embedded = re.findall(r'src="data:image/png;base64,([^"]+)"', text)
    assert base64.b64decode(embedded[0]).startswith(b"\x89PNG\r\n\x1a\n")


def test_every_text_is_escaped(results_dir, capsys):
    out, data = results_dir
    r = data["results"][0]
    for key in ("name", "source", "element"):
        r[key] = key + HOSTILE
    r["message"] = ["why" + HOSTILE, "</li></ul><script>alert(2)</script>"]
    r["settings"]["environment"] = "env" + HOSTILE
    r["metrics"]["parity"] = "parity" + HOSTILE
    r["timings"] = {"x" + HOSTILE + "_s": 0.5}
    data["notes"] = ["note" + HOSTILE]
    data["tolerance"]["threshold"] = 2
    write_results(out, data)
    rc, err, _ = run_report(capsys, out)
    assert rc == 0, err
    text = (out / "report.html").read_text(encoding="utf-8")
    assert "<img src=x" not in text and "<script>alert" not in text and "</script><!--" not in text
    assert "<!--" not in text and text.count("<script>") == 1          # the report's own
    for key in ("name", "source", "element", "why", "env", "parity", "note"):
        assert key + "&lt;img src=x onerror=alert(1)&gt;&lt;/script&gt;&lt;!--" in text, key


@pytest.mark.parametrize("status", ['fail"><script>alert(1)</script>', "FAIL", "", None, 3])
def test_status_outside_the_schema_is_refused(results_dir, capsys, status):
    out, data = results_dir
    data["results"][0]["status"] = status
    write_results(out, data)
    line = assert_refused(capsys, out, "results[0].status")
    assert "<script>" not in line or "'" in line       # the value is quoted as data in the problem line


@pytest.mark.parametrize("mutate, where", [
    (lambda d: d["results"][0].pop("status"), "results[0]: missing 'status'"),
    (lambda d: d["results"][1].pop("name"), "results[1]: missing 'name'"),
    (lambda d: d.pop("results"), "missing 'results'"),
    (lambda d: d["results"][0].update(message="one line"), "results[0].message"),
    (lambda d: d["results"][0].update(message=[1]), "results[0].message[0]"),
    (lambda d: d["results"][0]["metrics"].update(fraction="x"), "results[0].metrics.fraction"),
    (lambda d: d["results"][0]["metrics"].pop("pixels"), "results[0].metrics: missing 'pixels'"),
    (lambda d: d["results"][0]["metrics"].update(flip=[]), "results[0].metrics.flip"),
    (lambda d: d["results"][0]["timings"].update(render_s="fast"), "results[0].timings.render_s"),
    (lambda d: d["results"][0]["settings"].update(lights=5), "results[0].settings.lights"),
    (lambda d: d["results"][0].update(files=["a.png"]), "results[0].files"),
    (lambda d: d["tolerance"].update(max_fraction="all"), "tolerance.max_fraction"),
    (lambda d: d.update(notes="x"), "notes"),
    (lambda d: d.update(results={}), "results"),
])
def test_a_field_outside_the_schema_is_one_line(results_dir, capsys, mutate, where):
    out, data = results_dir
    data = copy.deepcopy(data)
    mutate(data)
    write_results(out, data)
    assert_refused(capsys, out, where)


@pytest.mark.parametrize("text, fragment", [
    ("[1, 2]", "not an object"),
    ('{"results": [}', "results.json:1: not JSON"),
    ('{\n"results": [\n  {"name": }]}', "results.json:3: not JSON"),
    ('{"results": [{"name": NaN}]}', "results[0]: missing 'source'"),
    (b"\xff\xfe{}", "not UTF-8"),
    ('{"results": [{"name": "a", "source": "s", "element": "e", "status": "pass", "message": [], "metrics": '
     '{"mean": Infinity}, "timings": {}, "files": {}, "settings": {}}]}', "results[0].metrics.mean"),
])
def test_malformed_results_json(tmp_path, capsys, text, fragment):
    out = tmp_path / "r"
    out.mkdir()
    if isinstance(text, bytes):
        (out / "results.json").write_bytes(text)
    else:
        (out / "results.json").write_text(text)
    assert_refused(capsys, out, fragment)


def test_results_json_that_is_a_device_fifo_or_huge(tmp_path, capsys):
    out = tmp_path / "dev"
    out.mkdir()
    os.symlink("/dev/zero", out / "results.json")
    assert "system file" in assert_refused(capsys, out)
    out = tmp_path / "fifo"
    out.mkdir()
    os.mkfifo(out / "results.json")
    assert "FIFO" in assert_refused(capsys, out)       # refused before opening: does not block
    out = tmp_path / "huge"
    out.mkdir()
    with open(out / "results.json", "wb") as f:
        f.truncate(65 * 2 ** 20)                       # sparse: no disk used
    assert "larger than 64 MB" in assert_refused(capsys, out)


def test_files_outside_the_results_folder_are_refused(results_dir, tmp_path, capsys):
    out, data = results_dir
    outside = write_png(tmp_path / "outside.png", 7)
    secret = base64.b64encode(outside.read_bytes()).decode()
    cases = [("/etc/passwd", "outside the results folder"), (str(outside), "outside the results folder"),
             ("../outside.png", "outside the results folder")]
    os.symlink(str(outside), out / "link.png")
    cases.append(("link.png", "outside the results folder"))
    for name, fragment in cases:
        d = copy.deepcopy(data)
        d["results"][0]["files"]["new"] = name
        write_results(out, d)
        line = assert_refused(capsys, out, "results[0].files.new", fragment)
        assert name in line or repr(name) in line
    assert not (out / "report.html").exists() or secret not in (out / "report.html").read_text()


def test_image_files_must_be_png_images(results_dir, capsys):
    out, data = results_dir
    (out / "fake.png").write_text("root:x:0:0:secret\n")
    (out / "sig.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"secret, not a PNG")
    os.mkfifo(out / "fifo.png")
    for name, fragment in (("fake.png", "not a PNG image"), ("sig.png", "not a PNG image"),
                           ("fifo.png", "a FIFO")):
        d = copy.deepcopy(data)
        d["results"][0]["files"]["diff"] = name
        write_results(out, d)
        assert_refused(capsys, out, "results[0].files.diff", fragment)


def test_image_named_but_gone_is_not_embedded(results_dir, capsys):
    """An image deleted since the check is not an error: the report shows what remains."""
    out, data = results_dir
    os.remove(out / "doc__M.diff.png")
    rc, err, _ = run_report(capsys, out)
    assert rc == 0, err
    text = (out / "report.html").read_text(encoding="utf-8")
    assert len(re.findall(r'<img class="(?:golden|new|diff)"', text)) == 2


def test_report_replaces_a_symlink_at_its_output(results_dir, tmp_path, capsys):
    out, data = results_dir
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    os.symlink(str(victim), out / "report.html")
    rc, err, _ = run_report(capsys, out)
    assert rc == 0, err
    assert victim.read_text() == "keep me"
    assert not os.path.islink(out / "report.html") and "<!DOCTYPE html>" in (out / "report.html").read_text()
    other = tmp_path / "other.html"
    os.symlink(str(victim), other)
    rc, err, _ = run_report(capsys, out, "-o", str(other))
    assert rc == 0, err
    assert victim.read_text() == "keep me" and not os.path.islink(other)


def test_load_results_returns_what_golden_check_writes(results_dir):
    out, data = results_dir
    assert report.load_results(str(out)) == data
