"""Classes of failure found by sweeping documents the project had not seen (issue 16; tools/unseen_sweep.py over
MaterialX's own TestSuite and Examples files outside ../shared/corpus, PhysicallyBased's materials, usd-wg's
shader-ball materials and others). Each class is isolated in a small document of our own, drawn by us and by
MaterialX with its colour management on (as the scoreboard runs it), in the same harness.
"""
import numpy as np
import pytest

from mtlxgen.draw import compare
from util import assert_parity_with_materialx, bsdf_material, generate_one, render_with_materialx, write_doc

UNLIT = ('<surface_unlit name="s" type="surfaceshader"><input name="emission_color" type="color3" nodename="c" />'
         '</surface_unlit><surfacematerial name="m" type="material"><input name="surfaceshader" '
         'type="surfaceshader" nodename="s" /></surfacematerial>')


# ---------------------------------------------------------------- an undefined value into smoothstep
# MaterialX's Examples/SurfaceUnlit/surface_unlit_toon.mtlx raises N.L (negative on the unlit side) to a power:
# pow of a negative base is undefined (NaN), and the smoothstep after it drew that side as NaN (black) in ours,
# 0 in MaterialX's. smoothstep's value is in [0, 1] whatever arrives.

NAN_INTO_SMOOTHSTEP = (
    '<position name="p" type="vector3" />'
    '<extract name="x" type="float"><input name="in" type="vector3" nodename="p" />'
    '<input name="index" type="integer" value="0" /></extract>'
    '<power name="pw" type="float"><input name="in1" type="float" nodename="x" />'
    '<input name="in2" type="float" value="0.5" /></power>'
    '<smoothstep name="st" type="float"><input name="in" type="float" nodename="pw" />'
    '<input name="low" type="float" value="0.2" /><input name="high" type="float" value="0.6" /></smoothstep>'
    '<add name="lift" type="float"><input name="in1" type="float" nodename="st" />'
    '<input name="in2" type="float" value="0.25" /></add>'
    '<convert name="c" type="color3"><input name="in" type="float" nodename="lift" /></convert>' + UNLIT)


