"""Kept elements (elementcache.py): a document's materials of one structure instantiated from a checked template give
the shaders of a full generation, byte for byte: under names that collide or nearly collide once they are GLSL
identifiers (with each other, with the library's and the expansions' names, with reserved prefixes, past the
identifier length), with values that are negative, tiny, huge or colour-managed, with nodegraphs of their own, and
where generation makes a choice from a value (a structure then never kept). Also the Hole (a value refusing every
use but being written), the key (every document field in it or named as left out), and the check that refuses a
template that differs from a full generation."""
import copy
import glob
import os
import random
import sys

import pytest

from conftest import EXAMPLES, HAVE_CORPUS, ROOT, TESTSUITE, generate_switched
from mtlxgen import document, elementcache, emit, mxtypes, pipeline

sys.path.insert(0, os.path.join(ROOT, "benchmarks"))

DOCUMENTS = sorted(glob.glob(os.path.join(ROOT, "examples", "**", "*.mtlx"), recursive=True)
                   + glob.glob(os.path.join(ROOT, "tests", "data", "**", "*.mtlx"), recursive=True))
CORPUS_DOCUMENTS = sorted(glob.glob(os.path.join(EXAMPLES, "**", "*.mtlx"), recursive=True)
                          + glob.glob(os.path.join(TESTSUITE, "**", "*.mtlx"), recursive=True)) \
    if HAVE_CORPUS else ["(corpus absent)"]

# names that collide with each other (a / a_b / a_b_c), with the library's and the expansions' identifiers (mg_*,
# geomprop, the inner nodes of standard_surface), with reserved words and prefixes (gl, u, i, float, sample), with
# the sentinels themselves (QX1XQ), Windows' device names as file stems (CON, aux), or run past the identifier
# length (58 and 61 characters: their identifiers are cut), or glsl_identifier changes (_lead, trail_, dbl__u)
NAMES = ["a", "a_b", "b", "mg", "mg_V", "geomprop", "u", "gl", "i", "CON", "aux", "x" * 58, "y" * 61, "N2", "n",
         "p", "c", "float", "sample", "_lead", "trail_", "dbl__u", "M", "M_out", "out", "ss", "ss_coat",
         "ss_coat_bsdf", "QX1XQ", "QX0XQ_base", "base", "Nworld", "z1", "z12", "z1_2"]
VALUES = ["0", "-0.5", "1e-7", "1e30", "-3", "0.1", "2", "1.0", "0.333333333333", "5e-324"]


