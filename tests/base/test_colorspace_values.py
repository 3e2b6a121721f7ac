"""Colour spaces on values (issue 16, class 1): a color3 / color4 value whose active colour space (its own
`colorspace`, else its node's, nodegraph's or document's) is not the working space is converted as MaterialX's
default colour-management system converts it; files in every space of that system too.

Each case is a small document of our own drawn by us and by MaterialX with its colour management on (the
`cms_reference` fixture, as the scoreboard and MaterialX's viewer run it), in our harness.
"""
import os
import re

import numpy as np
import pytest

from conftest import DATA_IMAGES
from mtlxgen.nodes import cmlib
from util import assert_parity_with_materialx, generate_one, write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLOTH = os.path.abspath(os.path.join(DATA_IMAGES, "cloth.png"))

# every space MaterialX's default colour-management system names (issue 16), rec709_display (gamma24's
# target), and names it does not know (case matters to it: "sRGB" is not srgb_texture), left unconverted
SPACES = ["srgb_texture", "lin_rec709", "g22_rec709", "g18_rec709", "rec709_display", "acescg", "lin_ap1",
          "g22_ap1", "g18_ap1", "lin_srgb", "adobergb", "lin_adobergb", "srgb_displayp3", "lin_displayp3",
          "gamma18", "gamma22", "gamma24"]
UNKNOWN = ["sRGB", "ACEScg", "raw", "Utility - sRGB - Texture"]
CONVERTED = [s for s in SPACES if cmlib.canonical(s)]
VALUE = "0.8, 0.35, 0.1"        # saturated, so that every transform moves it visibly


def _doc(tmp_path, body, colorspace="lin_rec709", name="doc.mtlx"):
    path = write_doc(tmp_path, body, name=name)
    if colorspace is not None:
        text = open(path).read().replace('<materialx version="1.39">',
                                         '<materialx version="1.39" colorspace="%s">' % colorspace)
        open(path, "w").write(text)
    return path


def _material(shader, category="surface_unlit", inputs="", attrs=""):
    return ('<%s name="%s" type="surfaceshader"%s>%s</%s>\n'
            '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" '
            'nodename="%s" /></surfacematerial>' % (category, shader, attrs, inputs, category, shader))


def _unlit_value(cs, type_name="color3", value=VALUE):
    return _material("s", inputs='<input name="emission_color" type="%s" value="%s" colorspace="%s" />'
                     % (type_name, value, cs))


# ---------------------------------------------------------------- values on shader inputs

@pytest.mark.parametrize("cs", SPACES + UNKNOWN)
def test_value_on_unlit_emission_matches_materialx(renderer, cms_reference, tmp_path, cs):
    assert_parity_with_materialx(renderer, cms_reference, _doc(tmp_path, _unlit_value(cs)), "m")


@pytest.mark.parametrize("cs", SPACES)
def test_value_on_standard_surface_base_color_matches_materialx(renderer, cms_reference, tmp_path, cs):
    body = _material("ss", "standard_surface", '<input name="base_color" type="color3" value="%s" colorspace="%s" />'
                     % (VALUE, cs))
    assert_parity_with_materialx(renderer, cms_reference, _doc(tmp_path, body), "m")


@pytest.mark.parametrize("cs", CONVERTED)
def test_public_uniform_keeps_the_authored_value_and_the_shader_converts_it(tmp_path, cs):
    """Complete interface, as MaterialX's: the uniform holds what the document says; the transform follows
    it in the shader (so an application setting the uniform sets the encoded value)."""
    shader = generate_one(_doc(tmp_path, _unlit_value(cs)), "m")
    u = {u["name"]: u for u in shader.manifest["uniforms"]}["s_emission_color"]
    assert u["value"] == [0.8, 0.35, 0.1]
    files, template = cmlib.transform(cs)
    call = template.format(c="s_emission_color")
    assert call in shader.fragment, shader.fragment


@pytest.mark.parametrize("cs", ["lin_rec709", "lin_srgb", "g18_ap1"] + UNKNOWN)
def test_spaces_without_a_transform_leave_the_value_alone(tmp_path, cs):
    shader = generate_one(_doc(tmp_path, _unlit_value(cs)), "m")
    assert "s_emission_color" in shader.fragment
    assert not any(f in shader.fragment for f in ("mg_srgb_to_linear(", "mg_gamma_to_linear(", "_to_rec709("))


