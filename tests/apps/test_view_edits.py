"""The viewer's quick edits (issue 12, edit-to-pixel latency), drawn offscreen (no display needed):

  - a value edit of the document (only <input> values of the shown shader's public uniforms changed) sets the
    values on the linked program without running the generator; the picture is the one a fresh viewer draws
    of the edited document; anything else (a new node, an input the shader does not have as a uniform, one
    repeating its name, a value that does not read cleanly) generates as before; each input edited sets the
    uniforms whose Origin names it (its element's name path and name), not those of its line or of a name alike;
  - the zero-weight specialization: inputs at zero are constants in the viewer's shader (their lobes left out),
    the picture is `render`'s; an edit moving one off zero generates again with it kept, and it stays kept;
    the panel's edit of a folded input (Viewer.unfold) does the same with the panel's value.
"""
import io
import os
import time

import numpy as np
import pytest

from mtlxgen.draw import compare
from mtlxgen.apps.view import OffscreenWindow, OurGenerator, Viewer

SIZE = 32

DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  <checkerboard name="chk" type="color3">
    <input name="color1" type="color3" value="0.9, 0.5, 0.1" />
    <input name="uvtiling" type="vector2" value="8, 8" />
  </checkerboard>
  <standard_surface name="SR" type="surfaceshader">
    <input name="base_color" type="color3" {base_color} />
    <input name="specular_roughness" type="float" value="{roughness}" />
    <input name="coat" type="float" value="{coat}" />
    <input name="emission_color" type="color3" value="0.2, 0.3, 0.4" colorspace="srgb_texture" />
    <input name="emission" type="float" value="{emission}" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
</materialx>
"""


def doc(base_color='value="0.8, 0.2, 0.1"', roughness="0.3", coat="0", emission="0"):
    return DOC.format(base_color=base_color, roughness=roughness, coat=coat, emission=emission)


class Counting(OurGenerator):
    """Our generator, counting the shaders it generates."""

    def __init__(self, **kw):
        super().__init__(**kw)
        self.calls = 0

    def shader(self, session, name):
        self.calls += 1
        return super().shader(session, name)


@pytest.fixture(scope="module")
def window():
    pytest.importorskip("watchdog", reason="hot reload needs watchdog (pip install 'mtlxgen[view]')")
    w = OffscreenWindow((SIZE, SIZE))
    yield w
    w.close()


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def open_viewer(window, path, generator=None, watch=True):
    return Viewer(window.ctx, str(path), size=(SIZE, SIZE), background=False, samples=16, frame_samples=16,
                  out=io.StringIO(), watch=watch, generator=generator)


def settle(v, done=lambda: True, timeout=60.0):
    """Frames until done() and the picture is converged with nothing pending."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        v.frame()
        if done() and v.converged() and not v.reloader.busy() and not v._catch_up:
            return
        time.sleep(0.005)
    raise AssertionError("nothing happened in %.0f s; problems: %s" % (timeout, v.problems))


def fresh(window, tmp_path, text, name="fresh.mtlx", generator=None):
    """The converged picture a new viewer draws of `text`, and its shader's manifest."""
    path = tmp_path / name
    write(path, text)
    v = open_viewer(window, path, generator=generator, watch=False)
    try:
        settle(v)
        return v.image().copy(), v.loaded[v.element].generated.manifest
    finally:
        v.close()


def edit(v, path, text):
    g = v.generation
    write(path, text)
    settle(v, lambda: v.generation > g)