def awkward_document(path, count=90, seed=7):
    """Six material structures met `count` / 6 times each under NAMES, with VALUES: standard_surface (plain and
    colour-managed), gltf_pbr fed by a nodegraph of its own (inner node names varying), enterprise_pbr (whose
    clearcoat 0 compiles a layer out: a choice from a value), UsdPreviewSurface and open_pbr_surface (with layout
    attributes)."""
    rnd = random.Random(seed)
    parts = ['<?xml version="1.0"?>', '<materialx version="1.39" colorspace="lin_rec709">']

    def v3():
        return ", ".join(rnd.choice(VALUES) for _ in range(3))

    used = set()
    for i in range(count):
        base = rnd.choice(NAMES)
        n, k = base, 0
        while n in used or "M" + n in used:
            k += 1
            n = "%s%d" % (base, k) if not base.endswith("_") else "%sx%d" % (base, k)
        m = "M" + n
        used |= {n, m}
        kind = i % 6
        if kind == 0:
            parts.append('<standard_surface name="%s" type="surfaceshader"><input name="base_color" type="color3" '
                         'value="%s" /><input name="specular_roughness" type="float" value="%s" /></standard_surface>'
                         % (n, v3(), rnd.choice(VALUES)))
        elif kind == 1:
            parts.append('<standard_surface name="%s" type="surfaceshader"><input name="base_color" type="color3" '
                         'value="%s" colorspace="srgb_texture" /><input name="coat" type="float" value="%s" />'
                         '</standard_surface>' % (n, v3(), rnd.choice(VALUES)))
        elif kind == 2:
            g, inner = n + "_g", rnd.choice(["c", "mix1", "mg", "p"])
            parts.append('<nodegraph name="%s"><position name="pos" type="vector3" /><noise3d name="nz" type="float">'
                         '<input name="position" type="vector3" nodename="pos" /><input name="amplitude" type="float" '
                         'value="%s" /></noise3d><mix name="%s" type="color3"><input name="fg" type="color3" '
                         'value="%s" /><input name="bg" type="color3" value="%s" /><input name="mix" type="float" '
                         'nodename="nz" /></mix><output name="out" type="color3" nodename="%s" /></nodegraph>'
                         % (g, rnd.choice(VALUES), inner, v3(), v3(), inner))
            parts.append('<gltf_pbr name="%s" type="surfaceshader"><input name="base_color" type="color3" '
                         'nodegraph="%s" output="out" /><input name="roughness" type="float" value="%s" /></gltf_pbr>'
                         % (n, g, rnd.choice(VALUES)))
        elif kind == 3:
            parts.append('<enterprise_pbr name="%s" type="surfaceshader"><input name="clearcoat" type="float" '
                         'value="%s" /><input name="albedo" type="color3" value="%s" /></enterprise_pbr>'
                         % (n, rnd.choice(["0", "0.5"]), v3()))
        elif kind == 4:
            parts.append('<UsdPreviewSurface name="%s" type="surfaceshader"><input name="diffuseColor" type="color3" '
                         'value="%s" /><input name="roughness" type="float" value="%s" /><input name="opacity" '
                         'type="float" value="%s" /></UsdPreviewSurface>' % (n, v3(), rnd.choice(VALUES),
                                                                              rnd.choice(["1", "0.5", "0"])))
        else:
            parts.append('<open_pbr_surface name="%s" type="surfaceshader" xpos="%d" ypos="3"><input name="base_color" '
                         'type="color3" value="%s" /><input name="specular_ior" type="float" value="%s" />'
                         '</open_pbr_surface>' % (n, i, v3(), rnd.choice(VALUES)))
        parts.append('<surfacematerial name="%s" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="%s" /></surfacematerial>' % (m, n))
    parts.append("</materialx>")
    with open(path, "w") as f:
        f.write("\n".join(parts) + "\n")
    return path


def _generate(path, reuse, **options):
    return generate_switched(path, {elementcache: reuse}, **options)


def _same(path, **options):
    """The shaders with templates kept are those without; returns what was counted (elementcache.STATS' growth)."""
    before = dict(elementcache.STATS)
    on = _generate(path, True, **options)
    grown = {k: elementcache.STATS[k] - before[k] for k in before}
    assert on == _generate(path, False, **options)
    return grown


@pytest.mark.parametrize("options", [{}, {"target": "essl"}, {"target": "vulkan"}, {"max_lights": 2},
                                     {"environment": "prefiltered"}],
                         ids=lambda o: ",".join("%s=%s" % kv for kv in o.items()) or "glsl")
def test_awkward_names_and_values_give_the_shaders_of_a_full_generation(tmp_path, options):
    grown = _same(awkward_document(str(tmp_path / "awkward.mtlx")), **options)
    assert grown["reused"] >= 30, "nothing instantiated: the test tests nothing (%s)" % grown
    assert grown["names"] >= 1, "no name refused: the awkward names test nothing (%s)" % grown
    assert grown["refused"] >= 1, "enterprise_pbr's choice from a value was not refused (%s)" % grown


def test_many_materials_give_the_shaders_of_a_full_generation(tmp_path):
    import bench_generate
    path = bench_generate.many_materials(str(tmp_path / "many.mtlx"), 60)
    grown = _same(path)
    assert grown["recorded"] == 3 and grown["checked"] == 6 and grown["reused"] == 60 - 9, grown
    # three of each structure: none would be instantiated, so nothing is recorded (no sentinel run paid for)
    path = bench_generate.many_materials(str(tmp_path / "nine.mtlx"), 9)
    assert _same(path) == dict.fromkeys(elementcache.STATS, 0)


