"""Classes of failure from a third set of documents and stages nobody here had seen (issue 26): each class
isolated in documents of our own (tests/data/unseen3), read as the reference reads it with a `FILE:LINE: warning:`
(an error with --strict), drawn by us and by MaterialX in the scoreboard's scene (the `harness` fixture), and the
refusals that remain pointing at the exact element with the names there are.
"""
import os
import re

import numpy as np
import pytest

from conftest import ROOT
from mtlxgen.draw import compare
from mtlxgen.base import diagnostics
from mtlxgen import pipeline
from util import assert_harness_parity, build_graph, harness_render_ours, write_doc

DATA = os.path.join(ROOT, "tests", "data", "unseen3")

UNLIT_BODY = """<materialx version="1.39">
  <constant name="c" type="color3"><input name="value" type="color3" value="0.9, 0.3, 0.1" /></constant>
  <surface_unlit name="s" type="surfaceshader"><input name="emission_color" type="color3" nodename="c" />
  </surface_unlit>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" />
  </surfacematerial>
</materialx>"""
DECLARATION = '<?xml version="1.0" encoding="UTF-8"?>\n'


def warnings_of(path, elements=None):
    seen = diagnostics.Warnings()
    shaders = pipeline.generate(path, elements=elements, warnings=seen)
    return shaders, seen.lines()


def line_of(path, fragment):
    with open(path) as f:
        return next(i for i, line in enumerate(f, 1) if fragment in line)


# ---------------------------------------------------------------- XML MaterialX's reader reads on

# (text of the file, [(line, what the warning says)]): MaterialX's reader (pugixml) reads each of these
XML_SLIPS = {
    "blank_lines_before_declaration": ("\n\n" + DECLARATION + UNLIT_BODY + "\n",
                                       [(3, "the XML declaration is not at the start of the file (2 blank lines")]),
    "text_before_declaration": ("Exported by SomeTool 2.1\n" + DECLARATION + UNLIT_BODY + "\n",
                                [(2, "the XML declaration is not at the start of the file (text 'Exported by")]),
    "text_after_root": (DECLARATION + UNLIT_BODY + "\n\n%%EOF\n",
                        [(10, "text '%%EOF' after the root element <materialx>: ignored")]),
    "element_after_root": (DECLARATION + UNLIT_BODY + "\n<thumbnail file=\"t.png\" />\n",
                           [(9, "element <thumbnail> after the root element <materialx>: ignored")]),
    "text_before_root_no_declaration": ("junk\n" + UNLIT_BODY + "\n",
                                        [(1, "text 'junk' before the root element <materialx>: ignored")]),
    "all_of_them": ("\n" + DECLARATION + UNLIT_BODY + "\nNUL padding\n<extra/>\n",
                    [(2, "1 blank line before it"), (10, "text 'NUL padding' after the root"),
                     (11, "element <extra> after the root")]),
}


@pytest.mark.parametrize("case", sorted(XML_SLIPS))
def test_xml_materialx_reads_is_read_with_a_warning_at_its_line(tmp_path, case):
    text, expected = XML_SLIPS[case]
    path = str(tmp_path / (case + ".mtlx"))
    open(path, "w").write(text)
    shaders, lines = warnings_of(path)
    assert [s.element for s in shaders] == ["m"]
    assert len(lines) == len(expected), lines
    for line, what in expected:
        assert any(ln.startswith("%s:%d: warning: " % (path, line)) and what in ln for ln in lines), (line, lines)
    with pytest.raises(diagnostics.MtlxError) as e:
        pipeline.generate(path, strict=True)
    assert all("(a warning; an error with --strict)" in ln for ln in e.value.lines())
    assert len(e.value.lines()) == len(expected)


@pytest.mark.parametrize("case", ["blank_lines_before_declaration", "all_of_them"])
def test_xml_slips_draw_as_materialx_draws_them(harness, cms_reference, tmp_path, case):
    path = str(tmp_path / (case + ".mtlx"))
    open(path, "w").write(XML_SLIPS[case][0])
    assert cms_reference.elements(path) == ["m"]        # MaterialX reads it
    assert_harness_parity(harness, cms_reference, path, "m")


