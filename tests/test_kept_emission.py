"""Kept emissions of kept expansions (emitcache.py): the shaders generated with a replayed expansion's emission reused
are those of a full emission, byte for byte, wherever names collide or are awkward (names that differ only by
case or by characters glsl_identifier maps alike, ending in '_' or digits, cut and hashed for length, a document
node named like an expansion's inner node, two expansions of one key in one shader), for every target and
emitter setting, and in every example, test and corpus document."""
import glob
import os
import sys

import pytest

from conftest import EXAMPLES, HAVE_CORPUS, ROOT, TESTSUITE, generate_switched
from mtlxgen import elementcache, emitcache, pipeline
from mtlxgen.graph import _Expansion

sys.path.insert(0, os.path.join(ROOT, "benchmarks"))

DOCUMENTS = sorted(glob.glob(os.path.join(ROOT, "examples", "**", "*.mtlx"), recursive=True)
                   + glob.glob(os.path.join(ROOT, "tests", "data", "**", "*.mtlx"), recursive=True))
CORPUS_DOCUMENTS = sorted(glob.glob(os.path.join(EXAMPLES, "**", "*.mtlx"), recursive=True)
                          + glob.glob(os.path.join(TESTSUITE, "**", "*.mtlx"), recursive=True)) \
    if HAVE_CORPUS else ["(corpus absent)"]

LONG = "s" + "x" * 70          # past IDENTIFIER_CHARS: ids and names cut and hashed
NAMES = ["ss_a", "SS_a", "ss_b_", "ss_b", "ss__c", "ss_c", "s1", "s12", "s1_2", "u_ss", "gl_x", "main", "ssq",
         LONG, LONG + "y", "ss9", "ss9_", "coat", "out", "ss0_main_roughness", "v_normal"]
CATEGORIES = ["standard_surface", "open_pbr_surface", "gltf_pbr"]


def awkward_document(path):
    parts = ['<?xml version="1.0"?>', '<materialx version="1.39">']
    for i, n in enumerate(NAMES * 2):
        repeat = i // len(NAMES)
        name = n if repeat == 0 else n + "r"
        category = CATEGORIES[i % 3]
        inputs = '<input name="base_color" type="color3" value="%.2f, 0.3, 0.2" />' % (i / 50)
        if repeat == 1 and category != "gltf_pbr":
            # an outer input read from a document node named like the expansion's inner node
            inputs += '<input name="coat_roughness" type="float" nodename="%s_coat_roughness" />' % name
            parts.append('<constant name="%s_coat_roughness" type="float"><input name="value" type="float" '
                         'value="%.2f" /></constant>' % (name, i / 60))
        parts.append('<%s name="%s" type="surfaceshader">%s</%s>' % (category, name, inputs, category))
        parts.append('<surfacematerial name="M_%s" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="%s" /></surfacematerial>' % (name, name))
    # two expansions of one key in one shader, their names colliding under glsl_identifier
    for j, (a, b) in enumerate([("mx", "mx_"), ("p_", "p__"), ("q1", "q"), ("ssA", "ssa"), ("m2_main", "m2")]):
        for k, name in enumerate((a, b)):
            parts.append('<standard_surface name="%s" type="surfaceshader"><input name="specular_roughness" '
                         'type="float" value="%.2f" /></standard_surface>' % (name, 0.1 * (j + k)))
        parts.append('<mix name="%sm_mix" type="surfaceshader"><input name="fg" type="surfaceshader" nodename="%s" />'
                     '<input name="bg" type="surfaceshader" nodename="%s" /><input name="mix" type="float" '
                     'value="0.5" /></mix>' % (a, a, b))
        parts.append('<surfacematerial name="MM%d" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="%sm_mix" /></surfacematerial>' % (j, a))
    # an outer input shared by two inputs, from a nodegraph whose interface is a public uniform
    parts.append('<nodegraph name="NGT"><input name="tint" type="color3" value="0.5, 0.5, 0.5" />'
                 '<multiply name="mul" type="color3"><input name="in1" type="color3" interfacename="tint" />'
                 '<input name="in2" type="float" value="0.5" /></multiply>'
                 '<output name="out" type="color3" nodename="mul" /></nodegraph>')
    for i in range(6):
        parts.append('<standard_surface name="t%d" type="surfaceshader"><input name="base_color" type="color3" '
                     'nodegraph="NGT" output="out" /><input name="coat_color" type="color3" nodegraph="NGT" '
                     'output="out" /></standard_surface>' % i)
        parts.append('<surfacematerial name="MT%d" type="material"><input name="surfaceshader" type="surfaceshader" '
                     'nodename="t%d" /></surfacematerial>' % (i, i))
    parts.append("</materialx>")
    with open(path, "w") as f:
        f.write("\n".join(parts) + "\n")
    return path


