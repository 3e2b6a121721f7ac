"""The Enterprise PBR material (ND_enterprise_pbr_surfaceshader, glsl_lib/enterprise/): the white furnace
(a white, non-absorbing material under a uniform white environment renders 1, never above) over
roughness and F0 / IOR, including the seed post's F0 {0.04, 0.5, 1} at roughness 0.5 example; reciprocity
of the BSDF evaluated in a fragment shader for swapped (l, v) on a grid; the energy tables against Monte
Carlo; and what the main parameters do."""
import json
import os
import re
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from mtlxgen.base import images
from mtlxgen import pipeline
from mtlxgen.emit.emitter import lib_source
from mtlxgen.draw import renderer as render
from mtlxgen.draw.renderer import Renderer, create_context
from doc_tables import page_text, table_differences, table_rows
from util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools"))
import enterprise_tables as tables          # noqa: E402

FURNACE_EXAMPLE = os.path.join(ROOT, "examples", "enterprise", "enterprise_furnace.mtlx")
WHITE_HDR = os.path.join(ROOT, "examples", "enterprise", "white_furnace.hdr")
ROUGHNESS = [0.0, 0.25, 0.5, 0.75, 1.0]
# white, non-absorbing configurations: (name, inputs)
FURNACE = [
    ("dielectric_ior1.5", {"ior": 1.5}),
    ("dielectric_ior2.5", {"ior": 2.5}),
    ("dielectric_f0_0.5", {"ior": 5.828427}),
    ("dielectric_f0_1", {"ior": 100000.0}),
    ("metal", {"metallic": 1.0}),
    ("translucent_ior1.5", {"ior": 1.5, "translucency": 0.5}),
    ("anisotropic_ior1.5", {"ior": 1.5, "anisotropy": 0.8}),
    ("glass_thin_ior1.5", {"ior": 1.5, "transparency": 1.0}),
    ("glass_solid_ior1.33", {"ior": 1.33, "transparency": 1.0, "thinWalled": False}),
]


def _input(name, value):
    if isinstance(value, bool):
        return '<input name="%s" type="boolean" value="%s" />' % (name, "true" if value else "false")
    if isinstance(value, tuple):
        return '<input name="%s" type="color3" value="%s" />' % (name, ", ".join(str(v) for v in value))
    return '<input name="%s" type="float" value="%r" />' % (name, float(value))


def material(tmp_path, inputs, name="doc.mtlx"):
    body = ('<enterprise_pbr name="SR" type="surfaceshader">%s</enterprise_pbr>\n'
            '<surfacematerial name="M" type="material"><input name="surfaceshader" type="surfaceshader" '
            'nodename="SR" /></surfacematerial>' % "".join(_input(k, v) for k, v in inputs.items()))
    return pipeline.generate(write_doc(tmp_path, body, name))[0]


@pytest.fixture(scope="module")
def furnace():
    with Renderer(size=64, environment=np.ones((32, 64, 3), np.float32)) as r:
        yield r


def sphere(img):
    return img[..., :3][img[..., 3] > 0]


# ---------------------------------------------------------------- white furnace

