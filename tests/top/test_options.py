"""options.GenerateOptions: every generation setting in one object, checked once where it is made (one error naming
the option per bad value), derived with replace(), taken whole by pipeline.Session / generate, batch's workers
(pickled), the command line and the public API's boundary."""
import os
import pickle

import pytest

from conftest import ROOT
from mtlxgen import api, pipeline
from mtlxgen.apps import cli
from mtlxgen.passes import reduce
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.interface import LIGHTS_LIMIT
from mtlxgen.options import FIELDS, GenerateOptions
from mtlxgen.read.usdstage import StageOptions

QUICK_START = os.path.join(ROOT, "examples", "quick_start.mtlx")
STAGE = os.path.join(ROOT, "examples", "usd", "preview_stage.usda")


@pytest.mark.parametrize("field, value, error", [
    ("target", "hlsl", ValueError), ("target", None, ValueError),
    ("interface", "partial", ValueError), ("interface", 3, TypeError),
    ("environment", "bogus", ValueError),
    ("max_lights", LIGHTS_LIMIT + 1, ValueError), ("max_lights", -1, ValueError), ("max_lights", 1.5, ValueError),
    ("max_lights", True, ValueError),
    ("strict", "yes", TypeError), ("usd_seed_rules", "on", TypeError),
    ("library_dirs", "one/folder", TypeError), ("library_dirs", (3,), TypeError),
    ("variants", (("look",),), ValueError), ("variants", (("look", ""),), ValueError),
    ("render_context", "preview", ValueError), ("unreadable_textures", "ignore", ValueError),
    ("keep", ("",), ValueError), ("keep", (3,), TypeError),
])
def test_each_bad_value_is_one_error_naming_its_option(field, value, error):
    base = GenerateOptions(interface="reduced") if field == "keep" else GenerateOptions()
    with pytest.raises(error) as caught:
        base.replace(**{field: value})
    message = str(caught.value)
    assert message.startswith(field) and "\n" not in message, message
    with pytest.raises(error):              # made new, the same check
        GenerateOptions(**dict({"interface": base.interface}, **{field: value}))


def test_keep_needs_the_reduced_interface_and_unknown_names_are_refused():
    with pytest.raises(ValueError, match="keep names inputs kept uniforms in the reduced interface"):
        GenerateOptions(keep=("base_color",))
    with pytest.raises(TypeError, match="unknown generation option.*colour.*the options are target, interface"):
        GenerateOptions().replace(colour="red")
    with pytest.raises(TypeError, match="options must be a GenerateOptions, not list"):
        pipeline.generate(QUICK_START, ["M_tiles"])         # elements where the options go: said, not guessed


def test_replace_derives_a_checked_variant_and_leaves_the_original():
    base = GenerateOptions(target="essl", interface="reduced", keep=("a", ("b", Loc("keep.txt", 2))))
    lit = base.replace(max_lights=2)
    assert (lit.max_lights, lit.target, lit.keep) == (2, "essl", (("a", None), ("b", Loc("keep.txt", 2))))
    assert base.max_lights == 0 and base != lit
    with pytest.raises(AttributeError):
        base.max_lights = 3                                  # frozen
    with pytest.raises(ValueError):
        lit.replace(interface="complete")                   # its keep list needs reduced: checked again
    assert lit.replace(interface="complete", keep=()).interface == "complete"
    assert GenerateOptions.of(None) == GenerateOptions() and GenerateOptions.of(lit) is lit
    assert GenerateOptions.of(lit, strict=True) == lit.replace(strict=True)
    assert set(FIELDS) >= {"target", "interface", "keep", "environment", "max_lights", "strict", "usd_seed_rules",
                           "library_dirs", "variants", "render_context", "unreadable_textures"}


def test_an_interface_object_is_taken_apart_and_each_session_gets_a_fresh_one():
    opts = GenerateOptions(interface=reduce.interface("reduced", ["ss_coat"]))
    assert (opts.interface, opts.keep) == ("reduced", (("ss_coat", None),))
    assert GenerateOptions().replace(interface=reduce.Interface("reduced", [("x", None)])).keep == (("x", None),)
    one, two = opts.make_interface(), opts.make_interface()
    assert one is not two and one.matched is not two.matched and one.keep == [("ss_coat", None)]
    # the same options for two documents: a name kept that names an input of the first but none of the second is a
    # problem with the second (which names matched is each session's own record, not the options')
    kept = GenerateOptions(interface="reduced", keep=("tiles_color1",))
    assert "tiles_color1" in pipeline.generate(QUICK_START, kept, elements=["M_tiles"])[0].manifest["kept"]
    with pytest.raises(MtlxError, match="--keep 'tiles_color1': no public input"):
        pipeline.generate(os.path.join(ROOT, "examples", "unlit_checker.mtlx"), kept)
    assert "tiles_color1" in pipeline.generate(QUICK_START, kept, elements=["M_tiles"])[0].manifest["kept"]


