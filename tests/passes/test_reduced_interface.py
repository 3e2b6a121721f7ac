"""The reduced shader interface (--interface reduced, mtlxgen/passes/reduce.py + fold.py, issue 14).

- Reduced shaders draw what complete ones draw (the scoreboard's parity: mean <= 2/255, <= 1% of pixels > 8/255) for
  every element of examples/ and a set from tests/data/materialx (and, marked corpus, MaterialX's Examples).
- uniform="true" (on the input or its nodedef's) and --keep / --keep-file keep exactly those inputs uniforms: the
  manifest lists them, the shader declares them.
- Bad --keep names and --interface values: one line, status 1.
- Reduction and folding build new graphs: the input graph is unchanged (deep compare).
"""
import copy
import glob
import json
import os

import pytest

from conftest import DATA_EXAMPLES, DATA_TESTSUITE, EXAMPLES, ROOT, corpus_params
from util import write_doc

from mtlxgen.draw import compare
from mtlxgen.passes import fold, reduce
from mtlxgen import pipeline
from mtlxgen.options import GenerateOptions

EXAMPLE_FILES = sorted(glob.glob(os.path.join(ROOT, "examples", "**", "*.mtlx"), recursive=True))
DATA_FILES = [os.path.join(DATA_EXAMPLES, "StandardSurface", "standard_surface_onyx_hextiled.mtlx"),   # textured
              os.path.join(DATA_EXAMPLES, "GltfPbr", "gltf_pbr_default.mtlx"),
              os.path.join(DATA_TESTSUITE, "stdlib", "units", "standard_surface_unit.mtlx"),
              os.path.join(DATA_TESTSUITE, "stdlib", "compositing", "compositing.mtlx"),
              os.path.join(DATA_TESTSUITE, "stdlib", "adjustment", "hsvtorgb.mtlx"),
              os.path.join(DATA_TESTSUITE, "stdlib", "math", "trig.mtlx"),
              os.path.join(DATA_TESTSUITE, "pbrlib", "surfaceshader", "transparency_hints.mtlx")]
CORPUS_FILES = ["StandardSurface/standard_surface_default.mtlx", "StandardSurface/standard_surface_glass.mtlx",
                "StandardSurface/standard_surface_brick_procedural.mtlx",
                "StandardSurface/standard_surface_marble_solid.mtlx", "StandardSurface/standard_surface_wood_tiled.mtlx",
                "OpenPbr/open_pbr_default.mtlx", "OpenPbr/open_pbr_velvet.mtlx", "OpenPbr/open_pbr_soapbubble.mtlx",
                "UsdPreviewSurface/usd_preview_surface_plastic.mtlx", "GltfPbr/gltf_pbr_carpaint.mtlx",
                "DisneyPrincipled/disney_principled_default.mtlx"]


def _elements(paths):
    out = []
    for path in paths:
        for name in pipeline.Session(path).elements:
            out.append(pytest.param(path, name, id="%s:%s" % (os.path.basename(path), name)))
    return out


def _assert_same_pictures(renderer, path, element):
    complete = pipeline.generate(path, elements=[element])[0]
    reduced = pipeline.generate(path, elements=[element], interface="reduced")[0]
    assert reduced.manifest["interface"] == "reduced" and complete.manifest["interface"] == "complete"
    assert len(reduced.fragment) <= len(complete.fragment)
    p = compare.parity(renderer.render(complete), renderer.render(reduced))
    assert p.passes, "%s %s: %s" % (os.path.basename(path), element, p)
    assert p.mean <= 0.1, p                 # in fact the same picture: folding changes float rounding only
    return p


@pytest.mark.parametrize("path, element", _elements(EXAMPLE_FILES + DATA_FILES))
def test_reduced_draws_what_complete_draws(path, element, renderer):
    _assert_same_pictures(renderer, path, element)


def _corpus_cases():
    return _elements([os.path.join(EXAMPLES, f) for f in CORPUS_FILES if os.path.exists(os.path.join(EXAMPLES, f))])


@pytest.mark.corpus
@pytest.mark.parametrize("path, element", corpus_params(_corpus_cases, 2))
def test_reduced_draws_what_complete_draws_on_materialx_examples(path, element, renderer):
    _assert_same_pictures(renderer, path, element)


# ---------------------------------------------------------------- which inputs stay uniforms

SURFACE = """
  <standard_surface name="ss" type="surfaceshader">
    <input name="base_color" type="color3" value="0.8, 0.2, 0.1" %s/>
    <input name="specular_roughness" type="float" value="0.35" />
    <input name="coat" type="float" value="0.5" />
  </standard_surface>
  <surfacematerial name="m" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="ss" />
  </surfacematerial>"""


def _material_uniforms(shader):
    """The material's uniforms the fragment declares (not the application's u_*)."""
    lines = [line for line in shader.fragment.splitlines() if line.startswith("uniform ")]
    return sorted(line.split()[2].split("[")[0].rstrip(";") for line in lines
                  if not line.split()[2].startswith("u_"))