class UniformRig:
    """One compiled shader drawn in the render harness's scene (render.Renderer's sphere, camera and
    environment) with its public uniforms set per draw, so a sweep compiles once."""

    def __init__(self, renderer, shader):
        self.r, ctx = renderer, renderer.ctx
        ctx.__enter__()
        self.prog = ctx.program(vertex_shader=shader.vertex, fragment_shader=shader.fragment)
        for unit, (name, t) in enumerate([("u_envRadiance", renderer.env), ("u_envIrradiance", renderer.irradiance)]):
            if name in self.prog:
                t.use(unit)
                self.prog[name].value = unit
        content = [(buf, fmt, name) for name, (buf, fmt) in renderer.buffers.items() if name in self.prog]
        self.vao = ctx.vertex_array(self.prog, content, renderer.index)
        view_proj = render.perspective(render.FOV_Y, 1.0, 0.1, 100.0) @ render.look_at(render.EYE, (0, 0, 0), (0, 1, 0))
        for name, m in {"u_viewProjectionMatrix": view_proj, "u_envMatrix": np.diag([-1.0, 1.0, -1.0, 1.0])}.items():
            if name in self.prog:
                self.prog[name].write(np.ascontiguousarray(m.T, dtype="f4").tobytes())
        for name, value in {"u_viewPosition": render.EYE, "u_envRadianceMips": renderer.env_mips,
                            "u_envRadianceSamples": renderer.env_samples}.items():
            if name in self.prog:
                self.prog[name].value = value

    DEFAULTS = {"albedo": (1.0, 1.0, 1.0), "metallic": 0.0, "roughness": 0.5, "anisotropy": 0.0, "ior": 1.5,
                "translucency": 0.0, "transparency": 0.0, "thinWalled": True, "specular": 1.0, "clearcoat": 0.0,
                "clearcoatRoughness": 0.0, "emissionColor": (1.0, 1.0, 1.0), "emissionValue": 0.0,
                "cutoutOpacity": 1.0, "attenuationColor": (1.0, 1.0, 1.0), "attenuationDistance": 1.0e30}

    def render(self, **uniforms):
        """Draw with the DEFAULTS (the furnace's white configuration) changed by `uniforms`."""
        self.r.ctx.__enter__()       # another context may be current
        for unit, t in enumerate((self.r.env, self.r.irradiance)):
            t.use(unit)
        for name, value in dict(self.DEFAULTS, **uniforms).items():
            self.prog["SR_" + name].value = value
        self.r.fbo.use()
        self.r.ctx.enable(self.r.mgl.DEPTH_TEST)
        self.r.ctx.clear(0.0, 0.0, 0.0, 0.0)
        self.vao.render()
        raw = self.r.fbo.read(components=4, dtype="f4")
        return np.frombuffer(raw, dtype="f4").reshape(self.r.size, self.r.size, 4)[::-1].copy()

    def release(self):
        self.vao.release()
        self.prog.release()


@pytest.fixture(scope="module")
def furnace_rig(furnace, tmp_path_factory):
    # clearcoat non-zero in the document keeps the coat layer compiled in (a uniform, 0 unless set)
    rig = UniformRig(furnace, material(tmp_path_factory.mktemp("furnace"), {"roughness": 0.5, "clearcoat": 1.0}))
    yield rig
    rig.release()


def test_uniform_rig_draws_what_the_renderer_draws(furnace, furnace_rig, tmp_path):
    cfg = {"roughness": 0.3, "ior": 2.0, "metallic": 0.5, "albedo": (0.8, 0.6, 0.4)}
    a = furnace.render(material(tmp_path, cfg))
    b = furnace_rig.render(**cfg)
    assert np.abs(a - b).max() < 1e-5


@pytest.fixture(scope="module")
def furnace_figures(furnace_rig):
    """figures(name) -> {roughness: (mean, pixel min, pixel max)} of one FURNACE configuration on the sphere,
    measured once per module: the parametrized tests and the documented table share them (also under pytest -n,
    where each worker measures what it needs)."""
    inputs, done = dict(FURNACE), {}

    def figures(name):
        if name not in done:
            out = {}
            for r in ROUGHNESS:
                px = sphere(furnace_rig.render(**dict(inputs[name], roughness=r)))
                out[r] = (float(px.mean()), float(px.min()), float(px.max()))
            done[name] = out
        return done[name]
    return figures


@pytest.mark.parametrize("name", [n for n, _ in FURNACE])
def test_white_furnace_renders_one(furnace_figures, name):
    """Mean sphere radiance within 1% of 1 and no pixel above 1.01, at every roughness."""
    for r, (mean, _, top) in furnace_figures(name).items():
        assert abs(mean - 1.0) <= 0.01, (name, r, mean)
        assert top <= 1.01, (name, r, top)


