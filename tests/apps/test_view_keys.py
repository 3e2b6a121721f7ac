"""The viewer's keys, camera and geometry (issue 12), drawn offscreen (no display needed): lights, background,
elements, environment method (regenerated), samples, geometry, screenshot naming, frame time; orbit, pan, zoom
and home; built-in shapes and mesh files through trimesh."""
import io
import os

import numpy as np
import pytest

from mtlxgen.draw import geometry
from mtlxgen.base import images
from mtlxgen.apps.view import OffscreenWindow, Viewer, handle_key

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RIG = os.path.join(ROOT, "tests", "data", "materialx", "resources", "Lights", "san_giuseppe_bridge_split.mtlx")
SIZE = 32

DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  <oren_nayar_diffuse_bsdf name="diffuse" type="BSDF">
    <input name="color" type="color3" value="0.6, 0.6, 0.6" />
  </oren_nayar_diffuse_bsdf>
  <dielectric_bsdf name="gloss" type="BSDF">
    <input name="roughness" type="vector2" value="0.35, 0.35" />
  </dielectric_bsdf>
  <layer name="both" type="BSDF">
    <input name="top" type="BSDF" nodename="gloss" />
    <input name="base" type="BSDF" nodename="diffuse" />
  </layer>
  <surface name="lit" type="surfaceshader">
    <input name="bsdf" type="BSDF" nodename="both" />
  </surface>
  <surfacematerial name="M_lit" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="lit" />
  </surfacematerial>
  <surface_unlit name="flat" type="surfaceshader">
    <input name="emission_color" type="color3" value="0.2, 0.4, 0.8" />
  </surface_unlit>
  <surfacematerial name="M_flat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="flat" />
  </surfacematerial>
