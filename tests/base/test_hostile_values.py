"""Hostile values, names, templates and struct typedefs: the CLI exits 0 or 1, never 3; every problem is one
`FILE:LINE: ` line pointing at the element at fault; whatever it writes compiles, under safe file names."""
import json
import os
import re

import pytest

from mtlxgen.apps import cli

LINE = re.compile(r"^[^:]+:\d+: ")
WARNING = re.compile(r"^[^:]+:\d+: warning: ")      # a slip MaterialX reads on: read as it reads it, status 0
SAFE_STEM = re.compile(r"[A-Za-z0-9_+][A-Za-z0-9_.+-]*")


def write(tmp_path, lines, name="doc.mtlx"):
    """A document of the given element lines, one a line: line i of `lines` is line i + 3 of the file."""
    path = os.path.join(str(tmp_path), name)
    with open(path, "w", encoding="utf-8") as f:
        f.write('<?xml version="1.0"?>\n<materialx version="1.39">\n%s\n</materialx>\n' % "\n".join(lines))
    return path


def line_of(lines, fragment):
    """File line of the first document line holding `fragment`."""
    return next(i + 3 for i, text in enumerate(lines) if fragment in text)


def generate(tmp_path, lines, capsys, renderer, name="doc.mtlx"):
    """Run `mtlxgen generate`; check the contract every outcome keeps. Returns (status, problem lines, out dir)."""
    path = write(tmp_path, lines, name)
    out = os.path.join(str(tmp_path), "out")
    capsys.readouterr()
    status = cli.main(["generate", path, "-o", out])
    err = capsys.readouterr().err.splitlines()
    assert status in (0, 1), err
    assert all(LINE.match(e) for e in err), err
    assert (status == 1) == any(not WARNING.match(e) for e in err), err
    for stem in written_stems(out):
        vertex, fragment = (open(os.path.join(out, stem + ext), encoding="utf-8").read() for ext in (".vert", ".frag"))
        renderer.ctx.program(vertex_shader=vertex, fragment_shader=fragment).release()
        for text in (vertex, fragment):
            for comment in re.findall(r"//.*", text):
                assert re.fullmatch(r"[ -~]*", comment) and "*/" not in comment and not comment.endswith("\\"), comment
    return status, err, out


def written_stems(out):
    if not os.path.isdir(out):
        return []
    return sorted({os.path.splitext(f)[0] for f in os.listdir(out)})


def assert_refused(status, err, path_line, *words):
    assert status == 1
    assert len(err) == 1, err
    assert err[0].split(": ", 1)[0].endswith(":%d" % path_line), err
    for w in words:
        assert w in err[0], err


def constant(type_name, value):
    return ['<constant name="c" type="%s">' % type_name,
            '  <input name="value" type="%s" value="%s" />' % (type_name, value),
            '</constant>',
            '<output name="o" type="%s" nodename="c" />' % type_name]


# ---------------------------------------------------------------- values

@pytest.mark.parametrize("text", ["inf", "-inf", "nan", "NaN", "1e999", "-1e39", "Infinity", "+infinity"])
@pytest.mark.parametrize("type_name,template", [
    ("float", "%s"), ("color3", "1, %s, 0"), ("vector2", "%s 0"), ("matrix33", "1,0,0, 0,%s,0, 0,0,1")])
def test_non_finite_values_are_refused_at_their_input(tmp_path, capsys, renderer, text, type_name, template):
    lines = constant(type_name, template % text)
    status, err, out = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, line_of(lines, "<input"), "input 'value'", "non-finite value '%s'" % text)
    assert written_stems(out) == []


def test_a_non_finite_float_array_item_is_refused(tmp_path, capsys, renderer):
    lines = ['<nodedef name="ND_first" node="first">',
             '  <input name="in" type="floatarray" value="1.0, 1e999" />',
             '  <output name="out" type="float" />',
             '</nodedef>',
             '<implementation name="IM_first" nodedef="ND_first" sourcecode="{{in}}[0]" />',
             '<first name="f" type="float" />',
             '<output name="o" type="float" nodename="f" />']
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, 4, "non-finite value '1e999' in '1.0, 1e999'")


@pytest.mark.parametrize("text,why", [
    ("Infinity", "not an integer"), ("\u0661\u0662", "not an integer"), ("abc", "not an integer"),
    ("2147483648", "outside the 32-bit range"), ("-2147483649", "outside the 32-bit range"),
    ("99999999999999999999", "outside the 32-bit range")])