@pytest.mark.parametrize("tail, message", [
    ("\n</materialx>\n", "malformed XML"),         # a second end tag: MaterialX's reader stops too
    ("\n<\n", "malformed XML"),
])
def test_xml_materialx_refuses_stays_an_error(tmp_path, cms_reference, tail, message):
    path = str(tmp_path / "bad.mtlx")
    open(path, "w").write(DECLARATION + UNLIT_BODY + tail)
    with pytest.raises(Exception):
        cms_reference.load(path)
    with pytest.raises(diagnostics.MtlxError, match=message):
        pipeline.generate(path)


def test_the_slip_is_the_first_materialx_element_not_the_first_element(tmp_path):
    """pugixml keeps every top-level element; MaterialX reads the first <materialx>."""
    path = str(tmp_path / "two.mtlx")
    open(path, "w").write("<note>exported</note>\n" + UNLIT_BODY + "\n")
    shaders, lines = warnings_of(path)
    assert [s.element for s in shaders] == ["m"]
    assert lines == ["%s:1: warning: element <note> before the root element <materialx>: ignored, as MaterialX's "
                     "reader ignores it" % path]


# ---------------------------------------------------------------- a float input connected to a colour or vector

FLOAT_FROM_VECTOR = os.path.join(DATA, "float_from_vector.mtlx")
FLOAT_FROM_VECTOR_EXPLICIT = os.path.join(DATA, "float_from_vector_explicit.mtlx")


def test_float_from_vector_reads_the_first_component_with_a_warning_at_the_input():
    _, lines = warnings_of(FLOAT_FROM_VECTOR)
    expected = [("input name=\"base\"", "input 'base' of node 'wired' has type float but is connected to a value of "
                                        "type color3: reads its first component (r)"),
                ("input name=\"metalness\"", "type vector3: reads its first component (x)"),
                ("input name=\"coat\"", "type color4: reads its first component (r)"),
                ("nodename=\"uv\"", "input 'in1' of node 'rough' has type float but is connected to a value of type "
                                    "vector2: reads its first component (x)")]
    assert len(lines) == len(expected), lines
    for fragment, what in expected:
        line = line_of(FLOAT_FROM_VECTOR, fragment)
        assert any(ln.startswith("%s:%d: warning: " % (FLOAT_FROM_VECTOR, line)) and what in ln for ln in lines), \
            (fragment, lines)
    with pytest.raises(diagnostics.MtlxError, match="reads its first component"):
        pipeline.generate(FLOAT_FROM_VECTOR, strict=True)


def test_float_from_vector_draws_its_first_component(harness):
    """Pixel for pixel the document that extracts each first component itself."""
    implicit = harness_render_ours(harness, FLOAT_FROM_VECTOR, "M_wired")
    explicit = harness_render_ours(harness, FLOAT_FROM_VECTOR_EXPLICIT, "M_wired")
    np.testing.assert_allclose(implicit, explicit, atol=1e-5)


def test_float_from_vector_is_at_parity_with_materialx(harness, cms_reference):
    """MaterialX's GLSL assigns the vector to the float (`float x = v;`, a vector passed for a float parameter):
    a driver that compiles it (NVIDIA's) reads the first component, Mesa's refuses it. MaterialX's render of the
    conversion written out (extract, index 0) is the render of what that driver draws."""
    _, fragment, _, _ = cms_reference.generate(FLOAT_FROM_VECTOR, "M_wired")
    assert re.search(r"\bfloat \w+_out = \w+_out\b", fragment) or "NG_standard_surface" in fragment
    ours = harness_render_ours(harness, FLOAT_FROM_VECTOR, "M_wired")
    vs, fs, tex, _ = cms_reference.generate(FLOAT_FROM_VECTOR_EXPLICIT, "M_wired")
    theirs, _ = harness.render_timed(vs, fs, None, tex)
    p = compare.parity(ours, theirs)
    assert p.passes, p


def test_float_from_a_colour_value_reads_its_first_component(tmp_path):
    from mtlxgen.graph import build as graph
    from mtlxgen.read.library import load_library
    body = ('<constant name="k" type="color3"><input name="value" type="color3" value="0.25, 0.5, 0.75" /></constant>'
            '<sin name="s" type="float"><input name="in" type="float" nodename="k" /></sin>'
            '<output name="o" type="float" nodename="s" />')
    g = build_graph(tmp_path, body, "o", load_library())
    assert isinstance(g, graph.Graph)
    sources = [n.inputs["in"] for n in g.nodes if n.category == "sin"]
    assert sources and (sources[0].node is not None or sources[0].value == pytest.approx(0.25))


