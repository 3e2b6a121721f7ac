"""glsldeps: glsl_lib files split into top-level items, and stages that paste only the items main reaches.

The splitter on every glsl_lib file (every item found, the file re-assembled exactly from its header and items;
overloads, macros, conditional groups), what it refuses, reachability on small made-up files, and generated
shaders (examples/, tests/data/targets) that hold no function nothing calls and draw the pixels of whole files.
"""
import glob
import os
import re

import numpy as np
import pytest

from conftest import DATA_EXAMPLES, ROOT
from mtlxgen.emit import emitter as emit, glsldeps
from mtlxgen import pipeline
from mtlxgen.emit.glsldeps import GlslSplitError

LIB = os.path.join(ROOT, "glsl_lib")
LIB_FILES = sorted(os.path.relpath(p, LIB).replace(os.sep, "/")
                   for p in glob.glob(os.path.join(LIB, "**", "*.glsl"), recursive=True))
DOCUMENTS = sorted(glob.glob(os.path.join(ROOT, "examples", "**", "*.mtlx"), recursive=True)
                   + glob.glob(os.path.join(ROOT, "tests", "data", "targets", "*.mtlx")))


def lib(rel):
    return glsldeps.split_file(rel, emit.read_lib_file(rel)[0])


# ---------------------------------------------------------------- the splitter on glsl_lib

def test_glsl_lib_is_not_empty():
    assert len(LIB_FILES) > 50 and "enterprise/tables.glsl" in LIB_FILES


@pytest.mark.parametrize("rel", LIB_FILES)
def test_every_glsl_lib_file_splits_into_items_that_reassemble_it(rel):
    text = emit.read_lib_file(rel)[0]
    lf = lib(rel)
    assert lf.header + "".join(lf.item_text(it) for it in lf.items) == text
    assert all(it.names for it in lf.items)
    # each item's text starts with its comments or its first token, and holds its tokens
    for it in lf.items:
        t = lf.item_text(it)
        assert not t.strip() or t.lstrip().startswith(("//", "/*", lf.text[it.code_start]))
        assert it.start <= it.code_start and it.code_end <= it.end
    # every top-level definition the glsl_lib style writes at column 0 is an item's name (a check on the
    # tokenizer's own reading, which does not rely on columns)
    names = set().union(*(it.names for it in lf.items)) if lf.items else set()
    code = re.sub(r"//[^\n]*", "", text)
    expected = set(re.findall(r"^(?:const\s+)?[A-Za-z_]\w*(?:\[\d*\])?\s+([A-Za-z_]\w*)\s*[(\[=;]", code, re.M))
    expected |= set(re.findall(r"^struct\s+([A-Za-z_]\w*)", code, re.M))
    expected |= set(re.findall(r"^#define\s+([A-Za-z_]\w*)", code, re.M))
    expected -= {"struct"}
    assert expected <= names, sorted(expected - names)


def test_header_travels_with_the_file_and_comments_with_their_item():
    lf = lib("pbrlib/microfacet/fresnel.glsl")
    assert lf.header.startswith("// Fresnel reflectance curves")
    first = lf.items[0]
    assert first.names == {"mg_fresnel_dielectric"}
    assert lf.item_text(first).lstrip().startswith("// Unpolarized Fresnel reflectance")


def test_overloads_are_items_sharing_a_name():
    lf = lib("stdlib/procedural/perlin.glsl")
    grads = [it for it in lf.items if it.names == {"mg_grad"}]
    assert len(grads) == 4 and all(it.kind == "function" for it in grads)
    keep = glsldeps.reachable([lf], {"mg_grad"})
    assert all(id(it) in keep for it in grads)


