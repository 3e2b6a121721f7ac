"""Kept expansions and kept emissions against fresh generation, on documents hypothesis makes: many materials of
standard_surface, open_pbr_surface and gltf_pbr whose names collide or nearly collide under GLSL's rules, whose
inputs are values, colour-managed values or connections to small upstream nodes (shared between materials or not),
each material's structure met several times in one document so that expansions are recorded and replayed and their
emissions recorded, checked and reused. The shaders must be byte for byte those of a generation that keeps nothing
(every kept expansion forgotten before each element, emission reuse off).

MTLXGEN_FUZZ_EXAMPLES (default 25) sets how many documents; derandomized (reproducible in CI) unless
MTLXGEN_FUZZ_SEED seeds hypothesis."""
import os

import pytest

hypothesis = pytest.importorskip("hypothesis", reason="hypothesis is a test dependency (pip install -e '.[test]')")
from hypothesis import HealthCheck, example, given, seed, settings, strategies as st  # noqa: E402

from mtlxgen import emitcache, library, pipeline  # noqa: E402

EXAMPLES = int(os.environ.get("MTLXGEN_FUZZ_EXAMPLES", "25"))
SEED = os.environ.get("MTLXGEN_FUZZ_SEED")

# per shader category: its inputs this test sets, by type (names from the libraries' nodedefs)
INPUTS = {
    "standard_surface": {"float": ["base", "specular_roughness", "metalness", "coat", "coat_roughness",
                                   "thin_film_thickness", "transmission", "sheen"],
                         "color3": ["base_color", "coat_color", "specular_color"],
                         "vector3": ["normal", "coat_normal"]},
    "open_pbr_surface": {"float": ["base_weight", "specular_roughness", "base_metalness", "coat_weight",
                                   "thin_film_weight", "transmission_weight", "fuzz_weight"],
                         "color3": ["base_color", "coat_color", "specular_color"],
                         "vector3": ["geometry_normal", "geometry_coat_normal"]},
    "gltf_pbr": {"float": ["roughness", "metallic", "clearcoat", "iridescence", "iridescence_thickness",
                           "transmission"],
                 "color3": ["base_color", "sheen_color"],
                 "vector3": ["normal", "clearcoat_normal"]},
}
# names that collide or nearly collide once made GLSL identifiers (case, '_' runs, reserved prefixes, digits, a
# name past the identifier length, names like the expansions' inner nodes)
STEMS = ["ss", "SS", "s_", "s__", "a1", "a1_", "a_1", "main", "u_x", "gl_y", "coat", "out", "x" * 70, "x" * 71,
         "m_main_roughness", "n"]

# upstream nodes by type: (XML of the node named {n}, its output type); {v} a value of that type
UPSTREAM = {
    "float": ['<constant name="{n}" type="float"><input name="value" type="float" value="{v}" /></constant>',
              '<texcoord name="{n}_uv" type="vector2" /><extract name="{n}" type="float">'
              '<input name="in" type="vector2" nodename="{n}_uv" /><input name="index" type="integer" value="0" />'
              '</extract>'],
    "color3": ['<constant name="{n}" type="color3"><input name="value" type="color3" value="{v}, 0.4, 0.2" />'
               '</constant>',
               '<position name="{n}_p" type="vector3" /><convert name="{n}" type="color3">'
               '<input name="in" type="vector3" nodename="{n}_p" /></convert>'],
    "vector3": ['<normal name="{n}" type="vector3" space="world" />',
                '<normalmap name="{n}" type="vector3"><input name="in" type="vector3" value="0.5, {v}, 1.0" />'
                '</normalmap>'],
}


@st.composite
def input_settings(draw, category):
    """[(input name, type, how)] for one material: how is ("value", v), ("managed", v) or ("node", k, shared)."""
    out = []
    for t, names in INPUTS[category].items():
        for name in draw(st.lists(st.sampled_from(names), max_size=3, unique=True)):
            how = draw(st.sampled_from(["value", "managed", "node"] if t == "color3" else ["value", "node"]))
            v = draw(st.sampled_from([0.0, 0.25, 0.5, 1.0]))
            if how == "node":
                out.append((name, t, ("node", draw(st.integers(0, 1)), draw(st.booleans()))))
            else:
                out.append((name, t, (how, v)))
    return out


