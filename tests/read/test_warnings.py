"""Slips MaterialX reads on (issue 16, class 6): read as MaterialX 1.39 reads them, each reported as one
`FILE:LINE: warning: ...` line; --strict makes each one an error. What MaterialX refuses stays an error.

The rules were measured with the materialx wheel (1.39.5): Value.createValueFromStrings for values, doc.validate()
and GenGlsl for the rest. The tests compare with the wheel where it can answer (values, renders)."""
import json
import os
import re

import numpy as np
import pytest

from mtlxgen.apps import batch, cli
from mtlxgen.base import mxtypes
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError, Warnings
from mtlxgen.options import GenerateOptions
from util import assert_parity_with_materialx, write_doc

WARNING = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+): warning: (?P<message>.+)$")
PROBLEM = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+): (?!warning: )(?P<message>.+)$")


def run(capsys, *args):
    """cli.main in this process: (status, warning lines, problem lines); every stderr line is one of the two."""
    capsys.readouterr()
    status = cli.main(list(args))
    err = capsys.readouterr().err.splitlines()
    warnings = [e for e in err if WARNING.match(e)]
    problems = [e for e in err if PROBLEM.match(e)]
    assert len(warnings) + len(problems) == len(err), err
    assert status in (0, 1) and (status == 1) == bool(problems), (status, err)
    return status, warnings, problems


def line_of(path, fragment):
    with open(path) as f:
        return next(i + 1 for i, text in enumerate(f) if fragment in text)


def written(out):
    return sorted(os.listdir(out)) if os.path.isdir(out) else []


# ---------------------------------------------------------------- values, against MaterialX's own reader

# (type, text, whether we warn): MaterialX reads a value or not; where it reads one, so do we (the same value),
# warning where it read past a slip
READ = [
    ("float", "0.25", False), ("float", " 0.5", False), ("float", "0.5 ", False), ("float", "+.5", False),
    ("float", "5.", False), ("float", "1.0E+3", False), ("float", "08", False), ("float", "1e-50", False),
    ("float", "1.842,1.044,0.35", True), ("float", "0.5.0", True), ("float", "0.5abc", True), ("float", "0.5 0.7", True),
    ("float", "1e5e3", True), ("float", "0x1p3", True), ("float", "1_000", True), ("float", "1,", True),
    ("float", "1d", True), ("float", "1.0e-3x", True),
    ("integer", "7", False), ("integer", "+3", False), ("integer", " 4", False), ("integer", "2.0", False),
    ("integer", "2.7", True), ("integer", "2,3", True), ("integer", "2abc", True), ("integer", "0x10", True),
    ("integer", "1e3", True), ("integer", "1_0", True),
    ("boolean", "true", False), ("boolean", "false", False),
    ("color3", "0.1,0.2,0.3", False), ("color3", "0.1 0.2 0.3", False), ("color3", "0.1, 0.2, 0.3", False),
    ("color3", "0.1 ,0.2 ,0.3", False), ("color3", "0.1,,0.2,0.3", True), ("color3", "0.1,0.2.5,0.3", True),
    ("color3", "0.1,0.2x,0.3", True), ("color3", "0.1,0.2,0.3,", True), ("color3", ",0.1,0.2,0.3", True),
    ("vector2", "1 2", False), ("vector4", "1,2,3,4", False),
    ("matrix33", "1,0,0, 0,1,0, 0,0,1", False), ("matrix33", "1,0,0,0,1,0,0.5.0,0,1", True),
    ("matrix44", "1,0,0,0, 0,1,0,0, 0,0,1,0, 0.5.0,0,0,1", True),
    ("floatarray", "1,2,3", False), ("floatarray", "", False), ("floatarray", "1,2.5.3,3", True),
    ("floatarray", "1 2 3", True), ("floatarray", "1,,2", True),
    ("integerarray", "1,2,3", False), ("integerarray", "1,2.5,3", True),
]
# "" is not here: MaterialX reads no value from it either, and ours reads it as no value, the default, with a
# warning (tests/read/test_unseen_classes.py, issue 16)
REFUSED = [
    ("float", "abc"), ("float", "."), ("float", "-"), ("float", "1e"), ("float", "1.5eabc"),
    ("float", "1e+"), ("float", "inf"), ("float", "nan"), ("float", "1e39"), ("float", "-1e39"), ("float", ",1"),
    ("float", "\u0967"),
    ("integer", "abc"), ("integer", "2147483648"), ("integer", "-2147483649"),
    ("integer", "Infinity"),
    ("boolean", "1"), ("boolean", "True"), ("boolean", " true"), ("boolean", "true,false"),
    ("color3", "0.1,0.2"), ("color3", "0.1,0.2,0.3,0.4"), ("color3", "0.5"), ("color3", "0.1;0.2;0.3"),
    ("color3", "0.1,x,0.3"), ("color3", "0.1,inf,0.3"), ("color3", "[0.1,0.2,0.3]"), ("color3", "0.1,1e39,0.3"),
    ("vector2", "1,2,3"), ("matrix33", "1,0,0,0,1,0,0,0"), ("floatarray", "1,x,3"), ("integerarray", "1,x"),
]