def test_macro_invocations_define_what_their_expansion_defines():
    lf = lib("pbrlib/closures_combine.glsl")
    calls = [it for it in lf.items if it.kind == "macro_call"]
    assert [sorted(it.names) for it in calls] == [["mg_add", "mg_layer", "mg_scale"]] * 2
    assert all("MG_CLOSURE_COMBINATORS" in it.uses for it in calls)
    perlin = lib("stdlib/procedural/perlin.glsl")
    vec3 = [it for it in perlin.items if it.names == {"mg_perlin_vec3"}]
    assert len(vec3) == 2 and all("mg_hash_bytes3" in it.uses for it in vec3)


def test_conditional_groups_are_one_item():
    lf = lib("lighting/environment_lod.glsl")
    group = lf.items[0]
    assert group.kind == "conditional" and group.names == {"MG_ENV_LOD_BIAS"}
    assert lf.item_text(group).strip().startswith("#ifndef MG_ENV_LOD_BIAS")
    lf = glsldeps.split("#ifdef GL_ES\nfloat f() { return 1.0; }\n#else\nfloat f(int x) { return 2.0; }\n"
                        "#define K 3\n#endif\nfloat g() { return f(); }\n")
    assert [it.kind for it in lf.items] == ["conditional", "function"]
    assert lf.items[0].names == {"f", "K"} and "GL_ES" in lf.items[0].uses
    # directives inside a function are part of it
    lf = lib("lighting/hammersley.glsl")
    assert any(it.names == {"mg_reverse_bits"} and it.kind == "function" for it in lf.items)


def test_items_of_every_kind():
    lf = glsldeps.split("struct S { float a; };\nfloat p(S s);\nconst float A = 1.0, B[2] = float[](1.0, 2.0);\n"
                        "#define M(x) (x + A)\n#define N 2\nfloat f(S s) { return M(s.a); }\n"
                        "int q(int a) { return a; } int r(int a) { return q(a); }\n")
    assert [(it.kind, sorted(it.names)) for it in lf.items] == [
        ("struct", ["S"]), ("prototype", ["p"]), ("declaration", ["A", "B"]), ("define", ["M"]),
        ("define", ["N"]), ("function", ["f"]), ("function", ["q"]), ("function", ["r"])]
    assert "a" not in lf.items[5].uses                 # a member name after '.' is not a use
    assert {"M", "S"} <= lf.items[5].uses and lf.items[3].uses == {"A"}
    assert "".join(lf.item_text(it) for it in lf.items) == lf.text


@pytest.mark.parametrize("text, message", [
    ("float f() { return 1.0; ", "without its end"),
    ("float f() { return 1.0; }}\n", "unbalanced"),
    ("#pragma optimize(off)\nfloat f() { return 1.0; }\n", "#pragma"),
    ("#ifdef X\nfloat f() { return 1.0; }\n", "without its #endif"),
    ("#ifdef X\n#endif\n", "defines nothing"),
    ("UNKNOWN_MACRO(float, f)\n", "neither a function nor a macro"),
    ("float f()\n#ifdef X\n{ return 1.0; }\n#endif\n", "directive inside a top-level item"),
    ("/* open comment\nfloat f() { return 1.0; }\n", "unterminated"),
    ("#define M(a, b) float a() { return b; }\nM(f)\n", "takes 2 arguments"),
    (";\n", "defines no name"),
])
def test_what_the_splitter_cannot_place_is_an_error(text, message):
    with pytest.raises(GlslSplitError, match=re.escape(message)):
        glsldeps.split(text, "made_up.glsl")


def test_a_glsl_lib_file_that_cannot_be_split_fails_generation(monkeypatch):
    path = os.path.join(ROOT, "examples", "pbs", "pbs_nodes.mtlx")
    rel = "pbrlib/microfacet/fresnel.glsl"
    text, deps = emit.read_lib_file(rel)
    monkeypatch.setitem(emit._FILE_CACHE, rel, (text + "\nfloat broken() {\n", deps))
    with pytest.raises(Exception, match="without its end"):
        pipeline.generate(path)


# ---------------------------------------------------------------- reachability

