"""Nodegraphs and nodes with several outputs (issue 16, class 2): the output a connection names is the one drawn,
as MaterialX 1.39 draws it, and the renderable elements of such documents are the ones MaterialX finds."""
import numpy as np
import pytest

from mtlxgen.graph import build as graph
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError, Warnings
from util import assert_parity_with_materialx, generate_one, write_doc

RED, GREEN, BLUE = (0.8, 0.1, 0.05), (0.1, 0.7, 0.2), (0.05, 0.2, 0.9)


def unlit(name, connection):
    """A surface_unlit `name`_s emitting what `connection` (attributes of its input) reads, and material `name`."""
    return ('<surface_unlit name="%s_s" type="surfaceshader"><input name="emission_color" type="color3" %s />'
            '</surface_unlit><surfacematerial name="%s" type="material"><input name="surfaceshader" '
            'type="surfaceshader" nodename="%s_s" /></surfacematerial>' % (name, connection, name, name))


def constant(name, rgb):
    return ('<constant name="%s" type="color3"><input name="value" type="color3" value="%s" /></constant>'
            % (name, ", ".join(map(str, rgb))))


THREE = ('<nodegraph name="g">%s%s%s<output name="first" type="color3" nodename="c1" />'
         '<output name="second" type="color3" nodename="c2" /><output name="third" type="color3" nodename="c3" />'
         '</nodegraph>' % (constant("c1", RED), constant("c2", GREEN), constant("c3", BLUE)))

# a document nodedef with two outputs, implemented by a nodegraph: `two` scales each colour by k
TWO = """
<nodedef name="ND_two" node="two"><input name="k" type="float" value="0.5" />
  <output name="a" type="color3" /><output name="b" type="color3" /></nodedef>
<nodegraph name="NG_two" nodedef="ND_two">
  <multiply name="ma" type="color3"><input name="in1" type="color3" value="%s" /><input name="in2" type="float" interfacename="k" /></multiply>
  <multiply name="mb" type="color3"><input name="in1" type="color3" value="%s" /><input name="in2" type="float" interfacename="k" /></multiply>
  %%s
</nodegraph>""" % (", ".join(map(str, RED)), ", ".join(map(str, BLUE)))
TWO_OUTPUTS = '<output name="a" type="color3" nodename="ma" /><output name="b" type="color3" nodename="mb" />'


