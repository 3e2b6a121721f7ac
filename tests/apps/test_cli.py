"""The command-line contract: files written per element, and one FILE:LINE line per problem on bad input."""
import json
import os
import re
import subprocess
import sys

import pytest

from util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run_cli(*args):
    return subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), *args], capture_output=True, text=True,
                          cwd=ROOT, timeout=120)


def assert_one_line_error(proc, pattern):
    assert proc.returncode != 0
    assert "Traceback" not in proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    assert re.search(pattern, lines[0]), lines[0]


def test_generate_writes_vert_frag_json_per_renderable_element(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="NG_a">
    <sin name="s" type="float" />
    <output name="out" type="float" nodename="s" />
  </nodegraph>
  <cos name="c" type="float" />
  <output name="top" type="float" nodename="c" />""")
    out = tmp_path / "out"
    proc = run_cli("generate", path, "-o", str(out))
    assert proc.returncode == 0, proc.stderr
    assert sorted(os.listdir(out)) == ["NG_a_out.frag", "NG_a_out.json", "NG_a_out.vert",
                                       "top.frag", "top.json", "top.vert"]
    manifest = json.loads((out / "NG_a_out.json").read_text())
    assert manifest["element"] == "NG_a/out"
    assert manifest["vertex"] == "NG_a_out.vert" and manifest["fragment"] == "NG_a_out.frag"
    assert manifest["glsl_version"] == "400"
    assert {"name": "s_in", "type": "float", "mtlx_type": "float", "value": 0.0} in manifest["uniforms"]


def test_element_option_selects_one(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="A"><sin name="s" type="float" /><output name="out" type="float" nodename="s" /></nodegraph>
  <nodegraph name="B"><cos name="c" type="float" /><output name="out" type="float" nodename="c" /></nodegraph>""")
    proc = run_cli("generate", path, "-o", str(tmp_path / "o"), "--element", "B/out")
    assert proc.returncode == 0, proc.stderr
    assert sorted(os.listdir(tmp_path / "o")) == ["B_out.frag", "B_out.json", "B_out.vert"]


def test_malformed_xml(tmp_path):
    path = tmp_path / "bad.mtlx"
    path.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n  <constant name="c" type="float">\n</materialx>\n')
    assert_one_line_error(run_cli("generate", str(path), "-o", str(tmp_path / "o")),
                          r"bad\.mtlx:4: malformed XML: mismatched tag")


def test_unknown_node_category(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="g">
    <wobble name="w" type="float" />
    <output name="out" type="float" nodename="w" />
  </nodegraph>""")
    assert_one_line_error(run_cli("generate", path, "-o", str(tmp_path / "o")),
                          r"doc\.mtlx:5: unknown node category 'wobble' \(node 'w'\)")


def test_connection_of_the_wrong_type(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="g">
    <constant name="c" type="float" />
    <sin name="s" type="vector3">
      <input name="in" type="vector3" nodename="c" />
    </sin>
    <output name="out" type="vector3" nodename="s" />
  </nodegraph>""")
    assert_one_line_error(run_cli("generate", path, "-o", str(tmp_path / "o")),
                          r"doc\.mtlx:7: input 'in' of node 's' has type vector3 but is connected to a value of type float")


def test_cycle(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="g">
    <add name="a" type="float"><input name="in1" type="float" nodename="b" /></add>
    <add name="b" type="float"><input name="in1" type="float" nodename="a" /></add>
    <output name="out" type="float" nodename="a" />
  </nodegraph>""")
    assert_one_line_error(run_cli("generate", path, "-o", str(tmp_path / "o")),
                          r"doc\.mtlx:[56]: cycle: '[ab]' -> '[ab]' -> '[ab]'")


def test_missing_input_file(tmp_path):
    missing = str(tmp_path / "nowhere.mtlx")
    assert_one_line_error(run_cli("generate", missing, "-o", str(tmp_path / "o")), r"nowhere\.mtlx:0: no such file")


def test_value_that_does_not_parse(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="g">
    <sin name="s" type="float"><input name="in" type="float" value="one" /></sin>
    <output name="out" type="float" nodename="s" />
  </nodegraph>""")
    assert_one_line_error(run_cli("generate", path, "-o", str(tmp_path / "o")),
                          r"doc\.mtlx:5: input 'in' of type float: not a number: 'one'")


