"""A coloured rough conductor against a simulation of every order of scattering (docs/differences/README.md,
coloured rough conductors; tools/metal_furnace.py). The random walk on GGX's microsurface (Heitz et al. 2016) is
checked first (nothing absorbed with F = 1; its first order is the single-scattering integral), then ours in a white
furnace: standard_surface metalness 1, gold, specular_roughness 1, ring by ring over the sphere."""
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "tools"))
import metal_furnace as mf  # noqa: E402

GOLD = (0.944, 0.776, 0.373)


def _gold_fresnel():
    n, k = mf.artistic_ior(GOLD, (1.0, 1.0, 1.0))
    return lambda c: mf.conductor_fresnel(c, n, k)


@pytest.mark.parametrize("mu", [1.0, 0.4, 0.1])
def test_random_walk_conserves_energy_and_its_first_order_is_the_integral(mu):
    white = lambda c: np.ones(c.shape[:-1] + (3,))      # noqa: E731
    total, single = mf.random_walk_albedo(mu, 1.0, white, n=20000)
    np.testing.assert_allclose(total, 1.0, atol=1e-9)            # every walk leaves with all its energy
    e = mf.model_albedo(mu, 1.0, [1.0], fresnel=white, compensate=False)
    np.testing.assert_allclose(single, e, atol=6e-3)             # order 1: the single-scattering integral
    gold_total, gold_single = mf.random_walk_albedo(mu, 1.0, _gold_fresnel(), n=20000)
    e_gold = mf.model_albedo(mu, 1.0, GOLD, fresnel=_gold_fresnel(), compensate=False)
    np.testing.assert_allclose(gold_single, e_gold, atol=6e-3)
    assert np.all(gold_total > gold_single) and np.all(gold_total < total)


def test_rough_gold_in_a_white_furnace_follows_the_random_walk(cms_reference, tmp_path):
    from mtlxgen.draw.renderer import Renderer
    ref = cms_reference
    walk_mus = np.linspace(0.02, 1.0, 13)
    fresnel = _gold_fresnel()
    walk = np.array([mf.random_walk_albedo(m, 1.0, fresnel, n=20000)[0] for m in walk_mus])
    with Renderer(size=96, environment=np.ones((32, 64, 3), np.float32)) as r:
        mu_img = mf.draw(r, ref, str(tmp_path), mf.NDOTV, "ndotv")[0][..., 0]
        ours, theirs = mf.draw(r, ref, str(tmp_path), mf.METAL % {"c": "%g, %g, %g" % GOLD, "r": 1.0}, "gold")
    covered = theirs[..., 3] > 0.99
    mu = np.clip(mu_img, 0.02, 1.0)
    truth = np.stack([np.interp(mu, walk_mus, walk[:, k]) for k in range(3)], -1).mean(-1)
    o, t = ours[..., :3].mean(-1), theirs[..., :3].mean(-1)
    rings = mf.rings(covered)
    ours_dev = [o[m].mean() / truth[m].mean() - 1.0 for m in rings]
    theirs_dev = [t[m].mean() / truth[m].mean() - 1.0 for m in rings]
    assert max(abs(d) for d in ours_dev) < 0.03, ours_dev                  # ours within 3% on every ring
    assert abs(ours_dev[-1]) < 0.01 and abs(ours_dev[-2]) < 0.015, ours_dev  # and at the rim within 1-1.5%
    assert theirs_dev[-1] > 0.025, theirs_dev     # MaterialX's rim gains energy (its compensation: F at the view)
