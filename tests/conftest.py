"""Shared fixtures (one renderer and one MaterialX reference per test session) and where test data lives.

Two sources of MaterialX documents, both laid out as MaterialX's own resources/ folder:
- DATA (tests/data/materialx): the few files the core tests read, copied with MaterialX's licence; always here.
- CORPUS (../shared/corpus/materialx): the scoreboard's corpus, for sweeps over many files. It is not part of
  the project (absent on a clone): tests that read it are marked `corpus` and skip, with CORPUS_ABSENT, there.
"""
import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
DATA = os.path.join(ROOT, "tests", "data", "materialx")
DATA_TESTSUITE = os.path.join(DATA, "resources", "Materials", "TestSuite")
DATA_EXAMPLES = os.path.join(DATA, "resources", "Materials", "Examples")
DATA_IMAGES = os.path.join(DATA, "resources", "Images")
SHARED = os.path.abspath(os.path.join(ROOT, "..", "shared"))
CORPUS = os.path.join(SHARED, "corpus", "materialx")
TESTSUITE = os.path.join(CORPUS, "resources", "Materials", "TestSuite")
EXAMPLES = os.path.join(CORPUS, "resources", "Materials", "Examples")
HAVE_CORPUS = os.path.isdir(os.path.join(CORPUS, "resources", "Materials"))
CORPUS_ABSENT = "needs ../shared/corpus (the scoreboard's corpus), absent on a clone"
TEST_SIZE = 128
# MaterialX resolves resources/... file names against these; the copied subset first, so that a test reads
# the same files with or without ../shared
REFERENCE_SEARCH = [DATA] + ([CORPUS] if HAVE_CORPUS else [])


def corpus_params(make, width=1):
    """Parameters built from the corpus by `make()` (a list of values or pytest.param), or, with the corpus
    absent, one case that skips with CORPUS_ABSENT (not an empty set, and `make` never runs)."""
    if HAVE_CORPUS:
        return list(make())
    values = (None,) * width
    return [pytest.param(*values, id="corpus-absent", marks=pytest.mark.skip(reason=CORPUS_ABSENT))]


def generate_switched(path, switches, **options):
    """pipeline.generate(path, partial=True, **options) with module flags set for the call ({module: value}, e.g.
    {emitcache: False} sets emitcache.REUSE), as comparable data: ([(element, stem, vertex, fragment, manifest)],
    problem lines or None), or (None, lines) for a document that does not open."""
    from mtlxgen import pipeline
    from mtlxgen.base.diagnostics import MtlxError
    saved = {m: m.REUSE for m in switches}
    for m, value in switches.items():
        m.REUSE = value
    try:
        shaders, error = pipeline.generate(path, partial=True, **options)
    except MtlxError as e:              # (a document that does not open: the same either way)
        return None, e.lines()
    finally:
        for m, value in saved.items():
            m.REUSE = value
    return [(s.element, s.stem, s.vertex, s.fragment, s.manifest) for s in shaders], \
        (error.lines() if error is not None else None)


# ---------------------------------------------------------------- what each test needs (markers)
#
# gl: a GL context (moderngl on EGL/OSMesa/X11: rendering, glslcheck's driver compile) or a GLSL compiler run
#     (glslangValidator, spirv-val, ../shared/tools/gpu_proxy); browser: Chromium or Node (the web and three
#     pages); window: a window on a display (the viewer, on Xvfb). `pytest -m "not gl"` is the fast subset.
# A test gets its markers from the fixtures it uses (directly or through other fixtures), else from its module
# below; a test not marked gl that creates a context or runs a compiler fails, saying so, and one not marked
# browser that starts Chromium or Node (nogl_guard.py).