def test_reduced_interface_and_a_graph_given_are_not_kept(tmp_path):
    import bench_generate
    path = bench_generate.many_materials(str(tmp_path / "many.mtlx"), 12)
    assert _same(path, interface="reduced") == dict.fromkeys(elementcache.STATS, 0)
    session = pipeline.Session(path)
    before = dict(elementcache.STATS)
    for name in session.elements:
        session.shader(name, graph=session.graph(name))
    assert elementcache.STATS == before


def test_a_choice_made_from_a_value_refuses_the_structure(tmp_path):
    """enterprise_pbr compiles its clearcoat layer out where the input is an unconnected 0 (a public uniform's
    initial value read): the sentinel run reads a Hole there, so the structure is never instantiated, and the
    materials with clearcoat 0 and 0.5 keep their own shaders."""
    path = str(tmp_path / "epbr.mtlx")
    lines = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for i in range(8):
        lines.append('<enterprise_pbr name="e%d" type="surfaceshader"><input name="clearcoat" type="float" value="%s" />'
                     '</enterprise_pbr><surfacematerial name="M%d" type="material"><input name="surfaceshader" '
                     'type="surfaceshader" nodename="e%d" /></surfacematerial>' % (i, "0" if i % 2 else "0.5", i, i))
    with open(path, "w") as f:
        f.write("\n".join(lines + ["</materialx>"]) + "\n")
    refused = mxtypes.Hole.refused
    grown = _same(path)
    assert grown["refused"] == 1 and grown["reused"] == 0, grown
    assert mxtypes.Hole.refused > refused
    shaders = pipeline.generate(path)

    def renamed(shader, k):
        return shader.fragment.replace("e0", "e%d" % k).replace("M0", "M%d" % k)

    assert renamed(shaders[0], 2) == shaders[2].fragment
    assert renamed(shaders[0], 1) != shaders[1].fragment      # the layer compiled out in one


def test_a_template_that_differs_from_the_full_generation_is_refused(tmp_path, monkeypatch):
    """The comparison is what keeps a wrong template out: one made wrong on purpose is refused when it is recorded
    and the shaders stay those of a full generation."""
    real = elementcache.Template.make

    def wrong(self, element, st):
        made = real(self, element, st)
        if made is not None:
            made.fragment = made.fragment.replace(";", " ;", 1)
        return made

    monkeypatch.setattr(elementcache.Template, "make", wrong)
    import bench_generate
    grown = _same(bench_generate.many_materials(str(tmp_path / "many.mtlx"), 12))
    assert grown["refused"] == 3 and grown["reused"] == 0, grown


def test_instances_share_no_mutable_data(tmp_path):
    import bench_generate
    path = bench_generate.many_materials(str(tmp_path / "many.mtlx"), 15)
    before = elementcache.STATS["reused"]
    shaders = pipeline.generate(path)
    assert elementcache.STATS["reused"] - before == 6
    a, b = shaders[-1], shaders[-4]         # two instances of one template
    assert a.manifest["uniforms"] is not b.manifest["uniforms"]
    kept = copy.deepcopy(b.manifest)
    a.manifest["uniforms"][0]["value"] = "changed"
    a.manifest["application"].append("changed")
    assert b.manifest == kept