def test_integers_glsl_cannot_hold_are_refused(tmp_path, capsys, renderer, text, why):
    lines = constant("integer", text)
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, line_of(lines, "<input"), "input 'value'", why)


# MaterialX 1.39.5 reads the whole number an integer value starts with and ignores the rest (C++ stream
# extraction; measured with the materialx wheel): these were refused before issue 16, now read as it reads them
@pytest.mark.parametrize("text,value", [("1e3", 1), ("0x10", 0), ("1_000", 1), ("1.5", 1), ("2,3", 2)])
def test_integers_with_more_after_the_number_read_as_materialx_reads_them(tmp_path, capsys, renderer, text, value):
    lines = constant("integer", text)
    status, err, out = generate(tmp_path, lines, capsys, renderer)
    assert status == 0, err
    assert len(err) == 1 and WARNING.match(err[0]), err
    assert err[0].split(": ")[0].endswith(":%d" % line_of(lines, "<input")), err
    assert "%r has more after its number: read as %d" % (text, value) in err[0], err
    manifest = json.load(open(os.path.join(out, "o.json")))
    assert [u["value"] for u in manifest["uniforms"]] == [value]


@pytest.mark.parametrize("text,value", [("2147483647", 2147483647), ("-2147483648", -2147483648), ("+7", 7),
                                        ("3.0", 3)])
def test_integers_in_range_compile_with_their_value(tmp_path, capsys, renderer, text, value):
    status, err, out = generate(tmp_path, constant("integer", text), capsys, renderer)
    assert status == 0, err
    manifest = json.load(open(os.path.join(out, "o.json")))
    assert [u["value"] for u in manifest["uniforms"]] == [value]


# "" is read as no value (the default) with a warning, as MaterialX reads it: tests/read/test_unseen_classes.py
@pytest.mark.parametrize("text", ["1", "0", "TRUE", "False", "yes"])
def test_booleans_other_than_true_and_false_are_refused(tmp_path, capsys, renderer, text):
    # MaterialX reads only "true" and "false" (createValueFromStrings gives None for the rest)
    lines = constant("boolean", text)
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, line_of(lines, "<input"), "not a boolean: '%s'" % text)


@pytest.mark.parametrize("text", ["true", "false"])
def test_true_and_false_compile(tmp_path, capsys, renderer, text):
    status, err, out = generate(tmp_path, constant("boolean", text), capsys, renderer)
    assert status == 0, err
    assert "uniform bool c_value = %s;" % text in open(os.path.join(out, "o.frag")).read()


def test_a_non_finite_unit_scale_and_a_bad_geomprop_index_are_refused_where_written(tmp_path, capsys, renderer):
    lines = ['<unitdef name="UD_x" unittype="distance">',
             '  <unit name="far" scale="inf" />',
             '</unitdef>',
             '<geompropdef name="uv9" type="vector2" geomprop="texcoord" index="1e3" />'] + constant("float", "1")
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert status == 1
    assert len(err) == 2, err
    # index '1e3': MaterialX reads 1 (a warning since issue 16); scale 'inf': MaterialX reads nothing (an error)
    assert err[0].split(": ")[0].endswith(":6") and "warning: geompropdef 'uv9': index: '1e3' has more" in err[0]
    assert err[1].split(": ")[0].endswith(":4") and "non-finite value 'inf'" in err[1]


# ---------------------------------------------------------------- implementation templates

def sourcecode_doc(source):
    return ['<nodedef name="ND_f" node="f">',
            '  <input name="in" type="float" value="0.5" />',
            '  <input name="mode" type="string" value="fast" />',
            '  <output name="out" type="float" />',
            '</nodedef>',
            '<implementation name="IM_f" nodedef="ND_f" target="genglsl" sourcecode="%s" />' % source,
            '<f name="n" type="float" />',
            '<output name="o" type="float" nodename="n" />']


