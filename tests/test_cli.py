"""The command-line contract: files written per element, and one FILE:LINE line per problem on bad input."""
import json
import os
import re
import subprocess
import sys

import pytest

from util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


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
  <output name="top" type="float" nodegraph="NG_a" output="out" />""")
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
    <constant name="c" type="vector3" />
    <sin name="s" type="float">
      <input name="in" type="float" nodename="c" />
    </sin>
    <output name="out" type="float" nodename="s" />
  </nodegraph>""")
    assert_one_line_error(run_cli("generate", path, "-o", str(tmp_path / "o")),
                          r"doc\.mtlx:7: input 'in' of node 's' has type float but is connected to a value of type vector3")


def test_cycle(tmp_path):
    path = write_doc(tmp_path, """
  <nodegraph name="g">
    <add name="a" type="float"><input name="in1" type="float" nodename="b" /></add>
    <add name="b" type="float"><input name="in1" type="float" nodename="a" /></add>
    <output name="out" type="float" nodename="a" />
  </nodegraph>""")
    assert_one_line_error(run_cli("generate", path, "-o", str(tmp_path / "o")),
                          r"doc\.mtlx:[56]: cycle: node '[ab]' depends on itself")


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
    from mtlxgen.images import read_image
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