def materialx_value(reference, type_name, text):
    """MaterialX's reading of a value string: a float, int, bool or tuple of numbers, or None where it reads none."""
    value = reference.mx.Value.createValueFromStrings(text, type_name)
    if value is None:
        return None
    if type_name.startswith("matrix"):
        n = 3 if type_name == "matrix33" else 4
        m = value.getData()
        return tuple(m[i, j] for i in range(n) for j in range(n))
    data = value.getData()
    return data if isinstance(data, (bool, int, float)) else tuple(data)


@pytest.mark.parametrize("type_name,text,warned", READ)
def test_values_materialx_reads_are_read_alike(reference, type_name, text, warned):
    theirs = materialx_value(reference, type_name, text)
    assert theirs is not None, "MaterialX reads no value from %r: the table is wrong" % text
    slips = []
    ours = mxtypes.parse_value(type_name, text, slips=slips)
    assert np.allclose(np.float32(ours), np.float32(theirs), rtol=0, atol=0) if ours != () else theirs == ()
    assert bool(slips) == warned, slips
    if not warned:                      # a clean value reads the same without a place for slips
        assert mxtypes.parse_value(type_name, text) == ours
    else:                               # and a slip is refused where no one asked for slips (other readers)
        with pytest.raises(mxtypes.ValueError_):
            mxtypes.parse_value(type_name, text)


@pytest.mark.parametrize("type_name,text", REFUSED)
def test_values_materialx_cannot_read_stay_refused(reference, type_name, text):
    assert materialx_value(reference, type_name, text) is None, "MaterialX reads %r: the table is wrong" % text
    with pytest.raises(mxtypes.ValueError_):
        mxtypes.parse_value(type_name, text, slips=[])


# ---------------------------------------------------------------- the warnings channel and --strict

TWO = """
  <constant name="bad" type="float"><input name="value" type="float" value="1.842,1.044,0.35" /></constant>
  <output name="slip" type="float" nodename="bad" />
  <constant name="good" type="float"><input name="value" type="float" value="0.25" /></constant>
  <output name="clean" type="float" nodename="good" />"""


def test_a_slip_is_one_warning_line_and_the_value_materialx_reads(tmp_path, capsys):
    path = write_doc(tmp_path, TWO)
    out = str(tmp_path / "out")
    status, warnings, problems = run(capsys, "generate", path, "-o", out)
    assert status == 0 and not problems
    assert len(warnings) == 1, warnings
    m = WARNING.match(warnings[0])
    assert m["file"] == path and int(m["line"]) == line_of(path, "1.842,1.044,0.35")
    assert "input 'value' of type float" in m["message"] and "read as 1.842" in m["message"]
    assert written(out) == ["clean.frag", "clean.json", "clean.vert", "slip.frag", "slip.json", "slip.vert"]
    uniforms = json.load(open(os.path.join(out, "slip.json")))["uniforms"]
    assert [u["value"] for u in uniforms] == [1.842]