@pytest.mark.parametrize("source,why", [
    ("{{@}}", "names no geometric stream"),
    ("{{@geomprop_my-attr}}", "names no geometric stream"),
    ("{{@texcoord_-1}}.x", "names no geometric stream"),
    ("{{$type:nope}}({{in}})", "names no input of ND_f"),
    ("{{nope}} * 2.0", "names no input of ND_f"),
    ("{{=nope}}", "names no input of ND_f"),
    ("{{}}", "names no input of ND_f"),
    ("{{in}} * {{in", "unterminated '{{'"),
    ("{{=mode}} == 1 ? 1.0 : 0.0", "pastes a string as GLSL"),
    ("{{in}}; }", "not one GLSL expression"),
    ("{{in}} // comment", "not one GLSL expression"),
    ("{{in}} /* x", "not one GLSL expression"),
    ("1.0, 2.0", "not one GLSL expression"),
    ("{{in}} \\", "not one GLSL expression"),
    ("#define X", "not one GLSL expression"),
    ("max({{in}}, 1.0", "unbalanced brackets"),
    ("{{in}}]", "unbalanced brackets"),
    ("(1.0]", "unbalanced brackets"),
    ("  ", "empty sourcecode"),
    ("material", "names 'material', which is neither a field nor one of GLSL's built-in"),
    ("M_PI * {{in}}", "names 'M_PI'"),
    ("2.5.0", "follows a value without an operator"),
    ("99999999999 * {{in}}", "does not fit in 32 bits"),
    ("1e39", "beyond the range of a 32-bit float"),
    ("09", "no octal literal"),
    ("{{in}} +", "it ends in '+'"),
    ("{{in}} = 1.0", "it holds '='"),
    ("{{in}}++", "it holds '++'"),
    ("(1.0)(2.0)", "follows a value that is no function"),
    ("\u00e9", "it holds '\u00e9'"),
])
def test_malformed_sourcecode_is_refused_at_the_implementation(tmp_path, capsys, renderer, source, why):
    lines = sourcecode_doc(source)
    status, err, out = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, line_of(lines, "<implementation"), "implementation 'IM_f'", why)
    assert written_stems(out) == []


@pytest.mark.parametrize("source", ["{{in}} * 2.0", "max({{ in }}, {{@texcoord_0}}.x)", "{{$type}}({{=in}})",
                                    "{{in}} > 0.25 ? vec2({{in}}, 1.0)[1] : 0.0"])
def test_wellformed_sourcecode_compiles(tmp_path, capsys, renderer, source):
    status, err, out = generate(tmp_path, sourcecode_doc(source), capsys, renderer)
    assert status == 0, err
    assert written_stems(out) == ["o"]


@pytest.mark.parametrize("source,why", [
    ("true", "initializer of type bool"), ("{{in}}.zz", "zz"), ("vec3({{in}})", "vec3"),
    ("sin({{in}}, 1.0)", "sin")])
def test_sourcecode_that_does_not_compile_is_refused_at_the_implementation(tmp_path, capsys, renderer, source, why):
    # well-formed text, wrong types: the shader holding it is compiled before it is written
    lines = sourcecode_doc(source)
    status, err, out = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, line_of(lines, "<implementation"), "implementation 'IM_f': its GLSL does not compile",
                   why)
    assert written_stems(out) == []


def test_a_compile_error_is_reported_at_the_implementation_whose_code_fails(tmp_path, capsys, renderer):
    with open(os.path.join(str(tmp_path), "g.glsl"), "w") as f:
        f.write("void g_fn(float x, out float r)\n{\n    r = x.yy;\n}\n")
    lines = ['<nodedef name="ND_a" node="a"><input name="in" type="float" value="0.5" /><output name="out" type="float" /></nodedef>',
             '<implementation name="IM_a" nodedef="ND_a" sourcecode="{{in}} * 2.0" />',
             '<nodedef name="ND_b" node="b"><input name="in" type="float" value="0.5" /><output name="out" type="float" /></nodedef>',
             '<implementation name="IM_b" nodedef="ND_b" sourcecode="{{in}}.yy" />',
             '<nodedef name="ND_g" node="g"><input name="in" type="float" value="0.5" /><output name="out" type="float" /></nodedef>',
             '<implementation name="IM_g" nodedef="ND_g" file="g.glsl" function="g_fn" />',
             '<a name="na" type="float" />',
             '<b name="nb" type="float"><input name="in" type="float" nodename="na" /></b>',
             '<g name="ng" type="float"><input name="in" type="float" nodename="na" /></g>',
             '<output name="ob" type="float" nodename="nb" />',
             '<output name="og" type="float" nodename="ng" />']
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert status == 1
    assert [e.split(": ", 1)[0].rsplit(":", 1)[1] + " " + e.split(": ", 2)[1] for e in err] == \
        ["6 implementation 'IM_b'", "8 implementation 'IM_g'"], err


