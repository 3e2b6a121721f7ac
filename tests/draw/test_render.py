"""The render harness: exact colours, deterministic pixels, geometry streams as documented."""
import numpy as np
import pytest

from mtlxgen import pipeline
from mtlxgen.draw import renderer as render
from util import write_doc


def unlit(tmp_path, color, name="doc.mtlx"):
    return write_doc(tmp_path, """
  <surface_unlit name="sh" type="surfaceshader">
    <input name="emission_color" type="color3" value="%s" />
  </surface_unlit>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="sh" /></surfacematerial>
""" % ", ".join(str(c) for c in color), name=name)


def test_a_constant_colour_material_renders_that_exact_colour(tmp_path, renderer):
    color = (0.25, 0.5, 0.75)
    img = renderer.render(pipeline.generate(unlit(tmp_path, color))[0])
    covered = img[..., 3] > 0
    assert covered.mean() > 0.3                      # the sphere fills a good part of the frame
    assert np.allclose(img[covered][:, :3], color, atol=1e-6)
    assert np.all(img[~covered] == 0.0)              # background cleared to transparent black


def test_rendering_twice_gives_identical_pixels(tmp_path, renderer):
    path = write_doc(tmp_path, """<nodegraph name="g"><normal name="n" type="vector3" />
      <output name="out" type="vector3" nodename="n" /></nodegraph>""")
    shader = pipeline.generate(path)[0]
    assert renderer.render(shader).tobytes() == renderer.render(shader).tobytes()


def test_object_normals_face_the_camera_at_the_centre(tmp_path, renderer):
    path = write_doc(tmp_path, """<nodegraph name="g"><normal name="n" type="vector3" />
      <output name="out" type="vector3" nodename="n" /></nodegraph>""")
    img = renderer.render(pipeline.generate(path)[0])
    c = renderer.size // 2
    assert img[c, c, :3] == pytest.approx([0.0, 0.0, 1.0], abs=0.03)
    assert img[c - int(0.7 * c), c, 1] > 0.5          # upper part of the sphere: normal points up (y)


def test_texcoords_run_left_to_right_and_bottom_to_top(tmp_path, renderer):
    path = write_doc(tmp_path, """<nodegraph name="g"><texcoord name="t" type="vector2" />
      <output name="out" type="vector2" nodename="t" /></nodegraph>""")
    img = renderer.render(pipeline.generate(path)[0])
    c = renderer.size // 2
    assert img[c - 30, c, 1] > img[c + 30, c, 1]      # v grows upwards (row 0 is the top)
    assert img[c, c - 20, 0] < img[c, c + 20, 0]      # u grows to the right on the visible side


def test_irradiance_of_a_uniform_environment_is_that_radiance():
    env = np.full((32, 64, 3), 0.7, dtype=np.float32)
    irr = render.irradiance_map(env, 16, 8)
    assert np.allclose(irr, 0.7, atol=2e-3)


def test_builtin_sky_is_deterministic_hdr():
    a, b = render.builtin_sky(), render.builtin_sky()
    assert a.tobytes() == b.tobytes()
    assert a.max() > 4.0 and a.min() >= 0.0


def test_a_renderer_still_draws_after_another_renderer_came_and_went(tmp_path, renderer):
    shader = pipeline.generate(unlit(tmp_path, (0.1, 0.2, 0.3)))[0]
    before = renderer.render(shader)
    with render.Renderer(size=16) as other:
        other.render(shader)
    assert renderer.render(shader).tobytes() == before.tobytes()


def test_image_files_are_read_with_straight_alpha(tmp_path):
    from mtlxgen.base import images
    rgba = np.zeros((4, 4, 4), dtype=np.float32)
    rgba[..., 0], rgba[..., 1], rgba[..., 3] = 1.0, 0.6, 0.25
    for name in ("t.png", "t.exr"):
        path = str(tmp_path / name)
        images.write_image(path, rgba)
        back = images.read_image(path)
        stored = images.srgb_encode(np.array([1.0, 0.6, 0.0])) if name.endswith(".png") else [1.0, 0.6, 0.0]
        assert back[0, 0, :3] == pytest.approx(stored, abs=2.5 / 255)    # as stored, not multiplied by alpha
        assert back[0, 0, 3] == pytest.approx(0.25, abs=1 / 255)


def test_the_osmesa_fallback_draws_what_egl_draws(tmp_path, monkeypatch):
    from mtlxgen.draw import osmesa
    try:
        osmesa._library()
    except RuntimeError as e:
        pytest.skip(str(e))
    path = write_doc(tmp_path, """<nodegraph name="g"><normal name="n" type="vector3" />
      <output name="out" type="vector3" nodename="n" /></nodegraph>""")
    shader = pipeline.generate(path)[0]
    images = {}
    for backend in ("egl", "osmesa"):
        monkeypatch.setenv("MTLXGEN_GL_BACKEND", backend)
        with render.Renderer(size=32) as r:
            images[backend] = r.render(shader)
    assert images["egl"].tobytes() == images["osmesa"].tobytes()
    assert (images["osmesa"][..., 3] > 0).mean() > 0.3


def test_an_unknown_backend_is_reported(monkeypatch):
    monkeypatch.setenv("MTLXGEN_GL_BACKEND", "nonesuch")
    with pytest.raises(RuntimeError, match="no headless OpenGL 4 context"):
        render.create_context()