def test_strict_makes_each_warning_an_error_and_writes_only_the_clean_elements(tmp_path, capsys):
    path = write_doc(tmp_path, TWO)
    out = str(tmp_path / "out")
    status, warnings, problems = run(capsys, "generate", path, "-o", out, "--strict")
    assert status == 1 and not warnings
    assert len(problems) == 1, problems
    m = PROBLEM.match(problems[0])
    assert int(m["line"]) == line_of(path, "1.842,1.044,0.35") and "read as 1.842" in m["message"]
    assert "an error with --strict" in m["message"]
    assert written(out) == ["clean.frag", "clean.json", "clean.vert"]


def test_a_slip_read_by_several_elements_is_warned_once(tmp_path, capsys):
    path = write_doc(tmp_path, """
  <nodegraph name="g">
    <constant name="c" type="color3"><input name="value" type="color3" value="0.2,0.4.5,0.6" /></constant>
    <output name="o" type="color3" nodename="c" />
  </nodegraph>
  <surface_unlit name="s1" type="surfaceshader"><input name="emission_color" type="color3" nodegraph="g" output="o" /></surface_unlit>
  <surface_unlit name="s2" type="surfaceshader"><input name="transmission_color" type="color3" nodegraph="g" output="o" /></surface_unlit>
  <surfacematerial name="m1" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s1" /></surfacematerial>
  <surfacematerial name="m2" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s2" /></surfacematerial>""")
    status, warnings, _ = run(capsys, "generate", path, "-o", str(tmp_path / "out"))
    assert status == 0 and len(warnings) == 1, warnings
    assert "'0.4.5' in '0.2,0.4.5,0.6' has more after its number: read as 0.4" in warnings[0]


def test_info_and_render_warn_too(tmp_path, capsys):
    path = write_doc(tmp_path, TWO)
    status, warnings, _ = run(capsys, "info", path)
    assert status == 0 and len(warnings) == 1 and "read as 1.842" in warnings[0]
    status, warnings, _ = run(capsys, "render", path, "-o", str(tmp_path / "r"), "--size", "8")
    assert status == 0 and len(warnings) == 1
    assert written(str(tmp_path / "r")) == ["clean.exr", "clean.png", "slip.exr", "slip.png"]


def test_info_strict_shows_the_element_unresolved(tmp_path, capsys):
    path = write_doc(tmp_path, TWO)
    capsys.readouterr()
    assert cli.main(["info", path, "--strict"]) == 1
    out, err = capsys.readouterr()
    assert "slip: unresolved" in out and "read as 1.842" in out and "an error with --strict" in out
    assert "clean [output]" in out and not err


def test_batch_warns_once_and_strict_fails_the_element(tmp_path, capsys):
    path = write_doc(tmp_path, TWO)
    status, warnings, _ = run(capsys, "batch", path, "-o", str(tmp_path / "b"), "-j", "1", "--no-progress",
                              "--size", "8")
    assert status == 0 and len(warnings) == 1 and "read as 1.842" in warnings[0]
    items = batch.render_jobs([batch.Job(path)], workers=1, progress=False, options=GenerateOptions(strict=True))
    by = {it.element: it for it in items}
    assert by["clean"].ok and not by["clean"].error
    assert not by["slip"].ok and any("an error with --strict" in line for line in by["slip"].error)


def test_golden_update_strict_refuses_an_element_with_a_slip(tmp_path, capsys):
    path = write_doc(tmp_path, TWO)
    goldens = str(tmp_path / "goldens")
    capsys.readouterr()
    status = cli.main(["golden", "update", path, "--goldens", goldens, "-j", "1", "--no-progress", "--size", "8",
                       "--strict"])
    out, err = capsys.readouterr()
    assert status == 1 and not err                  # golden update lists its errors on stdout
    assert re.search(r"error +doc__slip\n +\S+:\d+: .*read as 1\.842.*an error with --strict", out), out
    assert sorted(f for f in os.listdir(goldens) if f.endswith(".png")) == ["doc__clean.png"]
    status, warnings, _ = run(capsys, "golden", "update", path, "--goldens", goldens, "-j", "1", "--no-progress",
                              "--size", "8")
    assert status == 0 and len(warnings) == 1 and "read as 1.842" in warnings[0]
    assert sorted(f for f in os.listdir(goldens) if f.endswith(".png")) == ["doc__clean.png", "doc__slip.png"]
    status, warnings, _ = run(capsys, "golden", "check", path, "--goldens", goldens, "-j", "1", "--no-progress",
                              "-o", str(tmp_path / "check"), "--no-flip")
    assert status == 0 and len(warnings) == 1 and "read as 1.842" in warnings[0]


