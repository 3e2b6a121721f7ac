"""Progressive refinement (issue 12): frame k of K draws its block of the environment's sample sequence
(u_envSampleFrame, u_envSampleFrames); the mean of K frames of n samples is an n K sample estimate. The
default (frame 0 of 1) is the plain Hammersley estimate, so `render` is unchanged; a reduced shader reads the pair as
constants (one frame) unless it keeps them, and the viewer's keep them. Also Renderer.draw from
another camera into another framebuffer: the path `mtlxgen view` draws with."""
import os

import numpy as np
import pytest

from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.draw import compare, renderer as render
from mtlxgen import pipeline

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SIZE = 64


@pytest.fixture(scope="module")
def quick_start():
    return pipeline.generate(os.path.join(ROOT, "examples", "quick_start.mtlx"))[0]


def _read(r, fbo=None):
    fbo = fbo or r.fbo
    w, h = fbo.size
    return np.frombuffer(fbo.read(components=4, dtype="f4"), "f4").reshape(h, w, 4)[::-1].copy()


def test_frame_zero_of_one_is_render(quick_start):
    with render.Renderer(size=SIZE) as r:
        plain = r.render(quick_start)
        p = r.prepare(quick_start.vertex, quick_start.fragment, quick_start.manifest)
        try:
            r.draw(p, sample_frame=(0, 1))
            assert np.array_equal(_read(r), plain)
            r.draw(p, sample_frame=(3, 8))          # another block of the sequence: other pixels
            assert not np.array_equal(_read(r), plain)
        finally:
            p.release()


def test_frames_converge_to_the_total_sample_count(quick_start):
    total, per_frame = 256, 16
    frames = total // per_frame
    with render.Renderer(size=SIZE, env_samples=total) as ref:
        high = ref.render(quick_start)
    with render.Renderer(size=SIZE) as r:
        p = r.prepare(quick_start.vertex, quick_start.fragment, quick_start.manifest)
        try:
            acc = np.zeros((SIZE, SIZE, 4))
            for k in range(frames):
                r.draw(p, env_samples=per_frame, sample_frame=(k, frames))
                acc += _read(r)
            r.draw(p, env_samples=per_frame)
            single = _read(r)
        finally:
            p.release()
    converged = compare.parity(acc / frames, high)
    alone = compare.parity(single, high)
    assert converged.mean <= 0.25 and converged.max <= 4, converged
    assert alone.mean > 2 * converged.mean, (alone, converged)     # accumulation is what brought it there


def test_draw_into_another_framebuffer_from_another_camera(quick_start):
    """A window's framebuffer (any size) and an orbit camera: the same binding, another aspect and eye."""
    with render.Renderer(size=SIZE) as r:
        ctx = r.ctx
        wide = ctx.framebuffer(color_attachments=[ctx.texture((2 * SIZE, SIZE), 4, dtype="f4")],
                               depth_attachment=ctx.depth_renderbuffer((2 * SIZE, SIZE)))
        p = r.prepare(quick_start.vertex, quick_start.fragment, quick_start.manifest)
        try:
            r.draw(p, target=wide)
            img = _read(r, wide)
            # the sphere keeps its shape: as tall as in the square image, centred, nothing drawn at the sides
            square = r.render(quick_start)
            assert img.shape == (SIZE, 2 * SIZE, 4)
            cols = np.nonzero(img[..., 3].max(0) > 0)[0]
            assert cols.min() > SIZE // 2 - 2 and cols.max() < SIZE * 3 // 2 + 2
            assert compare.parity(img[:, SIZE // 2:SIZE // 2 + SIZE], square).mean <= 0.5
            side = render.Camera(eye=(3.0, 0.0, 0.0))
            r.draw(p, camera=side)
            assert compare.parity(_read(r), square).mean > 5      # another side of the tiles
        finally:
            p.release()
            wide.release()


# A reduced shader is made for one use: progressive refinement's pair (interface.PROGRESSIVE) is constant there, at
# frame 0 of 1, and the frames' code is not pasted (MG_ENV_ONE_FRAME), unless --keep names either of the pair.

def _reduced(keep=()):
    return pipeline.generate(os.path.join(ROOT, "examples", "quick_start.mtlx"), interface="reduced", keep=keep)[0]


def _application(shader):
    return {a["name"] for a in shader.manifest["application"]}


def test_a_reduced_shader_reads_one_frame(quick_start):
    one = _reduced()
    assert "u_envSampleFrames" in _application(quick_start) and "mg_sobol2" in quick_start.fragment
    assert not {"u_envSampleFrame", "u_envSampleFrames"} & _application(one)
    assert "const int u_envSampleFrames = 1;" in one.fragment and "const int u_envSampleFrame = 0;" in one.fragment
    assert "uniform int u_envSampleFrame" not in one.fragment and "mg_sobol2" not in one.fragment
    for name in ("u_envSampleFrame", "u_envSampleFrames"):     # either name keeps both, and the frames' code
        kept = _reduced(keep=(name,))
        assert {"u_envSampleFrame", "u_envSampleFrames"} <= _application(kept), name
        assert "mg_sobol2" in kept.fragment and "const int u_envSample" not in kept.fragment
        assert kept.manifest["kept"] == one.manifest["kept"]      # not a material input


def test_one_frame_draws_the_kept_pair_at_frame_zero():
    one, kept = _reduced(), _reduced(keep=("u_envSampleFrames",))
    with render.Renderer(size=SIZE) as r:
        assert np.array_equal(r.render(one), r.render(kept))
        p = r.prepare(kept.vertex, kept.fragment, kept.manifest)
        q = r.prepare(one.vertex, one.fragment, one.manifest)
        try:
            r.draw(p, sample_frame=(3, 8))
            assert not np.array_equal(_read(r), r.render(one))     # the kept pair refines
            with pytest.raises(MtlxError, match="--keep u_envSampleFrames"):
                r.draw(q, sample_frame=(3, 8))                  # never the same frame drawn K times, silently
        finally:
            p.release()
            q.release()


def test_keeping_the_pair_on_an_unlit_shader_is_no_error(tmp_path, capsys):
    from mtlxgen.apps import cli
    doc = tmp_path / "unlit.mtlx"
    doc.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n'
                   '  <surface_unlit name="u" type="surfaceshader" />\n'
                   '  <surfacematerial name="m" type="material">\n'
                   '    <input name="surfaceshader" type="surfaceshader" nodename="u" />\n'
                   '  </surfacematerial>\n</materialx>\n')
    assert cli.main(["generate", str(doc), "-o", str(tmp_path / "out"), "--interface", "reduced",
                     "--keep", "u_envSampleFrame"]) == 0
    shader = (tmp_path / "out" / "m.frag").read_text()
    assert "u_envSampleFrame" not in shader                  # nothing samples the environment: nothing declared


def test_the_viewers_reduced_shaders_keep_the_pair():
    from mtlxgen.apps.view import OurGenerator
    from mtlxgen.options import GenerateOptions
    path = os.path.join(ROOT, "examples", "quick_start.mtlx")
    for generator in (OurGenerator(), OurGenerator(GenerateOptions(interface="reduced"))):   # specialized; asked for
        session = generator.open(path, "fis")
        s = generator.shader(session, generator.elements(session)[0])
        assert s.manifest["interface"] == "reduced" and "u_envSampleFrames" in _application(s)
