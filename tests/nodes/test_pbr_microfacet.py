"""Microfacet BSDFs (dielectric, conductor, generalized_schlick): parity with MaterialX in the scoreboard's
scene (conftest's `harness`: its sky bound to radiance and irradiance, 64 environment samples), and the
directional albedo table of tools/ggx_albedo.py against an independent Monte Carlo estimate."""
import os
import sys

import numpy as np
import pytest

from util import assert_harness_parity, write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))


def surface(bsdf):
    return ('<nodegraph name="g">%s<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" '
            'nodename="b"/></surface><output name="out" type="surfaceshader" nodename="s"/></nodegraph>' % bsdf)


def inputs(_ior="float", **kw):
    types = {"roughness": "vector2", "tint": "color3", "ior": _ior, "scatter_mode": "string", "weight": "float",
             "color0": "color3", "color82": "color3", "color90": "color3", "exponent": "float",
             "extinction": "color3", "thinfilm_thickness": "float", "thinfilm_ior": "float"}
    return "".join('<input name="%s" type="%s" value="%s"/>' % (k, types[k], v) for k, v in kw.items())


def dielectric(**kw):
    return '<dielectric_bsdf name="b" type="BSDF">%s</dielectric_bsdf>' % inputs(**kw)


def conductor(**kw):
    return '<conductor_bsdf name="b" type="BSDF">%s</conductor_bsdf>' % inputs(_ior="color3", **kw)


def schlick(**kw):
    return '<generalized_schlick_bsdf name="b" type="BSDF">%s</generalized_schlick_bsdf>' % inputs(**kw)


CASES = {
    "dielectric_R_smooth": dielectric(roughness="0.02, 0.02", tint="0.8, 0.9, 1"),
    "dielectric_R_rough_ior2": dielectric(roughness="0.4, 0.4", ior="2.0"),
    "dielectric_R_anisotropic": dielectric(roughness="0.1, 0.4", ior="1.8"),
    "dielectric_T": dielectric(scatter_mode="T", tint="0.7, 0.8, 0.9"),
    "dielectric_RT_mirror_ior133": dielectric(scatter_mode="RT", roughness="0.001, 0.001", ior="1.33"),
    "dielectric_R_half_weight": dielectric(weight="0.5", roughness="0.2, 0.2"),
    "conductor_gold": conductor(ior="0.143, 0.374, 1.442", extinction="3.983, 2.385, 1.603", roughness="0.15, 0.15"),
    "conductor_anisotropic": conductor(roughness="0.05, 0.3"),
    "schlick_f82": schlick(color0="0.9, 0.6, 0.3", color82="0.5, 0.8, 1.0", roughness="0.1, 0.1"),
    "schlick_RT": schlick(scatter_mode="RT", color0="0.1, 0.1, 0.1", roughness="0.03, 0.03"),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_microfacet_bsdf_matches_materialx(name, harness, reference, tmp_path):
    path = write_doc(tmp_path, surface(CASES[name]), name=name + ".mtlx")
    assert_harness_parity(harness, reference, path, "g/out")


def test_albedo_table_matches_monte_carlo():
    import ggx_albedo
    rng = np.random.default_rng(7)
    tab = ggx_albedo.table()
    mus, alphas = ggx_albedo.grid()
    for ai, mi in [(2, 31), (8, 4), (16, 16), (24, 10), (31, 1), (5, 27)]:
        est = np.mean([ggx_albedo.albedo(mus[mi], alphas[ai], strata=32, jitter=rng) for _ in range(4)], axis=0)
        assert np.allclose(tab[ai, mi], est, atol=0.01), (mus[mi], alphas[ai], tab[ai, mi], est)
    # white furnace bound: a lobe with F = 1 never reflects more than it receives
    assert (tab.sum(-1) <= 1.0 + 1e-3).all()


def test_albedo_fit_follows_table():
    import ggx_albedo
    tab = ggx_albedo.table()
    coef, names, err = ggx_albedo.fit(tab)
    assert err < 0.05