# ---------------------------------------------------------------- 1.38 thin_film_bsdf layered over a BSDF graph

UBER_138 = os.path.join(DATA, "thin_film_uber_138.mtlx")
UBER_INCLUDE = os.path.join(DATA, "thin_film_uber_include.mtlx")
FILM_GRAPH = os.path.join(DATA, "thin_film_graph_138.mtlx")


def _materialx_upgraded_nodes(path, graph_name):
    import MaterialX as mx
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, path)
    ng = doc.getNodeGraph(graph_name)
    return {n.getName(): (n.getCategory(), sorted((i.getName(), i.getInterfaceName() or i.getNodeName() or
                                                   i.getValueString()) for i in n.getInputs()))
            for n in ng.getNodes()}


def test_thin_film_layers_upgrade_as_materialx_upgrades_them():
    """Every BSDF beneath that takes a film (not a transmitting one), through mixes, layers and sums; a film
    with no inputs gives nothing; the layers and the films gone; the same nodes and inputs as MaterialX 1.39's."""
    from mtlxgen.read import upgrade, xmlreader
    root = upgrade.upgrade_tree(xmlreader.read_file(FILM_GRAPH), [])
    ng = next(c for c in root.children if c.tag == "nodegraph")
    ours = {c.get("name"): (c.tag, sorted((p.get("name"), p.get("interfacename") or p.get("nodename") or
                                           p.get("value")) for p in c.children if p.tag == "input"))
            for c in ng.children if c.tag not in ("input", "output")}
    assert ours == _materialx_upgraded_nodes(FILM_GRAPH, "NG_tf")
    assert "tf" not in ours and "tf_layer" not in ours
    assert ("thinfilm_thickness", "thickness") in ours["metal"][1]


def test_thin_film_over_a_graph_is_warned_at_the_layer():
    _, lines = warnings_of(UBER_138)
    line = line_of(UBER_138, '<layer name="thin_film_layer"')
    assert lines == ["%s:%d: warning: layer 'thin_film_layer': thin_film_bsdf 'thin_film_bsdf' over mix "
                     "'metalness_mix' (gone in 1.39): its thickness and ior are given to each BSDF beneath that "
                     "reflects (metal_bsdf, specular_bsdf), as MaterialX's upgrade gives them" % (UBER_138, line)]
    for path in (UBER_138, UBER_INCLUDE):
        with pytest.raises(diagnostics.MtlxError, match="thin_film_bsdf 'thin_film_bsdf' over mix"):
            pipeline.generate(path, strict=True)


def test_thin_film_over_one_bsdf_is_no_warning(tmp_path):
    body = ('<thin_film_bsdf name="tf" type="BSDF"><input name="thickness" type="float" value="400" /></thin_film_bsdf>'
            '<dielectric_bsdf name="d" type="BSDF" />'
            '<layer name="b" type="BSDF"><input name="top" type="BSDF" nodename="tf" />'
            '<input name="base" type="BSDF" nodename="d" /></layer>'
            '<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="b" /></surface>'
            '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" '
            'nodename="s" /></surfacematerial>')
    _, lines = warnings_of(write_doc(tmp_path, body, version="1.38"))
    assert lines == []


@pytest.mark.parametrize("path, element", [(UBER_138, "M_soap"), (UBER_138, "M_film_metal"),
                                           (UBER_INCLUDE, "M_soap"), (UBER_INCLUDE, "M_film_metal"),
                                           (UBER_INCLUDE, "M_film_green")])
def test_thin_film_uber_shader_is_at_parity_with_materialx(harness, cms_reference, path, element):
    assert_harness_parity(harness, cms_reference, path, element)


def test_the_film_is_drawn(harness, tmp_path):
    """The film changes the render: the same document with the film's thickness 0 draws otherwise."""
    text = open(UBER_138).read()
    bare = str(tmp_path / "bare.mtlx")
    open(bare, "w").write(text.replace('name="thin_film_thickness" type="float" value="480"',
                                       'name="thin_film_thickness" type="float" value="0"'))
    with_film = harness_render_ours(harness, UBER_138, "M_soap")
    without = harness_render_ours(harness, bare, "M_soap")
    assert np.abs(with_film - without)[..., :3].max() > 0.05


