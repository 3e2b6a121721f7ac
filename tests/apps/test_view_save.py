"""The property panel's model and "Save", without a window: docedit.public_inputs lists an element's public
inputs with the nodedef's ui metadata and where each is written; save_values writes edited values back as the
smallest text edit (the value attribute of the input, or one <input> line added to its node), touching nothing
else; the document generated again gives the edited values. (tests/apps/test_writeback.py: encodings, line endings,
files changed on disk, failed writes.)"""
import os

import pytest

from mtlxgen.apps import docedit
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError

DOC = """<?xml version="1.0"?>
<!-- a comment that stays -->
<materialx version="1.39">
  <standard_surface name="SR" type="surfaceshader">
    <input name="base" type="float" value="0.8"/>
    <input   type="color3"   name="base_color" value='0.1, 0.2, 0.3' />
    <input name="metalness" type="float" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
  <checkerboard name="chk" type="color3"/>
  <surface_unlit name="U" type="surfaceshader">
    <input name="emission_color" type="color3" nodename="chk" />
  </surface_unlit>
  <surfacematerial name="M2" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="U" />
  </surfacematerial>
</materialx>
"""


def write(tmp_path, text, newline="\n"):
    path = str(tmp_path / "doc.mtlx")
    with open(path, "w", newline="") as f:
        f.write(text.replace("\n", newline))
    return path


def inputs(path, element):
    return {i.uniform: i for i in docedit.public_inputs(pipeline.Session(path), element)}


def values(path, element):
    s = pipeline.generate(path, elements=[element])[0]
    return {u["name"]: u["value"] for u in s.manifest["uniforms"]}


def test_inputs_carry_the_nodedefs_ui_metadata(tmp_path):
    got = inputs(write(tmp_path, DOC), "M")
    base = got["SR_base"]
    assert (base.node, base.input, base.label, base.folder, base.group) == ("SR", "base", "Base", "Base", "SR / Base")
    assert base.ui == {"uimin": 0.0, "uimax": 1.0} and base.value == 0.8
    assert base.where.line == 5 and base.node_loc.line == 4
    assert got["SR_metalness"].where.line == 7            # authored without a value: the default, still its line
    ior = got["SR_specular_IOR"]
    assert ior.where is None and ior.ui["uisoftmin"] == 1.0 and ior.ui["uisoftmax"] == 3.0
    assert got["SR_thin_walled"].mtlx_type == "boolean"
    assert "SR_base_color" in got and got["SR_base_color"].value == (0.1, 0.2, 0.3)


@pytest.mark.parametrize("newline", ["\n", "\r\n"])
def test_save_is_the_smallest_edit_and_reads_back(tmp_path, newline):
    path = write(tmp_path, DOC, newline)
    got = inputs(path, "M")
    edits = [(got["SR_base"], 0.25), (got["SR_base_color"], (0.5, 0.25, 1.0)), (got["SR_metalness"], 1.0),
             (got["SR_specular_IOR"], 2.2), (got["SR_coat"], 0.5)]
    assert docedit.save_values(edits) == [path]
    with open(path, newline="") as f:
        text = f.read()
    # the inputs it did not author: one line each after the node's start tag, at its children's indentation;
    # the others: their value attribute alone (quotes, spacing and attribute order as they were)
    expected = DOC.replace(
        '  <standard_surface name="SR" type="surfaceshader">\n',
        '  <standard_surface name="SR" type="surfaceshader">\n'
        '    <input name="specular_IOR" type="float" value="2.2" />\n'
        '    <input name="coat" type="float" value="0.5" />\n').replace(
        'value="0.8"/>', 'value="0.25"/>').replace(
        "value='0.1, 0.2, 0.3' />", "value='0.5, 0.25, 1' />").replace(
        '<input name="metalness" type="float" />', '<input name="metalness" type="float" value="1" />')
    assert text == expected.replace("\n", newline)
    v = values(path, "M")
    assert v["SR_base"] == 0.25 and v["SR_base_color"] == [0.5, 0.25, 1.0] and v["SR_metalness"] == 1.0
    assert v["SR_specular_IOR"] == 2.2 and v["SR_coat"] == 0.5