def test_good_elements_are_written_when_another_fails(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="good"><sin name="s" type="float" /><output name="out" type="float" nodename="s" /></nodegraph>
  <nodegraph name="bad"><wobble name="w" type="float" /><output name="out" type="float" nodename="w" /></nodegraph>""")
    proc = run_cli("generate", path, "-o", str(tmp_path / "o"))
    assert proc.returncode == 1
    assert sorted(os.listdir(tmp_path / "o")) == ["good_out.frag", "good_out.json", "good_out.vert"]


def test_info_lists_elements_and_nodes(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="g"><sin name="s" type="float" /><output name="out" type="float" nodename="s" /></nodegraph>""")
    proc = run_cli("info", path)
    assert proc.returncode == 0, proc.stderr
    assert "g/out [output] 1 nodes" in proc.stdout and "ND_sin_float" in proc.stdout


def test_render_writes_png_and_exr(tmp_path):
    path = write_doc(tmp_path, """
  <surface_unlit name="sh" type="surfaceshader">
    <input name="emission_color" type="color3" value="0.2, 0.4, 0.8" />
  </surface_unlit>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="sh" /></surfacematerial>""")
    proc = run_cli("render", path, "-o", str(tmp_path / "r"), "--size", "32")
    assert proc.returncode == 0, proc.stderr
    from mtlxgen.base.images import read_image
    png = read_image(str(tmp_path / "r" / "m.png"))
    exr = read_image(str(tmp_path / "r" / "m.exr"))
    assert png.shape == (32, 32, 4) and exr.shape == (32, 32, 4)
    assert exr[16, 16, :3] == pytest.approx([0.2, 0.4, 0.8], abs=1e-3)


