"""Hot reload in `mtlxgen view` (issue 12): the document is edited while the viewer runs in a glfw window
under Xvfb. A colour edited: the new colour drawn without relinking (the value set on the linked program).
A broken node written: the last good shader still drawn, the FILE:LINE problem printed and in the title.
Fixed with a new node: linked again, the new colour drawn, 'no problems' printed. A texture rewritten: the
texture read again, nothing regenerated. Elements not shown are not relinked when their text is unchanged."""
import io
import os
import time

import numpy as np
import pytest

from mtlxgen.base import images

from xvfb import start_xvfb, stop_xvfb

# A glfw (GLX) window beside the EGL contexts other tests leave in a pytest-xdist worker has crashed the worker
# (twice in full runs, never alone): these tests run in a process of their own, started by
# tests/apps/test_view_isolated.py, which sets MTLXGEN_VIEW_WINDOW_PROCESS.
pytestmark = pytest.mark.skipif(not os.environ.get("MTLXGEN_VIEW_WINDOW_PROCESS"),
                                reason="run in a fresh process by tests/apps/test_view_isolated.py")

SIZE = 32

DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  {extra}
  <surface_unlit name="unlit" type="surfaceshader">
    <input name="emission_color" type="color3" {color} />
  </surface_unlit>
  <surfacematerial name="M_red" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="unlit" />
  </surfacematerial>
  <surface_unlit name="other" type="surfaceshader">
    <input name="emission_color" type="color3" value="0, 0, 1" />
  </surface_unlit>
  <surfacematerial name="M_other" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="other" />
  </surfacematerial>