def test_value_edit_sets_the_uniform_without_generating(tmp_path, window):
    path = tmp_path / "live.mtlx"
    write(path, doc())
    gen = Counting()
    v = open_viewer(window, path, gen)
    try:
        settle(v)
        prepared, calls = v.loaded["M"].prepared, gen.calls
        g = v.generation
        write(path, doc(base_color='value="0.1, 0.6, 0.3"', roughness="0.55"))
        deadline = time.time() + 30
        while v.generation == g and time.time() < deadline:
            v.poll()                  # what frame() does first (a frame then asks the session to read it again)
            time.sleep(0.005)
        assert v.generation == g + 1 and gen.calls == calls          # set, nothing generated ...
        assert "M: 2 values set, not generated" == v.last_reload[1]
        assert v.loaded["M"].prepared is prepared
        assert v.loaded["M"].values["SR_base_color"] == (0.1, 0.6, 0.3)
        settle(v)                     # ... then the session reads the document again (off the drawing thread)
        assert not v.behind and v.loaded["M"].prepared is prepared       # the same text: nothing relinked
        img = v.image().copy()
        want, _ = fresh(window, tmp_path, doc(base_color='value="0.1, 0.6, 0.3"', roughness="0.55"))
        assert np.abs(img - want).max() <= 1e-6

        # an input whose value is converted from its colour space in the shader: the value set is the authored
        # one, the picture a fresh viewer's
        edit(v, path, doc(base_color='value="0.1, 0.6, 0.3"', roughness="0.55", emission="0.5"))   # folded: linked
        assert v.loaded["M"].prepared is not prepared
        prepared, calls = v.loaded["M"].prepared, gen.calls
        text = doc(base_color='value="0.1, 0.6, 0.3"', roughness="0.55", emission="0.5").replace(
            'value="0.2, 0.3, 0.4" colorspace', 'value="0.7, 0.2, 0.2" colorspace')
        edit(v, path, text)
        assert v.last_reload[1] == "M: 1 value set, not generated" and v.loaded["M"].prepared is prepared
        img = v.image().copy()
        want, _ = fresh(window, tmp_path, text, "fresh2.mtlx")
        assert np.abs(img - want).max() <= 1e-6
    finally:
        v.close()


TINT = """<?xml version="1.0"?>
<materialx version="1.39">
  <nodedef name="ND_tint" node="tint">
    <input name="amount" type="float" value="{amount}" />
    <output name="out" type="color3" />
  </nodedef>
  <nodegraph name="NG_tint" nodedef="ND_tint">
    <multiply name="m" type="color3">
      <input name="in1" type="color3" value="{colour}" />
      <input name="in2" type="float" interfacename="amount" />
    </multiply>
    <output name="out" type="color3" nodename="m" />
  </nodegraph>
  <tint name="t" type="color3" />
  <surface_unlit name="SR" type="surfaceshader">
    <input name="emission_color" type="color3" nodename="t" />
  </surface_unlit>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
</materialx>
"""


def test_same_document_draws_on(tmp_path, window):
    """The same bytes written again (a touch, a save's trailing event) or a comment changed on its line: nothing
    generated, nothing set."""
    path = tmp_path / "same.mtlx"
    write(path, doc())
    gen = Counting()
    v = open_viewer(window, path, gen)
    try:
        settle(v)
        calls, g, prepared = gen.calls, v.generation, v.loaded["M"].prepared
        write(path, doc())
        write(path, doc().replace("<materialx", "<!-- a note --><materialx"))
        deadline = time.time() + 2.0
        while time.time() < deadline:
            v.frame()
            time.sleep(0.01)
        assert (gen.calls, v.generation) == (calls, g) and v.loaded["M"].prepared is prepared
    finally:
        v.close()


@pytest.mark.parametrize("before, after", [
    # a nodedef's default (the node leaves it unauthored: a uniform; a default may be read as a constant too)
    (TINT.format(amount="0.5", colour="1, 0.5, 0.2"), TINT.format(amount="0.8", colour="1, 0.5, 0.2")),
    # a value inside a nodegraph implementing a nodedef (a constant of the implementation)
    (TINT.format(amount="0.5", colour="1, 0.5, 0.2"), TINT.format(amount="0.5", colour="0.2, 0.5, 1")),
    # a new node feeding base_color: structure changed
    (doc(), doc(base_color='nodename="chk"')),
    # the checkerboard's colour: an input of a node the shown shader does not read
    (doc(), doc().replace('value="0.9, 0.5, 0.1"', 'value="0.2, 0.5, 0.1"')),
    # an input repeating its name in its node (MaterialX reads one of the two by that name)
    (doc(coat='0.25" /><input name="coat" type="float" value="0.25'),
     doc(coat='0.25" /><input name="coat" type="float" value="0.5')),
    # a value MaterialX reads past a slip (text after the number): read with its warning, by the generator
    (doc(roughness="0.3"), doc(roughness="0.4x")),
])
def test_other_edits_generate(tmp_path, window, before, after):
    path = tmp_path / "other.mtlx"
    write(path, before)
    gen = Counting()
    v = open_viewer(window, path, gen)
    try:
        settle(v)
        calls = gen.calls
        edit(v, path, after)
        assert gen.calls > calls and "not generated" not in (v.last_reload or (0, ""))[1]
        img = v.image().copy()
    finally:
        v.close()
    want, _ = fresh(window, tmp_path, after)
    assert np.abs(img - want).max() <= 1e-6