def _example_iors():
    root = ET.parse(FURNACE_EXAMPLE).getroot()
    return [float(i.get("value")) for i in root.iter("input") if i.get("name") == "ior"]


def test_furnace_example_vanishes_into_the_background(furnace_rig):
    """The seed post's figure: F0 0.04, 0.5 and 1 at roughness 0.5 under white light are the background.
    Linear: every sphere pixel within 0.5% of the environment's 1; the example's goldens (rendered under
    white_furnace.hdr): every sphere pixel is 255 in 8-bit sRGB, as the environment is."""
    iors = _example_iors()
    assert [round(((n - 1) / (n + 1)) ** 2, 3) for n in iors] == [0.04, 0.5, 1.0]
    for ior in iors:
        px = sphere(furnace_rig.render(roughness=0.5, ior=ior))
        assert np.abs(px - 1.0).max() < 0.005, (ior, px.min(), px.max())
    index = json.load(open(os.path.join(ROOT, "golden_images", "index.json")))["goldens"]
    names = [n for n, e in index.items() if e["source"] == "examples/enterprise/enterprise_furnace.mtlx"]
    assert len(names) == 3
    for n in names:
        assert index[n]["settings"]["environment"].endswith("white_furnace.hdr")
        png = images.read_image(os.path.join(ROOT, "golden_images", index[n]["png"]))
        covered = png[..., 3] > 0.5
        assert covered.sum() > 5000
        assert (images.to_srgb8(png)[..., :3][covered] == 255).all(), n


# ---------------------------------------------------------------- reciprocity

GRID = 32
VERTEX = "#version 400\nin vec2 i_pos;\nvoid main() { gl_Position = vec4(i_pos, 0.0, 1.0); }\n"
RECIPROCITY = {
    "plastic": "m.roughness = 0.4; m.ior = 1.5; m.albedo = vec3(0.8, 0.3, 0.1);",
    "rough_white": "m.roughness = 1.0; m.ior = 1.5;",
    "smooth_f0_0.5": "m.roughness = 0.1; m.ior = 5.828427; m.specularTint = vec3(1.0, 0.5, 0.2);",
    "anisotropic_metal": "m.metallic = 1.0; m.albedo = vec3(0.9, 0.6, 0.3); m.roughness = 0.5; m.anisotropy = 0.8; "
                         "m.anisotropyRotation = 0.1;",
    "thin_film": "m.metallic = 0.5; m.roughness = 0.3; m.thinFilm = 1.0; m.thinFilmThickness = 0.4;",
    "sheen": "m.roughness = 0.7; m.albedo = vec3(0.3, 0.05, 0.1); m.sheenColor = vec3(0.9, 0.7, 0.8); m.sheenRoughness = 0.4;",
    "flakes_coat": "m.metallic = 1.0; m.albedo = vec3(0.02, 0.05, 0.1); m.roughness = 0.4; m.flakeCoverage = 0.7; "
                   "m.flakeRoughness = 0.3; m.flakeColor = vec3(0.9, 0.8, 0.6); m.flipFlop = 1.0; "
                   "m.flipFlopColor = vec3(0.4, 0.2, 0.9); m.clearcoat = 1.0; m.clearcoatRoughness = 0.2;",
    "translucent_transparent": "m.roughness = 0.3; m.translucency = 0.6; m.transparency = 0.3; m.specular = 0.7;",
}
DEFAULTS = """
    m.albedo = vec3(1.0); m.metallic = 0.0; m.roughness = 0.0; m.anisotropy = 0.0; m.anisotropyRotation = 0.0;
    m.N = vec3(0.0, 0.0, 1.0); m.T = vec3(1.0, 0.0, 0.0); m.translucency = 0.0; m.translucencyColor = vec3(1.0);
    m.transparency = 0.0; m.specular = 1.0; m.specularTint = vec3(1.0); m.thinFilm = 0.0; m.thinFilmThickness = 0.4;
    m.thinFilmIor = 1.3; m.sheenColor = vec3(0.0); m.sheenRoughness = 0.5; m.flakeCoverage = 0.0; m.flakeColor = vec3(1.0);
    m.flakeSize = 0.0; m.flakeRoughness = 0.0; m.flipFlop = 0.0; m.flipFlopColor = vec3(1.0); m.clearcoat = 0.0;
    m.clearcoatRoughness = 0.0; m.Nc = vec3(0.0, 0.0, 1.0); m.emissionColor = vec3(1.0); m.emissionValue = 0.0;
    m.thinWalled = true; m.ior = 1.5; m.attenuationColor = vec3(1.0); m.attenuationDistance = 1.0e30;
    m.subsurfaceColor = vec3(0.0); m.subsurfaceAnisotropy = 0.0; m.P = vec3(0.0); m.footprint = 1.0;
"""