def test_a_self_closed_node_is_opened_for_its_input(tmp_path):
    path = write(tmp_path, DOC)
    got = inputs(path, "M2")
    assert got["chk_color1"].where is None and got["chk_color1"].node_loc.line == 12
    docedit.save_values([(got["chk_color1"], (0.0, 1.0, 0.0)), (got["chk_uvtiling"], (4.0, 4.0))])
    text = open(path).read()
    assert ('  <checkerboard name="chk" type="color3">\n'
            '    <input name="color1" type="color3" value="0, 1, 0" />\n'
            '    <input name="uvtiling" type="vector2" value="4, 4" />\n'
            '  </checkerboard>\n') in text
    v = values(path, "M2")
    assert v["chk_color1"] == [0.0, 1.0, 0.0] and v["chk_uvtiling"] == [4.0, 4.0]
    assert text.replace(text[text.index("  <checkerboard"):text.index("  <surface_unlit")], "") == \
        DOC.replace('  <checkerboard name="chk" type="color3"/>\n', "")


def test_a_file_changed_since_it_was_read_is_not_written(tmp_path):
    path = write(tmp_path, DOC)
    got = inputs(path, "M")
    with open(path, "w") as f:                    # an editor moved the input since
        f.write(DOC.replace('    <input name="base" type="float" value="0.8"/>\n', "\n"))
    before = open(path).read()
    with pytest.raises(MtlxError) as e:
        docedit.save_values([(got["SR_base"], 0.1), (got["SR_metalness"], 0.3)])
    assert e.value.lines() == ["%s:5: changed on disk since it was read: not saved; reload first" % path]
    assert open(path).read() == before            # nothing written, not even the edit that still fitted


def test_format_value():
    assert docedit.format_value("float", 0.10000000149011612) == "0.1"
    assert docedit.format_value("color3", (1.0, 0.5, -0.0)) == "1, 0.5, 0"
    assert docedit.format_value("integer", 3.0) == "3"
    assert docedit.format_value("boolean", True) == "true"
    assert docedit.format_value("filename", "a&b.png") == "a&b.png"
    assert docedit._escape(docedit.format_value("filename", 'a&"b.png')) == "a&amp;&quot;b.png"


def test_a_usd_stage_is_not_written(tmp_path):
    """The panel edits a USD stage's inputs live; Save refuses them, one line at the attribute, file untouched."""
    pytest.importorskip("pxr", reason="USD stages need usd-core")
    import shutil
    stage = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples", "usd")
    for name in ("preview_stage.usda", "leaf_ga.png", "stripes_r.png"):
        shutil.copy(os.path.join(stage, name), str(tmp_path / name))
    path = str(tmp_path / "preview_stage.usda")
    s = pipeline.Session(path)
    items = docedit.public_inputs(s, s.elements[0])
    assert items
    before = open(path).read()
    with pytest.raises(MtlxError) as e:
        docedit.save_values([(items[0], items[0].value)])
    assert len(e.value.lines()) == 1 and "saved into .mtlx documents only" in e.value.lines()[0]
    assert e.value.lines()[0].startswith(path + ":/")
    assert open(path).read() == before


def test_the_panels_save_says_what_it_did(tmp_path):
    """Panel.save (no window needed): the values saved and where; a refusal is the first problem line (the
    count of the others after it), every line printed, the file untouched; nothing to save said so."""
    from types import SimpleNamespace
    from mtlxgen.apps.viewpanel import Panel
    path = write(tmp_path, DOC)
    session = pipeline.Session(path)
    said = []
    loaded = SimpleNamespace(overrides={"SR_base": 0.25, "SR_coat": 0.5})
    panel = Panel.__new__(Panel)
    panel.viewer = SimpleNamespace(element="M", loaded={"M": loaded}, say=said.append)
    panel.inputs = docedit.public_inputs(session, "M")
    assert panel.save() == [path] and panel.message == "saved 2 values to doc.mtlx" and said == [panel.message]
    assert 'value="0.25"' in open(path).read()
    # an editor adds a line above the node; the panel lists the inputs again before the viewer has read the file
    # (its session has the old lines): they are not confirmed, and not saved
    with open(path, "w") as f:
        f.write(DOC.replace("<materialx", "\n<materialx"))
    panel.inputs, said[:] = docedit.public_inputs(session, "M"), []
    assert panel.save() == []
    assert said == ["%s:5: input 'base' of 'SR': the file changed while the document was read: not saved; reload "
                    "first" % path, "%s:4: input 'coat' of 'SR': the file changed while the document was read: not "
                    "saved; reload first" % path]
    assert panel.message == said[0] + " (and 1 more)"
    assert open(path).read() == DOC.replace("<materialx", "\n<materialx")
    # read again (as the viewer does after the change): saved
    panel.inputs = docedit.public_inputs(pipeline.Session(path), "M")
    assert panel.save() == [path] and 'value="0.25"' in open(path).read()
    loaded.overrides = {"not_an_input": 1.0}
    assert panel.save() == [] and panel.message.startswith("nothing to save")