def test_an_implementation_function_that_is_no_identifier_is_refused(tmp_path, capsys, renderer):
    lines = ['<nodedef name="ND_g" node="g"><output name="out" type="float" /></nodedef>',
             '<implementation name="IM_g" nodedef="ND_g" file="g.glsl" function="g); evil(" />',
             '<g name="n" type="float" />',
             '<output name="o" type="float" nodename="n" />']
    with open(os.path.join(str(tmp_path), "g.glsl"), "w") as f:
        f.write("void g(out float r) { r = 1.0; }\n")
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, 4, "function 'g); evil(' is not a GLSL identifier")


@pytest.mark.parametrize("node,why", [
    ('<texcoord name="t" type="vector2"><input name="index" type="integer" value="-1" /></texcoord>', "texcoord_-1"),
    ('<geompropvalue name="t" type="vector2"><input name="geomprop" type="string" value="my attr" /></geompropvalue>',
     "geomprop_my attr")])
def test_streams_no_vertex_attribute_can_carry_are_refused_at_the_node(tmp_path, capsys, renderer, node, why):
    lines = [node, '<output name="o" type="vector2" nodename="t" />']
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, 3, "no geometric stream '%s'" % why)


# ---------------------------------------------------------------- names

def graph_named(name):
    return ['<nodegraph name="%s">' % name,
            '  <constant name="c" type="float"><input name="value" type="float" value="0.5" /></constant>',
            '  <output name="out" type="float" nodename="c" />',
            '</nodegraph>']


@pytest.mark.parametrize("name,why", [("a&#10;b", "control character"), ("a&#9;b", "control character"),
                                      ("x&#13;", "control character"), ("a&#127;", "control character"),
                                      ("a/b", "separates MaterialX name paths"),
                                      ("..&#47;..&#47;etc", "separates MaterialX name paths")])
def test_names_with_line_breaks_control_characters_or_slashes_are_refused(tmp_path, capsys, renderer, name, why):
    lines = graph_named(name)
    status, err, out = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, 3, "<nodegraph> name", why)
    assert written_stems(out) == []


@pytest.mark.parametrize("name", ["a b", "..", ".hidden", "-rf", "a*b?c", "semi;colon", "back\\slash", "CON",
                                  "Mat\u00e9riau", "\u6750\u8d28", "x" * 300, "\u00e9" * 200, "a:b"])
def test_unusual_names_give_safe_bounded_file_names_and_the_manifest_keeps_the_real_name(
        tmp_path, capsys, renderer, name):
    status, err, out = generate(tmp_path, graph_named(name), capsys, renderer)
    assert status == 0, err
    stems = written_stems(out)
    assert len(stems) == 1 and SAFE_STEM.fullmatch(stems[0]), stems
    assert len(stems[0].encode()) <= 200 and stems[0].split(".")[0].upper() != "CON"
    assert sorted(os.listdir(out)) == [stems[0] + ext for ext in (".frag", ".json", ".vert")]
    manifest = json.load(open(os.path.join(out, stems[0] + ".json"), encoding="utf-8"))
    assert manifest["element"] == name + "/out"
    assert (manifest["vertex"], manifest["fragment"]) == (stems[0] + ".vert", stems[0] + ".frag")


def test_names_that_differ_only_by_unsafe_characters_get_different_files(tmp_path, capsys, renderer):
    lines = graph_named("a b") + graph_named("a*b") + graph_named("a?b")
    status, err, out = generate(tmp_path, lines, capsys, renderer)
    assert status == 0, err
    elements = {json.load(open(os.path.join(out, s + ".json")))["element"] for s in written_stems(out)}
    assert elements == {"a b/out", "a*b/out", "a?b/out"}