@st.composite
def documents(draw):
    """A document's text: a few material structures, each met 3 to 6 times under different names and values."""
    lines = ['<?xml version="1.0"?>', '<materialx version="1.39" colorspace="lin_rec709">']
    used, shared = set(), {}
    serial = 0
    for _ in range(draw(st.integers(1, 3))):
        category = draw(st.sampled_from(sorted(INPUTS)))
        settings_ = draw(input_settings(category))
        for _ in range(draw(st.integers(3, 6))):
            name = draw(st.sampled_from(STEMS))
            while name in used:
                name += draw(st.sampled_from(["_", "1", "a", "A"]))
            used.add(name)
            serial += 1
            inputs = []
            for iname, t, how in settings_:
                if how[0] == "node":
                    k, share = how[1], how[2]
                    up = "up_%s_%d" % (t, k) if share else "%s_%s" % (name, iname)
                    if up not in shared:
                        shared[up] = True
                        lines.append(UPSTREAM[t][k].format(n=up, v=draw(st.sampled_from(["0.1", "0.6"]))))
                    inputs.append('<input name="%s" type="%s" nodename="%s" />' % (iname, t, up))
                else:
                    v = how[1] + serial / 1000.0
                    value = ", ".join(["%.3f" % v] * (3 if t in ("color3", "vector3") else 1))
                    cs = ' colorspace="srgb_texture"' if how[0] == "managed" else ""
                    inputs.append('<input name="%s" type="%s" value="%s"%s />' % (iname, t, value, cs))
            lines.append('<%s name="%s" type="surfaceshader">%s</%s>' % (category, name, "".join(inputs), category))
            lines.append('<surfacematerial name="M_%s" type="material"><input name="surfaceshader" '
                         'type="surfaceshader" nodename="%s" /></surfacematerial>' % (name, name))
    lines.append("</materialx>")
    return "\n".join(lines) + "\n"


def _shaders(path, keep, **options):
    saved = emitcache.REUSE
    emitcache.REUSE = keep
    try:
        lib = library.load_library()
        lib.expansions.clear()
        if keep:
            return [(s.element, s.vertex, s.fragment, s.manifest)
                    for s in pipeline.generate(path, **options)]
        out = []
        for name in pipeline.Session(path).elements:
            lib.expansions.clear()                      # nothing kept: every element a full walk and emission
            s = pipeline.generate(path, [name], **options)[0]
            out.append((s.element, s.vertex, s.fragment, s.manifest))
        return out
    finally:
        emitcache.REUSE = saved
        library.load_library().expansions.clear()


def _check(tmp_path_factory, text, **options):
    path = str(tmp_path_factory.mktemp("kept") / "doc.mtlx")
    with open(path, "w") as f:
        f.write(text)
    kept = _shaders(path, True, **options)
    assert kept == _shaders(path, False, **options), text


def _settings(fn):
    s = settings(max_examples=EXAMPLES, deadline=None, derandomize=SEED is None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture,
                                        HealthCheck.data_too_large])(fn)
    return seed(int(SEED))(s) if SEED is not None else s


def _one_source_document():
    """standard_surfaces whose normal and coat_normal are one Source (both the geometry's normal), then ones whose
    normal is a normal map: a kept expansion keyed without which inputs are one Source reads the wrong normal."""
    lines = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for n in ("y1", "y2", "y3", "x1", "x2"):
        inputs = ""
        if n[0] == "x":
            lines.append('<normalmap name="%s_nm" type="vector3"><input name="in" type="vector3" value="0.5, 0.6, 1.0" />'
                         '</normalmap>' % n)
            inputs = '<input name="normal" type="vector3" nodename="%s_nm" />' % n
        lines.append('<standard_surface name="%s" type="surfaceshader">%s</standard_surface>' % (n, inputs))
        lines.append('<surfacematerial name="M_%s" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="%s" /></surfacematerial>' % (n, n))
    lines.append("</materialx>")
    return "\n".join(lines) + "\n"


@_settings
@given(text=documents())
@example(text=_one_source_document())
def test_generated_documents_give_the_shaders_of_a_generation_that_keeps_nothing(tmp_path_factory, text):
    _check(tmp_path_factory, text)


@_settings
@given(text=documents())
def test_the_same_in_the_reduced_interface_and_for_webgl(tmp_path_factory, text):
    _check(tmp_path_factory, text, interface="reduced")
    _check(tmp_path_factory, text, target="essl")


def test_the_generated_documents_reuse_emissions(tmp_path_factory):
    """The property above is about something: documents of this shape do replay expansions and reuse emissions."""
    lines = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for name in STEMS[:8]:
        lines.append('<standard_surface name="%s" type="surfaceshader"><input name="base_color" type="color3" '
                     'value="0.2, 0.3, 0.4" /></standard_surface>' % name)
        lines.append('<surfacematerial name="M_%s" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="%s" /></surfacematerial>' % (name, name))
    lines.append("</materialx>")
    text = "\n".join(lines) + "\n"
    before = dict(emitcache.STATS)
    _check(tmp_path_factory, text)
    assert emitcache.STATS["reused"] > before["reused"]