# a constant named like SR's coat uniform (built first: SR's coat is 'SR_coat2'); two inputs on one line, and one on
# the node's own line
LINES = """<?xml version="1.0"?>
<materialx version="1.39">
  <constant name="SR_coat" type="float">
    <input name="value" type="float" value="{value}" />
  </constant>
  <standard_surface name="SR" type="surfaceshader"><input name="specular_roughness" type="float" value="{rough}" />
    <input name="base" type="float" nodename="SR_coat" />
    <input name="base_color" type="color3" value="{colour}" /><input name="coat" type="float" value="{coat}" />
  </standard_surface>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
</materialx>
"""


def test_value_edit_sets_the_inputs_origin_names(tmp_path, window):
    """Inputs sharing a line (with each other, with their node's start tag) and a uniform whose name is another
    node's with a counter: each edit sets the uniform its input's Origin names, without generating; the picture
    is a fresh viewer's."""
    before = LINES.format(value="0.8", rough="0.3", colour="0.8, 0.2, 0.1", coat="0.25")
    after = LINES.format(value="0.6", rough="0.5", colour="0.1, 0.6, 0.3", coat="0.75")
    path = tmp_path / "lines.mtlx"
    write(path, before)
    gen = Counting()
    v = open_viewer(window, path, gen)
    try:
        settle(v)
        sources = v.loaded["M"].generated.sources
        assert [t[0] for t in sources[("SR", "coat")]] == ["SR_coat2"]      # the name this test is about
        assert [t[0] for t in sources[("SR_coat", "value")]] == ["SR_coat_value"]
        prepared, calls, g = v.loaded["M"].prepared, gen.calls, v.generation
        write(path, after)
        deadline = time.time() + 30
        while v.generation == g and time.time() < deadline:
            v.poll()                  # what frame() does first (a frame then asks the session to read it again)
            time.sleep(0.005)
        assert gen.calls == calls and v.last_reload[1] == "M: 4 values set, not generated"
        values = v.loaded["M"].values
        assert (values["SR_coat_value"], values["SR_specular_roughness"], values["SR_base_color"],
                values["SR_coat2"]) == (0.6, 0.5, (0.1, 0.6, 0.3), 0.75)
        settle(v)                     # the session reads it again: the same text, nothing relinked
        assert v.loaded["M"].prepared is prepared
        img = v.image().copy()
    finally:
        v.close()
    want, _ = fresh(window, tmp_path, after)
    assert np.abs(img - want).max() <= 1e-6


def test_specialized_shader_folds_zero_inputs_and_keeps_them_once_moved(tmp_path, window):
    path = tmp_path / "special.mtlx"
    write(path, doc())
    gen = Counting()
    v = open_viewer(window, path, gen)
    try:
        settle(v)
        m = v.loaded["M"].generated.manifest
        assert m["interface"] == "reduced" and "SR_coat" in m["folded"] and "SR_coat" not in m["kept"]
        assert "SR_base_color" in m["kept"] and "SR_specular_roughness" in m["kept"]
        # the picture is render's (the complete interface), but for float rounding
        complete, cm = fresh(window, tmp_path, doc(), generator=OurGenerator(specialize=False))
        assert cm["interface"] == "complete" and "folded" not in cm
        assert len(v.loaded["M"].generated.fragment) < 0.7 * len(fresh_fragment(window, tmp_path, doc()))
        p = compare.parity(v.image(), complete)
        assert p.mean <= 0.01 and np.abs(v.image() - complete).max() <= 1e-3, p

        # coat moved off zero: not a uniform, so generated again with it kept ...
        prepared, calls = v.loaded["M"].prepared, gen.calls
        edit(v, path, doc(coat="0.6"))
        assert gen.calls > calls and v.loaded["M"].prepared is not prepared
        assert "SR_coat" in v.loaded["M"].generated.manifest["kept"]
        want, _ = fresh(window, tmp_path, doc(coat="0.6"), generator=OurGenerator(specialize=False))
        assert np.abs(v.image() - want).max() <= 1e-3
        # ... and kept: back to zero and off again are values set
        prepared, calls = v.loaded["M"].prepared, gen.calls
        edit(v, path, doc(coat="0"))
        edit(v, path, doc(coat="0.3"))
        assert v.loaded["M"].prepared is prepared and v.last_reload[1] == "M: 1 value set, not generated"
        want, _ = fresh(window, tmp_path, doc(coat="0.3"), generator=OurGenerator(specialize=False))
        assert np.abs(v.image() - want).max() <= 1e-3
    finally:
        v.close()