def test_output_piped_into_a_reader_that_stops_early_is_not_an_error():
    path = os.path.join(ROOT, "examples", "pbs", "pbs_nodes.mtlx")
    proc = subprocess.run("%s %s info %s | head -n 1" % (sys.executable, os.path.join(ROOT, "cli.py"), path),
                          shell=True, capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert proc.stdout.startswith(path) or "pbs_nodes.mtlx" in proc.stdout
    assert "internal error" not in proc.stderr and "Traceback" not in proc.stderr


# ---------------------------------------------------------------- bad option values: one line, status 1

@pytest.fixture
def places(tmp_path):
    """A valid document, a regular non-document file, a directory, a FIFO and a path that does not exist."""
    doc = write_doc(tmp_path, """
  <nodegraph name="g"><sin name="s" type="float" /><output name="out" type="float" nodename="s" /></nodegraph>""")
    plain = tmp_path / "plain.txt"
    plain.write_text("not a document\n")
    folder = tmp_path / "folder"
    folder.mkdir()
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    return {"doc": doc, "file": str(plain), "dir": str(folder), "fifo": str(fifo),
            "missing": str(tmp_path / "missing"), "out": str(tmp_path / "new_out")}


def run_main(capsys, argv):
    from mtlxgen.apps.cli import main
    rc = main(argv)
    out, err = capsys.readouterr()
    return rc, out, err


def assert_usage_error(rc, err, *named):
    """Status 1, exactly one line on stderr, naming each of `named`; no traceback, no internal error."""
    assert rc == 1, (rc, err)
    assert "Traceback" not in err and "internal error" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    for text in named:
        assert text in lines[0], (text, lines[0])


# (case id, argv with {doc} {file} {dir} {fifo} {missing} {out} filled in, texts the error line must name)
BAD_OPTIONS = [
    ("no-command", [], ["mtlxgen: error", "required"]),
    ("unknown-command", ["frobnicate"], ["invalid choice", "frobnicate"]),
    ("unknown-option", ["info", "{doc}", "--bogus"], ["unrecognized arguments", "--bogus"]),
    ("generate-output-missing", ["generate", "{doc}"], ["mtlxgen generate: error", "-o/--output"]),
    ("generate-output-existing-file", ["generate", "{doc}", "-o", "{file}"], ["-o/--output", "{file}",
                                                                            "not a directory"]),
    ("generate-output-below-a-file", ["generate", "{doc}", "-o", "{file}/sub"], ["-o/--output", "{file}/sub",
                                                                               "not a directory"]),
    ("generate-output-empty", ["generate", "{doc}", "-o", ""], ["-o/--output", "empty path"]),
    ("generate-library-missing", ["generate", "{doc}", "-o", "{out}", "--library", "{missing}"],
     ["--library", "{missing}", "no such directory"]),
    ("generate-library-file", ["generate", "{doc}", "-o", "{out}", "--library", "{file}"],
     ["--library", "{file}", "not a directory"]),
    ("generate-element-empty", ["generate", "{doc}", "-o", "{out}", "--element", ""], ["--element", "empty"]),
    ("generate-environment-unknown", ["generate", "{doc}", "-o", "{out}", "--environment", "bogus"],
     ["--environment", "bogus", "fis"]),
    ("render-size-zero", ["render", "{doc}", "-o", "{out}", "--size", "0"], ["--size", "0", "1 to 8192"]),
    ("render-size-negative", ["render", "{doc}", "-o", "{out}", "--size", "-5"], ["--size", "-5", "1 to 8192"]),
    ("render-size-huge", ["render", "{doc}", "-o", "{out}", "--size", "8193"], ["--size", "8193", "1 to 8192"]),
    ("render-size-not-a-number", ["render", "{doc}", "-o", "{out}", "--size", "big"], ["--size", "big"]),
    ("render-output-existing-file", ["render", "{doc}", "-o", "{file}"], ["-o/--output", "{file}"]),
    ("render-element-empty", ["render", "{doc}", "-o", "{out}", "--element", " "], ["--element", "empty"]),
    ("render-env-missing", ["render", "{doc}", "-o", "{out}", "--env", "{missing}"],
     ["--env", "{missing}", "no such file"]),
    ("render-env-directory", ["render", "{doc}", "-o", "{out}", "--env", "{dir}"], ["--env", "{dir}", "directory"]),
    ("render-env-fifo", ["render", "{doc}", "-o", "{out}", "--env", "{fifo}"],
     ["--env", "{fifo}", "not a regular file"]),
    ("render-env-device", ["render", "{doc}", "-o", "{out}", "--env", "/dev/zero"],
     ["--env", "/dev/zero", "not a regular file"]),
    ("render-lights-missing", ["render", "{doc}", "-o", "{out}", "--lights", "{missing}"],
     ["--lights", "{missing}", "no such file"]),
    ("render-lights-directory", ["render", "{doc}", "-o", "{out}", "--lights", "{dir}"], ["--lights", "{dir}"]),
    ("render-library-missing", ["render", "{doc}", "-o", "{out}", "--library", "{missing}"],
     ["--library", "{missing}"]),
    ("info-library-missing", ["info", "{doc}", "--library", "{missing}"], ["--library", "{missing}"]),
    ("info-usd-rules-with-value", ["info", "{doc}", "--usd-seed-rules=yes"], ["--usd-seed-rules"]),
    ("golden-no-subcommand", ["golden"], ["mtlxgen golden: error", "check,update"]),
    ("golden-check-workers-zero", ["golden", "check", "-j", "0"], ["-j/--workers", "0", "1 to 256"]),
    ("golden-check-workers-huge", ["golden", "check", "-j", "100000"], ["-j/--workers", "100000"]),
    ("golden-check-workers-not-a-number", ["golden", "check", "-j", "all"], ["-j/--workers", "all"]),
    ("golden-check-threshold-negative", ["golden", "check", "--threshold", "-1"], ["--threshold", "-1", "0 to 255"]),
    ("golden-check-threshold-over-255", ["golden", "check", "--threshold", "256"], ["--threshold", "256"]),
    ("golden-check-threshold-fraction", ["golden", "check", "--threshold", "1.5"], ["--threshold", "1.5"]),
    ("golden-check-max-fraction-negative", ["golden", "check", "--max-fraction", "-0.1"],
     ["--max-fraction", "-0.1", "0 to 1"]),
    ("golden-check-max-fraction-over-one", ["golden", "check", "--max-fraction", "1.5"], ["--max-fraction", "1.5"]),
    ("golden-check-max-fraction-nan", ["golden", "check", "--max-fraction", "nan"], ["--max-fraction", "nan"]),
    ("golden-check-flip-limit-over-one", ["golden", "check", "--flip-limit", "2"], ["--flip-limit", "2"]),
    ("golden-check-flip-limit-inf", ["golden", "check", "--flip-limit", "inf"], ["--flip-limit", "inf"]),
    ("golden-check-goldens-missing", ["golden", "check", "--goldens", "{missing}"], ["--goldens", "{missing}"]),
    ("golden-check-goldens-file", ["golden", "check", "--goldens", "{file}"], ["--goldens", "{file}"]),
    ("golden-check-output-existing-file", ["golden", "check", "-o", "{file}"], ["-o/--output", "{file}"]),
    ("golden-check-library-missing", ["golden", "check", "--library", "{missing}"], ["--library", "{missing}"]),
    ("golden-update-size-zero", ["golden", "update", "--size", "0"], ["--size", "0"]),
    ("golden-update-env-missing", ["golden", "update", "--env", "{missing}"], ["--env", "{missing}"]),
    ("golden-update-goldens-existing-file", ["golden", "update", "--goldens", "{file}"], ["--goldens", "{file}"]),
    ("golden-update-workers-negative", ["golden", "update", "-j", "-2"], ["-j/--workers", "-2"]),
    ("report-dir-missing", ["report", "{missing}"], ["DIR", "{missing}", "no such directory"]),
    ("report-dir-file", ["report", "{file}"], ["DIR", "{file}", "not a directory"]),
    ("report-output-directory", ["report", "{dir}", "-o", "{dir}"], ["-o/--output", "{dir}"]),
    ("report-output-below-a-file", ["report", "{dir}", "-o", "{file}/r.html"], ["-o/--output", "{file}/r.html"]),
    ("report-output-empty", ["report", "{dir}", "-o", ""], ["-o/--output", "empty path", "not a file name"]),
    ("report-checks-existing-file", ["report", "{dir}", "--checks", "{file}"], ["--checks", "{file}"]),
    ("report-goldens-missing", ["report", "{dir}", "--goldens", "{missing}"], ["--goldens", "{missing}"]),
    ("report-workers-zero", ["report", "{dir}", "-j", "0"], ["-j/--workers", "0"]),
    ("batch-paths-missing", ["batch", "-o", "{out}"], ["mtlxgen batch: error", "PATH"]),
    ("batch-size-zero", ["batch", "{dir}", "-o", "{out}", "--size", "0"], ["--size", "0"]),
    ("batch-env-missing", ["batch", "{dir}", "-o", "{out}", "--env", "{missing}"], ["--env", "{missing}"]),
    ("batch-output-existing-file", ["batch", "{dir}", "-o", "{file}"], ["-o/--output", "{file}"]),
    ("batch-workers-zero", ["batch", "{dir}", "-o", "{out}", "-j", "0"], ["-j/--workers", "0"]),
    ("batch-library-missing", ["batch", "{dir}", "-o", "{out}", "--library", "{missing}"], ["--library", "{missing}"]),
]


@pytest.mark.parametrize("argv,named", [pytest.param(a, n, id=i) for i, a, n in BAD_OPTIONS])
def test_bad_option_is_one_line_and_status_1_before_any_work(argv, named, places, capsys):
    fill = lambda s: s.format(**places)
    rc, out, err = run_main(capsys, [fill(a) for a in argv])
    assert_usage_error(rc, err, *[fill(n) for n in named])
    assert not os.path.exists(places["out"]), "a refused command must not create its output directory"


@pytest.mark.parametrize("what,problem", [("missing", "no such file"), ("dir", "is a directory"),
                                          ("fifo", "not a regular file")])
@pytest.mark.parametrize("command", ["generate", "render", "info"])
def test_input_document_that_is_not_a_readable_file_is_a_file_error(command, what, problem, places, capsys):
    argv = [command, places[what]] + (["-o", places["out"]] if command != "info" else [])
    rc, out, err = run_main(capsys, argv)
    assert_usage_error(rc, err, "%s:0: %s" % (places[what], problem))


def test_unknown_element_names_the_document_and_the_element(places, capsys):
    rc, out, err = run_main(capsys, ["generate", places["doc"], "-o", places["out"], "--element", "g/nope"])
    assert_usage_error(rc, err, "%s:0:" % places["doc"], "'g/nope'")


def test_help_still_exits_0(capsys):
    for argv in (["--help"], ["render", "--help"], ["golden", "check", "--help"], ["batch", "--help"]):
        rc, out, err = run_main(capsys, argv)
        assert rc == 0 and out.startswith("usage: mtlxgen") and err == "", argv


def test_bad_option_from_the_installed_command_line_exits_1_with_one_line(tmp_path):
    proc = run_cli("render", os.path.join(ROOT, "examples", "quick_start.mtlx"), "-o", str(tmp_path / "o"),
                   "--size", "0")
    assert proc.returncode == 1
    assert_one_line_error(proc, r"^mtlxgen render: error: argument --size: 0 is out of range")


def test_good_options_at_their_limits_are_accepted(places, capsys):
    rc, out, err = run_main(capsys, ["render", places["doc"], "-o", places["out"], "--size", "1"])
    assert rc == 0, err
    assert os.path.exists(os.path.join(places["out"], "g_out.png"))
    nested = os.path.join(places["out"], "a", "b")           # -o may name directories yet to be made
    rc, out, err = run_main(capsys, ["generate", places["doc"], "-o", nested, "--library", places["dir"]])
    assert rc == 0, err
    assert sorted(os.listdir(nested)) == ["g_out.frag", "g_out.json", "g_out.vert"]