</materialx>
"""


@pytest.fixture(scope="module")
def window():
    """A glfw window on an Xvfb display of our own; DISPLAY is this process's only while the window is open."""
    pytest.importorskip("glfw", reason="the viewer's window needs glfw (pip install 'mtlxgen[view]')")
    pytest.importorskip("watchdog", reason="hot reload needs watchdog (pip install 'mtlxgen[view]')")
    display = start_xvfb()
    saved = {k: os.environ.get(k) for k in ("DISPLAY", "WAYLAND_DISPLAY")}
    os.environ["DISPLAY"] = display.name
    os.environ.pop("WAYLAND_DISPLAY", None)
    try:
        from mtlxgen.apps.view import GlfwWindow
        w = GlfwWindow((SIZE, SIZE), visible=True)
        try:
            yield w
        finally:
            w.close()
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
        stop_xvfb(display)


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def run_until(viewer, window, done, timeout=60.0):
    """Draw frames until done() (a reload applied, a texture read) or fail after `timeout` seconds."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        window.poll()
        viewer.frame(window.screen)
        window.swap()
        if done():
            for _ in range(2):            # the frame that shows it, and one more
                viewer.frame(window.screen)
            return
        time.sleep(0.01)
    raise AssertionError("nothing happened in %.0f s; problems: %s" % (timeout, viewer.problems))


def centre(viewer):
    return viewer.image()[SIZE // 2, SIZE // 2, :3]


def reloaded(viewer, before):
    return lambda: viewer.generation > before and not viewer.reloader.busy()


def test_edit_colour_break_fix(tmp_path, window):
    from mtlxgen.apps.view import Viewer
    doc = str(tmp_path / "live.mtlx")
    write(doc, DOC.format(extra="", color='value="0.8, 0.1, 0.1"'))
    out = io.StringIO()
    viewer = Viewer(window.ctx, doc, size=(SIZE, SIZE), background=False, out=out)
    titles = []
    viewer.set_title = lambda: titles.append(viewer.title())
    try:
        run_until(viewer, window, lambda: viewer.frames >= 1)
        assert viewer.element == "M_red" and viewer.problems == []
        assert np.allclose(centre(viewer), [0.8, 0.1, 0.1], atol=1e-3)
        first = viewer.loaded["M_red"].prepared
        viewer.cycle_element()                                  # M_other linked once ...
        run_until(viewer, window, lambda: "M_other" in viewer.loaded)
        assert np.allclose(centre(viewer), [0, 0, 1], atol=1e-3)
        other = viewer.loaded["M_other"].prepared
        viewer.cycle_element()

        # 1. a colour edited: set on the linked program, nothing relinked
        g = viewer.generation
        write(doc, DOC.format(extra="", color='value="0.1, 0.7, 0.2"'))
        run_until(viewer, window, reloaded(viewer, g))
        assert viewer.loaded["M_red"].prepared is first
        assert np.allclose(centre(viewer), [0.1, 0.7, 0.2], atol=1e-3)
        assert viewer.last_reload is not None and "1 value set" in viewer.last_reload[1]
        viewer.cycle_element()                                  # ... and not again: its text did not change
        run_until(viewer, window, lambda: True)
        assert viewer.loaded["M_other"].prepared is other
        viewer.cycle_element()

        # 2. a broken node: the last good shader kept, the problem printed with its file and line
        g = viewer.generation
        write(doc, DOC.format(extra='<bogus_noise name="n" type="color3" />',
                              color='nodename="n"'))
        run_until(viewer, window, reloaded(viewer, g))
        assert len(viewer.problems) == 1
        assert viewer.problems[0].startswith("%s:3: unknown node category 'bogus_noise'" % doc), viewer.problems
        assert viewer.problems[0] in out.getvalue()
        assert "PROBLEM: " + viewer.problems[0] in titles[-1]
        assert np.allclose(centre(viewer), [0.1, 0.7, 0.2], atol=1e-3)      # still drawn

        # 3. fixed, with a node of its own: linked again, the new colour drawn
        g = viewer.generation
        write(doc, DOC.format(extra='<constant name="n" type="color3"><input name="value" type="color3" '
                                    'value="0.9, 0.6, 0.0" /></constant>', color='nodename="n"'))
        run_until(viewer, window, reloaded(viewer, g))
        assert viewer.problems == []
        assert viewer.loaded["M_red"].prepared is not first
        assert np.allclose(centre(viewer), [0.9, 0.6, 0.0], atol=1e-3)
        assert "%s: no problems: drawing M_red" % doc in out.getvalue()
        assert "PROBLEM" not in titles[-1]
    finally:
        viewer.close()


def test_texture_edit_reads_the_texture_again(tmp_path, window):
    from mtlxgen.apps.view import Viewer
    tex = str(tmp_path / "swatch.png")
    images.write_image(tex, np.full((4, 4, 3), [1.0, 0.0, 0.0], np.float32))
    doc = str(tmp_path / "textured.mtlx")
    write(doc, DOC.format(extra='<image name="img" type="color3"><input name="file" type="filename" '
                                'value="swatch.png" /></image>', color='nodename="img"'))
    viewer = Viewer(window.ctx, doc, size=(SIZE, SIZE), background=False, out=io.StringIO())
    try:
        run_until(viewer, window, lambda: viewer.frames >= 1)
        assert np.allclose(centre(viewer), [1, 0, 0], atol=1e-3)
        prepared, g = viewer.loaded["M_red"].prepared, viewer.generation
        viewer.last_reload = None
        images.write_image(tex, np.full((4, 4, 3), [0.0, 1.0, 0.0], np.float32))
        run_until(viewer, window, lambda: viewer.last_reload is not None)
        assert viewer.last_reload[1] == "texture"
        assert viewer.generation == g and viewer.loaded["M_red"].prepared is prepared   # nothing regenerated
        assert np.allclose(centre(viewer), [0, 1, 0], atol=1e-3)
    finally:
        viewer.close()


def test_panel_sets_a_value_and_saves_it(tmp_path, window):
    """The property panel: a colour set on the linked program (no relink); Save writes it into the document,
    whose reload then draws the same colour from the file; the panel itself is drawn over the picture."""
    pytest.importorskip("imgui_bundle", reason="the property panel needs imgui-bundle (pip install 'mtlxgen[view]')")
    from mtlxgen.apps.view import Viewer
    from mtlxgen.apps.viewpanel import Panel
    doc = str(tmp_path / "panel.mtlx")
    write(doc, DOC.format(extra="", color='value="0.8, 0.1, 0.1"'))
    viewer = Viewer(window.ctx, doc, size=(SIZE, SIZE), background=False, out=io.StringIO())
    panel = Panel(viewer, window)
    try:
        run_until(viewer, window, lambda: viewer.frames >= 1)
        panel.draw(window.screen)
        panel._refresh()
        item = {i.uniform: i for i in panel.inputs}["unlit_emission_color"]
        assert (item.label, item.mtlx_type, item.value) == ("emission_color", "color3", (0.8, 0.1, 0.1))
        prepared = viewer.loaded["M_red"].prepared
        panel.set_value(item, (0.2, 0.4, 0.6))
        run_until(viewer, window, lambda: True)
        assert np.allclose(centre(viewer), [0.2, 0.4, 0.6], atol=1e-3)
        assert viewer.loaded["M_red"].prepared is prepared
        g = viewer.generation
        assert panel.save() == [doc]
        assert '<input name="emission_color" type="color3" value="0.2, 0.4, 0.6" />' in open(doc).read()
        run_until(viewer, window, reloaded(viewer, g))
        assert viewer.loaded["M_red"].overrides == {} and viewer.loaded["M_red"].prepared is prepared
        assert np.allclose(centre(viewer), [0.2, 0.4, 0.6], atol=1e-3)
        # the panel over the picture: its window's pixels in the top-left corner of the screen
        viewer.frame(window.screen)
        bare = np.frombuffer(window.screen.read(viewport=(0, 0, SIZE, SIZE), components=3), np.uint8).copy()
        panel.draw(window.screen)
        drawn = np.frombuffer(window.screen.read(viewport=(0, 0, SIZE, SIZE), components=3), np.uint8).copy()
        assert (bare != drawn).mean() > 0.1
        # an input the specialized shader folded (transmission, 0 by default): generated again with it a
        # uniform holding the panel's value, and kept
        item = {i.uniform: i for i in panel.inputs}["unlit_transmission"]
        loaded = viewer.loaded["M_red"]
        assert loaded.folded("unlit_transmission") and panel.value_of(item) == 0.0
        panel.set_value(item, 0.5)
        run_until(viewer, window, lambda: not viewer.loaded["M_red"].folded("unlit_transmission"))
        loaded = viewer.loaded["M_red"]
        assert loaded.prepared is not prepared and "unlit_transmission" in loaded.generated.manifest["kept"]
        assert loaded.overrides["unlit_transmission"] == 0.5 and panel.value_of(item) == 0.5
        assert loaded.prepared.prog["unlit_transmission"].value == 0.5
    finally:
        panel.release()
        viewer.close()


def test_window_input_drives_the_camera_and_keys(tmp_path, window):
    """glfw's callbacks as the window gets them: a left drag orbits, a right drag pans, the wheel zooms, keys act."""
    import glfw
    from mtlxgen.apps.view import Viewer
    doc = str(tmp_path / "input.mtlx")
    write(doc, DOC.format(extra="", color='value="0.8, 0.1, 0.1"'))
    viewer = Viewer(window.ctx, doc, size=(SIZE, SIZE), background=False, out=io.StringIO())
    window.viewer, w = viewer, window.window
    try:
        window._on_cursor(w, 10.0, 10.0)
        window._on_button(w, glfw.MOUSE_BUTTON_LEFT, glfw.PRESS, 0)
        window._on_cursor(w, 10.0 + SIZE / 4.0, 10.0)          # a quarter of the height: an eighth of a turn
        window._on_button(w, glfw.MOUSE_BUTTON_LEFT, glfw.RELEASE, 0)
        assert abs(viewer.camera.yaw + np.pi / 4) < 1e-9 and viewer._moved
        window._on_cursor(w, 30.0, 30.0)                        # no button held: nothing moves
        assert abs(viewer.camera.yaw + np.pi / 4) < 1e-9
        window._on_button(w, glfw.MOUSE_BUTTON_RIGHT, glfw.PRESS, 0)
        window._on_cursor(w, 30.0, 40.0)
        window._on_button(w, glfw.MOUSE_BUTTON_RIGHT, glfw.RELEASE, 0)
        assert viewer.camera.target[1] > 0                      # dragged down: the view's centre goes up
        window._on_scroll(w, 0.0, 2.0)
        assert abs(viewer.camera.distance - 3 * 0.81) < 1e-9
        window._on_key(w, glfw.KEY_B, glfw.get_key_scancode(glfw.KEY_B), glfw.PRESS, 0)
        assert viewer.background
        window._on_key(w, glfw.KEY_TAB, 0, glfw.PRESS, 0)
        assert viewer.element == "M_other"
        window._on_key(w, glfw.KEY_TAB, 0, glfw.PRESS, glfw.MOD_SHIFT)
        assert viewer.element == "M_red"
        window._on_key(w, glfw.KEY_F, glfw.get_key_scancode(glfw.KEY_F), glfw.PRESS, 0)
        assert viewer.camera.yaw == 0 and viewer.camera.distance == 3 and not viewer.camera.target.any()
        window._on_key(w, glfw.KEY_ESCAPE, 0, glfw.PRESS, 0)
        assert window.should_close()
    finally:
        glfw.set_window_should_close(window.window, False)
        window.viewer = None
        viewer.close()