def test_an_included_138_document_is_upgraded_from_its_own_version():
    from mtlxgen.read import upgrade, xmlreader
    root = xmlreader.read_file(UBER_INCLUDE, upgrade=upgrade.upgrade_tree)
    assert root.get("version") == "1.39"
    tags = set()
    stack = [root]
    while stack:
        el = stack.pop()
        tags.add(el.tag)
        stack.extend(el.children)
    assert "thin_film_bsdf" not in tags and "dielectric_bsdf" in tags


# ---------------------------------------------------------------- USD: an output the shader's definition declares

PREVIEW_USD = os.path.join(DATA, "preview_displacement_output.usda")


def test_usd_output_declared_by_the_definition_resolves_with_a_warning(renderer):
    shaders, lines = warnings_of(PREVIEW_USD)
    assert sorted(s.element for s in shaders) == ["Looks_Bumped", "Looks_Metal", "Looks_Red"]
    for name in ("Red", "Metal", "Bumped"):
        where = "%s:/Looks/%s.outputs:displacement: warning: connects to </Looks/%s/Surface.outputs:displacement>" \
                % (PREVIEW_USD, name, name)
        assert any(ln.startswith(where) and "read as the output UsdPreviewSurface declares" in ln for ln in lines), \
            lines
    images = {s.element: renderer.render(s) for s in shaders}       # each compiles and draws
    for img in images.values():
        assert (img[..., 3] > 0.5).any()
    with pytest.raises(diagnostics.MtlxError, match="does not author"):
        pipeline.generate(PREVIEW_USD, strict=True)


def test_usd_bumped_material_displaces(renderer):
    """The Bumped material's displacement input (0.05) moves the surface: its silhouette grows."""
    shaders = {s.element: s for s in pipeline.generate(PREVIEW_USD)}
    bumped = renderer.render(shaders["Looks_Bumped"])[..., 3] > 0.5
    flat = renderer.render(shaders["Looks_Red"])[..., 3] > 0.5
    assert bumped.sum() > flat.sum()


def test_usd_output_no_definition_declares_stays_an_error(tmp_path):
    text = open(PREVIEW_USD).read().replace("</Looks/Red/Surface.outputs:displacement>",
                                            "</Looks/Red/Surface.outputs:displace>")
    path = str(tmp_path / "bad.usda")
    open(path, "w").write(text)
    with pytest.raises(diagnostics.MtlxError, match="does not declare"):
        pipeline.generate(path, elements=["Looks_Red"])


# ---------------------------------------------------------------- refusals: where, what and the names there are

REFUSED_BODY = """  <standard_surfce name="s0" type="surfaceshader" />
  <standard_surface name="s1" type="surfaceshader">
    <input name="base_colour" type="color3" value="1, 0, 0" />
  </standard_surface>
  <multiply name="mm" type="color3">
    <input name="in1" type="color3" value="1, 0, 0" />
    <input name="in2" type="vector3" value="1, 0, 0" />
  </multiply>
  <mix name="mi" type="color3">
    <input name="fg" type="color3" value="1, 0, 0" />
    <input name="bgg" type="color3" value="1, 0, 0" />
  </mix>
  <add name="ad" type="color3">
    <input name="in1" type="color3" nodename="mmm" />
  </add>
  <surfacematerial name="m0" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s0" />
  </surfacematerial>
  <surfacematerial name="m1" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s1" />
  </surfacematerial>
  <output name="o_mm" type="color3" nodename="mm" />
  <output name="o_mi" type="color3" nodename="mi" />
  <output name="o_ad" type="color3" nodename="ad" />"""


def refused_doc(tmp_path):
    """refused.mtlx, REFUSED_BODY's elements from line 3 on."""
    return write_doc(tmp_path, REFUSED_BODY, "refused.mtlx")


