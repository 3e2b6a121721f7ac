"""Progressive refinement (issue 12): frame k of K draws its block of the environment's sample sequence
(u_envSampleFrame, u_envSampleFrames); the mean of K frames of n samples is an n K sample estimate. The
default (frame 0 of 1) is the plain Hammersley estimate, so `render` is unchanged. Also Renderer.draw from
another camera into another framebuffer: the path `mtlxgen view` draws with."""
import os

import numpy as np
import pytest

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