MADE_UP = [
    ("a.glsl", "// requires: nothing\n// A made-up file.\n\nstruct Light { vec3 c; };\n\n"
               "// only the unused function calls this\nfloat only_dead(float x) { return x; }\n"
               "float dead(float x) { return only_dead(x); }\n"
               "float via_macro(float x) { return 2.0 * x; }\n#define TWICE(x) via_macro(x)\n"
               "vec3 shade(Light l) { return l.c; }\n"),
    ("b.glsl", "// b\n\nfloat unused_b() { return 0.0; }\n"),
    ("c.glsl", "// c\n\nconst float TABLE[2] = float[](0.0, 1.0);\nfloat lookup(int i) { return TABLE[i]; }\n"),
]


def test_reachability_keeps_what_main_reaches_and_nothing_else():
    out = dict(glsldeps.used_code(MADE_UP, ["void main() { out_color = vec4(TWICE(1.0)); }",
                                            "vec3 c = shade(u_light);", "float t = lookup(1);"]))
    assert list(out) == ["a.glsl", "c.glsl"]             # b contributes nothing: no marker
    a = out["a.glsl"]
    assert a.startswith("// requires: nothing\n// A made-up file.\n")
    assert "via_macro" in a and "#define TWICE" in a      # used through a macro
    assert "struct Light" in a                           # used only in a signature
    assert "dead" not in a and "only the unused" not in a  # its comment goes with it
    assert "TABLE" in out["c.glsl"]
    out = dict(glsldeps.used_code(MADE_UP, ["void main() { }"]))
    assert out == {}


def test_identifiers_are_those_of_the_regular_expression():
    """identifiers() reads ASCII text by translate and split: the same set as _IDENT (members and swizzles after a
    '.', the letters inside numbers, not identifiers; comments not read), and other scripts through _IDENT."""
    texts = ["vec3 a = b.xyz * 1.0e5 + c.d.e; float f = .5e3 + 0x1fu + 2.0f; // g h\n/* i */ _j = k2[l].m;",
             "x.y", ".z", "1.w", "a..b", "_", "__x9", "#define M(p) (p.x + q)", "s.t(u)", "v\t\x0bw\x1cx\x7fy~z",
             "float r\u00e9sum\u00e9 = \u00fcber.x + a;", ""]
    for text in texts:
        assert glsldeps.identifiers(text) == set(glsldeps._IDENT.findall(glsldeps._strip_comments(text, "t"))), text


def test_used_code_kept_per_process_is_what_a_fresh_reading_gives(monkeypatch):
    """used_code is kept per (files, the root identifiers the files define): roots that reach other items, files
    that differ in one text, and a repeat, in turns, each the same as with nothing kept."""
    other = [MADE_UP[0], ("b.glsl", "// b\n\nfloat unused_b() { return lookup(0); }\n"), MADE_UP[2]]
    cases = [(MADE_UP, ["float t = lookup(1);"]), (MADE_UP, ["vec3 c = shade(u_light); float t = lookup(1);"]),
             (other, ["float t = unused_b();"]), (MADE_UP, ["float t = unused_b();"]),
             (MADE_UP, ["float t = lookup(1); float n = not_a_library_name;"]), (MADE_UP, ["float t = lookup(1);"])]
    kept = [glsldeps.used_code(files, roots) for files, roots in cases]
    fresh = []
    for files, roots in cases:
        monkeypatch.setattr(glsldeps, "_USED", {})
        fresh.append(glsldeps.used_code(files, roots))
    assert kept == fresh
    assert kept[0] != kept[1] and kept[2] != kept[3] and kept[0] == kept[4] == kept[5]
    kept[0].append(("x.glsl", "changed by a caller"))          # a copy: what is kept stays as it was
    assert glsldeps.used_code(*cases[0]) == fresh[0]


def test_switch_keeps_whole_files(monkeypatch):
    monkeypatch.setenv("MTLXGEN_GLSL_DCE", "0")
    assert glsldeps.used_code(MADE_UP, ["void main() { }"]) == MADE_UP