def test_uniform_true_keeps_exactly_those_inputs(tmp_path):
    path = write_doc(tmp_path, SURFACE % 'uniform="true" ')
    shader = pipeline.generate(path, interface="reduced")[0]
    assert shader.manifest["kept"] == ["ss_base_color"]
    assert [u["name"] for u in shader.manifest["uniforms"]] == ["ss_base_color"]
    assert _material_uniforms(shader) == ["ss_base_color"]
    assert "uniform vec3 ss_base_color = vec3(0.8, 0.2, 0.1);" in shader.fragment
    # complete: every input a uniform, as before
    complete = pipeline.generate(path)[0]
    assert "ss_coat" in _material_uniforms(complete) and "kept" not in complete.manifest


def test_uniform_true_on_the_nodedef_keeps_the_input(tmp_path):
    # gltf_pbr's nodedef marks ior, attenuation_color, ... uniform="true"
    path = write_doc(tmp_path, """
  <gltf_pbr name="g" type="surfaceshader"><input name="ior" type="float" value="1.4" /></gltf_pbr>
  <surfacematerial name="m" type="material"><input name="surfaceshader" type="surfaceshader" nodename="g" />
  </surfacematerial>""")
    session = pipeline.Session(path)
    marked = sorted(u.name for u in session.graph("m").uniforms.values() if u.marked)
    assert "g_ior" in marked
    shader = pipeline.generate(path, interface="reduced")[0]
    assert sorted(shader.manifest["kept"]) == marked
    assert _material_uniforms(shader) == marked
    assert "g_base_color" not in shader.fragment


def test_keep_names_keep_exactly_those_inputs(tmp_path, capsys):
    from mtlxgen.apps.cli import main
    path = write_doc(tmp_path, SURFACE % "")
    out = str(tmp_path / "out")
    rc = main(["generate", path, "-o", out, "--interface", "reduced", "--keep", "ss_coat",
               "--keep", "ss/specular_roughness"])
    assert rc == 0, capsys.readouterr().err
    manifest = json.load(open(os.path.join(out, "m.json")))
    frag = open(os.path.join(out, "m.frag")).read()
    assert manifest["interface"] == "reduced"
    assert manifest["kept"] == ["ss_specular_roughness", "ss_coat"]
    assert sorted(u["name"] for u in manifest["uniforms"]) == ["ss_coat", "ss_specular_roughness"]
    assert "uniform float ss_coat = 0.5;" in frag and "uniform float ss_specular_roughness = 0.35;" in frag
    assert "ss_base_color" not in frag and "vec3(0.8, 0.2, 0.1)" in frag


@pytest.mark.parametrize("form", ["lines", "json", "manifest"])
def test_keep_file(tmp_path, capsys, form):
    from mtlxgen.apps.cli import main
    path = write_doc(tmp_path, SURFACE % "")
    keep = tmp_path / "keep.txt"
    if form == "lines":
        keep.write_text("# inputs a look-dev panel edits\nss_coat\n\nss.base_color\n")
    elif form == "json":
        keep.write_text(json.dumps(["ss_coat", "ss/base_color"], indent=1))
    else:           # a manifest of ours: its uniforms
        keep.write_text(json.dumps({"element": "m", "uniforms": [{"name": "ss_coat"}, {"name": "ss_base_color"}]}))
    out = str(tmp_path / "out")
    rc = main(["generate", path, "-o", out, "--keep-file", str(keep)])      # --keep-file implies reduced
    assert rc == 0, capsys.readouterr().err
    manifest = json.load(open(os.path.join(out, "m.json")))
    assert manifest["interface"] == "reduced"
    assert manifest["kept"] == ["ss_base_color", "ss_coat"]


def _one_line(capsys, rc, *named):
    err = capsys.readouterr().err
    assert rc == 1, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    for text in named:
        assert text in lines[0], (text, lines[0])
    return lines[0]


def test_bad_keep_names_and_interface_values_are_one_line(tmp_path, capsys):
    from mtlxgen.apps.cli import main
    path = write_doc(tmp_path, SURFACE % "")
    out = str(tmp_path / "out")
    _one_line(capsys, main(["generate", path, "-o", out, "--interface", "reduced", "--keep", "ss_nope"]),
              path + ":0:", "--keep 'ss_nope'")
    keep = tmp_path / "keep.txt"
    keep.write_text("ss_coat\n\nnot_an_input\n")
    _one_line(capsys, main(["generate", path, "-o", out, "--interface", "reduced", "--keep-file", str(keep)]),
              "%s:3:" % keep, "'not_an_input'")
    keep.write_text('["ss_coat",\n 3]')
    _one_line(capsys, main(["generate", path, "-o", out, "--keep-file", str(keep)]), "%s:2:" % keep, "not a name")
    keep.write_text('["ss_coat",')
    _one_line(capsys, main(["render", path, "-o", out, "--keep-file", str(keep)]), str(keep), "JSON")
    _one_line(capsys, main(["generate", path, "-o", out, "--interface", "simplified"]),
              "argument --interface", "simplified")
    _one_line(capsys, main(["golden", "check", path, "--interface", "reduce"]), "argument --interface")
    _one_line(capsys, main(["generate", path, "-o", out, "--interface", "complete", "--keep", "ss_coat"]),
              "--interface reduced")
    _one_line(capsys, main(["generate", path, "-o", out, "--keep-file", str(tmp_path / "missing.txt")]),
              "--keep-file", "no such file")


