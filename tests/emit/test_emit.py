"""The GLSL emitter: deterministic text, public uniforms with initializers, only the streams used."""
import os
import subprocess
import sys

from mtlxgen import pipeline
from util import write_doc

DOC = """
  <nodegraph name="g">
    <texcoord name="uv" type="vector2" />
    <position name="p" type="vector3"><input name="space" type="string" value="world" /></position>
    <rotate2d name="r" type="vector2"><input name="in" type="vector2" nodename="uv" /></rotate2d>
    <rotate2d name="r2" type="vector2"><input name="in" type="vector2" nodename="r" /></rotate2d>
    <extract name="x" type="float"><input name="in" type="vector2" nodename="r2" /></extract>
    <extract name="z" type="float">
      <input name="in" type="vector3" nodename="p" /><input name="index" type="integer" value="2" />
    </extract>
    <multiply name="m" type="float">
      <input name="in1" type="float" nodename="x" /><input name="in2" type="float" nodename="z" />
    </multiply>
    <output name="out" type="float" nodename="m" />
  </nodegraph>"""


def test_same_input_gives_byte_identical_output(tmp_path):
    path = write_doc(tmp_path, DOC)
    a = pipeline.generate(path)[0]
    b = pipeline.generate(path)[0]
    assert (a.vertex, a.fragment, a.manifest) == (b.vertex, b.fragment, b.manifest)


def test_output_is_identical_across_processes_with_different_hash_seeds(tmp_path):
    path = write_doc(tmp_path, DOC)
    code = ("import sys; sys.path.insert(0, %r); from mtlxgen import pipeline; s = pipeline.generate(%r)[0]; "
            "sys.stdout.write(s.vertex + s.fragment)") % (os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), path)
    outs = {subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           env=dict(os.environ, PYTHONHASHSEED=seed)).stdout for seed in ("1", "2", "3")}
    assert len(outs) == 1 and len(next(iter(outs))) > 100


def test_variable_names_come_from_the_graph(tmp_path):
    s = pipeline.generate(write_doc(tmp_path, DOC))[0]
    for var in ("vec2 r_out", "vec2 r2_out", "float x_out", "float m_out"):
        assert var in s.fragment


def test_every_unconnected_input_is_a_uniform_with_its_initializer(tmp_path):
    s = pipeline.generate(write_doc(tmp_path, DOC))[0]
    assert "uniform float r_amount = 0.0;" in s.fragment
    names = {u["name"]: u["value"] for u in s.manifest["uniforms"]}
    assert names == {"r_amount": 0.0, "r2_amount": 0.0, "uv_index": 0, "x_index": 0, "z_index": 2}
    # compile-time inputs (stream index, channel index) are literal in the code, not read from the uniform
    assert "x_in" not in names and "[2]" in s.fragment


def test_library_functions_are_emitted_once(tmp_path):
    s = pipeline.generate(write_doc(tmp_path, DOC))[0]
    assert s.fragment.count("vec2 mg_rotate2d(") == 1


def test_vertex_stage_passes_exactly_the_streams_used(tmp_path):
    s = pipeline.generate(write_doc(tmp_path, DOC))[0]
    assert s.manifest["attributes"] == {"i_position": "vec3", "i_texcoord_0": "vec2"}
    assert "out vec2 v_texcoord_0;" in s.vertex and "out vec3 v_position_world;" in s.vertex
    assert "i_normal" not in s.vertex and "v_normal" not in s.fragment
    path = write_doc(tmp_path, """<nodegraph name="c"><constant name="k" type="float" />
      <output name="out" type="float" nodename="k" /></nodegraph>""", name="c.mtlx")
    plain = pipeline.generate(path)[0]
    assert plain.manifest["attributes"] == {"i_position": "vec3"}
    assert " v_" not in plain.vertex


def test_closure_types_appear_only_when_used(tmp_path):
    s = pipeline.generate(write_doc(tmp_path, DOC))[0]
    assert "struct surfaceshader" not in s.fragment
    path = write_doc(tmp_path, """<surface_unlit name="sh" type="surfaceshader" />""", name="u.mtlx")
    assert "struct surfaceshader" in pipeline.generate(path)[0].fragment