@pytest.mark.parametrize("cs", CONVERTED)
def test_color4_value_converts_rgb_and_keeps_alpha(renderer, cms_reference, tmp_path, cs):
    body = ('<nodegraph name="g"><constant name="c" type="color4"><input name="value" type="color4" '
            'value="0.8, 0.35, 0.1, 0.4" colorspace="%s" /></constant>'
            '<extract name="a" type="float"><input name="in" type="color4" nodename="c" />'
            '<input name="index" type="integer" value="3" /></extract>'
            '<output name="rgba" type="color4" nodename="c" /><output name="alpha" type="float" nodename="a" />'
            '</nodegraph>' % cs)
    path = _doc(tmp_path, body)
    assert_parity_with_materialx(renderer, cms_reference, path, "g/rgba")
    assert_parity_with_materialx(renderer, cms_reference, path, "g/alpha")
    img = renderer.render(generate_one(path, "g/alpha"))
    covered = img[..., 3] > 0.5
    assert covered.any()
    np.testing.assert_allclose(img[covered][:, 0], 0.4, atol=1e-3)     # the alpha as authored


# ---------------------------------------------------------------- inherited colour spaces

@pytest.mark.parametrize("cs", ["srgb_texture", "acescg", "gamma22", "srgb_displayp3"])
def test_nodegraph_colorspace_reaches_its_constants(renderer, cms_reference, tmp_path, cs):
    body = ('<nodegraph name="g" colorspace="%s"><constant name="c" type="color3"><input name="value" type="color3" '
            'value="%s" /></constant><output name="out" type="color3" nodename="c" /></nodegraph>' % (cs, VALUE)
            + _material("s", inputs='<input name="emission_color" type="color3" nodegraph="g" />'))
    path = _doc(tmp_path, body)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    assert_parity_with_materialx(renderer, cms_reference, path, "g/out")


@pytest.mark.parametrize("cs", ["adobergb", "g22_ap1", "lin_displayp3"])
def test_node_colorspace_reaches_its_inputs(renderer, cms_reference, tmp_path, cs):
    body = ('<nodegraph name="g"><constant name="c" type="color3" colorspace="%s"><input name="value" type="color3" '
            'value="%s" /></constant><output name="out" type="color3" nodename="c" /></nodegraph>' % (cs, VALUE)
            + _material("ss", "standard_surface", '<input name="base_color" type="color3" nodegraph="g" />'
                        '<input name="specular_color" type="color3" value="0.2, 0.6, 0.9" />', ' colorspace="%s"' % cs))
    path = _doc(tmp_path, body)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    assert_parity_with_materialx(renderer, cms_reference, path, "g/out")


@pytest.mark.parametrize("doc_cs", ["acescg", "srgb_texture", "lin_srgb", None])
def test_working_space_other_than_lin_rec709_converts_nothing(renderer, cms_reference, tmp_path, doc_cs):
    """MaterialX converts to the document's colour space, and cmlib has transforms to lin_rec709 only: in any
    other working space (or none) values and files are drawn as authored, whatever their colour space."""
    body = ('<nodegraph name="g"><image name="i" type="color3"><input name="file" type="filename" value="%s" '
            'colorspace="srgb_texture" /></image><constant name="c" type="color3"><input name="value" type="color3" '
            'value="%s" colorspace="g22_rec709" /></constant><multiply name="mul" type="color3">'
            '<input name="in1" type="color3" nodename="i" /><input name="in2" type="color3" nodename="c" />'
            '</multiply><output name="out" type="color3" nodename="mul" /></nodegraph>' % (CLOTH, VALUE)
            + _material("s", inputs='<input name="emission_color" type="color3" nodegraph="g" />'
                        '<input name="transmission_color" type="color3" value="%s" colorspace="acescg" />' % VALUE))
    path = _doc(tmp_path, body, colorspace=doc_cs)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    fragment = generate_one(path, "m").fragment
    assert "mg_srgb_to_linear(" not in fragment and "mg_gamma_to_linear(" not in fragment