def test_big_tables_vanish_where_unused():
    shader = pipeline.generate(os.path.join(DATA_EXAMPLES, "StandardSurface", "standard_surface_onyx_hextiled.mtlx"))[0]
    assert "MG_EPBR_" not in shader.fragment
    sheen = lib("pbrlib/bsdf/sheen.glsl")
    assert any("MG_SHEEN_CK_ALBEDO" in it.names for it in sheen.items)
    shader = pipeline.generate(os.path.join(ROOT, "examples", "pbs", "pbs_nodes.mtlx"), elements=["brushed_gold"])[0]
    assert "MG_SHEEN_CK_ALBEDO" not in shader.fragment


# ---------------------------------------------------------------- generated shaders

def uncalled_functions(text):
    """Functions defined at the top level of a stage's text whose name nothing outside their own definitions
    uses (in code or in a #define)."""
    toks = glsldeps.tokenize(text)
    defs, depth, i = {}, 0, 0
    while i < len(toks):
        t = toks[i]
        if (depth == 0 and t.kind == "id" and i > 0 and toks[i - 1].kind == "id" and i + 1 < len(toks)
                and toks[i + 1].text == "("):
            j, d = i + 1, 0
            while True:
                d += {"(": 1, ")": -1}.get(toks[j].text, 0)
                if d == 0:
                    break
                j += 1
            if j + 1 < len(toks) and toks[j + 1].text == "{":
                k, d = j + 1, 0
                while True:
                    d += {"{": 1, "}": -1}.get(toks[k].text, 0)
                    if d == 0:
                        break
                    k += 1
                defs.setdefault(t.text, []).append((i, k))
                i = k + 1
                continue
        depth += {"(": 1, "{": 1, "[": 1, ")": -1, "}": -1, "]": -1}.get(t.text, 0)
        i += 1
    used = {}
    for n, t in enumerate(toks):
        names = [t.text] if t.kind == "id" else (glsldeps.identifiers(t.text[1:]) if t.kind == "directive" else ())
        for name in names:
            if name in defs and not any(a <= n <= b for a, b in defs[name]):
                used[name] = True
    return sorted(name for name in defs if name != "main" and name not in used)


def test_the_scan_sees_an_uncalled_function():
    assert uncalled_functions("float f() { return 1.0; }\nfloat g() { return f(); }\nvoid main() { }\n") == ["g"]
    assert uncalled_functions("float f() { return 1.0; }\n#define F f()\nvoid main() { float x = F; }\n") == []


def _shaders():
    out = []
    for path in DOCUMENTS:
        for environment in ("fis", "prefiltered"):
            shaders, _ = pipeline.generate(path, partial=True, environment=environment)
            out += [(os.path.relpath(path, ROOT), environment, s) for s in shaders]
    return out


@pytest.fixture(scope="module")
def shaders():
    return _shaders()


def test_generated_shaders_hold_no_function_that_nothing_calls(shaders):
    assert len(shaders) > 60
    problems = []
    for path, environment, s in shaders:
        for stage, text in (("frag", s.fragment), ("vert", s.vertex)):
            dead = uncalled_functions(text)
            if dead:
                problems.append("%s %s %s %s: %s" % (path, s.element, environment, stage, dead))
            markers = re.findall(r"^// ---- glsl_lib/(\S+)$", text, re.M)
            assert len(markers) == len(set(markers)), (path, s.element, stage)
    assert not problems, "\n".join(problems)


def test_generated_shaders_are_smaller_and_keep_their_markers(shaders, monkeypatch):
    path, element = os.path.join(ROOT, "examples", "stride", "stride_metalness.mtlx"), "M_gold"
    small = pipeline.generate(path, elements=[element])[0].fragment
    monkeypatch.setenv("MTLXGEN_GLSL_DCE", "0")
    whole = pipeline.generate(path, elements=[element])[0].fragment
    assert len(small) < 0.85 * len(whole)
    assert set(re.findall(r"^// ---- glsl_lib/(\S+)$", small, re.M)) <= set(
        re.findall(r"^// ---- glsl_lib/(\S+)$", whole, re.M))