def test_complete_is_the_default_and_unchanged(tmp_path):
    path = write_doc(tmp_path, SURFACE % "")
    default = pipeline.generate(path)[0]
    complete = pipeline.generate(path, interface="complete")[0]
    assert (default.vertex, default.fragment, default.manifest) == (complete.vertex, complete.fragment,
                                                                    complete.manifest)
    assert default.manifest["interface"] == "complete"


def _snapshot(g):
    return copy.deepcopy((g.element, g.kind, g.result, [(n.id, n.category, n.nodedef.name, n.inputs, n.outputs,
                                                          n.static, n.loc) for n in g.nodes],
                          g.uniforms, g.structs, g.doc_path, g.colorspace, g.warnings))


@pytest.mark.parametrize("path, element", [
    (os.path.join(ROOT, "examples", "quick_start.mtlx"), None),
    (os.path.join(ROOT, "examples", "openpbr", "open_pbr_released_names.mtlx"), None),
    (os.path.join(ROOT, "examples", "math_outputs.mtlx"), None)])
def test_reduction_and_folding_leave_the_input_graph_unchanged(path, element):
    session = pipeline.Session(path)
    for name in session.elements:
        g = session.graph(name)
        nodes, uniforms, before = list(g.nodes), dict(g.uniforms), _snapshot(g)
        iface = reduce.interface("reduced", [next(iter(g.uniforms))] if g.uniforms else [])
        r, kept = reduce.reduce(g, iface)
        f = fold.fold(r)
        assert _snapshot(g) == before
        assert g.nodes == nodes and all(a is b for a, b in zip(g.nodes, nodes)) and g.uniforms == uniforms
        assert not g.static_guards and f.static_guards and f is not g and r is not g
        assert len(f.nodes) <= len(g.nodes)


def test_render_batch_golden_and_view_take_the_interface(tmp_path, capsys):
    from mtlxgen.apps import view
    from mtlxgen.apps.cli import main
    path = os.path.join(ROOT, "examples", "unlit_checker.mtlx")
    out = str(tmp_path / "out")
    assert main(["render", path, "-o", out, "--size", "16", "--interface", "reduced"]) == 0
    assert main(["batch", path, "-o", out, "--size", "16", "-j", "1", "--no-progress", "--interface", "reduced"]) == 0
    assert main(["golden", "check", path, "-o", str(tmp_path / "golden"), "-j", "1", "--no-progress", "--no-flip",
                 "--interface", "reduced"]) == 0, capsys.readouterr()
    gen = view.OurGenerator(GenerateOptions(interface="reduced"))
    session = gen.open(path, "fis")
    shown = gen.shader(session, session.elements[0])
    assert shown.manifest["interface"] == "reduced"
    from mtlxgen.apps.cli import build_parser
    args = build_parser().parse_args(["view", path, "--interface", "reduced", "--keep", "x"])
    assert args.interface == "reduced" and args.keep == ["x"]


def test_reduced_shaders_paste_library_code_without_comments(tmp_path):
    """A reduced shader is made for one use: its glsl_lib code comes without comments and blank lines (the
    complete shader keeps the citations), each file still marked, the code token for token the same (same
    pixels: the parity tests above) and valid to the reference compiler in every target."""
    from mtlxgen.emit import glsldeps
    from mtlxgen.apps.glslvalidate import GLSLANG, validate
    path = os.path.join(ROOT, "examples", "quick_start.mtlx")
    complete = pipeline.generate(path)[0].fragment
    reduced = pipeline.generate(path, interface="reduced")[0].fragment
    lib = reduced[:reduced.index("void main()")]
    comments = [line for line in lib.splitlines() if "//" in line and not line.startswith("// ---- glsl_lib/")]
    assert comments == [reduced.splitlines()[1]]            # the header's "generated by" line alone
    markers = lib.count("// ---- glsl_lib/")
    assert markers > 3 and lib.split("\n").count("") <= markers + 3      # one blank line after a file, no more
    assert len(reduced) < 0.6 * len(complete)
    assert glsldeps.compact("a; // x\n\n/* y\n z */\nb;\n#define K 1 // k\n") == "a;\nb;\n#define K 1"
    if GLSLANG is not None:
        for target in ("glsl", "essl", "vulkan"):
            s = pipeline.generate(path, interface="reduced", target=target)[0]
            assert not validate(s, str(tmp_path), target)