def test_hole_refuses_every_use_and_counts_it():
    h = mxtypes.Hole(3)
    uses = [lambda: h == 0.0, lambda: h != 1, lambda: h < 1, lambda: hash(h), lambda: bool(h), lambda: float(h),
            lambda: int(h), lambda: list(h), lambda: len(h), lambda: h[0], lambda: str(h), lambda: repr(h),
            lambda: "%s" % h, lambda: "{}".format(h), lambda: h + 1, lambda: 1 + h, lambda: -h, lambda: abs(h),
            lambda: h * 2, lambda: 2 ** h, lambda: h.real, lambda: h.strip(), lambda: 0.5 in [h], lambda: {h: 1},
            lambda: round(h)]
    for use in uses:
        before = mxtypes.Hole.refused
        with pytest.raises(TypeError):
            use()
        assert mxtypes.Hole.refused > before
    before = mxtypes.Hole.refused
    assert copy.copy(h) is h and copy.deepcopy([h])[0] is h and h is not None and isinstance(h, mxtypes.Hole)
    assert mxtypes.glsl_literal("color3", h) == "\x1e3:color3\x1e" and emit.manifest_value(h) is h
    assert mxtypes.Hole.refused == before


def test_the_key_holds_every_document_field_or_says_why_not():
    """A field added to the document's classes later must join the key's lists or the ones it handles itself."""
    from dataclasses import fields
    handled = {document.Port: set(elementcache.PORT_FIELDS) | {"loc", "value", "text", "nodename", "nodegraph"},
               document.Node: set(elementcache.NODE_FIELDS) | {"name", "loc", "inputs", "outputs", "tokens", "attrs"},
               document.NodeGraph: set(elementcache.GRAPH_FIELDS) | {"name", "loc", "inputs", "outputs", "tokens",
                                                                     "nodes"}}
    for cls, names in handled.items():
        assert {f.name for f in fields(cls)} == names, cls.__name__


KEY_DOC = """<?xml version="1.0"?>
<materialx version="1.39">
<standard_surface name="A" type="surfaceshader"><input name="base" type="float" value="0.5" /></standard_surface>
<surfacematerial name="MA" type="material"><input name="surfaceshader" type="surfaceshader" nodename="A" />
</surfacematerial>
<standard_surface name="B" type="surfaceshader" xpos="3"><input name="base" type="float" value="0.7" />
</standard_surface>
<surfacematerial name="MB" type="material"><input name="surfaceshader" type="surfaceshader" nodename="B" />
</surfacematerial>
<standard_surface name="C" type="surfaceshader"><input name="base" type="float" value="0.5" />
<input name="thin_walled" type="boolean" value="true" /></standard_surface>
<surfacematerial name="MC" type="material"><input name="surfaceshader" type="surfaceshader" nodename="C" />
</surfacematerial>
<standard_surface name="D" type="surfaceshader"><input name="base" type="float" value="0.5" />
<input name="base_color" type="color3" value="0.5, 0.5, 0.5" colorspace="srgb_texture" /></standard_surface>
<surfacematerial name="MD" type="material"><input name="surfaceshader" type="surfaceshader" nodename="D" />
</surfacematerial>
<constant name="k" type="float"><input name="value" type="float" value="0.5" /></constant>
<standard_surface name="E" type="surfaceshader"><input name="base" type="float" nodename="k" /></standard_surface>
<surfacematerial name="ME" type="material"><input name="surfaceshader" type="surfaceshader" nodename="E" />
</surfacematerial>
<standard_surface name="F" type="surfaceshader"><input name="coat" type="float" value="0.5" /></standard_surface>
<surfacematerial name="MF" type="material"><input name="surfaceshader" type="surfaceshader" nodename="F" />
</surfacematerial>
</materialx>
"""


def test_the_key_is_the_structure_up_to_names_float_values_and_layout(tmp_path):
    path = str(tmp_path / "keys.mtlx")
    with open(path, "w") as f:
        f.write(KEY_DOC)
    doc = pipeline.Session(path).doc
    keys = {m: elementcache.structure(doc, m) for m in ("MA", "MB", "MC", "MD", "ME", "MF")}
    assert keys["MA"].key == keys["MB"].key                    # renamed, another value, laid out elsewhere
    assert keys["MA"].names == ["MA", "A"] and [p.value for p in keys["MB"].holes] == [0.7]
    others = [keys[m].key for m in ("MA", "MC", "MD", "ME", "MF")]
    assert None not in others and len(set(others)) == 5        # a boolean, a colour space, a link, another input
    assert elementcache.structure(doc, "nothing").key is None