def _hemisphere(rng, n):
    mu = rng.uniform(0.02, 1.0, n)
    phi = rng.uniform(0.0, 2.0 * np.pi, n)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)


@pytest.fixture(scope="module")
def bsdf_eval():
    """bsdf_eval(setup) -> (f(l, v), f(v, l)) on GRID x GRID direction pairs, the material set up by GLSL `setup`."""
    ctx = create_context()
    rng = np.random.default_rng(11)
    n = GRID * GRID
    L, V = _hemisphere(rng, n), _hemisphere(rng, n)
    V[:GRID] = L[:GRID] * np.array([-1, -1, 1])       # some mirror pairs, where the specular peaks
    tex = [ctx.texture((GRID, GRID), 4, np.concatenate([d, np.zeros((n, 1))], 1).astype("f4").tobytes(), dtype="f4")
           for d in (L, V)]
    fbo = ctx.framebuffer(color_attachments=[ctx.texture((GRID, GRID), 4, dtype="f4")])
    quad = ctx.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], np.float32).tobytes())
    lib = lib_source(["constants.glsl", "closures.glsl", "pbrlib/microfacet/fresnel.glsl",
                                                 "pbrlib/microfacet/thin_film.glsl", "pbrlib/microfacet/ggx.glsl",
                                                 "lighting/environment.glsl", "lighting/environment_lod.glsl",
                                                 "lighting/hammersley.glsl",
                                                 "enterprise/tables.glsl", "enterprise/frame.glsl",
                                                 "enterprise/fresnel.glsl", "enterprise/specular.glsl",
                                                 "enterprise/diffuse.glsl", "enterprise/sheen.glsl",
                                                 "enterprise/flakes.glsl", "enterprise/transmission.glsl",
                                                 "enterprise/environment.glsl", "enterprise/enterprise_pbr.glsl"])

    programs = {}

    def run(setup, expr=None):
        """Both orders of the BSDF, or with `expr` that GLSL vec4 expression once. `setup` is GLSL, or an
        index into the configurations compiled together as one program (u_config)."""
        result = expr or "u_swap ? mg_epbr_bsdf(m, k, V, L) : mg_epbr_bsdf(m, k, L, V), 1.0"
        config = 0
        if isinstance(setup, int):
            config, setup = setup, " else ".join("if (u_config == %d) { %s }" % (j, RECIPROCITY[n])
                                                 for j, n in enumerate(sorted(RECIPROCITY)))
        fragment = """#version 400
%s
uniform sampler2D u_l;
uniform sampler2D u_v;
uniform bool u_swap = false;
uniform int u_config = 0;
out vec4 o;
void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 L = texelFetch(u_l, p, 0).xyz;
    vec3 V = texelFetch(u_v, p, 0).xyz;
    MgEpbr m;
    %s
    %s
    MgEpbrLobes k = mg_epbr_lobes(m);
    o = vec4(%s);
}
""" % (lib, DEFAULTS, setup, result)
        ctx.__enter__()         # this context current again: a Renderer's may have been made current since
        if fragment not in programs:
            programs[fragment] = ctx.program(vertex_shader=VERTEX, fragment_shader=fragment)
        prog = programs[fragment]
        for name, value in (("u_l", 0), ("u_v", 1), ("u_config", config)):
            if name in prog:
                prog[name].value = value
        tex[0].use(0)
        tex[1].use(1)
        vao = ctx.vertex_array(prog, [(quad, "2f", "i_pos")])
        out = []
        for swap in ((False, True) if expr is None else (False,)):
            if "u_swap" in prog:
                prog["u_swap"].value = swap
            fbo.use()
            vao.render(mode=ctx.TRIANGLE_STRIP)
            out.append(np.frombuffer(fbo.read(components=4, dtype="f4"), np.float32).reshape(-1, 4)[:, :3].copy())
        vao.release()
        return out

    yield run
    for p in programs.values():
        p.release()
    ctx.release()