</materialx>
"""


@pytest.fixture(scope="module")
def viewer(tmp_path_factory):
    folder = tmp_path_factory.mktemp("keys")
    doc = folder / "keys.mtlx"
    doc.write_text(DOC)
    window = OffscreenWindow((SIZE, SIZE))
    out = io.StringIO()
    v = Viewer(window.ctx, str(doc), size=(SIZE, SIZE), lights_file=RIG, background=False, samples=16,
               frame_samples=16, output_dir=str(folder / "shots"), watch=False, out=out)
    v.window, v.log = window, out
    yield v
    v.close()
    window.close()


def still(v):
    """Frames until the picture is converged; the image."""
    for _ in range(64):
        v.frame(v.window.screen)
        if v.converged():
            return v.image().copy()
    raise AssertionError("not converged")


def test_lights_background_elements(viewer):
    v = viewer
    assert v.elements == ["M_lit", "M_flat"] and v.element == "M_lit"
    lit = still(v)
    assert handle_key(v, "l")
    dark = still(v)
    assert lit[..., :3].mean() > dark[..., :3].mean() + 0.02          # the directional light adds light
    handle_key(v, "l")
    assert np.array_equal(still(v), lit)
    assert lit[0, 0, 3] == 0.0
    handle_key(v, "b")
    back = still(v)
    assert back[0, 0, 3] == 1.0 and back[0, 0, :3].max() > 0.05         # the sky behind the sphere
    handle_key(v, "b")
    handle_key(v, "tab")
    assert v.element == "M_flat"
    assert np.allclose(still(v)[SIZE // 2, SIZE // 2, :3], [0.2, 0.4, 0.8], atol=1e-3)
    handle_key(v, "tab", shift=True)
    assert v.element == "M_lit"
    assert np.array_equal(still(v), lit)
    assert not handle_key(v, "z")


def test_environment_samples_screenshot_time(viewer):
    v = viewer
    fis = still(v)
    first = v.loaded["M_lit"].prepared
    handle_key(v, "e")
    assert v.environment_method == "prefiltered"
    pre = still(v)
    assert v.loaded["M_lit"].generated.manifest["environment"] == "prefiltered"
    assert v.loaded["M_lit"].prepared is not first and v.sample_status() == "prefiltered environment"
    assert np.abs(pre - fis).max() > 0                               # another integration
    handle_key(v, "e")
    assert v.environment_method == "fis"
    handle_key(v, "s")
    assert v.samples == 64 and v.plan(v.loaded["M_lit"]) == (16, 4)
    still(v)
    assert v.accumulated == 4 and v.sample_status() == "64/64 samples (converged)"
    handle_key(v, "s")
    handle_key(v, "s")
    handle_key(v, "s")
    handle_key(v, "s")
    assert v.samples == 16
    still(v)
    handle_key(v, "c")
    shots = os.path.join(v.output_dir, "M_lit")
    assert ("screenshot: %s.png" % shots) in v.log.getvalue()
    assert np.allclose(images.read_image(shots + ".exr"), v.image(), atol=2e-3)     # EXR is half float
    handle_key(v, "t")
    assert "frame " in v.log.getvalue().splitlines()[-1] and "16/16 samples (converged)" in v.log.getvalue()


def test_camera_and_geometry(viewer):
    v = viewer
    home = still(v)
    v.camera.orbit(0.25, 0.0)
    v.moved()
    v.frame(v.window.screen)
    assert v.moving and v.plan(v.loaded["M_lit"]) == (8, 1)            # a quick frame while moving
    turned = still(v)
    assert not np.array_equal(turned, home)
    assert np.allclose(v.camera.eye(), [-3 * np.sin(np.pi / 4), 0, 3 * np.cos(np.pi / 4)], atol=1e-6)
    v.camera.zoom(3)
    assert abs(v.camera.distance - 3 * 0.9 ** 3) < 1e-9
    v.camera.pan(0.1, 0.0)
    assert np.linalg.norm(v.camera.target) > 0
    handle_key(v, "f")
    assert np.array_equal(still(v), home)
    handle_key(v, "g")
    assert v.geometry_name == "plane"
    plane = still(v)
    def box_filled(img):                 # the drawn pixels fill their bounding box: a square facing the camera
        rows, cols = np.nonzero(img[..., 3] > 0)
        return img[rows.min():rows.max() + 1, cols.min():cols.max() + 1, 3].min() > 0
    assert box_filled(plane) and not box_filled(home)
    for _ in range(3):
        handle_key(v, "g")
    assert v.geometry_name == "sphere"
    assert np.array_equal(still(v), home)


def test_mesh_file_through_trimesh(tmp_path, viewer):
    pytest.importorskip("trimesh", reason="mesh files need trimesh (pip install 'mtlxgen[view]')")
    obj = tmp_path / "quad.obj"
    obj.write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                   "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n")
    attrs, index = geometry.load_mesh(str(obj))
    assert len(index) == 6 and attrs["i_position"].shape == (4, 3)
    assert np.allclose(attrs["i_tangent"], [1, 0, 0]) and np.allclose(attrs["i_bitangent"], [0, 1, 0])
    assert np.allclose(attrs["i_normal"], [0, 0, 1])
    v = viewer
    v.set_geometry(str(obj))
    img = still(v)
    assert (img[..., 3] > 0).mean() > 0.2
    v.set_geometry("sphere")
    bad = tmp_path / "bad.obj"
    bad.write_text("this is not a mesh\n")
    with pytest.raises(Exception) as e:
        geometry.load_mesh(str(bad))
    assert str(bad) in str(e.value)


def test_builtin_shapes_face_outwards():
    for name in geometry.BUILTIN:
        attrs, index = geometry.geometry(name)
        p, n = attrs["i_position"], attrs["i_normal"]
        tri = index.reshape(-1, 3)
        face = np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])
        area = np.linalg.norm(face, axis=1)
        agree = (face * n[tri].sum(1)).sum(1)
        assert (agree[area > 1e-9] > 0).all(), name                   # counter-clockwise seen from outside
        assert np.allclose(np.linalg.norm(n, axis=1), 1, atol=1e-5)
        assert np.allclose((attrs["i_tangent"] * n).sum(1), 0, atol=1e-5), name


def test_cut_out_surface_shows_the_background_not_a_hole(tmp_path):
    """With the background on, the surface is composited over it (premultiplied): a fully cut-out sphere
    (opacity 0) leaves the environment visible everywhere, never a transparent black hole."""
    from mtlxgen.apps import cli
    doc = tmp_path / "cut.mtlx"
    doc.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n'
                   '<surface_unlit name="u" type="surfaceshader"><input name="opacity" type="float" value="0" />'
                   '</surface_unlit>\n<surfacematerial name="M" type="material"><input name="surfaceshader" '
                   'type="surfaceshader" nodename="u" /></surfacematerial>\n</materialx>\n')
    shot = tmp_path / "cut.png"
    env = dict(os.environ)
    try:
        os.environ.pop("DISPLAY", None)
        assert cli.main(["view", str(doc), "--size", "48", "48", "--headless-frames", "1",
                         "--screenshot", str(shot)]) == 0
    finally:
        os.environ.clear()
        os.environ.update(env)
    img = images.read_image(str(tmp_path / "cut.exr"))
    centre = img[20:28, 20:28]                      # inside the sphere's silhouette
    assert np.all(centre[..., 3] > 0.99) and float(centre[..., :3].mean()) > 0.05
