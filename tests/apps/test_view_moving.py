"""The viewer's moving frames (camera moves): a lit fis shader draws its prefiltered variant, which the generator
makes (OurGenerator.moving_shader: the same element and options, environment "prefiltered") on the reloader's
thread; the fis program draws until it is there, a variant made for another text is not taken, and a variant the
driver refuses leaves the fis program drawing. Drawn offscreen (no display needed)."""
from mtlxgen.base import records
import io
import threading

import numpy as np
import pytest

from mtlxgen.apps.view import Generated, Moving, OffscreenWindow, OurGenerator, Viewer

SIZE = 24

DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  <standard_surface name="ss" type="surfaceshader">
    <input name="metalness" type="float" value="1.0" />
    <input name="specular_roughness" type="float" value="0.3" />
    <input name="coat" type="float" value="0" />
  </standard_surface>
  <surfacematerial name="M_lit" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="ss" />
  </surfacematerial>
  <surface_unlit name="flat" type="surfaceshader">
    <input name="emission_color" type="color3" value="0.2, 0.4, 0.8" />
  </surface_unlit>
  <surfacematerial name="M_flat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="flat" />
  </surfacematerial>
</materialx>
"""

pytestmark = pytest.mark.gl             # draws (an offscreen context)


@pytest.fixture
def doc(tmp_path):
    path = tmp_path / "moving.mtlx"
    path.write_text(DOC)
    return str(path)


def _viewer(doc, tmp_path, generator=None):
    window = OffscreenWindow((SIZE, SIZE))
    v = Viewer(window.ctx, doc, size=(SIZE, SIZE), element="M_lit", generator=generator, background=False,
               samples=16, frame_samples=16, output_dir=str(tmp_path), watch=False, out=io.StringIO())
    return window, v


def _move(v, window):
    v.moved()
    v.frame(window.screen)
    assert v.moving
    return v.image().copy()


def test_the_moving_program_is_the_prefiltered_generation(doc, tmp_path):
    window, v = _viewer(doc, tmp_path)
    try:
        assert v.reloader.idle(timeout=120)
        v.frame(window.screen)                                   # takes the variant
        loaded = v.current()
        fis, pre = loaded.generated, loaded.moving_generated
        assert fis.manifest["environment"] == "fis" and pre is not None
        # what a generator asked for the prefiltered method makes of the element, with the same options
        fresh = OurGenerator(v.generator.options)
        expected = fresh.shader(fresh.open(doc, "prefiltered"), "M_lit")
        assert pre.fragment == expected.fragment and pre.vertex == expected.vertex
        assert pre.manifest["environment"] == "prefiltered" and pre.manifest["folded"] == fis.manifest["folded"]
        assert "mg_env_prefiltered_lobe(" in pre.fragment and "mg_env_prefiltered" not in fis.fragment
        assert loaded.moving is None                             # linked at the first move only
        moving = _move(v, window)
        assert loaded.moving is not None and loaded.moving.prog is not loaded.prepared.prog
        assert float(moving[..., :3].max()) > 0.05
        # an unlit element asks for no variant
        v.cycle_element()
        v.frame(window.screen)
        flat = v.current()
        assert v.element == "M_flat" and flat.moving_asked is None and v.moving_prepared(flat) is None
    finally:
        v.close()
        window.close()


class SlowVariants(OurGenerator):
    """Variants made only once `go` is set (a slow generation)."""

    def __init__(self, *args, **kw):
        super().__init__(*args, **kw)
        self.go = threading.Event()
        self.made = 0

    def moving_shader(self, session, name):
        assert threading.current_thread() is not threading.main_thread()      # off the drawing thread
        self.go.wait(120)
        self.made += 1
        return super().moving_shader(session, name)


def test_fis_draws_the_moving_frames_until_the_variant_is_there(doc, tmp_path):
    gen = SlowVariants()
    window, v = _viewer(doc, tmp_path, gen)
    try:
        v.frame(window.screen)
        loaded = v.current()
        fis_frame = _move(v, window)                             # the variant not made yet: the fis program drew
        assert loaded.moving is None and loaded.moving_generated is None and gen.made == 0
        assert float(fis_frame[..., :3].max()) > 0.05
        gen.go.set()
        assert v.reloader.idle(timeout=120) and gen.made == 1    # asked once for the text linked
        pre_frame = _move(v, window)
        assert loaded.moving is not None and gen.made == 1
        assert not np.array_equal(fis_frame, pre_frame)          # another estimator drew
    finally:
        gen.go.set()
        v.close()
        window.close()


def test_a_variant_made_for_another_text_is_not_taken(doc, tmp_path):
    window, v = _viewer(doc, tmp_path, SlowVariants())
    try:
        loaded = v.current()
        fis = loaded.generated
        other = records.replace(fis, fragment=fis.fragment.replace("void main()", "float mg_other() { return 1.0; }"
                                                                       "\nvoid main()"))
        pre = Generated("M_lit", fis.stem, fis.vertex, "#version 400\n", dict(fis.manifest, environment="prefiltered"))
        v.apply_moving(Moving("M_lit", other, pre))             # its fis text differs from the one drawn
        assert loaded.moving_generated is None
        v.apply_moving(Moving("M_lit", fis, records.replace(pre, manifest=dict(pre.manifest, uniforms=[]))))
        assert loaded.moving_generated is None                   # other uniforms than the drawn program's
        v.apply_moving(Moving("M_lit", fis, pre))
        assert loaded.moving_generated is pre
    finally:
        v.generator.go.set()
        v.close()
        window.close()


def test_a_variant_the_driver_refuses_leaves_fis_drawing(doc, tmp_path):
    gen = SlowVariants()
    window, v = _viewer(doc, tmp_path, gen)
    try:
        loaded = v.current()
        fis = loaded.generated
        broken = Generated("M_lit", fis.stem, fis.vertex, "#version 400\nvoid main() { not glsl }\n",
                           dict(fis.manifest, environment="prefiltered"))
        v.apply_moving(Moving("M_lit", fis, broken))
        frame = _move(v, window)
        assert loaded.moving is None and not v.moving_prefiltered   # refused once: fis from then on
        assert float(frame[..., :3].max()) > 0.05
    finally:
        gen.go.set()
        v.close()
        window.close()