FIXTURE_MARKS = {
    "renderer": ("gl",), "harness": ("gl",), "lit_renderer": ("gl",), "stage_renderer": ("gl",),
    "rig_renderers": ("gl",), "scoreboard_harness": ("gl",), "mxharness": ("gl",),
    "browser": ("browser", "gl"),           # Chromium draws the pages with WebGL
    # modules' own: a Renderer (a white furnace and what it draws) or a context evaluating GLSL on a grid
    "furnace": ("gl",), "furnace_rig": ("gl",), "furnace_figures": ("gl",), "bsdf_eval": ("gl",),
    "evaluate": ("gl",), "evaluator": ("gl",),
}
# The rest, by module ("test_x": every test in it) or by test ("test_x::test_name", each parametrization): what
# draws through a helper, a module's own Renderer or OffscreenWindow, or a CLI subprocess (render, batch, golden,
# view), or runs glslangValidator; Chromium or Node started by the test itself. A window (Xvfb) is a GL context
# too, and so is a page Chromium draws with WebGL; Node alone (checking the three module) is browser only.
_GL, _WINDOW, _BROWSER = ("gl",), ("gl", "window"), ("gl", "browser")
MODULE_MARKS = {
    "test_bench_gpu_compilers": _GL, "test_cluster": _GL, "test_shards": _GL, "test_golden": _GL, "test_glsl_validity": _GL,
    "test_render": _GL, "test_scoreboard_scene": _GL, "test_view_edits": _GL, "test_view_keys": _GL,
    "test_view_progressive": _GL,
    "test_view": _WINDOW, "test_view_reload": _WINDOW, "test_view_isolated": _WINDOW,
    "test_web": _BROWSER, "test_three": _BROWSER,
    "test_golden::test_report_opens_in_headless_chromium": _BROWSER,
    "test_manifest_schema::test_every_manifest_of_the_corpus_validates": _GL,
    "test_api::test_a_missing_dependency_is_one_line_naming_the_package": _GL,
    "test_api::test_render_a_shader_and_a_source_and_a_session": _GL,
    "test_api::test_the_host_example_draws_what_render_draws": _GL,
    "test_cli::test_good_options_at_their_limits_are_accepted": _GL,
    "test_cli::test_render_writes_png_and_exr": _GL,
    "test_closure_weights::test_rough_white_mirror_keeps_its_energy_where_materialx_loses_some": _GL,
    "test_edf_vdf::test_measured_edf_with_a_broken_ies_file_is_one_line_at_its_input": _GL,
    "test_enterprise_pbr::test_attenuation_darkens_solid_glass_by_beer_lambert": _GL,
    "test_environment_prefilter::test_levels_hold_the_ggx_lobe": _GL,
    "test_environment_prefilter::test_render_binds_the_prefiltered_map_only_for_prefiltered_shaders": _GL,
    "test_environment_prefilter::test_seven_materials_prefiltered_error_is_bounded": _GL,
    "test_environment_prefilter::test_viewer_draws_prefiltered_while_moving_and_fis_when_still": _GL,
    "test_escaping::test_three_module_syntax_and_import_in_node": ("browser",),
    "test_escaping::test_usd_colorspace_metadata_is_data_in_the_module": ("browser",),
    "test_escaping::test_web_page_loads_in_chromium_without_running_document_text": _BROWSER,
    "test_file_access::test_16k_texture_and_environment_render_in_bounded_memory": _GL,
    "test_file_access::test_64_channel_texture_decodes_four_channels": _GL,
    "test_file_access::test_renderer_keeps_a_texture_error_until_the_file_is_forgotten": _GL,
    "test_file_access::test_sparse_files_are_refused_on_their_size": _GL,
    "test_file_access::test_text_file_as_a_stage_texture_names_the_attribute": _GL,
    "test_file_access::test_truncated_png_is_one_line_without_libpng_output": _GL,
    "test_folders_outputs::test_an_internal_error_in_one_batch_document_is_one_line_naming_it": _GL,
    "test_folders_outputs::test_batch_never_writes_one_documents_image_over_anothers": _GL,
    "test_folders_outputs::test_batch_reports_each_unreadable_entry_and_draws_the_rest": _GL,
    "test_folders_outputs::test_dangling_links_and_loops_alone_are_reported_not_a_crash": _GL,
    "test_folders_outputs::test_empty_member_default_reads_as_the_member_types_zero": _GL,
    "test_folders_outputs::test_empty_struct_default_of_a_nodedef_reads_as_no_value_with_a_warning": _GL,
    "test_folders_outputs::test_glslvalidate_replaces_a_symlink_at_its_stage_file": _GL,
    "test_folders_outputs::test_golden_outputs_replace_symlinks_and_the_index_keeps_ordinary_modes": _GL,
    "test_folders_outputs::test_golden_outputs_the_file_system_refuses_are_named_not_their_temporary_files": _GL,
    "test_folders_outputs::test_golden_update_and_check_report_unreadable_entries_and_fail": _GL,
    "test_folders_outputs::test_screenshot_key_in_the_window_says_why_nothing_is_written": _GL,
    "test_folders_outputs::test_view_screenshot_of_a_document_that_draws_nothing_is_not_written": _GL,
    "test_hostile_sweep::test_batch_of_a_file_name_that_is_not_utf8": _GL,
    "test_hostile_sweep::test_capture_window_to_a_name_no_image_format_takes_is_one_line": _GL,
    "test_hostile_sweep::test_environment_of_non_finite_or_huge_values_prints_no_numpy_warnings": _GL,
    "test_hostile_sweep::test_golden_image_linked_from_outside_the_golden_folder_is_not_copied": _GL,
    "test_hostile_sweep::test_golden_index_entry_outside_the_shape_update_writes_is_one_line": _GL,
    "test_hostile_sweep::test_golden_of_a_file_name_with_a_line_break_is_checked": _GL,
    "test_hostile_sweep::test_golden_update_check_and_report_of_a_file_name_that_is_not_utf8": _GL,
    "test_hostile_sweep::test_images_under_a_folder_name_that_is_not_utf8_are_one_line": _GL,
    "test_hostile_sweep::test_light_rig_input_of_another_type_is_one_line_at_the_input": _GL,
    "test_hostile_sweep::test_results_json_with_a_lone_surrogate_is_reported": _GL,
    "test_hostile_sweep::test_two_channel_environment_is_read_as_grey": _GL,
    "test_hostile_sweep::test_usdz_texture_climbing_out_of_its_package_is_not_read": _GL,
    "test_manifest_schema::test_every_manifest_of_the_examples_and_test_data_validates": _GL,
    "test_metal_random_walk::test_rough_gold_in_a_white_furnace_follows_the_random_walk": _GL,
    "test_missing_textures::test_a_texture_that_does_not_decode_is_one_line_at_its_input": _GL,
    "test_missing_textures::test_batch_and_golden_report_it": _GL,
    "test_missing_textures::test_commands_that_draw_report_it": _GL,
    "test_missing_textures::test_view_says_it_and_draws_the_default": _GL,
    "test_openpbr_names::test_each_draft_input_gets_its_own_line": _GL,
    "test_packaging::test_readme_quick_start_runs_from_the_wheel": _GL,
    "test_pbr_misc::test_a_directional_light_on_a_lambert_sphere_gives_n_dot_l_albedo_over_pi": _GL,
    "test_pbr_misc::test_eon_white_furnace_reflects_all_light_at_every_roughness": _GL,
    "test_pbr_shading::test_mixed_closures_weigh_their_responses": _GL,
    "test_pbr_shading::test_thin_walled_surface_is_seen_straight_through": _GL,
    "test_pbrlib_suite_parity::test_rough_transmission_never_exceeds_the_furnace_where_materialx_does": _GL,
    "test_reduced_interface::test_reduced_shaders_paste_library_code_without_comments": _GL,
    "test_reduced_interface::test_render_batch_golden_and_view_take_the_interface": _GL,
    "test_security::test_rendering_a_texture_from_dev_zero_fails_with_one_line": _GL,
    "test_security::test_implementation_file_from_the_search_path_is_allowed": _GL,
    "test_security::test_implementation_file_in_a_subfolder_of_the_document_is_pasted_into_the_shader": _GL,
    "test_stride::test_cel_shading_quantizes_the_direct_light": _GL,
    "test_stride::test_direct_light_matches_numpy": _GL,
    "test_targets::test_cli_max_lights_and_render_lights": _GL,
    "test_targets::test_golden_check_passes_in_every_target": _GL,
    "test_unseen_sweep::test_a_stage_is_swept_for_generated_and_compiled": _GL,
    "test_unseen_sweep::test_every_document_is_swept": _GL,
    "test_unseen_sweep::test_every_element_materialx_generates_is_at_parity": _GL,
    "test_unseen_sweep::test_table_counts_generated_compiled_parity": _GL,
    "test_glsl_deps::test_generated_shaders_hold_no_function_that_nothing_calls": _GL,
    "test_glsl_deps::test_generated_shaders_are_smaller_and_keep_their_markers": _GL,
    "test_unseen_sweep::test_an_element_whose_materialx_shader_does_not_compile_is_not_counted": _GL,
    "test_usd_stage::test_cli_options_and_batch": _GL,
    "test_usd_stage::test_directory_sweeps_find_stages_not_the_layers_they_compose": _GL,
    "test_usd_stage::test_stage_shaders_are_valid_to_the_reference_compiler": _GL,
    "test_warnings::test_batch_warns_once_and_strict_fails_the_element": _GL,
    "test_warnings::test_golden_update_strict_refuses_an_element_with_a_slip": _GL,
    "test_warnings::test_info_and_render_warn_too": _GL,
}