RECIPROCITY_LIMIT = 1e-3


@pytest.fixture(scope="module")
def reciprocity_figures(bsdf_eval):
    """figures(name) -> (f(l, v), relative |f(l, v) - f(v, l)|) on the grid for one RECIPROCITY configuration,
    evaluated once per module (shared by the parametrized test and the documented figures)."""
    done = {}

    def figures(name):
        if name not in done:
            a, b = bsdf_eval(sorted(RECIPROCITY).index(name))
            done[name] = (a, np.abs(a - b) / np.maximum(np.maximum(a, b), 1e-6))
        return done[name]
    return figures


@pytest.mark.parametrize("name", sorted(RECIPROCITY))
def test_bsdf_is_reciprocal(reciprocity_figures, name):
    """|f(l, v) - f(v, l)| <= 1e-3 relative on a grid of direction pairs."""
    a, rel = reciprocity_figures(name)
    assert np.isfinite(a).all() and (a >= 0).all()
    assert a.max() > 0.01
    assert rel.max() <= RECIPROCITY_LIMIT, (name, rel.max(), np.unravel_index(rel.argmax(), rel.shape))


# ---------------------------------------------------------------- the tables

def _mc_ggx(mu, r, n=200000, seed=3):
    """Uniform-hemisphere Monte Carlo of the single-scattering GGX albedo at F = 1 (independent of the
    table's VNDF estimator)."""
    rng = np.random.default_rng(seed)
    a = float(tables.ggx_alpha(r))
    z, phi = rng.random(n), 2.0 * np.pi * rng.random(n)
    s = np.sqrt(1.0 - z * z)
    l = np.stack([s * np.cos(phi), s * np.sin(phi), z], -1)
    v = np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])
    h = l + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    D = a * a / (np.pi * (h[:, 2] ** 2 * (a * a - 1.0) + 1.0) ** 2)
    G2 = 1.0 / (1.0 + tables.lambda_ggx(mu, a) + tables.lambda_ggx(z, a))
    return float(np.mean(D * G2 / (4.0 * mu)) * 2.0 * np.pi)


@pytest.mark.parametrize("mu,r", [(0.1, 0.5), (0.5, 0.5), (1.0, 0.5), (0.2, 1.0), (0.8, 0.75), (0.3, 0.6)])
def test_ggx_albedo_matches_monte_carlo(mu, r):
    a, b = tables.ggx_albedo_split(mu, r, strata=48)
    assert abs((a + b) - _mc_ggx(mu, r)) < 0.01