def test_document_warnings_are_warned_with_its_problems_and_strict_fails_the_document(tmp_path, capsys):
    # MaterialX's reader keeps the first of two same-named elements; a unit scale 'inf' it cannot read
    path = write_doc(tmp_path, """
  <constant name="c" type="float"><input name="value" type="float" value="0.2" /></constant>
  <constant name="c" type="float"><input name="value" type="float" value="0.7" /></constant>
  <output name="o" type="float" nodename="c" />""")
    out = str(tmp_path / "out")
    status, warnings, _ = run(capsys, "generate", path, "-o", out)
    assert status == 0 and len(warnings) == 1 and "<constant> 'c' repeats the name" in warnings[0]
    assert int(WARNING.match(warnings[0])["line"]) == line_of(path, 'value="0.7"')
    uniforms = json.load(open(os.path.join(out, "o.json")))["uniforms"]
    assert [u["value"] for u in uniforms] == [0.2]          # the first, as MaterialX reads it
    status, warnings, problems = run(capsys, "generate", path, "-o", str(tmp_path / "strict"), "--strict")
    assert status == 1 and not warnings and len(problems) == 1 and written(str(tmp_path / "strict")) == []
    bad = write_doc(tmp_path, """
  <unitdef name="UD_x" unittype="distance"><unit name="far" scale="inf" /></unitdef>
  <geompropdef name="uv9" type="vector2" geomprop="texcoord" index="2.5" />
  <constant name="c" type="float" /><output name="o" type="float" nodename="c" />""", name="bad.mtlx")
    status, warnings, problems = run(capsys, "generate", bad, "-o", str(tmp_path / "bad"))
    assert status == 1 and len(warnings) == 1 and "index: '2.5' has more after its number: read as 2" in warnings[0]
    assert len(problems) == 1 and "non-finite value 'inf'" in problems[0]


# ---------------------------------------------------------------- what MaterialX refuses stays an error

@pytest.mark.parametrize("body,fragment,message", [
    # an input the nodedef lacks, where the node does not name its nodedef: MaterialX finds no nodedef (issue 26:
    # reported at the input's own line, naming it; a wrong type names the type expected)
    ("""<constant name="c" type="float"><input name="value" type="float" value="0.5" />
          <input name="bogus" type="float" value="1" /></constant>
        <output name="o" type="float" nodename="c" />""", 'name="bogus"', "node 'c' (constant, type float) has no input 'bogus'"),
    # an input declared with another type than its nodedef's, without nodedef=: the same
    ("""<multiply name="m" type="color3"><input name="in1" type="vector3" value="0.2,0.3,0.4" />
          <input name="in2" type="color3" value="2,2,2" /></multiply>
        <output name="o" type="color3" nodename="m" />""", 'name="in1"', "input 'in1' of node 'm' has type vector3; "
                                                                          "ND_multiply_color3 expects color3"),
    # connections between types of different GLSL spelling: MaterialX's GLSL does not compile
    ("""<position name="p" type="vector3" /><multiply name="m" type="color4">
          <input name="in1" type="color4" nodename="p" /><input name="in2" type="color4" value="1,1,1,1" /></multiply>
        <output name="o" type="color4" nodename="m" />""", 'name="in1"', "has type color4 but is connected to a value of type vector3"),
    ("""<position name="p" type="vector3" /><extract name="x" type="float"><input name="in" type="vector3" nodename="p" /></extract>
        <surface_unlit name="s" type="surfaceshader"><input name="emission_color" type="color3" nodename="x" /></surface_unlit>
        <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>""",
     'name="emission_color"', "has type color3 but is connected to a value of type float"),
    # a value MaterialX reads none from
    ("""<constant name="c" type="vector3"><input name="value" type="vector3" value="0.1,0.2,0.3,0.4" /></constant>
        <output name="o" type="vector3" nodename="c" />""", 'name="value"', "expected 3 comma-separated numbers, got 4"),
])
def test_what_materialx_refuses_stays_an_error(tmp_path, capsys, body, fragment, message):
    path = write_doc(tmp_path, body)
    status, warnings, problems = run(capsys, "generate", path, "-o", str(tmp_path / "out"))
    assert status == 1 and len(problems) == 1, problems
    assert int(PROBLEM.match(problems[0])["line"]) == line_of(path, fragment)
    assert message in problems[0]
    assert written(str(tmp_path / "out")) == []


