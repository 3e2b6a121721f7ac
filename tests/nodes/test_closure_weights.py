"""Closure weights outside [0, 1]: a BSDF `mix` and a BSDF `multiply` keep their weight in the unit range, so a
material never returns negative light or more than its lobes reflect; documents with out-of-range values (the
unit-tagged Jade of TestSuite/stdlib/units) then render as MaterialX's do."""
import os

import pytest

from conftest import DATA_TESTSUITE
from mtlxgen.draw import compare
from util import (assert_harness_parity, assert_parity_with_materialx, bsdf_material, generate_one,
                  render_with_materialx, write_doc)

JADE = os.path.join(DATA_TESTSUITE, "stdlib", "units", "standard_surface_unit.mtlx")

DIFFUSE = ('<oren_nayar_diffuse_bsdf name="a" type="BSDF"><input name="color" type="color3" value="0.8, 0.8, 0.8" />'
           '</oren_nayar_diffuse_bsdf>')
GREEN = ('<oren_nayar_diffuse_bsdf name="c" type="BSDF"><input name="color" type="color3" value="0.2, 0.5, 0.2" />'
         '</oren_nayar_diffuse_bsdf>')


@pytest.mark.parametrize("in2", ['type="float" value="2"', 'type="float" value="-1"', 'type="color3" value="1.5, 0.5, -0.5"'])
def test_bsdf_multiply_weight_is_held_to_unit_range_like_materialx(renderer, reference, tmp_path, in2):
    body = DIFFUSE + '<multiply name="b" type="BSDF"><input name="in1" type="BSDF" nodename="a" /><input name="in2" %s />' \
                     '</multiply>' % in2
    assert_parity_with_materialx(renderer, reference, write_doc(tmp_path, bsdf_material(body)), "m")


@pytest.mark.parametrize("weight, alone", [("3", "c"), ("-2", "a"), ("1", "c"), ("0", "a")])
def test_bsdf_mix_weight_is_held_to_unit_range(renderer, tmp_path, weight, alone):
    mixed = DIFFUSE + GREEN + ('<mix name="b" type="BSDF"><input name="fg" type="BSDF" nodename="c" />'
                               '<input name="bg" type="BSDF" nodename="a" /><input name="mix" type="float" value="%s" />'
                               '</mix>' % weight)
    ours = renderer.render(generate_one(write_doc(tmp_path, bsdf_material(mixed), "mix.mtlx"), "m"))
    lone = renderer.render(generate_one(write_doc(tmp_path, bsdf_material(DIFFUSE + GREEN, alone), "lone.mtlx"), "m"))
    assert compare.parity(ours, lone).passes
    assert ours[..., :3].min() >= 0.0


@pytest.mark.parametrize("subsurface", ["2", "400"])
def test_standard_surface_subsurface_beyond_one_matches_materialx(renderer, reference, tmp_path, subsurface):
    body = ('<standard_surface name="s" type="surfaceshader"><input name="subsurface" type="float" value="%s" />'
            '</standard_surface><surfacematerial name="m" type="material"><input name="surfaceshader" '
            'type="surfaceshader" nodename="s" /></surfacematerial>' % subsurface)
    assert_parity_with_materialx(renderer, reference, write_doc(tmp_path, body), "m")


def test_unit_tagged_jade_matches_materialx(harness, reference):
    """Jade's values are unit-tagged and far out of range (base 75, roughness 250, subsurface 400, IOR 150; no
    target unit, so none is converted, on either side): the subsurface mix held at 1 makes it MaterialX's jade."""
    assert_harness_parity(harness, reference, JADE, "Jade")


def test_rough_white_mirror_keeps_its_energy_where_materialx_loses_some(reference, tmp_path):
    """White furnace, a generalized Schlick lobe with F = 1 at roughness 1: ours reflects all the light (within
    1%); MaterialX's energy compensation falls short by more than 2% (listed in docs/differences)."""
    from mtlxgen.draw.renderer import Renderer
    from test_furnace import white_environment
    body = bsdf_material('<generalized_schlick_bsdf name="b" type="BSDF"><input name="roughness" type="vector2" '
                     'value="1, 1" /><input name="color0" type="color3" value="1, 1, 1" />'
                     '<input name="color90" type="color3" value="1, 1, 1" /></generalized_schlick_bsdf>')
    path = write_doc(tmp_path, body)
    with Renderer(size=64, environment=white_environment()) as r:
        ours, theirs = render_with_materialx(r, reference, path, "m")
    covered = theirs[..., 3] > 0.5
    assert abs(ours[..., :3][covered].mean() - 1.0) < 0.01
    assert theirs[..., :3][covered].mean() < 0.98