def _fast_subset(config):
    """Whether this run is the fast subset: its -m expression leaves gl out."""
    return "not gl" in " ".join((config.option.markexpr or "").split())


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config):
    """The fast subset (`-m "not gl"`, no `-n` given) runs on every core with pytest-xdist where it is installed:
    about 1,000 tests of generation, 114 s in one process on 2 cores, 58 s on both. `-n 0` or `-p no:xdist`
    keeps one process; a worker, --collect-only and --pdb are left alone."""
    option = config.option
    if (hasattr(config, "workerinput") or not config.pluginmanager.hasplugin("xdist")
            or getattr(option, "numprocesses", 0) is not None or option.collectonly or option.usepdb
            or not _fast_subset(config)):
        return
    option.numprocesses = "auto"


def _marks_of(item):
    module = item.module.__name__.rpartition(".")[2] if item.module else ""
    names = set(MODULE_MARKS.get(module, ())) | set(MODULE_MARKS.get("%s::%s" % (module, item.originalname), ()))
    for fixture in getattr(item, "fixturenames", ()):
        names.update(FIXTURE_MARKS.get(fixture, ()))
    return names


def pytest_collection_modifyitems(config, items):
    """Marks each test with what it needs (gl, browser, window; see FIXTURE_MARKS and MODULE_MARKS); tests marked
    `corpus` skip, saying why, where ../shared is absent, and are left out of the fast subset where it is not."""
    skip = None if HAVE_CORPUS else pytest.mark.skip(reason=CORPUS_ABSENT)
    if HAVE_CORPUS and _fast_subset(config) and "corpus" not in (config.option.markexpr or ""):
        # the fast subset leaves the corpus sweeps out here as on a clone (CI runs them alone, -m corpus);
        # `-m "not gl and corpus"` runs them without GL
        sweeps = [item for item in items if item.get_closest_marker("corpus")]
        if sweeps:
            config.hook.pytest_deselected(items=sweeps)
            items[:] = [item for item in items if not item.get_closest_marker("corpus")]
    for item in items:
        for name in sorted(_marks_of(item)):
            if not item.get_closest_marker(name):
                item.add_marker(name)
        if skip is not None and item.get_closest_marker("corpus"):
            item.add_marker(skip)