# ---------------------------------------------------------------- each slip drawn as MaterialX draws it

SLIPS = {
    # value slips
    "float_list": ("""<constant name="c" type="float"><input name="value" type="float" value="0.842,1.044,0.35" /></constant>
        <output name="o" type="float" nodename="c" />""", "o", ["read as 0.842"]),
    "matrix_0_5_0": ("""<constant name="c" type="matrix33"><input name="value" type="matrix33" value="1,0,0, 0,1,0, 0.5.0,0.25,1" /></constant>
        <transformmatrix name="t" type="vector3"><input name="in" type="vector3" value="0.2,0.3,1" /><input name="mat" type="matrix33" nodename="c" /></transformmatrix>
        <output name="o" type="vector3" nodename="t" />""", "o", ["'0.5.0' in '1,0,0, 0,1,0, 0.5.0,0.25,1'"]),
    "integer_2_7": ("""<constant name="c" type="integer"><input name="value" type="integer" value="2.7" /></constant>
        <convert name="f" type="float"><input name="in" type="integer" nodename="c" /></convert>
        <multiply name="m" type="float"><input name="in1" type="float" nodename="f" /><input name="in2" type="float" value="0.3" /></multiply>
        <output name="o" type="float" nodename="m" />""", "o", ["read as 2"]),
    "color_components": ("""<constant name="c" type="color3"><input name="value" type="color3" value="0.9,,0.4x,0.1" /></constant>
        <output name="o" type="color3" nodename="c" />""", "o", ["empty item", "'0.4x' in"]),
    # connections MaterialX passes through
    "color3_from_vector3": ("""<position name="p" type="vector3" />
        <multiply name="m" type="color3"><input name="in1" type="color3" nodename="p" /><input name="in2" type="color3" value="0.5,1,2" /></multiply>
        <output name="o" type="color3" nodename="m" />""", "o", ["input 'in1' of node 'm' has type color3 but is connected to a value of type vector3"]),
    "color4_from_vector4": ("""<position name="p" type="vector3" /><convert name="v" type="vector4"><input name="in" type="vector3" nodename="p" /></convert>
        <multiply name="m" type="color4"><input name="in1" type="color4" nodename="v" /><input name="in2" type="color4" value="0.5,1,2,1" /></multiply>
        <output name="o" type="color4" nodename="m" />""", "o", ["passed through as color4"]),
    "vector3_output_of_color3": ("""<nodegraph name="g"><texcoord name="t" type="vector2" />
          <combine3 name="c" type="color3"><input name="in1" type="float" value="0.3" /><input name="in2" type="float" value="0.6" /><input name="in3" type="float" value="0.1" /></combine3>
          <output name="o" type="vector3" nodename="c" /></nodegraph>""", "g/o", ["output 'o' of 'g' has type vector3"]),
    "interface_vector3_into_color3": ("""<nodegraph name="g"><input name="i" type="vector3" value="0.1,0.5,0.9" />
          <multiply name="m" type="color3"><input name="in1" type="color3" interfacename="i" /><input name="in2" type="color3" value="1,1,0.5" /></multiply>
          <output name="o" type="color3" nodename="m" /></nodegraph>""", "g/o", ["passed through as color3"]),
    # nodedef= named: MaterialX takes that nodedef as it is
    "named_nodedef_extra_input": ("""<image name="i" type="color3" nodedef="ND_image_color3">
          <input name="file" type="filename" value="resources/Images/grid.png" /><input name="gamma" type="float" value="2.2" /></image>
        <output name="o" type="color3" nodename="i" />""", "o", ["has no input 'gamma': ignored"]),
    "named_nodedef_vector3_for_color3": ("""<multiply name="m" type="color3" nodedef="ND_multiply_color3">
          <input name="in1" type="vector3" value="0.2,0.3,0.4" /><input name="in2" type="color3" value="2,2,2" /></multiply>
        <output name="o" type="color3" nodename="m" />""", "o", ["has type vector3; ND_multiply_color3 expects color3"]),
    "named_nodedef_of_another_node": ("""<constant name="c" type="float" nodedef="ND_add_float">
          <input name="value" type="float" value="0.5" /><input name="in1" type="float" value="0.25" /><input name="in2" type="float" value="0.5" /></constant>
        <output name="o" type="float" nodename="c" />""", "o", ["is a constant but names nodedef ND_add_float", "no input 'value'"]),
    # connections that lead nowhere: MaterialX reads the input's own value
    "node_not_there": ("""<multiply name="m" type="color3"><input name="in1" type="color3" nodename="gone" value="0.2,0.7,0.3" /><input name="in2" type="float" value="1" /></multiply>
        <output name="o" type="color3" nodename="m" />""", "o", ["connects to node 'gone', which does not exist"]),
    "interface_not_there": ("""<nodegraph name="g"><multiply name="m" type="color3"><input name="in1" type="color3" interfacename="gone" value="0.6,0.1,0.3" /><input name="in2" type="float" value="1" /></multiply>
          <output name="o" type="color3" nodename="m" /></nodegraph>""", "g/o", ["names interface input 'gone'"]),
    "graph_output_not_there": ("""<nodegraph name="a"><constant name="c" type="color3"><input name="value" type="color3" value="1,0,0" /></constant><output name="o" type="color3" nodename="c" /></nodegraph>
        <nodegraph name="g"><multiply name="m" type="color3"><input name="in1" type="color3" nodegraph="a" output="gone" value="0.3,0.3,0.8" /><input name="in2" type="float" value="1" /></multiply>
          <output name="o" type="color3" nodename="m" /></nodegraph>""", "g/o", ["nodegraph 'a' has no output 'gone'"]),
    "output_name_a_node_lacks": ("""<constant name="c" type="color3"><input name="value" type="color3" value="0.9,0.5,0.1" /></constant>
        <multiply name="m" type="color3"><input name="in1" type="color3" nodename="c" output="result" /><input name="in2" type="float" value="1" /></multiply>
        <output name="o" type="color3" nodename="m" />""", "o", ["node 'c' has no output 'result': 'in1' reads its first output, 'out'"]),
    # repeated names: MaterialX keeps the first
    "repeated_input": ("""<constant name="c" type="float"><input name="value" type="float" value="0.2" /><input name="value" type="float" value="0.7" /></constant>
        <output name="o" type="float" nodename="c" />""", "o", ["<input> 'value' repeats the name"]),
}