def test_clashing_file_names_within_one_run_are_made_unique(tmp_path, capsys, renderer):
    # "a/b" (nodegraph a, output b) and the top-level output "a_b" both have the stem a_b; "A_B" clashes with
    # it on case-insensitive file systems
    lines = graph_named("a")[:2] + ['  <output name="b" type="float" nodename="c" />', '</nodegraph>',
                                    '<constant name="k" type="float"><input name="value" type="float" value="0.25" /></constant>',
                                    '<output name="a_b" type="float" nodename="k" />',
                                    '<output name="A_B" type="float" nodename="k" />']
    status, err, out = generate(tmp_path, lines, capsys, renderer)
    assert status == 0, err
    stems = written_stems(out)
    assert len(stems) == 3 and len({s.casefold() for s in stems}) == 3, stems
    by_element = {json.load(open(os.path.join(out, s + ".json")))["element"]: s for s in stems}
    assert set(by_element) == {"a/b", "a_b", "A_B"}
    for element, stem in by_element.items():
        manifest = json.load(open(os.path.join(out, stem + ".json")))
        assert manifest["fragment"] == stem + ".frag"


def test_a_document_file_name_with_a_line_break_stays_out_of_the_comments(tmp_path, capsys, renderer):
    status, err, out = generate(tmp_path, constant("float", "0.5"), capsys, renderer, name="we\nird\u00e9 \\.mtlx")
    assert status == 0, err
    assert "// o: generated by mtlxgen from we?ird? ?.mtlx" in open(os.path.join(out, "o.frag")).read()


def test_a_connection_naming_a_line_break_is_reported_on_one_line(tmp_path, capsys, renderer):
    # a connection to a node that is not there: MaterialX ignores it (a warning since issue 16)
    lines = ['<sin name="s" type="float"><input name="in" type="float" nodename="no&#10;such" /></sin>',
             '<output name="o" type="float" nodename="s" />']
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert status == 0 and len(err) == 1 and WARNING.match(err[0]), err
    assert err[0].split(": ")[0].endswith(":3") and "'no\\nsuch'" in err[0], err


# ---------------------------------------------------------------- struct typedefs

def struct_doc(typedefs, value="{1.0}", source="1.0"):
    return typedefs + ['<nodedef name="ND_ex" node="ex">',
                       '  <input name="in" type="S" value="%s" />' % value,
                       '  <output name="out" type="float" />',
                       '</nodedef>',
                       '<implementation name="IM_ex" nodedef="ND_ex" sourcecode="%s" />' % source,
                       '<ex name="m" type="float" />',
                       '<output name="o" type="float" nodename="m" />']


@pytest.mark.parametrize("member_type,why", [
    ("lightshader", "which a struct cannot hold"), ("surfaceshader", "which a struct cannot hold"),
    ("BSDF", "which a struct cannot hold"), ("material", "which a struct cannot hold"),
    ("string", "which a struct cannot hold"), ("filename", "which a struct cannot hold"),
    ("floatarray", "which a struct cannot hold"), ("nope", "an unknown type")])
def test_struct_members_of_closure_string_array_or_unknown_type_are_refused(
        tmp_path, capsys, renderer, member_type, why):
    lines = struct_doc(['<typedef name="S">', '  <member name="a" type="%s" />' % member_type, '</typedef>'])
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, 4, "member 'a' of struct 'S' has type '%s'" % member_type, why)


@pytest.mark.parametrize("typedefs,problems", [
    (['<typedef name="S"><member name="a" type="S" /></typedef>'], [(3, "struct 'S' contains itself (S -> S)")]),
    (['<typedef name="S"><member name="a" type="T" /></typedef>',
      '<typedef name="T"><member name="b" type="float" /><member name="c" type="S" /></typedef>'],
     [(3, "struct 'S' contains itself (S -> T -> S)"), (4, "struct 'T' contains itself (T -> S -> T)")]),
])
def test_recursive_struct_typedefs_are_refused(tmp_path, capsys, renderer, typedefs, problems):
    status, err, _ = generate(tmp_path, struct_doc(typedefs), capsys, renderer)
    assert status == 1
    assert [(int(e.split(": ")[0].rsplit(":", 1)[1]), e.split(": ", 1)[1]) for e in err] == problems


def test_structs_nested_too_deep_are_refused(tmp_path, capsys, renderer):
    chain = ['<typedef name="S"><member name="a" type="S1" /></typedef>'] + [
        '<typedef name="S%d"><member name="a" type="S%d" /></typedef>' % (i, i + 1) for i in range(1, 40)] + [
        '<typedef name="S40"><member name="a" type="float" /></typedef>']
    status, err, _ = generate(tmp_path, struct_doc(chain), capsys, renderer)
    assert status == 1
    assert err[0].split(": ")[0].endswith(":3") and "struct 'S' nests structs more than 32 deep" in err[0], err