def test_sheen_albedo_matches_monte_carlo():
    rng = np.random.default_rng(5)
    n = 400000
    for mu, r in [(0.3, 0.4), (0.8, 0.7), (1.0, 1.0)]:
        ml, phi = rng.random(n), 2.0 * np.pi * rng.random(n)
        f = tables.sheen_brdf(mu, ml, np.cos(phi), tables.sheen_alpha(r))
        mc = float(np.mean(f * ml) * 2.0 * np.pi)
        assert abs(tables.sheen_albedo(mu, r) - mc) < 0.005, (mu, r)


def test_base_table_is_compensated_single_scattering_and_the_furnace_identity():
    """E_base = f0 A + B + F_ms (1 - E); for f0 = 1 it is 1 (the metal white furnace)."""
    base, base_avg = tables.base_tables(n=4, strata=24)
    assert np.allclose(base[-1], 1.0, atol=2e-3)
    assert (np.diff(base, axis=0) >= -1e-9).all()          # more F0, more reflection
    assert (base <= 1.0 + 1e-6).all() and (base_avg <= 1.0 + 1e-6).all()


def test_glsl_tables_match_numpy(bsdf_eval):
    """The generated GLSL table, read back through its lookups at grid nodes, is the numpy quantity."""
    for j, i in [(0, 16), (31, 8), (16, 31)]:
        mu, r = j / 31.0, i / 31.0
        a, b = tables.ggx_albedo_split(mu, r, strata=64)
        (out,) = bsdf_eval("", "mg_epbr_ggx_e(%r, %r), mg_epbr_base_e(1.0, %r, %r), 1.0" % (r, mu, r, mu))
        assert abs(out[0, 0] - a) < 2e-3 and abs(out[0, 1] - b) < 2e-3, (mu, r, out[0], (a, b))
        assert abs(out[0, 2] - 1.0) < 3e-3          # base E at f0 = 1 is the full (compensated) albedo


# ---------------------------------------------------------------- parameters

def test_metallic_tints_reflection_by_albedo(furnace_rig):
    px = sphere(furnace_rig.render(metallic=1.0, albedo=(0.9, 0.5, 0.1), roughness=0.3))
    r, g, b = px.mean(0)
    assert r > g > b and b < 0.5 * r and r > 0.85


def test_clearcoat_adds_a_white_lobe(furnace_rig):
    black = {"albedo": (0.0, 0.0, 0.0), "specular": 0.0}
    base = sphere(furnace_rig.render(**black)).mean(0)
    coat = sphere(furnace_rig.render(**black, clearcoat=1.0, clearcoatRoughness=0.1)).mean(0)
    assert base.max() < 1e-4
    added = coat - base
    assert added.min() > 0.03 and np.ptp(added) < 1e-3


def test_emission_adds_colour_times_value(furnace_rig):
    cfg = {"albedo": (0.4, 0.4, 0.4), "roughness": 0.5}
    off = sphere(furnace_rig.render(**cfg))
    on = sphere(furnace_rig.render(**cfg, emissionColor=(0.2, 0.4, 0.6), emissionValue=2.0))
    assert np.allclose(on - off, [0.4, 0.8, 1.2], atol=2e-3)


def test_cutout_opacity_is_alpha(furnace_rig):
    img = furnace_rig.render(cutoutOpacity=0.25)
    covered = img[..., 3] > 0
    assert np.allclose(img[..., 3][covered], 0.25, atol=1e-3)
    assert np.allclose(img[..., :3][covered], 0.25, atol=0.01)


def test_attenuation_darkens_solid_glass_by_beer_lambert(furnace_rig):
    glass = {"transparency": 1.0, "thinWalled": False, "roughness": 0.0}
    clear = sphere(furnace_rig.render(**glass)).mean(0)
    amber = sphere(furnace_rig.render(**glass, attenuationColor=(0.9, 0.5, 0.2), attenuationDistance=1.0)).mean(0)
    assert np.allclose(clear, 1.0, atol=0.01)
    assert amber[0] > amber[1] > amber[2] and amber[2] < 0.5