def test_options_pickle_whole_for_batch_workers():
    opts = GenerateOptions(target="vulkan", interface="reduced", keep=(("k", Loc("f.txt", 3)),), max_lights=4,
                           strict=True, library_dirs=("libs",), variants=(("look", "blue"),),
                           render_context="universal", unreadable_textures="error")
    back = pickle.loads(pickle.dumps(opts))
    assert back == opts and back.keep[0][1] == Loc("f.txt", 3)


def test_stage_options_for_stages_and_a_problem_for_a_document():
    assert GenerateOptions().stage_options(QUICK_START) is None
    assert GenerateOptions().stage_options(STAGE) == StageOptions((), "mtlx")
    assert GenerateOptions(variants=[["look", "blue"]], render_context="universal").stage_options(STAGE) == \
        StageOptions((("look", "blue"),), "universal")
    with pytest.raises(MtlxError) as caught:
        pipeline.generate(QUICK_START, GenerateOptions(variants=(("look", "blue"),)))
    assert caught.value.lines() == ["%s:0: --variant applies to USD stages (.usd, .usda, .usdc, .usdz) only"
                                    % QUICK_START]


def test_generate_takes_the_object_or_its_fields_as_keywords_alike():
    by_object = pipeline.generate(QUICK_START, GenerateOptions(target="essl", max_lights=2), elements=["M_tiles"])[0]
    by_keywords = pipeline.generate(QUICK_START, elements=["M_tiles"], target="essl", max_lights=2)[0]
    on_top = pipeline.generate(QUICK_START, GenerateOptions(target="essl"), elements=["M_tiles"], max_lights=2)[0]
    assert by_object.fragment == by_keywords.fragment == on_top.fragment
    assert by_object.manifest["max_lights"] == 2 and by_object.fragment.startswith("#version 300 es")
    session = pipeline.Session(QUICK_START, GenerateOptions(interface="reduced", environment="prefiltered"))
    assert (session.interface.kind, session.environment, session.target) == ("reduced", "prefiltered", "glsl")
    assert session.shader("M_tiles").manifest["environment"] == "prefiltered"


def test_the_command_line_makes_one_options_object_from_its_options(tmp_path):
    keep_file = tmp_path / "keep.txt"
    keep_file.write_text("# kept\nbase_color\n")
    args = cli.build_parser().parse_args(
        ["render", STAGE, "-o", str(tmp_path), "--target", "vulkan", "--keep", "roughness", "--keep-file",
         str(keep_file), "--max-lights", "3", "--variant", "look=blue", "--render-context", "universal",
         "--environment", "prefiltered", "--strict", "--no-usd-seed-rules", "--library", str(tmp_path)])
    assert cli._options(args) == GenerateOptions(
        target="vulkan", interface="reduced", keep=(("roughness", None), ("base_color", Loc(str(keep_file), 2))),
        environment="prefiltered", max_lights=3, strict=True, usd_seed_rules=False, library_dirs=(str(tmp_path),),
        variants=(("look", "blue"),), render_context="universal", unreadable_textures="error")
    # render binds a rig's lights where --max-lights does not say; web writes ES shaders and binds none
    rendered = cli.build_parser().parse_args(["render", QUICK_START, "-o", str(tmp_path)])
    assert cli._options(rendered, rig=("a", "b")).max_lights == 2
    web = cli.build_parser().parse_args(["web", QUICK_START, "-o", str(tmp_path)])
    assert cli._options(web) == GenerateOptions(target="essl", unreadable_textures="error")
    gen = cli.build_parser().parse_args(["generate", QUICK_START, "-o", str(tmp_path)])
    assert cli._options(gen, unreadable_textures="warning") == GenerateOptions()


def test_the_public_options_become_the_internal_ones_at_the_api_boundary():
    public = api.Options(library_dirs=["libs"], environment="prefiltered", max_lights=2, strict=True, keep=["a"],
                         usd_seed_rules=True, variants=[("look", "blue")], render_context="universal")
    assert api.generate_options("essl", "reduced", public) == GenerateOptions(
        target="essl", interface="reduced", keep=("a",), library_dirs=("libs",), environment="prefiltered",
        max_lights=2, strict=True, usd_seed_rules=True, variants=(("look", "blue"),), render_context="universal")
    assert api.generate_options(options={"max_lights": 1}, unreadable_textures="error") == \
        GenerateOptions(max_lights=1, unreadable_textures="error")
    with pytest.raises(ValueError, match="target must be one of glsl, essl, vulkan, not 'hlsl'"):
        api.generate(QUICK_START, target="hlsl")
    with pytest.raises(ValueError, match="max_lights must be a whole number from 0 to %d" % LIGHTS_LIMIT):
        api.generate(QUICK_START, options={"max_lights": 99})