def _generate(path, reuse, **options):
    """With emission reuse on or off; kept elements off (elementcache.py: an element instantiated from its template
    emits nothing, so it would leave the emissions of most materials untested)."""
    return generate_switched(path, {emitcache: reuse, elementcache: False}, **options)


def _same(path, **options):
    before = dict(emitcache.STATS)
    on = _generate(path, True, **options)
    reused = emitcache.STATS["reused"] - before["reused"]
    assert on == _generate(path, False, **options)
    return reused


@pytest.mark.parametrize("options", [{}, {"interface": "reduced"}, {"target": "essl"}, {"target": "vulkan"},
                                     {"max_lights": 3}, {"environment": "prefiltered"}],
                         ids=lambda o: ",".join("%s=%s" % kv for kv in o.items()) or "complete")
def test_awkward_names_give_the_shaders_of_a_full_emission(tmp_path, options):
    path = awkward_document(str(tmp_path / "awkward.mtlx"))
    reused = _same(path, **options)
    if options.get("interface") != "reduced":
        assert reused > 20, "emissions were not reused: the test tests nothing"


def test_many_materials_give_the_shaders_of_a_full_emission(tmp_path):
    import bench_generate
    path = bench_generate.many_materials(str(tmp_path / "many.mtlx"), 60)
    assert _same(path) >= 40


def test_a_recording_that_differs_from_the_full_emission_is_refused(tmp_path, monkeypatch):
    """The check is what keeps a wrong recording out: one made wrong on purpose (a line changed) is refused when
    it is recorded, and the shaders stay those of a full emission."""
    real = emitcache._record

    def wrong(em, run):
        rec = real(em, run)
        if rec is not None:
            parts = rec.texts.parts             # one ';' of the recorded text made ' ;'
            k = next(i for i, p in enumerate(parts) if ";" in p)
            parts[k] = parts[k].replace(";", " ;", 1)
        return rec

    monkeypatch.setattr(emitcache, "_record", wrong)
    from mtlxgen import library
    for t in library.load_library().expansions.values():
        if isinstance(t, _Expansion):
            t.emitted.clear()
    path = awkward_document(str(tmp_path / "awkward.mtlx"))
    before = dict(emitcache.STATS)
    assert _same(path) == 0
    assert emitcache.STATS["refused"] > before["refused"]
    for t in library.load_library().expansions.values():
        if isinstance(t, _Expansion):
            t.emitted.clear()         # (the refusals, kept per expansion, would keep later tests from reusing)


@pytest.mark.parametrize("path", DOCUMENTS, ids=lambda p: os.path.relpath(p, ROOT))
def test_documents_give_the_shaders_of_a_full_emission(path):
    _same(path)
    _same(path, interface="reduced")


@pytest.mark.corpus
@pytest.mark.parametrize("path", CORPUS_DOCUMENTS, ids=lambda p: os.path.relpath(p, ROOT))
def test_corpus_documents_give_the_shaders_of_a_full_emission(path):
    if not HAVE_CORPUS:
        pytest.skip("corpus absent")
    _same(path)


def test_the_check_compares_every_field_emission_changes():
    """_check compares the emitter's state field by field (emitcache._STATE); a field added to the Emitter later must
    join that list or this one of fields a run leaves as it found them (settings, the graph and its closure plan,
    the context stack a run leaves balanced) or compares on its own (the writer's lines, current)."""
    from mtlxgen import emit
    s = pipeline.Session(os.path.join(ROOT, "examples", "quick_start.mtlx"))
    em = emit.Emitter(s.graph(list(s.elements)[0]))
    unchanged = {"graph", "closure_plan", "environment", "target", "max_lights", "compact", "_contexts",
                 "writer", "body", "current"}
    assert set(vars(em)) - set(emitcache._STATE) - unchanged == set()