# one material of each kind: standard_surface (textures, hex tiling), gltf, enterprise, stride, OpenPBR, the pbrlib
# nodes, EDF/VDF, a USD seed, procedural noise, displacement with every uniform type (tests/data/targets)
PIXEL_CASES = [
    (os.path.join(DATA_EXAMPLES, "StandardSurface", "standard_surface_onyx_hextiled.mtlx"), None),
    (os.path.join(DATA_EXAMPLES, "GltfPbr", "gltf_pbr_default.mtlx"), None),
    (os.path.join(ROOT, "examples", "enterprise", "enterprise_car_paint.mtlx"), "M_car_paint_sparkle"),
    (os.path.join(ROOT, "examples", "stride", "stride_cel_glass_emissive.mtlx"), "M_cel_ramp"),
    (os.path.join(ROOT, "examples", "openpbr", "open_pbr_released_names.mtlx"), None),
    (os.path.join(ROOT, "examples", "pbs", "pbs_nodes.mtlx"), "iridescent_steel"),
    (os.path.join(ROOT, "examples", "edf_vdf", "edf_vdf.mtlx"), "glass_absorbing"),
    (os.path.join(ROOT, "examples", "usd", "usd_seed_rules.mtlx"), "stripes"),
    (os.path.join(ROOT, "examples", "quick_start.mtlx"), None),
    (os.path.join(ROOT, "tests", "data", "targets", "interface_types.mtlx"), None),
]


@pytest.mark.parametrize("path, element", PIXEL_CASES, ids=[os.path.basename(p) for p, _ in PIXEL_CASES])
def test_reachable_code_draws_the_pixels_of_whole_files(renderer, monkeypatch, path, element):
    small = pipeline.generate(path, elements=[element] if element else None)[0]
    monkeypatch.setenv("MTLXGEN_GLSL_DCE", "0")
    whole = pipeline.generate(path, elements=[small.element])[0]
    assert len(small.fragment) < len(whole.fragment)
    a, b = renderer.render(small), renderer.render(whole)
    assert np.array_equal(a, b, equal_nan=True), float(np.nanmax(np.abs(a - b)))


# ---------------------------------------------------------------- loop-invariant work out of the sample loops

@pytest.mark.parametrize("rel, loop", [("lighting/environment_specular.glsl", "mg_env_specular_samples"),
                                       ("lighting/environment_refraction.glsl", "mg_env_refraction_samples")])
def test_environment_sample_loops_are_one_loop_over_the_lobes_curve(rel, loop):
    """One sample loop per estimator, made by its macro, whose curve is mg_fresnel_eval (the film tested per sample:
    a uniform, the same side for every pixel); no film copy of the loop beside the bare one, which cost the GPU
    compilers 10% more instructions (docs/measuring.md, 2026-11-28); the caller calls it with no film test."""
    lf = lib(rel)
    body = [it for it in lf.items if it.names == {loop}]
    assert len(body) == 1 and body[0].kind == "macro_call" and {"for", "mg_fresnel_eval"} <= body[0].uses
    assert not [it for it in lf.items if it.names & {loop + "_film", loop + "_bare"}]
    caller = [it for it in lf.items if loop in it.uses]
    assert len(caller) == 1
    text = re.sub(r"\s+", " ", lf.item_text(caller[0]))
    assert "film_thickness" not in text and "MG_NO_THIN_FILM" not in text
    assert re.search(r"%s\(Vt, frame, " % loop, text)
    # where no film can be, mg_fresnel_eval's own paste switch leaves the base curve alone
    fresnel = lib("pbrlib/microfacet/fresnel_model.glsl")
    evaluate = [it for it in fresnel.items if it.names == {"mg_fresnel_eval"}]
    resolved = glsldeps.compact(glsldeps.resolve_switches(fresnel.item_text(evaluate[0]), {"MG_NO_THIN_FILM"}))
    assert "mg_fresnel_film" not in resolved and "mg_fresnel_base" in resolved