@pytest.hookimpl(wrapper=True)
def pytest_fixture_setup(fixturedef, request):
    """The guard of _gl_guard around the setup of a module's or session's fixture too: such a fixture is set up
    before the test's own fixtures, so a context it creates for a test not marked gl (a module's furnace Renderer)
    would pass unseen and slow the fast subset. It fails the test that asked for it, naming the fixture."""
    item = getattr(request, "_pyfuncitem", None)
    kinds = () if fixturedef.scope == "function" or item is None else \
        tuple(kind for kind in ("gl", "browser") if not item.get_closest_marker(kind))
    if not kinds:
        return (yield)
    import nogl_guard

    def refuse(what, kind):
        pytest.fail(nogl_guard.MESSAGES[kind] % ("%s, in the %s-scoped fixture '%s'" % (
            what, fixturedef.scope, fixturedef.argname)), pytrace=False)
    restore = nogl_guard.install(refuse, kinds)
    try:
        return (yield)
    finally:
        restore()


@pytest.fixture(scope="session")
def _nogl_report(tmp_path_factory):
    return str(tmp_path_factory.mktemp("nogl") / "report.txt")


@pytest.fixture(autouse=True)
def _gl_guard(request, _nogl_report, monkeypatch):
    """A test not marked gl fails when it (or a Python subprocess it starts) creates a GL context or runs a
    GLSL compiler: "test uses GL but is not marked gl"; one not marked browser, when it starts Chromium or Node."""
    kinds = tuple(kind for kind in ("gl", "browser") if not request.node.get_closest_marker(kind))
    if not kinds:
        yield
        return
    import nogl_guard

    def refuse(what, kind):
        pytest.fail(nogl_guard.MESSAGES[kind] % what, pytrace=False)
    restore = nogl_guard.install(refuse, kinds)
    if "gl" in kinds and "mtlxgen.draw.glslcheck" in sys.modules:
        # glslcheck keeps its compile context, or its failure to make one, per process: each test asks afresh,
        # so a test generating a document's own GLSL meets the guard whatever ran before it
        monkeypatch.setattr(sys.modules["mtlxgen.draw.glslcheck"], "_WORKER", {})
    for name, value in nogl_guard.child_env_changes(_nogl_report, kinds).items():
        monkeypatch.setenv(name, value)
    try:
        yield
    finally:
        restore()
    if os.path.exists(_nogl_report):
        with open(_nogl_report, encoding="utf-8") as f:
            lines = f.read().splitlines()
        os.remove(_nogl_report)
        if lines:
            pytest.fail(lines[0], pytrace=False)