# docs/materials.md's "Enterprise PBR" furnace table: its rows, each the FURNACE configurations it sums up
PAGE_ROWS = [
    ("dielectric ior 1.5 / 2.5", ["dielectric_ior1.5", "dielectric_ior2.5"]),
    ("dielectric f0 0.5 (ior 5.83)", ["dielectric_f0_0.5"]),
    ("dielectric f0 1 (ior 1e5), white metal", ["dielectric_f0_1", "metal"]),
    ("translucent 0.5, anisotropic 0.8", ["translucent_ior1.5", "anisotropic_ior1.5"]),
    ("glass thin-walled / solid", ["glass_thin_ior1.5", "glass_solid_ior1.33"]),
]
PAGE_TOL = 5e-4       # the furnace figures within 5 steps of their 4th decimal (drivers round differently)


def furnace_table(furnace_figures):
    lines = ["| configuration | mean min | mean max | pixel max |", "|---|---|---|---|"]
    for label, names in PAGE_ROWS:
        figs = [f for n in names for f in furnace_figures(n).values()]
        lines.append("| %s | %.4f | %.4f | %.4f |" % (label, min(f[0] for f in figs), max(f[0] for f in figs),
                                                      max(f[2] for f in figs)))
    return "\n".join(lines)


def test_furnace_and_reciprocity_figures_are_the_documented_ones(furnace_figures, reciprocity_figures, capsys):
    """docs/materials.md's "Enterprise PBR" figures are what the tests measure: the furnace table (printed with -s)
    within PAGE_TOL, over the page's roughness set and every configuration; the reciprocity sentence's pair count,
    configuration count, limit, and worst figure (float noise: within a factor of 10, and under the limit)."""
    assert sorted(n for _, names in PAGE_ROWS for n in names) == sorted(n for n, _ in FURNACE)
    table = furnace_table(furnace_figures)
    worst = max(float(reciprocity_figures(n)[1].max()) for n in RECIPROCITY)
    with capsys.disabled():
        print("\n" + table + "\nreciprocity: worst relative |f(l,v) - f(v,l)| %.1e over %d configurations"
              % (worst, len(RECIPROCITY)))
    text = page_text()
    section = text[text.index("## Enterprise PBR"):]
    section = section[:section.index("\n## ", 1)]
    bad = table_differences(table_rows(table, "| configuration |"), table_rows(section, "| configuration |"),
                            lambda col, ours, theirs: abs(ours - theirs) <= PAGE_TOL)
    rough = re.search(r"mean sphere radiance over roughness \{([^}]*)\}", section)
    if not rough or [float(v) for v in rough.group(1).split(",")] != ROUGHNESS:
        bad.append("the page's roughness set %s is not the tests' %s" % (rough and rough.group(1), ROUGHNESS))
    rec = re.search(r"on (\d+) pairs.*?over (.*?): ([0-9.]+e-\d+) \(limit ([0-9.e-]+)\)", section, re.S)
    if not rec:
        bad.append("the page's reciprocity sentence is not found")
    else:
        pairs, names, figure, limit = int(rec.group(1)), rec.group(2).split(","), float(rec.group(3)), float(rec.group(4))
        if pairs != GRID * GRID:
            bad.append("the page says %d pairs, the test evaluates %d" % (pairs, GRID * GRID))
        if len(names) != len(RECIPROCITY):
            bad.append("the page lists %d configurations, the test has %d" % (len(names), len(RECIPROCITY)))
        if limit != RECIPROCITY_LIMIT:
            bad.append("the page's limit %g, the test's %g" % (limit, RECIPROCITY_LIMIT))
        if not (worst <= RECIPROCITY_LIMIT and figure / 10 <= worst <= figure * 10):
            bad.append("worst relative difference %.1e, page %.1e (limit %g)" % (worst, figure, limit))
    assert not bad, "docs/materials.md's Enterprise PBR figures:\n  " + "\n  ".join(bad)