# ---------------------------------------------------------------- paste switches

SWITCH_TEXT = """a
#ifndef MG_NO_THIN_FILM
    film();
#ifdef OTHER
    other();
#endif
#else
    bare();
#endif
#ifdef MG_REFRACTION_UNBOUNDED
    p();
#endif
b"""


def test_paste_switch_groups_resolve_both_ways_and_other_groups_pass_through():
    on = glsldeps.resolve_switches(SWITCH_TEXT, {"MG_NO_THIN_FILM"})
    off = glsldeps.resolve_switches(SWITCH_TEXT, set())
    assert on.split() == ["a", "bare();", "#ifdef", "MG_REFRACTION_UNBOUNDED", "p();", "#endif", "b"]
    assert off.split() == ["a", "film();", "#ifdef", "OTHER", "other();", "#endif",
                           "#ifdef", "MG_REFRACTION_UNBOUNDED", "p();", "#endif", "b"]
    assert glsldeps.resolve_switches("x\n#ifdef MG_REFRACTION_UNBOUNDED\ny\n#endif", {"MG_NO_THIN_FILM"}) == \
        "x\n#ifdef MG_REFRACTION_UNBOUNDED\ny\n#endif"


FILM_DOC = """<?xml version="1.0"?>
<materialx version="1.39">
  <dielectric_bsdf name="lobe" type="BSDF">
    <input name="roughness" type="vector2" value="0.3, 0.3" />
    <input name="thinfilm_thickness" type="float" value="%s" />
    <input name="thinfilm_ior" type="float" value="1.4" />
  </dielectric_bsdf>
  <oren_nayar_diffuse_bsdf name="base" type="BSDF">
    <input name="color" type="color3" value="0.5, 0.3, 0.2" />
  </oren_nayar_diffuse_bsdf>
  <layer name="stack" type="BSDF">
    <input name="top" type="BSDF" nodename="lobe" />
    <input name="base" type="BSDF" nodename="base" />
  </layer>
  <surface name="surf" type="surfaceshader">
    <input name="bsdf" type="BSDF" nodename="stack" />
  </surface>
  <surfacematerial name="mat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="surf" />
  </surfacematerial>
</materialx>
"""


@pytest.mark.parametrize("thickness, interface, film_code", [
    ("0", "reduced", False),        # a literal 0: the shader holds no film code
    ("0", "complete", True),        # a uniform (editable): the film stays possible
    ("450", "reduced", True),       # a literal film
])
def test_a_shader_holds_film_code_only_where_a_film_can_be(tmp_path, renderer, monkeypatch, thickness, interface,
                                                           film_code):
    path = tmp_path / "film.mtlx"
    path.write_text(FILM_DOC % thickness)
    s = pipeline.generate(str(path), elements=["mat"], interface=interface, max_lights=1)[0]
    code = glsldeps.compact(s.fragment)        # (comments may name the switch)
    assert ("mg_thin_film" in code) == film_code and "MG_NO_THIN_FILM" not in code
    # the same pixels as the shader pasted with the film code (the switch never set)
    monkeypatch.setattr(emit.Emitter, "paste_switches", lambda self: set())
    whole = pipeline.generate(str(path), elements=["mat"], interface=interface, max_lights=1)[0]
    assert "mg_thin_film" in whole.fragment
    assert (len(s.fragment) < len(whole.fragment)) == (not film_code)
    a, b = renderer.render(s), renderer.render(whole)
    assert np.array_equal(a, b, equal_nan=True), float(np.nanmax(np.abs(a - b)))