@pytest.fixture(scope="session")
def renderer():
    from mtlxgen.draw.renderer import Renderer
    with Renderer(size=TEST_SIZE) as r:
        yield r


@pytest.fixture(scope="session")
def reference():
    """MaterialX's GenGlsl. Fails (not skips) when the wheel is missing: parity must be checked."""
    from mtlxgen.apps.reference import MaterialXReference, ReferenceUnavailable
    try:
        return MaterialXReference(REFERENCE_SEARCH)
    except ReferenceUnavailable as e:
        pytest.fail(str(e))


@pytest.fixture(scope="session")
def cms_reference():
    """MaterialX's GenGlsl with its colour management on (sRGB files converted as the spec says)."""
    from mtlxgen.apps.reference import MaterialXReference
    return MaterialXReference(REFERENCE_SEARCH, color_management=True)


@pytest.fixture(scope="session")
def harness():
    """Our Renderer in the scoreboard's scene (render.SCOREBOARD_SCENE: what ../shared/tools/mxharness.py
    draws; tests/draw/test_scoreboard_scene.py checks that), at the tests' size."""
    from mtlxgen.draw.renderer import Renderer
    with Renderer.scoreboard(size=TEST_SIZE) as r:
        yield r


@pytest.fixture(scope="session")
def library():
    from mtlxgen.read.library import load_library
    return load_library()


# ---------------------------------------------------------------- golden images

def pytest_addoption(parser):
    parser.addoption("--update-goldens", action="store_true", default=False,
                     help="rewrite golden_images/ from the current renders instead of checking against them")


@pytest.fixture(scope="session")
def update_goldens(request):
    """True under `pytest --update-goldens`: golden tests rewrite their goldens, then pass."""
    return request.config.getoption("--update-goldens")
