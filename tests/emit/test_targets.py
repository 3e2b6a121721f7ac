"""Shader targets (targets.py, interface.py): every target draws the same pixels, declares what its API
requires, and its manifest tells a renderer everything the shader leaves to it.

Validity to the reference compiler, and the vulkan block offsets against glslang's reflection, are in
test_glsl_validity.py."""
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import DATA_IMAGES, ROOT
from mtlxgen.base import interface, targets
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.draw.renderer import Renderer

OWN = os.path.join(ROOT, "tests", "data", "targets")
SIZE = 64
# one of each kind of material: procedural standard_surface, every uniform type with a texture and a displacement,
# a struct uniform, open_pbr, Enterprise PBR, Stride, UsdPreviewSurface, EDF/VDF, an unlit output
DOCUMENTS = [
    "examples/quick_start.mtlx", "tests/data/targets/interface_types.mtlx", "tests/data/targets/struct_uniform.mtlx",
    "examples/openpbr/open_pbr_released_names.mtlx", "examples/enterprise/enterprise_car_paint.mtlx",
    "examples/stride/stride_metalness.mtlx", "examples/usd/usd_seed_rules.mtlx", "examples/edf_vdf/edf_vdf.mtlx",
    "examples/math_outputs.mtlx",
]
LIGHT = {"type": 3, "position": (1.5, 2.0, 3.0), "direction": (-0.4, -0.5, -0.75), "color": (1.0, 0.8, 0.6),
         "intensity": 3.0, "decay_rate": 2.0, "inner_angle": 0.95, "outer_angle": 0.85}


@pytest.fixture(scope="module")
def lit_renderer():
    """A renderer with a spot light: the light record goes through u_lightData[] (a block member in vulkan)."""
    with Renderer(size=SIZE, lights=[LIGHT, dict(LIGHT, type=2, intensity=1.0)]) as r:
        yield r


@pytest.mark.parametrize("doc", DOCUMENTS)
def test_every_target_draws_the_pixels_of_the_default_one(doc, lit_renderer):
    path = os.path.join(ROOT, doc)
    images = {}
    for target in targets.NAMES:
        shaders, error = pipeline.generate(path, partial=True, target=target, max_lights=2)
        assert error is None, error
        for s in shaders:
            assert s.manifest["target"] == target
            images[(target, s.element)] = lit_renderer.render(s)
    for (target, element), img in images.items():
        base = images[("glsl", element)]
        assert img[..., 3].max() > 0, "%s drew nothing" % element
        assert np.abs(img - base).max() <= 1e-5, "%s (%s) differs from glsl by %g" % (
            element, target, np.abs(img - base).max())


def test_the_light_is_drawn_through_the_block(lit_renderer):
    """Not vacuous: the lights change the picture, so the equality above covers the packed light records."""
    s = pipeline.generate(os.path.join(OWN, "interface_types.mtlx"), target="vulkan", max_lights=2)[0]
    with Renderer(size=SIZE) as unlit:
        assert np.abs(lit_renderer.render(s) - unlit.render(s)).max() > 0.05


def _declarations(text):
    return [line for line in text.splitlines() if re.match(r"(layout\(.*\) )?uniform ", line)]


def test_each_target_spells_its_header_and_declarations():
    path = os.path.join(OWN, "interface_types.mtlx")
    glsl, essl, vulkan = (pipeline.generate(path, target=t)[0] for t in ("glsl", "essl", "vulkan"))
    for s, first in ((glsl, "#version 400"), (essl, "#version 300 es"), (vulkan, "#version 450")):
        for stage in (s.vertex, s.fragment):
            assert stage.splitlines()[0] == first
    assert essl.fragment.splitlines()[1:4] == ["precision highp float;", "precision highp int;",
                                               "precision highp sampler2D;"]
    # glsl: every uniform but samplers and the light records has its initializer; essl and vulkan: none has one
    assert all("=" in d for d in _declarations(glsl.fragment) if "sampler" not in d and "LightData" not in d)
    assert not any("=" in re.sub(r"^layout\(.*?\) ", "", d) for s in (essl, vulkan)
                   for d in _declarations(s.fragment + s.vertex))
    # vulkan: one block, the same in both stages; samplers with bindings; every in/out at a location
    block = re.compile(r"layout\(std140, set = 0, binding = 0\) uniform MaterialUniforms\n\{\n(.*?)\n\};", re.S)
    assert block.findall(vulkan.fragment) == block.findall(vulkan.vertex) != []
    assert all(re.match(r"layout\(set = 0, binding = \d+\) uniform sampler2D \w+;$", d)
               for d in _declarations(vulkan.fragment) if "sampler" in d)
    for stage in (vulkan.vertex, vulkan.fragment):
        for line in stage.splitlines():
            if re.match(r"(flat )?(in|out) ", line):
                pytest.fail("no location: " + line)