@pytest.mark.parametrize("typedef,line,why", [
    ('<typedef name="S"><member name="a b" type="float" /></typedef>', 3, "member 'a b' of struct 'S'"),
    ('<typedef name="S"><member name="float" type="float" /></typedef>', 3, "member 'float' of struct 'S'"),
    ('<typedef name="S"><member type="float" /></typedef>', 3, "member '' of struct 'S'"),
    ('<typedef name="S"><member name="a" type="float" /><member name="a" type="float" /></typedef>', 3,
     "struct 'S' has two members named 'a'"),
    ('<typedef name="S"><member name="a" type="float" value="inf" /></typedef>', 3, "non-finite value 'inf'"),
    ('<typedef name="float"><member name="a" type="float" /></typedef>', 3, "gives members to a built-in type"),
    ('<typedef name="S"><member name="a" type="float" /></typedef>\n'
     '<typedef name="S"><member name="a" type="vector3" /></typedef>', 4, "duplicate typedef 'S'"),
])
def test_struct_typedefs_glsl_cannot_declare_are_refused(tmp_path, capsys, renderer, typedef, line, why):
    status, err, _ = generate(tmp_path, struct_doc([typedef]), capsys, renderer)
    assert_refused(status, err, line, why)


@pytest.mark.parametrize("name", ["dot", "LightData", "mg_thing", "MgFresnel"])
def test_struct_names_the_generated_glsl_uses_are_refused(tmp_path, capsys, renderer, name):
    lines = struct_doc(['<typedef name="%s"><member name="a" type="float" /></typedef>' % name])
    lines = [line.replace('type="S"', 'type="%s"' % name) for line in lines]
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, 3, "typedef '%s': the generated GLSL already uses the name" % name)


def test_nested_struct_values_reach_the_shader(tmp_path, capsys, renderer):
    # S holds T: T is declared first, and the node's nested value {3;{4;...}} is read member by member
    lines = struct_doc(['<typedef name="T"><member name="b" type="float" /><member name="c" type="color3" /></typedef>',
                        '<typedef name="S"><member name="a" type="float" /><member name="t" type="T" /></typedef>'],
                       value="{1.0;{2.0;0,1,0}}", source="{{in}}.t.b + {{in}}.a * {{in}}.t.c.r")
    lines[-2] = '<ex name="m" type="float"><input name="in" type="S" value="{3.0; {0.25; 0.5, 1, 0}}" /></ex>'
    status, err, out = generate(tmp_path, lines, capsys, renderer)
    assert status == 0, err
    from mtlxgen import pipeline
    shader = pipeline.generate(write(tmp_path, lines))[0]
    image = renderer.render(shader)
    centre = image[image.shape[0] // 2, image.shape[1] // 2]
    assert abs(centre[0] - (0.25 + 3.0 * 0.5)) < 1e-5, centre


# ---------------------------------------------------------------- types without a GLSL spelling

def test_an_input_of_unknown_type_is_refused_at_its_line(tmp_path, capsys, renderer):
    lines = ['<nodedef name="ND_f" node="f">',
             '  <input name="in" type="nope" />',
             '  <output name="out" type="float" />',
             '</nodedef>',
             '<implementation name="IM_f" nodedef="ND_f" sourcecode="1.0" />',
             '<f name="n" type="float" />',
             '<output name="o" type="float" nodename="n" />']
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, 4, "a value of type 'nope' has no GLSL type")


@pytest.mark.parametrize("type_name", ["geomname", "nope"])
def test_a_node_output_without_glsl_type_is_refused_at_the_node(tmp_path, capsys, renderer, type_name):
    lines = ['<nodedef name="ND_f" node="f"><output name="out" type="%s" /></nodedef>' % type_name,
             '<nodedef name="ND_g" node="g"><input name="in" type="%s" /><output name="out" type="float" /></nodedef>'
             % type_name,
             '<implementation name="IM_f" nodedef="ND_f" sourcecode="1.0" />',
             '<implementation name="IM_g" nodedef="ND_g" sourcecode="{{in}}" />',
             '<f name="n" type="%s" />' % type_name,
             '<g name="m" type="float"><input name="in" type="%s" nodename="n" /></g>' % type_name,
             '<output name="o" type="float" nodename="m" />']
    status, err, _ = generate(tmp_path, lines, capsys, renderer)
    assert_refused(status, err, 7, "node 'n' (ND_f): a value of type '%s' has no GLSL type" % type_name)