def test_names_alike_in_different_scopes_are_different_elements(tmp_path):
    """A nodegraph named like a scope ('node', 'graph') whose inner node is named like a top-level node: each is
    numbered as its own element (the inner one read where the graph reads it), and the shaders are a full
    generation's."""
    lines = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for i in range(6):
        g, c = ("node", "graph")[i] if i < 2 else "g%d" % i, "c%d" % i
        lines.append('<nodegraph name="%s"><constant name="%s" type="color3"><input name="value" type="color3" '
                     'value="0.%d, 0.2, 0.3" /></constant><output name="out" type="color3" nodename="%s" /></nodegraph>'
                     % (g, c, i, c))
        lines.append('<standard_surface name="%s" type="surfaceshader"><input name="base_color" type="color3" '
                     'nodegraph="%s" output="out" /><input name="base" type="float" value="0.%d" /></standard_surface>'
                     % (c, g, i))
        lines.append('<surfacematerial name="M%d" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="%s" /></surfacematerial>' % (i, c))
    path = str(tmp_path / "scopes.mtlx")
    with open(path, "w") as f:
        f.write("\n".join(lines + ["</materialx>"]) + "\n")
    st = elementcache.structure(pipeline.Session(path).doc, "M0")
    assert st.names == ["M0", "c0", "node", "c0"] and st.key is not None
    grown = _same(path)
    assert grown["reused"] == 3, grown


def test_names_that_meet_inside_one_shader_are_generated_in_full(tmp_path):
    """A material whose nodegraph's inner node is named like one of its standard_surface's expanded nodes
    ('s4_coat_gamma' beside s4's 'coat_gamma'): a fresh generation gives one of the two another name, the template
    (made where they were two names) would not, so that material is generated in full, the others instantiated."""
    lines = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for i in range(7):
        inner = "s%d_coat_gamma" % i if i in (4, 6) else "c%d" % i
        lines.append('<nodegraph name="g%d"><constant name="%s" type="color3"><input name="value" type="color3" '
                     'value="0.%d, 0.2, 0.3" /></constant><output name="out" type="color3" nodename="%s" /></nodegraph>'
                     % (i, inner, i, inner))
        lines.append('<standard_surface name="s%d" type="surfaceshader"><input name="base_color" type="color3" '
                     'nodegraph="g%d" output="out" /></standard_surface>' % (i, i))
        lines.append('<surfacematerial name="M%d" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="s%d" /></surfacematerial>' % (i, i))
    path = str(tmp_path / "meet.mtlx")
    with open(path, "w") as f:
        f.write("\n".join(lines + ["</materialx>"]) + "\n")
    grown = _same(path)
    assert grown["names"] == 2 and grown["reused"] == 2, grown
    fresh = pipeline.generate(path)[4].fragment
    assert "s4_coat_gamma2" in fresh or "s4_coat_gamma_out2" in fresh


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: os.path.relpath(p, ROOT))
def test_documents_give_the_shaders_of_a_full_generation(path):
    _same(path)


@pytest.mark.corpus
@pytest.mark.parametrize("path", CORPUS_DOCUMENTS, ids=lambda p: os.path.relpath(p, ROOT))
def test_corpus_documents_give_the_shaders_of_a_full_generation(path):
    if not HAVE_CORPUS:
        pytest.skip("corpus absent")
    _same(path)


hypothesis = pytest.importorskip("hypothesis", reason="hypothesis is a test dependency (pip install -e '.[test]')")
from hypothesis import HealthCheck, given, seed, settings, strategies as st  # noqa: E402

FUZZ_EXAMPLES = int(os.environ.get("MTLXGEN_FUZZ_EXAMPLES", "25"))
FUZZ_SEED = os.environ.get("MTLXGEN_FUZZ_SEED")
FLOATS = st.one_of(st.sampled_from([0.0, -0.0, 1.0, 0.5, -2.0]),
                   st.floats(allow_nan=False, allow_infinity=False, width=32))