def test_manifest_lists_the_application_uniforms_with_the_tables_defaults():
    s = pipeline.generate(os.path.join(ROOT, "examples", "quick_start.mtlx"), target="essl", max_lights=3)[0]
    app = {e["name"]: e for e in s.manifest["application"]}
    assert {"u_worldMatrix", "u_viewProjectionMatrix", "u_viewPosition", "u_envMatrix", "u_envRadiance",
            "u_envRadianceMips", "u_envRadianceSamples", "u_numActiveLightSources", "u_lightData"} <= set(app)
    assert app["u_envMatrix"]["default"] == list(interface.ENV_MATRIX)
    assert app["u_lightData"]["type"] == "LightData[3]" and s.manifest["max_lights"] == 3
    # every uniform either stage declares is in the manifest: the material's or the application's
    declared = {re.search(r"(\w+)(\[\w+\])?;$", d).group(1) for d in _declarations(s.vertex + s.fragment)}
    listed = set(app) | {u["name"] for u in s.manifest["uniforms"]} | {t["uniform"] for t in s.manifest["textures"]}
    assert declared == listed


def test_glsl_initializers_are_the_tables_defaults():
    s = pipeline.generate(os.path.join(ROOT, "examples", "quick_start.mtlx"))[0]
    for name in ("u_envMatrix", "u_envRadianceSamples", "u_envLightIntensity", "u_envSampleFrames"):
        u = interface.TABLE[name]
        assert "uniform %s %s = %s;" % (u.type, name, interface.glsl_value(u)) in s.fragment


def _images_document(tmp_path, n):
    images = "\n".join(
        '<image name="i%d" type="color3"><input name="file" type="filename" value="%s" /></image>'
        % (i, os.path.join(DATA_IMAGES, "grid.png")) for i in range(n))
    adds = "\n".join('<add name="a%d" type="color3"><input name="in1" type="color3" nodename="%s" />'
                     '<input name="in2" type="color3" nodename="i%d" /></add>' % (i, "a%d" % (i - 1) if i > 1 else "i0", i)
                     for i in range(1, n))
    p = tmp_path / ("images_%d.mtlx" % n)
    p.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n%s\n%s\n'
                 '<output name="out" type="color3" nodename="a%d" />\n</materialx>\n' % (images, adds, n - 1))
    return str(p)


def test_essl_refuses_more_samplers_than_webgl2_guarantees(tmp_path):
    """WebGL2 guarantees 16 texture units to a fragment stage: 16 images fit an unlit output (no environment),
    17 are one FILE:LINE error naming the count; the other targets take them."""
    assert len(pipeline.generate(_images_document(tmp_path, 16), target="essl")) == 1
    path = _images_document(tmp_path, 17)
    with pytest.raises(MtlxError) as e:
        pipeline.generate(path, target="essl")
    (line,) = e.value.lines()
    assert line.startswith(path + ":") and "17 texture samplers" in line and "16" in line
    assert len(pipeline.generate(path, target="vulkan")) == 1
    r = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "generate", path, "-o", str(tmp_path / "o"),
                        "--target", "essl"], capture_output=True, text=True)
    assert r.returncode == 1 and len(r.stderr.strip().splitlines()) == 1 and "17 texture samplers" in r.stderr
    assert not (tmp_path / "o" / "out.frag").exists()


def test_cli_writes_the_target_and_refuses_an_unknown_one(tmp_path):
    doc = os.path.join(ROOT, "examples", "unlit_checker.mtlx")
    r = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "generate", doc, "-o", str(tmp_path),
                        "--target", "vulkan"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    manifest = json.loads((tmp_path / "M_checker.json").read_text())
    assert manifest["target"] == "vulkan" and manifest["glsl_version"] == "450"
    assert manifest["uniform_block"]["size"] % 16 == 0 and manifest["attribute_locations"]["i_position"] == 0
    r = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "generate", doc, "-o", str(tmp_path),
                        "--target", "metal"], capture_output=True, text=True)
    assert r.returncode == 1 and "--target" in r.stderr and "Traceback" not in r.stderr


def test_golden_check_passes_in_every_target(tmp_path):
    """A golden is an image: the essl and vulkan shaders of a bundled example match the default target's golden."""
    for target in ("essl", "vulkan"):
        r = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "golden", "check", "--no-progress", "-j", "1",
                            "--no-flip", "--target", target, "-o", str(tmp_path / target),
                            os.path.join(ROOT, "examples", "quick_start.mtlx")],
                           capture_output=True, text=True, cwd=ROOT)
        assert r.returncode == 0 and "1 passed, 0 failed" in r.stdout, r.stdout + r.stderr


