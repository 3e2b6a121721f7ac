"""The GGX-prefiltered environment (`--environment prefiltered`, issue 27): the prefilter pass's levels against a
brute-force integral of the lobe over the map, render binding the prefiltered map for prefiltered shaders (and the
box chain for fis ones), the manifest's recipe, the viewer drawing the prefiltered variant while the camera moves
and fis when still, and the error of the seven materials of docs/measuring.md against a 2,048-sample FIS render."""
import functools
import os

import jsonschema
import json
import numpy as np
import pytest

from mtlxgen.draw import compare, environment, renderer as render
from mtlxgen import pipeline

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _brute(env, r, alpha):
    """The prefilter's integral by summing every texel of `env` (level 0): the GGX lobe about n = v = r weighted by
    the masking G1(l), over the same weights."""
    d, solid = environment._latlong_directions(env.shape[1], env.shape[0])
    nl = (d * r).sum(-1)
    h = d + r
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nh = (h * r).sum(-1)
    D = alpha ** 2 / (np.pi * (nh ** 2 * (alpha ** 2 - 1.0) + 1.0) ** 2)
    c = np.clip(nl, 1e-6, 1.0)
    g1 = 2.0 / (1.0 + np.sqrt(1.0 + alpha ** 2 * (1.0 - c * c) / (c * c)))
    w = np.where(nl > 0, D * g1 * solid, 0.0)
    return (env * w[..., None]).sum((0, 1)) / w.sum()


def _direction(u, v):
    e, a = (0.5 - v) * np.pi, (u - 0.5) * 2.0 * np.pi
    return np.array([np.cos(e) * np.sin(a), np.sin(e), -np.cos(e) * np.cos(a)])


