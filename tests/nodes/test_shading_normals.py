"""Shading normals and the environment's irradiance, at parity with MaterialX in the scoreboard's harness:
a BSDF shades with its normal turned towards the viewer (a normal-mapped or authored normal facing away
would light the surface from behind), and the irradiance map is read at level 0 (its mips, chosen from
screen derivatives of the normal, blurred normal-mapped edges and the lat-long seam)."""
import os

import pytest

from conftest import DATA_IMAGES, DATA_TESTSUITE
from mtlxgen import pipeline
from util import assert_harness_parity as assert_parity, write_doc

SURFACESHADER = os.path.join(DATA_TESTSUITE, "pbrlib", "surfaceshader")


def _corpus_copy(tmp_path, name):
    # the corpus's image paths are relative to the resources' parent: make them absolute
    with open(os.path.join(SURFACESHADER, name)) as f:
        text = f.read().replace("resources/Images", os.path.abspath(DATA_IMAGES))
    path = os.path.join(str(tmp_path), name)
    with open(path, "w") as f:
        f.write(text)
    return path


# (mapped_surfaceshader.mtlx's NormalMapMaterial, whose wire-mesh tile edges turn away from the viewer near
# the silhouette, is at parity in tests/nodes/test_pbrlib_suite_parity.py)


@pytest.mark.parametrize("specular", ["0", "1"])
def test_normal_facing_away_is_turned_towards_the_viewer(harness, reference, tmp_path, specular):
    # an authored world normal tilted by (1.5, 0.3, 0): it faces away from the camera on the right rim
    body = """<standard_surface name="S" type="surfaceshader">
    <input name="base_color" type="color3" value="0.2, 0.5, 0.9" />
    <input name="specular" type="float" value="%s" />
    <input name="normal" type="vector3" nodegraph="G" />
  </standard_surface>
  <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="S" /></surfacematerial>
  <nodegraph name="G">
    <normal name="n" type="vector3" />
    <add name="a" type="vector3"><input name="in1" type="vector3" nodename="n" />
      <input name="in2" type="vector3" value="1.5, 0.3, 0" /></add>
    <normalize name="nz" type="vector3"><input name="in" type="vector3" nodename="a" /></normalize>
    <output name="out" type="vector3" nodename="nz" />
  </nodegraph>""" % specular
    assert_parity(harness, reference, write_doc(tmp_path, body, name="away%s.mtlx" % specular), "M")


def test_environment_irradiance_is_read_at_level_zero(tmp_path):
    body = """<oren_nayar_diffuse_bsdf name="b" type="BSDF" />
  <surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="b" /></surface>
  <output name="out" type="surfaceshader" nodename="s" />"""
    frag = pipeline.generate(write_doc(tmp_path, body))[0].fragment
    assert "textureLod(u_envIrradiance" in frag and "texture(u_envIrradiance" not in frag


def test_unit_mapped_shader_differs_only_by_materialx_merging_same_named_nodes(harness, reference, tmp_path):
    # UnitMappedShaderMaterial connects two nodegraphs whose ramp4 nodes share the name "ramp4";
    # MaterialX's generator then reads YellowRamp's values for BlueRamp's output too. With the names made
    # unique, both renders agree (docs/differences/README.md).
    path = _corpus_copy(tmp_path, "mapped_surfaceshader.mtlx")
    with open(path) as f:
        text = f.read()
    i = text.index('<nodegraph name="BlueRamp">')
    j = text.index("</nodegraph>", i)
    with open(path, "w") as f:
        f.write(text[:i] + text[i:j].replace('"ramp4"', '"ramp4_blue"') + text[j:])
    assert_parity(harness, reference, path, "UnitMappedShaderMaterial")


@pytest.mark.parametrize("length", ["2", "0.25"])
def test_bsdf_normal_of_any_length_shades_as_its_direction(renderer, tmp_path, length):
    """A connected normal need not be unit length (metal_definition.mtlx's nodedef defaults one to (1, 1, 1)):
    BSDFs shade with its direction. (MaterialX's environment integration uses the vector as given in part.)"""
    from mtlxgen.draw import compare
    from util import generate_one

    def render(scale):
        body = """<nodedef name="ND_tilted" node="tilted"><input name="N" type="vector3" value="0.3, 0.5, 0.8" />
      <output name="out" type="surfaceshader" /></nodedef>
    <nodegraph name="NG_tilted" nodedef="ND_tilted">
      <multiply name="k" type="vector3"><input name="in1" type="vector3" interfacename="N" />
        <input name="in2" type="float" value="%s" /></multiply>
      <normalize name="u" type="vector3"><input name="in" type="vector3" interfacename="N" /></normalize>
      <multiply name="s" type="vector3"><input name="in1" type="vector3" nodename="u" />
        <input name="in2" type="float" value="%s" /></multiply>
      <standard_surface name="ss" type="surfaceshader"><input name="metalness" type="float" value="0.6" />
        <input name="specular_roughness" type="float" value="0.3" /><input name="coat" type="float" value="0.5" />
        <input name="normal" type="vector3" nodename="s" /></standard_surface>
      <output name="out" type="surfaceshader" nodename="ss" /></nodegraph>
    <tilted name="t" type="surfaceshader" />
    <surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" nodename="t" /></surfacematerial>""" % (scale, scale)
        return renderer.render(generate_one(write_doc(tmp_path, body, name="len%s.mtlx" % scale), "M"))

    unit, scaled = render("1"), render(length)
    assert compare.parity(scaled, unit).passes


def test_metal_definition_with_a_unit_normal_matches_materialx(harness, reference, tmp_path):
    """metal_definition.mtlx differs only by its non-unit default normal (docs/differences): made unit, at parity."""
    src = os.path.join(DATA_TESTSUITE, "libraries", "metal", "libraries", "metal_definition.mtlx")
    text = open(src).read()
    unit = text.replace('name="SurfaceNormal" type="vector3" value="1, 1, 1"',
                        'name="SurfaceNormal" type="vector3" value="0.57735027, 0.57735027, 0.57735027"')
    assert unit != text
    path = os.path.join(str(tmp_path), "metal_unit.mtlx")
    open(path, "w").write(unit)
    assert_parity(harness, reference, path, "NG_TestMetal/out")
