"""Classes of failure found by sweeping documents the project had not seen (issue 16; tools/unseen_sweep.py over
MaterialX's own TestSuite and Examples files outside ../shared/corpus, PhysicallyBased's materials, usd-wg's
shader-ball materials and others). Each class is isolated in a small document of our own, drawn by us and by
MaterialX with its colour management on (as the scoreboard runs it), in the same harness.
"""
import numpy as np

from util import assert_parity_with_materialx, generate_one, write_doc

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