def test_document_colorspace_is_the_working_space_not_a_source(renderer, cms_reference, tmp_path):
    """Values inheriting the document's own colour space are in the working space already."""
    body = _material("s", inputs='<input name="emission_color" type="color3" value="%s" />' % VALUE)
    path = _doc(tmp_path, body, colorspace="lin_rec709")
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    assert "_to_rec709(" not in generate_one(path, "m").fragment


# ---------------------------------------------------------------- interfaces and implementations

_INTERFACE = '''
<nodegraph name="g"%s>
  <input name="tint" type="color3" value="%s"%s />
  <constant name="c" type="color3"><input name="value" type="color3" interfacename="tint" /></constant>
  <output name="out" type="color3" nodename="c" />
</nodegraph>
''' + _material("s", inputs='<input name="emission_color" type="color3" nodegraph="g" />')


@pytest.mark.parametrize("graph_cs, input_cs", [("srgb_texture", None), (None, "acescg"), ("gamma24", "adobergb")])
def test_interface_values_follow_the_reading_node_as_materialx(renderer, cms_reference, tmp_path, graph_cs, input_cs):
    """A node input bound by interfacename to a nodegraph input takes the input's value in the node input's
    own active colour space (the nodegraph's), not the nodegraph input's; and only where the nodegraph is
    read through a connection: drawn by its own output, its inputs are the shader's, unconverted."""
    body = _INTERFACE % (' colorspace="%s"' % graph_cs if graph_cs else "", VALUE,
                         ' colorspace="%s"' % input_cs if input_cs else "")
    path = _doc(tmp_path, body)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    assert_parity_with_materialx(renderer, cms_reference, path, "g/out")
    through_material = "_to_linear(g_tint" in generate_one(path, "m").fragment
    assert through_material == bool(graph_cs)
    assert "_to_linear(g_tint" not in generate_one(path, "g/out").fragment


def test_document_input_read_by_interfacename_is_not_converted(renderer, cms_reference, tmp_path):
    body = ('<input name="tint" type="color3" value="%s" colorspace="acescg" />' % VALUE
            + _material("s", inputs='<input name="emission_color" type="color3" interfacename="tint" />'))
    path = _doc(tmp_path, body)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")


_IMPLEMENTATION = '''
<nodedef name="ND_tinted" node="tinted"><input name="tint" type="color3" value="1, 1, 1" />
  <output name="out" type="color3" /></nodedef>
<nodegraph name="NG_tinted" nodedef="ND_tinted">
  <constant name="k" type="color3"><input name="value" type="color3" value="0.9, 0.5, 0.2" colorspace="%s" /></constant>
  <multiply name="mul" type="color3"><input name="in1" type="color3" interfacename="tint" />
    <input name="in2" type="color3" nodename="k" /></multiply>
  <output name="out" type="color3" nodename="mul" />
</nodegraph>
<nodegraph name="g">
  <tinted name="t" type="color3"><input name="tint" type="color3" value="%s" colorspace="%s" /></tinted>
  <output name="out" type="color3" nodename="t" />
</nodegraph>
''' + _material("s", inputs='<input name="emission_color" type="color3" nodegraph="g" />')


@pytest.mark.parametrize("inner, outer", [("srgb_texture", "acescg"), ("adobergb", "gamma18"),
                                          ("srgb_displayp3", "lin_rec709")])
def test_values_inside_a_nodedef_implementation_and_on_its_instance(renderer, cms_reference, tmp_path, inner, outer):
    """The implementation's constant is folded at generation time (convert_value), the instance's value is a
    public uniform converted in the shader: both as MaterialX draws them."""
    path = _doc(tmp_path, _IMPLEMENTATION % (inner, VALUE, outer))
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    assert_parity_with_materialx(renderer, cms_reference, path, "g/out")
    fragment = generate_one(path, "m").fragment
    expected = cmlib.convert_value(inner, (0.9, 0.5, 0.2))
    literals = [tuple(float(x) for x in m.split(",")) for m in re.findall(r"vec3\(([-0-9.e, ]+)\)", fragment)
                if m.count(",") == 2]
    assert any(np.allclose(lit, expected, atol=1e-5) for lit in literals), "folded constant not in the shader"