# uniforms whose names say nothing of their inputs: a node takes 'm_in2' first, so m's in2 is 'm_in22'; an image
# 'img' at the document's level and one inside nodegraph NG both leave 'default' unauthored (one uniform is
# 'img_default', the other 'img_default2')
CLASH = """<?xml version="1.0"?>
<materialx version="1.39">
  <constant name="m_in2" type="float">
    <input name="value" type="float" value="0.5" />
  </constant>
  <multiply name="m" type="float">
    <input name="in1" type="float" nodename="m_in2" />
  </multiply>
  <image name="img" type="float">
    <input name="file" type="filename" value="grey.png" />
  </image>
  <nodegraph name="NG">
    <input name="tint" type="float" value="0.9" />
    <image name="img" type="float">
      <input name="file" type="filename" value="grey.png" />
    </image>
    <multiply name="n" type="float">
      <input name="in1" type="float" nodename="img" />
      <input name="in2" type="float" interfacename="tint" />
    </multiply>
    <output name="out" type="float" nodename="n" />
  </nodegraph>
  <add name="s" type="float">
    <input name="in1" type="float" nodename="m" />
    <input name="in2" type="float" nodename="img" />
  </add>
  <add name="s2" type="float">
    <input name="in1" type="float" nodename="s" />
    <input name="in2" type="float" nodegraph="NG" output="out" />
  </add>
  <surface_unlit name="U" type="surfaceshader">
    <input name="emission" type="float" nodename="s2" />
  </surface_unlit>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="U" />
  </surfacematerial>
</materialx>
"""


def test_inputs_come_from_the_uniforms_origin_not_their_names(tmp_path):
    """Each panel input is the document input its uniform's Origin names, whatever the uniform is called: a
    counter appended to a clashing name, nodes of one name in and outside a nodegraph, textures; Save writes
    each into that input (one the document does not author added to its own node)."""
    path = write(tmp_path, CLASH)
    got = inputs(path, "M")
    g = pipeline.Session(path).graph("M")
    assert {"m_in22", "img_default", "img_default2", "NG_tint"} <= set(g.uniforms)   # the names this is about
    assert {u.name for u in g.uniforms.values() if u.type in docedit.EDITABLE_TYPES} == set(got)
    where = {(i.node, i.input): (i.mtlx_type, i.where and i.where.line, i.node_loc and i.node_loc.line,
                                 i.element_path) for i in got.values()}
    assert where[("m", "in2")] == ("float", None, 6, ("m", "in2"))           # not authored: added to m
    assert where[("NG", "tint")] == ("float", 13, 12, ("NG", "tint"))
    assert where[("img", "default")] == ("float", None, 9, ("img", "default"))
    assert where[("NG/img", "default")] == ("float", None, 14, ("NG", "img", "default"))
    assert where[("img", "file")] == ("filename", 10, 9, ("img", "file"))
    assert where[("NG/img", "file")] == ("filename", 15, 14, ("NG", "img", "file"))
    by = {(i.node, i.input): i for i in got.values()}
    docedit.save_values([(by[("m", "in2")], 0.75), (by[("NG", "tint")], 0.5), (by[("img", "default")], 0.25),
                         (by[("NG/img", "default")], 0.125), (by[("NG/img", "file")], "other.png")])
    text = open(path).read()
    assert text == CLASH.replace(
        '  <multiply name="m" type="float">\n',
        '  <multiply name="m" type="float">\n    <input name="in2" type="float" value="0.75" />\n').replace(
        '\n  <image name="img" type="float">\n',
        '\n  <image name="img" type="float">\n    <input name="default" type="float" value="0.25" />\n').replace(
        '    <image name="img" type="float">\n      <input name="file" type="filename" value="grey.png" />',
        '    <image name="img" type="float">\n      <input name="default" type="float" value="0.125" />\n'
        '      <input name="file" type="filename" value="other.png" />').replace('value="0.9"', 'value="0.5"')
    g = pipeline.Session(path).graph("M")
    values = {(u.origin.element, u.origin.input): u.value for u in g.uniforms.values()}
    assert values[("m", "in2")] == 0.75 and values[("NG", "tint")] == 0.5
    assert values[("img", "default")] == 0.25 and values[("NG/img", "default")] == 0.125
    assert values[("NG/img", "file")] == "other.png" and values[("img", "file")] == "grey.png"