def test_smoothstep_of_an_undefined_value_is_zero_like_materialx(renderer, cms_reference, tmp_path):
    path = write_doc(tmp_path, NAN_INTO_SMOOTHSTEP)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    img = renderer.render(generate_one(path, "m"))
    covered = img[..., 3] > 0.5
    assert np.isfinite(img[covered]).all()
    # the half of the sphere where x < 0 (pow undefined) draws smoothstep = 0, plus the 0.25 added after it
    half = img[:, : img.shape[1] // 2 - 4][covered[:, : img.shape[1] // 2 - 4]]
    np.testing.assert_allclose(half[:, 0], 0.25, atol=1e-3)


# ---------------------------------------------------------------- colour spaces by their interop names
# MaterialX's TestSuite/stdlib/color_management/all_colorspace_names.mtlx and colorspace_input_conversion.mtlx
# name spaces as the ASWF Color Interop Forum does (srgb_rec709_scene, lin_ap1_scene, ...) in a document whose
# working space is lin_rec709_scene: MaterialX 1.39.5 reads ten of them as its own spaces and lin_rec709_scene as
# the working space; we drew them all unconverted (all_colorspace_names: mean 21.8/255, 36% of pixels off).

INTEROP_CONVERTED = ["srgb_rec709_scene", "g22_rec709_scene", "g18_rec709_scene", "lin_ap1_scene", "g22_ap1_scene",
                     "lin_adobergb_scene", "g22_adobergb_scene", "srgb_p3d65_scene", "lin_p3d65_scene"]
# named by the forum, not converted by MaterialX 1.39.5 (nor by us)
INTEROP_UNCONVERTED = ["lin_rec709_scene", "g24_rec709_scene", "srgb_ap1_scene", "lin_ap0_scene", "lin_rec2020_scene",
                       "lin_ciexyzd65_scene", "none", "data"]


def _cs_doc(tmp_path, working, body):
    path = write_doc(tmp_path, body)
    text = open(path).read().replace('<materialx version="1.39">', '<materialx version="1.39" colorspace="%s">' % working)
    open(path, "w").write(text)
    return path


@pytest.mark.parametrize("working", ["lin_rec709", "lin_rec709_scene"])
@pytest.mark.parametrize("cs", INTEROP_CONVERTED + INTEROP_UNCONVERTED)
def test_interop_colorspace_names_match_materialx(renderer, cms_reference, tmp_path, working, cs):
    body = ('<constant name="c" type="color3"><input name="value" type="color3" value="0.8, 0.35, 0.1" '
            'colorspace="%s" /></constant>' % cs) + UNLIT
    assert_parity_with_materialx(renderer, cms_reference, _cs_doc(tmp_path, working, body), "m")


@pytest.mark.parametrize("cs", INTEROP_CONVERTED)
def test_interop_names_convert_as_the_names_they_stand_for(renderer, tmp_path, cs):
    """Pixel for pixel what the older name draws (so the conversion is not merely MaterialX's: it is the space)."""
    from mtlxgen.nodes import cmlib
    body = ('<constant name="c" type="color3"><input name="value" type="color3" value="0.8, 0.35, 0.1" '
            'colorspace="%s" /></constant>' + UNLIT)
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    new = renderer.render(generate_one(_cs_doc(tmp_path / "a", "lin_rec709_scene", body % cs), "m"))
    old = renderer.render(generate_one(_cs_doc(tmp_path / "b", "lin_rec709", body % cmlib.canonical(cs)), "m"))
    plain = renderer.render(generate_one(_cs_doc(tmp_path / "b", "lin_rec709", body % "lin_rec709"), "m"))
    np.testing.assert_allclose(new, old, atol=1e-6)
    assert np.abs(new - plain)[..., :3].max() > 0.02       # it did convert


def test_image_file_in_an_interop_space_matches_materialx(renderer, cms_reference, tmp_path):
    from conftest import DATA_IMAGES
    import os
    grid = os.path.abspath(os.path.join(DATA_IMAGES, "grid.png"))
    body = ('<image name="c" type="color3"><input name="file" type="filename" value="%s" '
            'colorspace="g22_ap1_scene" /></image>' % grid) + UNLIT
    assert_parity_with_materialx(renderer, cms_reference, _cs_doc(tmp_path, "lin_rec709_scene", body), "m")


# ---------------------------------------------------------------- an input naming a top-level output alone
# MaterialX's TestSuite/stdlib/convolution/heighttonormal_in_nodegraph.mtlx (1.37) binds standard_surface's
# base_color and normal with `bindinput output="..."`: after the upgrade, an input with an `output` attribute and
# no node or nodegraph, which MaterialX connects to the document's top-level <output> of that name. We read it as
# unconnected (a grey, smooth sphere where MaterialX's is blue and bumped: mean 39.5/255, 57% of pixels off).

TOP_OUTPUT = (
    '<nodedef name="ND_pair" node="pair"><output name="tint" type="color3" /><output name="level" type="float" />'
    '</nodedef>'
    '<nodegraph name="NG_pair" nodedef="ND_pair"><position name="p" type="vector3" />'
    '<convert name="c" type="color3"><input name="in" type="vector3" nodename="p" /></convert>'
    '<absval name="a" type="color3"><input name="in" type="color3" nodename="c" /></absval>'
    '<constant name="k" type="float"><input name="value" type="float" value="0.35" /></constant>'
    '<output name="tint" type="color3" nodename="a" /><output name="level" type="float" nodename="k" /></nodegraph>'
    '<pair name="inst" type="multioutput" />'
    '<output name="inst_tint" type="color3" nodename="inst" output="tint" />'
    '<output name="inst_level" type="float" nodename="inst" output="level" />'
    '<standard_surface name="s" type="surfaceshader"><input name="base_color" type="color3" output="%s" />'
    '<input name="specular_roughness" type="float" output="inst_level" /></standard_surface>'
    '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="s" />'
    '</surfacematerial>')

BINDINPUT_137 = """<?xml version="1.0"?>
<materialx version="1.37">
  <nodedef name="ND_pair" node="pair"><output name="tint" type="color3" /><output name="level" type="float" /></nodedef>
  <nodegraph name="NG_pair" nodedef="ND_pair">
    <constant name="c" type="color3"><parameter name="value" type="color3" value="0.1, 0.3, 0.9" /></constant>
    <constant name="k" type="float"><parameter name="value" type="float" value="0.6" /></constant>
    <output name="tint" type="color3" nodename="c" /><output name="level" type="float" nodename="k" />
  </nodegraph>
  <pair name="inst" type="multioutput" />
  <output name="inst_tint" type="color3" nodename="inst" output="tint" />
  <output name="inst_level" type="float" nodename="inst" output="level" />
  <material name="m">
    <shaderref name="s" node="standard_surface">
      <bindinput name="base_color" type="color3" output="inst_tint" />
      <bindinput name="specular_roughness" type="float" output="inst_level" />
    </shaderref>
  </material>
</materialx>
"""


def test_input_naming_a_document_output_connects_to_it_like_materialx(renderer, cms_reference, tmp_path):
    path = write_doc(tmp_path, TOP_OUTPUT % "inst_tint")
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    shader = generate_one(path, "m")
    assert "s_base_color" not in {u["name"] for u in shader.manifest["uniforms"]}     # connected, not a value


def test_bindinput_output_of_137_connects_like_materialx(renderer, cms_reference, tmp_path):
    path = str(tmp_path / "bind.mtlx")
    open(path, "w").write(BINDINPUT_137)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    img = renderer.render(generate_one(path, "m"))
    centre = img[img.shape[0] // 2, img.shape[1] // 2, :3]
    assert centre[2] > 2 * centre[0]        # the bound blue, not standard_surface's grey default


def test_input_naming_a_missing_document_output_reads_its_value_like_materialx(renderer, cms_reference, tmp_path):
    from mtlxgen.base import diagnostics
    path = write_doc(tmp_path, TOP_OUTPUT % "no_such_output")
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    with pytest.raises(diagnostics.MtlxError, match="no_such_output"):
        from mtlxgen import pipeline
        pipeline.generate(path, elements=["m"], strict=True)


def test_document_outputs_naming_each_other_are_a_cycle(tmp_path):
    from mtlxgen.base import diagnostics
    from mtlxgen import pipeline
    body = ('<output name="o1" type="color3" output="o2" /><output name="o2" type="color3" output="o1" />'
            '<surface_unlit name="s" type="surfaceshader"><input name="emission_color" type="color3" output="o1" />'
            '</surface_unlit><surfacematerial name="m" type="material"><input name="surfaceshader" '
            'type="surfaceshader" nodename="s" /></surfacematerial>')
    with pytest.raises(diagnostics.MtlxError, match="cycle"):
        pipeline.generate(write_doc(tmp_path, body), elements=["m"])


# ---------------------------------------------------------------- value="" on a number, colour or vector
# materialxgltf's standard_surface_marble_solid.mtlx_baked.mtlx (a file written by a converter) carries
# <input name="alpha_mode" type="integer" value="" />: MaterialX reads no value there, its nodedef's default;
# we refused the document.

@pytest.mark.parametrize("name, type_name", [("alpha_mode", "integer"), ("alpha_cutoff", "float"),
                                             ("roughness", "float"), ("base_color", "color3"),
                                             ("emissive", "color3")])
def test_empty_value_reads_the_default_like_materialx(renderer, cms_reference, tmp_path, name, type_name):
    from mtlxgen.base import diagnostics
    from mtlxgen import pipeline
    body = ('<gltf_pbr name="s" type="surfaceshader"><input name="%s" type="%s" value="" />'
            '<input name="alpha" type="float" value="0.6" /><input name="metallic" type="float" value="0.3" />'
            '</gltf_pbr><surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" '
            'nodename="s" /></surfacematerial>' % (name, type_name))
    path = write_doc(tmp_path, body)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    warnings = diagnostics.Warnings()
    pipeline.generate(path, elements=["m"], warnings=warnings)
    assert any("value is empty" in line and ":3: warning:" in line for line in warnings.lines()), warnings.lines()
    with pytest.raises(diagnostics.MtlxError, match="empty"):
        pipeline.generate(path, elements=["m"], strict=True)


def test_empty_string_values_stay_empty_strings(tmp_path):
    """Only numbers, booleans, colours, vectors and matrices read "" as no value; a string is the empty string."""
    from mtlxgen.base import mxtypes
    assert mxtypes.parse_value("string", "") == ""
    assert mxtypes.parse_value("filename", "") == ""
    assert mxtypes.parse_value("floatarray", "") == ()
    with pytest.raises(mxtypes.ValueError_):
        mxtypes.parse_value("float", " ")             # refused where no slip is allowed (strict readers)
    slips = []
    assert mxtypes.parse_value("color3", "", slips=slips) is None and slips


@pytest.mark.parametrize("type_name", ["float", "integer", "boolean", "color3", "vector4", "matrix33"])
def test_empty_value_is_no_value_in_materialx_and_in_ours(reference, type_name):
    """MaterialX reads no value from "" (as from "abc"); unlike "abc", which stays refused, "" is read as what it
    says, no value: the nodedef's default, with a warning (an error under --strict)."""
    from test_warnings import materialx_value
    from mtlxgen.base import mxtypes
    assert materialx_value(reference, type_name, "") is None
    slips = []
    assert mxtypes.parse_value(type_name, "", slips=slips) is None and len(slips) == 1
    with pytest.raises(mxtypes.ValueError_, match="empty"):
        mxtypes.parse_value(type_name, "")
    with pytest.raises(mxtypes.ValueError_):
        mxtypes.parse_value(type_name, "abc", slips=[])


# ---------------------------------------------------------------- <parameter> in a 1.38 or newer document
# MaterialX's TestSuite/pbrlib/bsdf/layer_vdf.mtlx (version 1.38) sets each dielectric_bsdf's scatter_mode with a
# <parameter>. MaterialX turns <parameter> into <input> only when it upgrades a document older than 1.38; in a 1.38
# document the element stays an unknown child that sets nothing, so both dielectrics keep scatter_mode "R". We read
# the parameter as an input (a blue-tinted glass where MaterialX draws a dark glossy sphere: mean 46/255, 57% of
# pixels off). Now: ignored, with a warning, in 1.38 and 1.39 documents; read as an input in older ones.

PARAMETER_BODY = ('<dielectric_bsdf name="b" type="BSDF"><input name="ior" type="float" value="1.5" />'
                  '<parameter name="scatter_mode" type="string" value="T" />'
                  '<parameter name="tint" type="color3" value="0.2, 0.5, 1.0" /></dielectric_bsdf>'
                  '<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="b" /></surface>'
                  '<surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" '
                  'nodename="s" /></surfacematerial>')


@pytest.mark.parametrize("version", ["1.37", "1.38", "1.39"])
def test_parameter_element_is_read_as_materialx_reads_it(renderer, cms_reference, tmp_path, version):
    from mtlxgen.base import diagnostics
    from mtlxgen import pipeline
    path = write_doc(tmp_path, PARAMETER_BODY, version=version)
    assert_parity_with_materialx(renderer, cms_reference, path, "m")
    warnings = diagnostics.Warnings()
    shader = pipeline.generate(path, elements=["m"], warnings=warnings)[0]
    flagged = [line for line in warnings.lines() if "<parameter>" in line]
    if version == "1.37":                       # upgraded: the parameters are the BSDF's inputs
        assert not flagged
        assert "b_tint" in {u["name"] for u in shader.manifest["uniforms"]}
    else:
        assert len(flagged) == 2 and all(":3: warning:" in line for line in flagged), flagged
        with pytest.raises(diagnostics.MtlxError, match="parameter"):
            pipeline.generate(path, elements=["m"], strict=True)


# ---------------------------------------------------------------- a negative colour on a Schlick curve
# The glTF-MaterialX-Converter's tests/data/bindings/gltf_stream_graph.mtlx feeds gltf_pbr's base_color from the
# world position, negative on half the sphere; gltf_pbr is a metal by default, so base_color is the color0 of a
# generalized_schlick_bsdf. MaterialX's GLSL holds color0, color82 and color90 at 0 or above (a reflectance below 0
# means nothing); ours subtracted light where color0 < 0 and darkened the grazing rise to color90 (mean 1.8/255,
# 4.2% of pixels off; a Schlick lobe of color0 (-0.3, 0.2, 0.5): mean 8/255, 23% off, up to 211/255 at the rim).

@pytest.mark.parametrize("color0, color90, roughness", [("-0.3, 0.2, 0.5", "1, 1, 1", "0.04, 0.04"),
                                                        ("-0.3, 0.2, 0.5", "1, 1, 1", "0.5, 0.5"),
                                                        ("0.3, 0.2, 0.5", "-0.5, 1, 1", "0.25, 0.25")])
def test_negative_schlick_colours_reflect_nothing_like_materialx(renderer, cms_reference, tmp_path, color0,
                                                                 color90, roughness):
    from util import bsdf_material
    body = bsdf_material('<generalized_schlick_bsdf name="b" type="BSDF">'
                         '<input name="color0" type="color3" value="%s" /><input name="color90" type="color3" '
                         'value="%s" /><input name="roughness" type="vector2" value="%s" />'
                         '</generalized_schlick_bsdf>' % (color0, color90, roughness))
    assert_parity_with_materialx(renderer, cms_reference, write_doc(tmp_path, body), "m")


@pytest.mark.parametrize("scatter_mode", ["R", "RT"])
def test_negative_dielectric_tint_reflects_nothing_like_materialx(renderer, cms_reference, tmp_path, scatter_mode):
    """The same for dielectric_bsdf's tint (found by setting each input of standard_surface out of its range:
    specular_color (-0.5, 0.3, 1.5) drew negative red light in the highlight, -0.29 where MaterialX draws the
    diffuse base alone, 0.17; mean 2.8/255, 7% of pixels off)."""
    from util import bsdf_material
    alpha = 0.2 if scatter_mode == "R" else 0.05    # rougher transmission: a difference of its own (rough_transmission)
    body = bsdf_material('<dielectric_bsdf name="b" type="BSDF"><input name="tint" type="color3" '
                         'value="-0.5, 0.3, 1.5" /><input name="roughness" type="vector2" value="%g, %g" />'
                         '<input name="scatter_mode" type="string" value="%s" /></dielectric_bsdf>'
                         % (alpha, alpha, scatter_mode))
    assert_parity_with_materialx(renderer, cms_reference, write_doc(tmp_path, body), "m")
    img = renderer.render(generate_one(write_doc(tmp_path, body), "m"))
    assert img[..., :3].min() >= 0.0                      # no negative light


def test_standard_surface_negative_specular_colour_matches_materialx(renderer, cms_reference, tmp_path):
    body = ('<standard_surface name="s" type="surfaceshader"><input name="specular_color" type="color3" '
            'value="-0.5, 0.3, 1.5" /></standard_surface><surfacematerial name="m" type="material">'
            '<input name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>')
    assert_parity_with_materialx(renderer, cms_reference, write_doc(tmp_path, body), "m")


def test_gltf_base_colour_from_position_matches_materialx(renderer, cms_reference, tmp_path):
    body = ('<position name="p" type="vector3"><input name="space" type="string" value="world" /></position>'
            '<convert name="c" type="color3"><input name="in" type="vector3" nodename="p" /></convert>'
            '<gltf_pbr name="s" type="surfaceshader"><input name="base_color" type="color3" nodename="c" />'
            '</gltf_pbr><surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" '
            'nodename="s" /></surfacematerial>')
    assert_parity_with_materialx(renderer, cms_reference, write_doc(tmp_path, body), "m")


# ---------------------------------------------------------------- an opaque lobe of zero weight over another
# Found by tools/range_sweep.py: a diffuse lobe (nothing passes through it at any weight) of weight 0 as a layer's
# top. MaterialX keeps it opaque, black over its base (as at a weight of 1e-6); ours made it the empty closure and
# the base showed (mean 62/255 off). Now such a lobe of zero weight is BSDF(0, 0) where it reflects, in both
# interfaces; a lobe that lets light through (a dielectric) still becomes the empty closure. The same sweep: a
# translucent or conductor lobe over a base let 1 - weight of it through in ours, nothing in MaterialX's (both are
# opaque: the weight scales what they send on); now nothing in ours either.

OPAQUE_TOP = ('<%s name="top" type="BSDF"><input name="weight" type="float" value="%s" />%s</%s>'
              '<oren_nayar_diffuse_bsdf name="base" type="BSDF"><input name="color" type="color3" value="0.9, 0.6, 0.4" />'
              '</oren_nayar_diffuse_bsdf>'
              '<layer name="b" type="BSDF"><input name="top" type="BSDF" nodename="top" />'
              '<input name="base" type="BSDF" nodename="base" /></layer>')


@pytest.mark.parametrize("top", ["oren_nayar_diffuse_bsdf", "burley_diffuse_bsdf", "subsurface_bsdf", "translucent_bsdf",
                                 "conductor_bsdf"])
@pytest.mark.parametrize("weight", ["0", "0.0000001", "0.3"])
@pytest.mark.parametrize("interface", ["complete", "reduced"])
def test_an_opaque_lobe_of_zero_weight_hides_its_base_like_materialx(renderer, cms_reference, tmp_path, monkeypatch,
                                                                      top, weight, interface):
    from mtlxgen import pipeline
    extra = ('<input name="roughness" type="vector2" value="0.3, 0.3" />' if top == "conductor_bsdf" else
             '<input name="color" type="color3" value="0.2, 0.9, 0.3" />')
    path = write_doc(tmp_path, bsdf_material(OPAQUE_TOP % (top, weight, extra, top)))
    monkeypatch.setattr("util.generate_one", lambda p, e=None: pipeline.generate(p, elements=[e], interface=interface)[0])
    ours, theirs = render_with_materialx(renderer, cms_reference, path, "m")
    p = compare.parity(ours, theirs)
    assert p.passes, p
    if float(weight) < 1e-6:        # black: nothing of the base
        covered = ours[..., 3] > 0.5
        assert np.abs(ours[covered][:, :3]).max() < 1e-6