@pytest.mark.parametrize("case", sorted(SLIPS))
def test_slips_draw_as_materialx_draws_them(tmp_path, renderer, reference, case):
    from conftest import DATA
    body, element, messages = SLIPS[case]
    path = write_doc(tmp_path, body.replace("resources/Images", os.path.join(DATA, "resources", "Images")))
    seen = Warnings()
    pipeline.generate(path, elements=[element], warnings=seen)
    lines = seen.lines()
    for message in messages:
        assert any(message in line for line in lines), (message, lines)
    with pytest.raises(MtlxError, match="an error with --strict"):
        pipeline.generate(path, elements=[element], strict=True)
    assert_parity_with_materialx(renderer, reference, path, element)


def test_vector_math_determinant_reads_0_5_0_as_materialx_does(renderer, reference):
    """The corpus document that writes `0.5.0` in a matrix44 value (MaterialX's own TestSuite), at parity."""
    from conftest import DATA_TESTSUITE
    path = os.path.join(DATA_TESTSUITE, "stdlib", "math", "vector_math.mtlx")
    seen = Warnings()
    pipeline.generate(path, elements=["determinant_matrix44/out"], warnings=seen)
    assert len(seen) == 1 and "'0.5.0'" in seen.lines()[0] and "read as 0.5" in seen.lines()[0], seen.lines()
    assert_parity_with_materialx(renderer, reference, path, "determinant_matrix44/out")