def test_levels_hold_the_ggx_lobe():
    sky = environment.builtin_sky(128, 64)
    with render.Renderer(size=8, environment=sky) as r:
        tex = r.prefiltered_env()
        sizes = environment.level_sizes(128, 64)
        assert tex.size == (128, 64)
        level0 = np.frombuffer(tex.read(level=0), "f4").reshape(64, 128, 4)[..., :3]
        assert np.array_equal(level0, sky)                  # level 0: the map itself
        for level in (1, 2, 3):          # alpha 0.2, 0.39, 0.79 (level 4, alpha 1.57, is read only by alpha near 1)
            w, h = sizes[level]
            img = np.frombuffer(tex.read(level=level), "f4").reshape(h, w, 4)[..., :3]
            alpha = environment.level_alpha(level, 128)
            for (x, y) in ((w // 4, h // 4), (w // 2, h // 2 + 1), (3 * w // 4, h // 2 - 2)):
                want = _brute(sky, _direction((x + 0.5) / w, (y + 0.5) / h), alpha)
                assert np.allclose(img[y, x], want, rtol=0.06, atol=0.01), (level, x, y, img[y, x], want)
        # and the lobes widen with the level: the sun's peak falls
        peaks = [np.frombuffer(tex.read(level=l), "f4").reshape(sizes[l][1], sizes[l][0], 4)[..., :3].max()
                 for l in range(5)]
        assert all(a > b for a, b in zip(peaks, peaks[1:])), peaks


def test_mapping_inverts():
    for level in range(1, 8):
        a = environment.level_alpha(level, 512)
        assert environment.prefiltered_lod(a, 512, 10) == pytest.approx(level)
    assert environment.prefiltered_lod(0.0, 512, 10) == 0.0
    assert environment.prefiltered_lod(1.0, 64, 7) <= 6.0


def test_manifest_carries_the_recipe(tmp_path):
    path = os.path.join(ROOT, "examples", "quick_start.mtlx")
    (pre,) = pipeline.generate(path, environment="prefiltered")
    (fis,) = pipeline.generate(path)
    entry = {e["name"]: e for e in pre.manifest["application"]}["u_envRadiance"]
    assert entry["prefilter"]["samples"] == environment.PREFILTER_SAMPLES and entry["prefilter"]["method"] == "ggx"
    assert "prefilter" not in {e["name"]: e for e in fis.manifest["application"]}["u_envRadiance"]
    with open(os.path.join(ROOT, "docs", "manifest.schema.json")) as f:
        schema = json.load(f)
    jsonschema.validate(pre.manifest, schema)
    jsonschema.validate(fis.manifest, schema)
    # each shader holds its own method's glsl_lib code only (paste switches): the prefiltered one the split sum's
    # lookup and none of the sampling loop, the fis one the loop and none of the lookup
    assert "mg_env_prefiltered_lobe(" in pre.fragment and "mg_env_specular_samples" not in pre.fragment
    assert "mg_env_specular_samples(" in fis.fragment and "mg_env_prefiltered" not in fis.fragment


def test_prefilter_sources_for_webgl_are_es():
    vertex, fragment = environment.prefilter_sources("essl")
    assert vertex.startswith("#version 300 es") and fragment.startswith("#version 300 es")
    assert "mg_env_prefilter_texel" in fragment and "uniform int u_envSampleFrame" not in fragment
    with pytest.raises(ValueError):
        environment.prefilter_sources("hlsl")


@pytest.mark.gl                     # renders (llvmpipe)
def test_render_binds_the_prefiltered_map_only_for_prefiltered_shaders():
    path = os.path.join(ROOT, "examples", "quick_start.mtlx")
    (fis,) = pipeline.generate(path)
    (pre,) = pipeline.generate(path, environment="prefiltered")
    with render.Renderer(size=32) as r:
        a = r.render(fis)
        assert r._prefiltered is None                       # fis shaders never make it
        b = r.render(pre)
        t = r._prefiltered
        assert t is not None
        r.render(pre)
        assert r._prefiltered is t                          # made once per environment
        assert np.array_equal(r.render(fis), a)
        # the prefiltered shader reads the prefiltered map: bound to the box chain it draws something else
        p = r.prepare(pre.vertex, pre.fragment, dict(pre.manifest, environment="fis"))
        try:
            r.draw(p)
            boxed = np.frombuffer(r.fbo.read(components=4, dtype="f4"), "f4").reshape(32, 32, 4)[::-1]
        finally:
            p.release()
        assert compare.parity(boxed, b).mean > 0.5
        r.set_environment(None)
        assert r._prefiltered is None


SEVEN = [("enterprise/enterprise_brushed_metal.mtlx", "M_brushed"), ("enterprise/enterprise_glass.mtlx", "M_glass"),
         ("enterprise/enterprise_soap_bubble.mtlx", "M_bubble"), ("enterprise/enterprise_car_paint.mtlx", "M_car_paint"),
         ("pbs/pbs_nodes.mtlx", "brushed_gold"), ("pbs/pbs_nodes.mtlx", "iridescent_steel"),
         ("quick_start.mtlx", "M_tiles")]


@functools.lru_cache(maxsize=None)
def seven_errors(size, reference_samples=2048):
    """{element: (error of 64-sample FIS, error of prefiltered)} against a reference_samples FIS render of the same
    shader: mean over the pixels either image covers of the max-channel sRGB difference, in 1/255."""
    out = {}
    with render.Renderer(size=size) as r:
        for rel, el in SEVEN:
            path = os.path.join(ROOT, "examples", rel)
            (f,) = pipeline.generate(path, elements=[el])
            (p,) = pipeline.generate(path, elements=[el], environment="prefiltered")
            r.env_samples = reference_samples
            ref = r.render(f)
            r.env_samples = 64
            fis, pre = r.render(f), r.render(p)
            mask = (ref[..., 3] > 0.5) | (pre[..., 3] > 0.5)
            out[el] = tuple(float(compare.diff_map(x, ref)[mask].mean()) for x in (fis, pre))
    return out


# issue 27's target: prefiltered no worse than 64-sample FIS over the seven materials (docs/measuring.md; met since the
# anisotropic lobes are read with taps along their major axis)
@pytest.mark.gl                     # renders (llvmpipe)
def test_seven_materials_prefiltered_within_fis64_error():
    errors = seven_errors(48, reference_samples=1024)
    fis = sum(e[0] for e in errors.values())
    pre = sum(e[1] for e in errors.values())
    assert pre <= fis, errors


@pytest.mark.gl                     # renders (llvmpipe)
def test_anisotropic_lobes_prefiltered_within_fis64_error():
    """The two brushed metals (anisotropic GGX, read with taps along the lobe's major axis): each within its own
    64-sample FIS error (one bent lookup: 2.4x and 2.8x it)."""
    errors = seven_errors(48, reference_samples=1024)
    for el in ("M_brushed", "brushed_gold"):
        fis, pre = errors[el]
        assert pre <= fis, (el, fis, pre)


def test_seven_materials_prefiltered_error_is_bounded():
    """What holds today, to keep it: a mirror-like and glass lobes stay at FIS's noise level, and no material's
    prefiltered error passes 3x its 64-sample FIS error plus 2/255."""
    errors = seven_errors(48, reference_samples=1024)
    for el, (fis, pre) in errors.items():
        assert pre <= 3.0 * fis + 2.0, (el, fis, pre)


def test_viewer_draws_prefiltered_while_moving_and_fis_when_still(tmp_path):
    import io
    from mtlxgen.apps.view import OffscreenWindow, Viewer
    size = 48
    path = os.path.join(ROOT, "examples", "quick_start.mtlx")
    window = OffscreenWindow((size, size))
    v = Viewer(window.ctx, path, size=(size, size), background=False, samples=16, frame_samples=16,
               output_dir=str(tmp_path), watch=False, out=io.StringIO())
    try:
        for _ in range(8):                                       # still: the fis program, accumulated
            v.frame(window.screen)
            if v.converged():
                break
        still_img = v.image().copy()
        loaded = v.current()
        assert loaded.moving is None                             # nothing prefiltered drawn yet
        assert v.reloader.idle(timeout=120)                      # its prefiltered variant generated (off-thread)
        v.moved()                                                # the camera moved (orbit by nothing: same view)
        v.frame(window.screen)
        moving = v.image().copy()
        assert loaded.moving is not None and v.moving
        assert loaded.moving_generated.manifest["environment"] == "prefiltered"
        assert compare.parity(moving, still_img).mean > 0.5         # another estimator than the still picture
        for _ in range(8):
            v.frame(window.screen)
            if v.converged():
                break
        again = v.image().copy()
        assert compare.parity(again, still_img).mean <= 0.25        # still again: fis, accumulated as before
        # what the moving frame drew is the prefiltered shader's picture: E (the prefiltered method) drawn still
        v.toggle_environment()
        for _ in range(8):
            v.frame(window.screen)
            if v.converged():
                break
        assert v.current().generated.manifest["environment"] == "prefiltered"
        assert compare.parity(v.image(), moving).mean <= 0.1, compare.parity(v.image(), moving)
    finally:
        v.close()
        window.close()