@pytest.mark.parametrize("element, line, message", [
    ("m0", 3, "unknown node category 'standard_surfce' (node 's0'); did you mean 'standard_surface'"),
    ("m1", 5, "node 's1' (standard_surface, type surfaceshader) has no input 'base_colour'; did you mean "
              "'base_color'"),
    ("o_mm", 9, "input 'in2' of node 'mm' has type vector3; ND_multiply_color3 expects color3 (other multiply "
                "nodedefs of type color3: float)"),
    ("o_mi", 13, "node 'mi' (mix, type color3) has no input 'bgg'; did you mean 'bg'?"),
    ("o_ad", 16, "connects to node 'mmm', which does not exist; did you mean 'mm'?"),
])
def test_refusals_name_the_input_its_line_and_the_closest_names(tmp_path, element, line, message):
    path = refused_doc(tmp_path)
    seen = diagnostics.Warnings()
    try:
        pipeline.generate(path, elements=[element], warnings=seen, strict=element == "o_ad")
        raise AssertionError("not refused")
    except diagnostics.MtlxError as e:
        lines = e.lines()
    assert any(ln.startswith("%s:%d: " % (path, line)) and message in ln for ln in lines), lines


def test_unknown_element_lists_the_renderable_elements(tmp_path):
    path = refused_doc(tmp_path)
    with pytest.raises(diagnostics.MtlxError) as e:
        pipeline.generate(path, elements=["m_1"])
    assert e.value.lines() == ["%s:0: no element 'm_1' in the document; did you mean 'm1'? (renderable "
                               "elements: m0, m1)" % path]


def test_unknown_element_list_is_bounded(tmp_path):
    body = "".join('<surface_unlit name="s%d" type="surfaceshader" /><surfacematerial name="mat%02d" '
                   'type="material"><input name="surfaceshader" type="surfaceshader" nodename="s%d" />'
                   '</surfacematerial>' % (i, i, i) for i in range(27))
    path = write_doc(tmp_path, body)
    with pytest.raises(diagnostics.MtlxError) as e:
        pipeline.generate(path, elements=["nothing_like_it"])
    line = e.value.lines()[0]
    assert "(renderable elements: mat00, mat01," in line and "mat19 and 7 more)" in line and "mat20" not in line


def test_unknown_element_from_the_command_line(tmp_path):
    import subprocess
    import sys
    path = refused_doc(tmp_path)
    proc = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "generate", path, "--element", "M1",
                           "-o", str(tmp_path / "o")], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().splitlines() == [
        "%s:0: no element 'M1' in the document; did you mean 'm1'? (renderable elements: m0, m1)" % path]


# ---------------------------------------------------------------- found by the sweep: a number for a colour

SCALAR_VALUE = os.path.join(DATA, "named_nodedef_scalar_value.mtlx")


def test_a_number_for_a_colour_of_a_named_nodedef_is_every_component(harness, cms_reference):
    """bhouston/materialx.js's standard_surface_combined example: opacity="0.7" typed float on a node naming
    ND_standard_surface_surfaceshader (opacity: color3). MaterialX writes vec3(0.7); so do we, warned at the input."""
    _, lines = warnings_of(SCALAR_VALUE)
    for name, value in (("base_color", "0.35"), ("opacity", "0.6"), ("specular_color", "0.8")):
        line = line_of(SCALAR_VALUE, 'name="%s"' % name)
        assert any(ln.startswith("%s:%d: warning: input '%s'" % (SCALAR_VALUE, line, name)) and
                   "its value %s is read as color3, every component %s" % (value, value) in ln for ln in lines), lines
    assert len(lines) == 3, lines
    with pytest.raises(diagnostics.MtlxError, match="every component"):
        pipeline.generate(SCALAR_VALUE, strict=True)
    assert_harness_parity(harness, cms_reference, SCALAR_VALUE, "M_scalar_colours")


def test_a_number_for_a_colour_without_a_named_nodedef_stays_refused(tmp_path, cms_reference):
    """Without nodedef= MaterialX finds no nodedef for the node (its inputs' types pick it): refused at the input."""
    text = open(SCALAR_VALUE).read().replace(' nodedef="ND_standard_surface_surfaceshader"', "")
    path = str(tmp_path / "unnamed.mtlx")
    open(path, "w").write(text)
    with pytest.raises(Exception, match="Could not find a nodedef"):
        cms_reference.generate(path, "M_scalar_colours")
    with pytest.raises(diagnostics.MtlxError) as e:
        pipeline.generate(path)
    assert any(":6: input 'base_color' of node 'scalar_colours' has type float; ND_standard_surface_surfaceshader "
               "expects color3" in ln for ln in e.value.lines()), e.value.lines()