def fresh_fragment(window, tmp_path, text):
    path = tmp_path / "complete.mtlx"
    write(path, text)
    gen = OurGenerator(specialize=False)
    return gen.shader(gen.open(str(path), "fis"), "M").fragment


def test_unfold_keeps_the_input_with_the_panels_value(tmp_path, window):
    """The panel set a folded input (its set_value calls Viewer.unfold): generated again with it a uniform,
    the panel's value drawn and kept as the panel's (Save writes it)."""
    path = tmp_path / "unfold.mtlx"
    write(path, doc())
    v = open_viewer(window, path, watch=False)
    try:
        settle(v)
        loaded = v.loaded["M"]
        assert loaded.folded("SR_coat")
        assert v.unfold("SR_coat", 0.6)
        settle(v)
        loaded = v.loaded["M"]
        assert not loaded.folded("SR_coat") and "SR_coat" in loaded.generated.manifest["kept"]
        assert loaded.overrides == {"SR_coat": 0.6} and loaded.prepared.prog["SR_coat"].value == pytest.approx(0.6)
        img = v.image().copy()
    finally:
        v.close()
    want, _ = fresh(window, tmp_path, doc(coat="0.6"), generator=OurGenerator(specialize=False))
    assert np.abs(img - want).max() <= 1e-3


def test_other_element_after_a_value_edit_has_the_new_value(tmp_path, window):
    """Shown next, before the session read the edited document again: it is read first (the element is drawn
    with the edited value, not the session's old one)."""
    two = doc().replace('</materialx>', '''  <surfacematerial name="M2" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR" />
  </surfacematerial>
</materialx>''')
    path = tmp_path / "two.mtlx"
    write(path, two)
    v = open_viewer(window, path)
    try:
        settle(v)
        v.cycle_element()
        settle(v, lambda: "M2" in v.loaded)
        v.cycle_element()
        settle(v)
        g = v.generation
        write(path, two.replace('value="0.8, 0.2, 0.1"', 'value="0.1, 0.2, 0.8"'))
        deadline = time.time() + 30
        while v.generation == g and time.time() < deadline:
            v.poll()
            time.sleep(0.005)
        assert v.behind and v.last_reload[1].endswith("not generated") and v.loaded["M2"].stale
        v.cycle_element()
        settle(v)
        assert v.element == "M2" and not v.behind
        assert v.loaded["M2"].values["SR_base_color"] == (0.1, 0.2, 0.8)
    finally:
        v.close()


def test_value_edit_then_a_reload_of_the_old_values_draws_them(tmp_path, window):
    """A value set, then the document read again with its old value before the session caught up (the text
    the program was linked from has that old value): the program is given it back."""
    path = tmp_path / "back.mtlx"
    write(path, doc())
    v = open_viewer(window, path)
    try:
        settle(v)
        prepared, g = v.loaded["M"].prepared, v.generation
        write(path, doc(base_color='value="0.1, 0.6, 0.3"'))
        deadline = time.time() + 30
        while v.generation == g and time.time() < deadline:
            v.poll()
            time.sleep(0.005)
        assert tuple(prepared.prog["SR_base_color"].value) == pytest.approx((0.1, 0.6, 0.3))
        write(path, doc())
        v._reload_now()
        assert v.loaded["M"].prepared is prepared
        assert tuple(prepared.prog["SR_base_color"].value) == pytest.approx((0.8, 0.2, 0.1))
        settle(v)
        img = v.image().copy()
    finally:
        v.close()
    want, _ = fresh(window, tmp_path, doc())
    assert np.abs(img - want).max() <= 1e-6