# (XML of a structure's shader node {n}, with {v0} {v1} {v2} float values and {g} its own nodegraph's name, or None)
STRUCTURES = [
    ('<standard_surface name="{n}" type="surfaceshader"><input name="base_color" type="color3" value="{v0}, {v1}, '
     '{v2}" /><input name="specular_roughness" type="float" value="{v1}" /></standard_surface>', None),
    ('<standard_surface name="{n}" type="surfaceshader"><input name="base_color" type="color3" value="{v0}, {v1}, '
     '{v2}" colorspace="srgb_texture" /><input name="thin_walled" type="boolean" value="true" /></standard_surface>',
     None),
    ('<gltf_pbr name="{n}" type="surfaceshader"><input name="base_color" type="color3" nodegraph="{g}" output="out" />'
     '<input name="roughness" type="float" value="{v2}" /></gltf_pbr>',
     '<nodegraph name="{g}"><input name="tint" type="color3" value="{v1}, {v0}, {v2}" /><position name="{i}p" '
     'type="vector3" /><multiply name="{i}m" type="color3"><input name="in1" type="color3" interfacename="tint" />'
     '<input name="in2" type="float" value="{v0}" /></multiply><output name="out" type="color3" nodename="{i}m" />'
     '</nodegraph>'),
    ('<open_pbr_surface name="{n}" type="surfaceshader" xpos="{v0}"><input name="base_weight" type="float" '
     'value="{v2}" /></open_pbr_surface>', None),
]


@st.composite
def documents(draw):
    """1-2 structures, each met 4-7 times under names drawn from NAMES (made unique), values drawn from FLOATS."""
    lines = ['<?xml version="1.0"?>', '<materialx version="1.39" colorspace="lin_rec709">']
    used = set()

    def unique(base):
        name, k = base, 0
        while name in used:
            k += 1
            name = "%s%s" % (base, draw(st.sampled_from(["1", "a", "_b", "2"])))
            base = name if k > 3 else base
        used.add(name)
        return name

    for index in draw(st.lists(st.integers(0, len(STRUCTURES) - 1), min_size=1, max_size=2)):
        shader, graph = STRUCTURES[index]
        for _ in range(draw(st.integers(4, 7))):
            n = unique(draw(st.sampled_from(NAMES)))
            values = {"v%d" % j: repr(float(draw(FLOATS))) for j in range(3)}
            g = unique(draw(st.sampled_from(["g", "node", "graph", "NG"]))) if graph else None
            if graph:
                lines.append(graph.format(g=g, i=draw(st.sampled_from(["", "a", "mg_", "u"])), **values))
            lines.append(shader.format(n=n, g=g, **values))
            lines.append('<surfacematerial name="%s" type="material"><input name="surfaceshader" type="surfaceshader" '
                         'nodename="%s" /></surfacematerial>' % (unique("M" + n), n))
    lines.append("</materialx>")
    return "\n".join(lines) + "\n"


def _fuzz_settings(fn):
    s = settings(max_examples=FUZZ_EXAMPLES, deadline=None, derandomize=FUZZ_SEED is None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture,
                                        HealthCheck.data_too_large])(fn)
    return seed(int(FUZZ_SEED))(s) if FUZZ_SEED is not None else s


REUSED = []


@_fuzz_settings
@given(text=documents())
def test_generated_documents_give_the_shaders_of_a_full_generation(tmp_path_factory, text):
    path = str(tmp_path_factory.mktemp("elements") / "doc.mtlx")
    with open(path, "w") as f:
        f.write(text)
    REUSED.append(_same(path)["reused"])


def test_the_generated_documents_were_instantiated():
    """(after the property test: its documents must have had materials instantiated, or it tested nothing)"""
    if not REUSED:
        pytest.skip("the property test did not run")
    assert sum(REUSED) >= FUZZ_EXAMPLES, REUSED