def centre(renderer, shader):
    img = renderer.render(shader)
    h, w = img.shape[:2]
    return img[h // 2, w // 2, :3]


def test_a_material_reads_the_nodegraph_output_it_names(tmp_path, renderer, reference):
    path = write_doc(tmp_path, THREE + unlit("m1", 'nodegraph="g" output="first"') +
                     unlit("m2", 'nodegraph="g" output="second"') + unlit("m3", 'nodegraph="g" output="third"'))
    for element, rgb in (("m1", RED), ("m2", GREEN), ("m3", BLUE)):
        assert np.allclose(centre(renderer, generate_one(path, element)), rgb, atol=0.01), element
        assert_parity_with_materialx(renderer, reference, path, element)


def test_a_node_of_a_multi_output_nodedef_gives_the_output_read(tmp_path, renderer, reference):
    path = write_doc(tmp_path, TWO % TWO_OUTPUTS + """
<two name="t" type="multioutput"><input name="k" type="float" value="0.8" /></two>
<nodegraph name="outer"><two name="t2" type="multioutput"><input name="k" type="float" value="1" /></two>
  <add name="ad" type="color3"><input name="in1" type="color3" nodename="t2" output="b" /><input name="in2" type="color3" value="0, 0, 0" /></add>
  <output name="o" type="color3" nodename="ad" /></nodegraph>""" + unlit("ma", 'nodename="t" output="a"') +
                     unlit("mb", 'nodename="t" output="b"') + unlit("mg", 'nodegraph="outer" output="o"'))
    expected = {"ma": 0.8 * np.array(RED), "mb": 0.8 * np.array(BLUE), "mg": np.array(BLUE)}
    for element, rgb in expected.items():
        assert np.allclose(centre(renderer, generate_one(path, element)), rgb, atol=0.01), element
        assert_parity_with_materialx(renderer, reference, path, element)


def test_a_library_multi_output_node_gives_each_output(tmp_path, renderer, reference):
    path = write_doc(tmp_path, """
<constant name="v" type="vector3"><input name="value" type="vector3" value="0.2, 0.5, 0.9" /></constant>
<separate3 name="sp" type="multioutput"><input name="in" type="vector3" nodename="v" /></separate3>
<combine3 name="cb" type="color3"><input name="in1" type="float" nodename="sp" output="outz" />
  <input name="in2" type="float" nodename="sp" output="outx" /><input name="in3" type="float" nodename="sp" output="outy" /></combine3>
""" + unlit("m", 'nodename="cb"'))
    assert np.allclose(centre(renderer, generate_one(path, "m")), (0.9, 0.2, 0.5), atol=0.01)
    assert_parity_with_materialx(renderer, reference, path, "m")


@pytest.mark.parametrize("connection,first", [
    ('nodegraph="g"', RED),                 # a nodegraph of three outputs read without naming one
    ('nodename="t"', 0.5 * np.array(RED)),  # a multi-output node read without naming one
])
def test_a_connection_naming_no_output_reads_the_first_with_a_warning(tmp_path, renderer, reference, connection,
                                                                        first):
    path = write_doc(tmp_path, THREE + TWO % TWO_OUTPUTS + '<two name="t" type="multioutput" />' +
                     unlit("m", connection))
    seen = Warnings()
    shader = pipeline.generate(path, elements=["m"], warnings=seen)[0]
    assert len(seen) == 1 and "without naming" in seen.lines()[0] and "as MaterialX does" in seen.lines()[0]
    assert np.allclose(centre(renderer, shader), first, atol=0.01)
    assert_parity_with_materialx(renderer, reference, path, "m")


def test_implementation_outputs_are_matched_by_name_not_position(tmp_path, renderer, reference):
    """NG_two lists its outputs b, a where ND_two declares a, b. The spec pairs them by name, and so do we;
    MaterialX 1.39.5 pairs them by position (its function takes the graph's order, its call passes the
    nodedef's), so it draws a where b is read: a difference kept on purpose (docs/differences)."""
    reordered = '<output name="b" type="color3" nodename="mb" /><output name="a" type="color3" nodename="ma" />'
    path = write_doc(tmp_path, TWO % reordered + '<two name="t" type="multioutput" />' +
                     unlit("m", 'nodename="t" output="b"'))
    assert np.allclose(centre(renderer, generate_one(path, "m")), 0.5 * np.array(BLUE), atol=0.01)
    vs, fs, tex, _ = reference.generate(path, "m")
    theirs, _ = renderer.render_timed(vs, fs, {}, tex)
    h, w = theirs.shape[:2]
    assert np.allclose(theirs[h // 2, w // 2, :3], 0.5 * np.array(RED), atol=0.01), \
        "MaterialX now pairs implementation outputs by name: drop the entry in docs/differences"


@pytest.mark.parametrize("outputs,read,rgb", [
    # output names the nodedef does not declare, as many as it declares: MaterialX pairs them by position
    ('<output name="x" type="color3" nodename="ma" /><output name="y" type="color3" nodename="mb" />', "b", BLUE),
    ('<output name="x" type="color3" nodename="ma" /><output name="b" type="color3" nodename="mb" />', "a", RED),
])
def test_implementation_outputs_named_otherwise_pair_by_position(tmp_path, renderer, reference, outputs, read, rgb):
    path = write_doc(tmp_path, TWO % outputs + '<two name="t" type="multioutput" />' +
                     unlit("m", 'nodename="t" output="%s"' % read))
    seen = Warnings()
    shader = pipeline.generate(path, elements=["m"], warnings=seen)[0]
    assert len(seen) == 1 and "paired by position, as MaterialX pairs them" in seen.lines()[0], seen.lines()
    assert np.allclose(centre(renderer, shader), 0.5 * np.array(rgb), atol=0.01)
    assert_parity_with_materialx(renderer, reference, path, "m")


def test_a_single_output_implementation_named_otherwise_is_its_output(tmp_path, renderer, reference):
    path = write_doc(tmp_path, """
<nodedef name="ND_one" node="one"><output name="out" type="color3" /></nodedef>
<nodegraph name="NG_one" nodedef="ND_one">%s<output name="result" type="color3" nodename="c" /></nodegraph>
<one name="t" type="color3" />""" % constant("c", GREEN) + unlit("m", 'nodename="t"'))
    seen = Warnings()
    shader = pipeline.generate(path, elements=["m"], warnings=seen)[0]
    assert len(seen) == 1 and "names its outputs 'result' where ND_one declares 'out'" in seen.lines()[0]
    assert np.allclose(centre(renderer, shader), GREEN, atol=0.01)
    assert_parity_with_materialx(renderer, reference, path, "m")


def test_an_implementation_lacking_an_output_is_refused(tmp_path):
    # MaterialX generates a call with more arguments than its function takes (its GLSL does not compile)
    path = write_doc(tmp_path, TWO % '<output name="a" type="color3" nodename="ma" />' +
                     '<two name="t" type="multioutput" />' + unlit("m", 'nodename="t" output="b"'))
    with pytest.raises(MtlxError, match="nodegraph 'NG_two' implements ND_two but has no output 'b'"):
        pipeline.generate(path, elements=["m"])


@pytest.mark.parametrize("element,rgb", [("g/first", RED), ("g/second", GREEN), ("g/third", BLUE)])
def test_each_output_of_a_multi_output_graph_is_an_element(tmp_path, renderer, reference, element, rgb):
    path = write_doc(tmp_path, THREE)
    assert reference.elements(path) == graph.renderable_elements(pipeline.load_document(path)) == \
        ["g/first", "g/second", "g/third"]
    assert np.allclose(centre(renderer, generate_one(path, element)), rgb, atol=0.01)
    assert_parity_with_materialx(renderer, reference, path, element)


RENDERABLE = {
    "value_only": '<nodegraph name="g"><output name="o" type="float" value="0.5" /><constant name="c" type="float" />'
                  '<output name="p" type="float" nodename="c" /></nodegraph>',
    "unconnected": '<nodegraph name="g"><output name="o" type="float" /><constant name="c" type="float" />'
                   '<output name="p" type="float" nodename="c" /></nodegraph>',
    "dangling": '<nodegraph name="g"><output name="o" type="float" nodename="nope" /><constant name="c" type="float" />'
                '<output name="p" type="float" nodename="c" /></nodegraph>',
    "interface": '<nodegraph name="g"><input name="i" type="float" value="0.3" /><output name="o" type="float" '
                 'interfacename="i" /><constant name="c" type="float" /><output name="p" type="float" nodename="c" />'
                 '</nodegraph>',
    "graph_to_graph": '<nodegraph name="a"><constant name="c" type="float" /><output name="o" type="float" nodename="c" />'
                      '</nodegraph><nodegraph name="b"><output name="p" type="float" nodegraph="a" output="o" />'
                      '</nodegraph><output name="top" type="float" nodegraph="a" output="o" />',
    "closures": '<nodegraph name="g"><oren_nayar_diffuse_bsdf name="b" type="BSDF" /><uniform_edf name="e" type="EDF" />'
                '<point_light name="l" type="lightshader" /><surface name="s" type="surfaceshader">'
                '<input name="bsdf" type="BSDF" nodename="b" /></surface><output name="ob" type="BSDF" nodename="b" />'
                '<output name="oe" type="EDF" nodename="e" /><output name="ol" type="lightshader" nodename="l" />'
                '<output name="os" type="surfaceshader" nodename="s" /></nodegraph>',
    "declared_type_ignored": '<nodegraph name="g"><constant name="c" type="float" /><output name="o1" type="BSDF" '
                             'nodename="c" /><oren_nayar_diffuse_bsdf name="b" type="BSDF" /><output name="o2" '
                             'type="float" nodename="b" /></nodegraph>',
    "multi_output_node": '<nodegraph name="g"><position name="p" type="vector3" /><separate3 name="sp" '
                         'type="multioutput"><input name="in" type="vector3" nodename="p" /></separate3><output '
                         'name="a" type="float" nodename="sp" output="outx" /><output name="b" type="float" '
                         'nodename="sp" output="outy" /></nodegraph>',
    "repeated_name": '<nodegraph name="g"><constant name="o" type="float" /><output name="o" type="float" '
                     'nodename="o" /><output name="p" type="float" nodename="o" /></nodegraph>',
    "implementation": TWO % TWO_OUTPUTS,
}


@pytest.mark.parametrize("case", sorted(RENDERABLE))
def test_renderable_elements_are_those_materialx_finds(tmp_path, reference, case):
    path = write_doc(tmp_path, RENDERABLE[case])
    theirs = reference.elements(path)
    assert theirs, "MaterialX finds nothing: the case tests nothing"
    assert graph.renderable_elements(pipeline.load_document(path)) == theirs


def test_where_materialx_finds_nothing_every_output_is_drawn(tmp_path, reference):
    """A document holding only a BSDF's output: MaterialX finds no renderable element; we still draw it."""
    path = write_doc(tmp_path, '<nodegraph name="g"><oren_nayar_diffuse_bsdf name="b" type="BSDF" />'
                               '<output name="o" type="BSDF" nodename="b" /></nodegraph>')
    assert reference.elements(path) == []
    assert graph.renderable_elements(pipeline.load_document(path)) == ["g/o"]
    assert [s.element for s in pipeline.generate(path)] == ["g/o"]