def test_included_file_and_light_rig_are_watched(tmp_path, window):
    """An edit of a file the document includes regenerates; an edit of the light rig rebinds its lights."""
    from mtlxgen.apps.view import Viewer
    part = tmp_path / "part.mtlx"
    part.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n  <constant name="n" type="color3">\n'
                    '    <input name="value" type="color3" value="0.3, 0.3, 0.9" />\n  </constant>\n</materialx>\n')
    doc = str(tmp_path / "main.mtlx")
    write(doc, DOC.format(extra='<xi:include href="part.mtlx" />', color='nodename="n"').replace(
        '<materialx version="1.39">', '<materialx version="1.39" xmlns:xi="http://www.w3.org/2001/XInclude">'))
    rig = tmp_path / "rig.mtlx"
    light = ('<?xml version="1.0"?>\n<materialx version="1.39">\n  <directional_light name="sun" type="lightshader">\n'
             '    <input name="intensity" type="float" value="%s" />\n  </directional_light>\n</materialx>\n')
    rig.write_text(light % "2")
    out = io.StringIO()
    viewer = Viewer(window.ctx, doc, size=(SIZE, SIZE), background=False, lights_file=str(rig), out=out)
    try:
        run_until(viewer, window, lambda: viewer.frames >= 1)
        assert np.allclose(centre(viewer), [0.3, 0.3, 0.9], atol=1e-3) and viewer.rig[0]["intensity"] == 2.0
        g = viewer.generation
        part.write_text(part.read_text().replace("0.3, 0.3, 0.9", "0.9, 0.3, 0.3"))
        run_until(viewer, window, reloaded(viewer, g))
        assert np.allclose(centre(viewer), [0.9, 0.3, 0.3], atol=1e-3)
        rig.write_text(light % "5")
        run_until(viewer, window, lambda: viewer.rig[0]["intensity"] == 5.0)
        rig.write_text(light % "five")
        run_until(viewer, window, lambda: viewer.rig_problems != [])
        assert viewer.rig_problems[0].startswith("%s:4: " % rig) and viewer.rig_problems[0] in out.getvalue()
        assert viewer.rig[0]["intensity"] == 5.0                  # the last good rig still bound
    finally:
        viewer.close()