# ---------------------------------------------------------------- files in every space

@pytest.mark.parametrize("cs", SPACES + ["sRGB"])
def test_file_in_every_space_matches_materialx(renderer, cms_reference, tmp_path, cs):
    body = ('<image name="img" type="color4"><input name="file" type="filename" value="%s" colorspace="%s" />'
            '</image><output name="out" type="color4" nodename="img" />' % (CLOTH, cs))
    assert_parity_with_materialx(renderer, cms_reference, _doc(tmp_path, body), "out")


@pytest.mark.parametrize("cs", ["gamma18", "gamma22", "gamma24"])
def test_file_colorspace_inherited_from_the_image_node(renderer, cms_reference, tmp_path, cs):
    body = ('<nodegraph name="g"><image name="img" type="color3" colorspace="%s"><input name="file" type="filename" '
            'value="%s" /></image><output name="out" type="color3" nodename="img" /></nodegraph>' % (cs, CLOTH))
    path = _doc(tmp_path, body)
    assert_parity_with_materialx(renderer, cms_reference, path, "g/out")
    assert "mg_gamma_to_linear(" in generate_one(path, "g/out").fragment


# ---------------------------------------------------------------- the constants themselves

def _glsl_matrix(name):
    text = open(os.path.join(ROOT, "glsl_lib", "cmlib", name)).read()
    body = text[text.index("mat3("):text.index(");", text.index("mat3("))]
    numbers = [float(x) for x in re.findall(r"-?\d+\.\d+", re.sub(r"//[^\n]*", "", body))]
    return np.array(numbers).reshape(3, 3).T        # GLSL lists columns


@pytest.mark.parametrize("glsl, primaries", [("ap1_to_rec709.glsl", "ap1"), ("adobergb_to_rec709.glsl", "adobergb"),
                                             ("displayp3_to_rec709.glsl", "displayp3")])
def test_glsl_matrices_are_the_ones_derived_from_the_chromaticities(glsl, primaries):
    """The shader's matrices and the generation-time ones (convert_value) are the same facts."""
    np.testing.assert_allclose(_glsl_matrix(glsl), cmlib.to_rec709_matrix(primaries), atol=2e-9)


@pytest.mark.parametrize("graph, primaries, tolerance", [("NG_acescg_to_lin_rec709_color3", "ap1", 1e-9),
                                                         ("NG_lin_adobergb_to_lin_rec709_color3", "adobergb", 1e-8),
                                                         ("NG_lin_displayp3_to_lin_rec709_color3", "displayp3", 2e-5)])
def test_matrices_agree_with_materialx_cmlib_data(library, graph, primaries, tolerance):
    """MaterialX's cmlib nodegraphs (data, read by our own parser) hold the same matrices (its Display P3 one
    is rounded to 8 places from slightly different primaries: within 2e-5)."""
    g = library.nodegraphs[graph]
    m = next(n.inputs["value"].value for n in g.nodes.values() if n.type == "matrix33")
    theirs = np.array(m, dtype=np.float64).reshape(3, 3)   # rows of MaterialX's row-vector convention
    np.testing.assert_allclose(theirs.T, cmlib.to_rec709_matrix(primaries), atol=tolerance)


def test_convert_value_matches_the_transfer_curves():
    srgb = cmlib.convert_value("srgb_texture", (0.02, 0.5, 1.0, 0.25))
    assert srgb[3] == 0.25
    np.testing.assert_allclose(srgb[:3], (0.02 / 12.92, ((0.5 + 0.055) / 1.055) ** 2.4, 1.0), rtol=1e-12)
    np.testing.assert_allclose(cmlib.convert_value("gamma22", (0.5, -0.1, 2.0)), (0.5 ** 2.2, 0.0, 2.0 ** 2.2))
    assert cmlib.convert_value("lin_srgb", (0.5, 0.3, 0.2)) == (0.5, 0.3, 0.2)
    assert cmlib.convert_value("sRGB", (0.5, 0.3, 0.2)) == (0.5, 0.3, 0.2)