def test_std140_layout_rules():
    """targets.std140 against the rules of OpenGL 4.5 sec. 7.6.2.2, on cases with known answers."""
    structs = {"S": [("a", "float", 0), ("b", "vec3", 0)]}
    layout, size = targets.block_layout([("f", "float", 0), ("v3", "vec3", 0), ("f2", "float", 0), ("v2", "vec2", 0),
                                         ("m3", "mat3", 0), ("arr", "float", 3), ("s", "S", 2), ("last", "int", 0)],
                                        structs)
    assert [(n, o) for n, o, _ in layout] == [("f", 0), ("v3", 16), ("f2", 28), ("v2", 32), ("m3", 48), ("arr", 96),
                                              ("s", 144), ("last", 208)]
    assert dict((n, s) for n, _, s in layout)["arr"] == 16 and dict((n, s) for n, _, s in layout)["s"] == 32
    assert size == 224


# ---------------------------------------------------------------- the light loop, only where lights are asked for

QUICK = os.path.join(ROOT, "examples", "quick_start.mtlx")


@pytest.mark.parametrize("doc", ["examples/quick_start.mtlx", "examples/stride/stride_metalness.mtlx",
                                 "examples/enterprise/enterprise_car_paint.mtlx"])
def test_lit_surfaces_loop_over_lights_only_when_asked(doc, lit_renderer):
    """Without lights asked for, a lit surface has no light loop and declares no light uniforms (issue 14: the
    loop and its uniforms cost compile time for nothing); with max_lights N, MG_MAX_LIGHTS is N, the manifest
    says so, and the lights change the picture. Environment-lit, the two draw the same pixels."""
    path = os.path.join(ROOT, doc)
    bare = pipeline.generate(path)[0]
    assert "u_lightData" not in bare.fragment and "mg_sample_light" not in bare.fragment
    assert "LightData" not in bare.fragment and bare.manifest["max_lights"] == 0
    assert not any(e["name"] in ("u_lightData", "u_numActiveLightSources") for e in bare.manifest["application"])
    lit = pipeline.generate(path, max_lights=2)[0]
    assert "#define MG_MAX_LIGHTS 2" in lit.fragment and "mg_sample_light(u_lightData[mg_i]" in lit.fragment
    assert lit.manifest["max_lights"] == 2
    with Renderer(size=SIZE) as env_only:
        env_lit = env_only.render(lit)
        assert np.abs(env_only.render(bare) - env_lit).max() <= 1e-6
    assert np.abs(lit_renderer.render(lit) - env_lit).max() > 0.01


def test_binding_more_lights_than_a_shader_takes_is_an_error(lit_renderer, tmp_path):
    """A renderer with lights refuses a lit shader generated for fewer (it would drop them silently)."""
    with pytest.raises(MtlxError) as e:
        lit_renderer.render(pipeline.generate(QUICK)[0])
    assert "generated for 0 direct lights, 2 bound" in str(e.value.lines())
    unlit = pipeline.generate(os.path.join(ROOT, "examples", "unlit_checker.mtlx"))[0]
    assert lit_renderer.render(unlit)[..., 3].max() > 0          # an unlit shader takes no lights: drawn as it is


def test_cli_max_lights_and_render_lights(tmp_path):
    cli = [sys.executable, os.path.join(ROOT, "cli.py")]
    r = subprocess.run(cli + ["generate", QUICK, "-o", str(tmp_path / "g"), "--max-lights", "4"], capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    assert json.loads((tmp_path / "g" / "M_tiles.json").read_text())["max_lights"] == 4
    assert "#define MG_MAX_LIGHTS 4" in (tmp_path / "g" / "M_tiles.frag").read_text()
    for bad in ("-1", "17", "two"):
        r = subprocess.run(cli + ["generate", QUICK, "-o", str(tmp_path / "g"), "--max-lights", bad],
                           capture_output=True, text=True)
        assert r.returncode == 1 and "--max-lights" in r.stderr and "Traceback" not in r.stderr
    rig = os.path.join(ROOT, "tests", "data", "materialx", "resources", "Lights", "san_giuseppe_bridge_split.mtlx")
    for lights in ([], ["--lights", rig]):
        r = subprocess.run(cli + ["render", QUICK, "-o", str(tmp_path / ("r%d" % len(lights))), "--size", "32"]
                           + lights, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
    from mtlxgen.base.images import read_image
    dark, lit = (read_image(str(tmp_path / d / "M_tiles.exr")) for d in ("r0", "r2"))
    assert np.abs(lit - dark).max() > 0.01, "render --lights draws the rig's light"
    r = subprocess.run(cli + ["render", QUICK, "-o", str(tmp_path / "r"), "--lights", rig, "--max-lights", "0"],
                       capture_output=True, text=True)
    assert r.returncode == 1 and "--max-lights 0" in r.stderr and len(r.stderr.strip().splitlines()) == 1
