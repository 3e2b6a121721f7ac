"""Helmholtz reciprocity of the BSDF nodes' GLSL (issue 6, item 6).

Each node's "reflection" closure template (the one the shader nodes call per direct light, returning
f(L, V) |N.L|) is instantiated in a fragment shader, with the glsl_lib files it needs and their
`// requires:` dependencies, and evaluated for every ordered pair (a, b) of a grid of directions:
pixel (i, j) holds f(a_i, b_j) and f(b_j, a_i), each divided by its |N.L|. Where the model is meant
to be reciprocal, |f(l, v) - f(v, l)| <= 1e-3 max(f(l, v), f(v, l)) everywhere on the grid.

Which models are meant to be reciprocal is decided from their papers (`why` of each case); the
worst figures go in docs/materials.md's "Physics: furnace and reciprocity" table:

    python3 tests/nodes/test_reciprocity.py      # the markdown table
"""
import os
import re
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))

from mtlxgen.base import mxtypes
from mtlxgen import nodes  # noqa: E402
from mtlxgen.emit.emitter import lib_source, read_lib_file  # noqa: E402
from tests.doc_tables import page_table, table_differences, table_rows  # noqa: E402

REL_TOL = 1.0e-3
RESPONDS = 1.0e-3      # a BSDF's largest f on the grid must exceed this: f = 0 is reciprocal and proves nothing
THETAS = np.radians(np.linspace(8.0, 82.0, 8))      # polar angles of the grid
PHIS = np.radians(np.arange(12) * 30.0 + 7.0)        # azimuths (offset from the tangent axis)
ROUGH = (0.1, 0.25, 0.5, 0.75, 1.0)


def grid_directions():
    t, p = np.meshgrid(THETAS, PHIS, indexing="ij")
    d = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3)
    return d.astype(np.float32)


class RCase:
    """template: a closure-template-style GLSL expression of a BSDF (fields {{input}}, {{=input}}),
    category: the node whose nodedef gives input types and defaults (and, without template, whose
    "reflection" closure is used), sweep: [(label, {input: value})], transmit: light from below the
    surface (the shading normal faces the viewer, so the swapped evaluation flips it)."""

    def __init__(self, name, category, sweep, reciprocal, why, template=None, files=(), inputs=None,
                 transmit=False, xfail=None):
        self.name, self.category, self.sweep, self.reciprocal, self.why = name, category, sweep, reciprocal, why
        self.template, self.files, self.inputs, self.transmit, self.xfail = template, files, inputs or {}, transmit, xfail


def _rough(vec2=False, extra=None):
    return [("r=%g" % r, dict({"roughness": (r, r) if vec2 else r}, **(extra or {}))) for r in ROUGH]


def _rough_ior(iors=(1.5, 2.5)):
    return [("r=%g ior=%g" % (r, n), {"roughness": (r, r), "ior": n}) for n in iors for r in ROUGH]


_GGX = "pbrlib/microfacet/microfacet_reflection.glsl"
_LOBE = "BSDF(mg_microfacet_reflection(mg_L, mg_V, mg_tangent_frame({{normal}}, {{tangent}}), " \
        "mg_ggx_alpha({{roughness}}), %s, {{=retroreflective}}), vec3(0.0))"
TURQUIN = ("the node multiplies the lobe by 1 + F0 (1 - E(n.v)) / E(n.v) (the scaling form of multiple-scattering "
           "compensation, Turquin 2019), a function of the view angle alone: not reciprocal by design; the GGX "
           "lobe itself is asserted below")
TURQUIN_CURVE = ("the node multiplies the lobe by 1 + F0 (1 - E(n.v)) / E(n.v) (the scaling form of multiple-scattering "
                 "compensation, Turquin 2019; the Fresnel curve at the view angle through a film or below an IOR of 1, "
                 "as MaterialX's), a function of the view angle alone: not reciprocal by design; the GGX lobe itself "
                 "is asserted below")

CASES = [
    RCase("oren_nayar_diffuse_bsdf", "oren_nayar_diffuse_bsdf", _rough(), True,
          "Oren & Nayar 1994: A + B max(0, cos dphi) sin(a) tan(b) with a, b the max/min angle: symmetric"),
    RCase("oren_nayar_diffuse_bsdf (EON)", "oren_nayar_diffuse_bsdf", _rough(), True,
          "EON (Portsmouth et al. 2025): FON's s/t symmetric; f_ms ~ (1 - E(mu_i))(1 - E(mu_o)) symmetric",
          inputs={"energy_compensation": True}),
    RCase("burley_diffuse_bsdf", "burley_diffuse_bsdf", _rough(), True,
          "Burley 2012: (1 + (F_D90 - 1)(1 - mu_l)^5)(1 + (F_D90 - 1)(1 - mu_v)^5) with F_D90 on l.h = v.h: "
          "symmetric, retro-reflection included"),
    RCase("translucent_bsdf", "translucent_bsdf", [("-", {})], True,
          "Lambertian transmission, 1/pi both ways", transmit=True),
    RCase("subsurface_bsdf", "subsurface_bsdf", [("-", {})], False,
          "wrap lighting (Green 2004) is a function of N.L only, not a BRDF; reduces to Lambert at zero curvature "
          "(this flat grid)"),
    RCase("sheen_bsdf conty_kulla", "sheen_bsdf", _rough(), True,
          "Conty & Kulla 2017: D(h) / (4 (mu_l + mu_v - mu_l mu_v)): symmetric"),
    RCase("sheen_bsdf zeltner", "sheen_bsdf", _rough(extra={"mode": "zeltner"}), False,
          "Zeltner et al. 2022: an LTC fitted per view direction times E(mu_v): not reciprocal by construction"),
    RCase("chiang_hair_bsdf", "chiang_hair_bsdf",
          [("r=%g" % r, {"roughness_R": (r, r), "roughness_TT": (r, r), "roughness_TRT": (r, r)}) for r in ROUGH[1:]],
          False, "Chiang et al. 2016: the azimuthal offset h belongs to the view ray (here from V's azimuth) and "
                 "cuticle tilts shift theta_o only: not reciprocal"),
    RCase("dielectric_bsdf", "dielectric_bsdf", _rough_ior(), False, TURQUIN_CURVE),
    RCase("conductor_bsdf", "conductor_bsdf", _rough(vec2=True), False, TURQUIN),
    RCase("generalized_schlick_bsdf", "generalized_schlick_bsdf",
          _rough(vec2=True, extra={"color0": (0.2, 0.4, 0.6), "color82": (0.9, 0.9, 0.9)}), False, TURQUIN),
    RCase("GGX lobe, dielectric F", "dielectric_bsdf", _rough_ior((1.25, 1.5, 2.5)), True,
          "Walter et al. 2007: D(h) F(v.h = l.h) G2(l, v) / (4 mu_l mu_v), height-correlated G2 (Heitz 2014) symmetric",
          template=_LOBE % "mg_fresnel_dielectric_model({{ior}}, 0.0, 1.5)", files=[_GGX]),
    RCase("GGX lobe, conductor F, anisotropic", "conductor_bsdf",
          [("a=%g,%g" % a, {"roughness": a}) for a in ((0.1, 0.4), (0.3, 0.9), (1.0, 0.2))], True,
          "anisotropic D and Lambda are even in h and symmetric in (l, v)",
          template=_LOBE % "mg_fresnel_conductor_model({{ior}}, {{extinction}}, 0.0, 1.5)", files=[_GGX]),
    RCase("GGX lobe, Schlick F82, retroreflective", "generalized_schlick_bsdf",
          _rough(vec2=True, extra={"color0": (0.2, 0.4, 0.6), "color82": (0.8, 0.8, 0.9), "retroreflective": True}),
          True, "retroreflection mirrors l about n: h' is h mirrored, F(v.h) = F(l'.h'): symmetric",
          template=_LOBE % "mg_fresnel_schlick_model({{color0}}, {{color82}}, {{color90}}, {{exponent}}, 0.0, 1.5)",
          files=[_GGX]),
]

CASE_IDS = [c.name for c in CASES]

VERTEX = """#version 400
void main()
{
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
"""


def _lib_files(rels):
    out = []

    def add(rel):
        if rel in out:
            return
        for d in read_lib_file(rel)[1]:
            add(d)
        if rel not in out:
            out.append(rel)
    for r in ["constants.glsl", "closures.glsl"] + list(rels):
        add(r)
    return out


def _glsl_value(t, v):
    return mxtypes.glsl_literal(t, v, {})


def build_shader(case, library):
    """(fragment source, {uniform name: input name}) evaluating the case's BSDF for grid pairs."""
    nd = _nodedef(case.category, library)
    impl = nodes.BY_CATEGORY[case.category]
    template = case.template or impl.closure["reflection"]
    files = list(case.files) if case.template else list(impl.files)
    swept = set(k for _, s in case.sweep for k in s)
    uniforms, decls = {}, []

    def field(m):
        f = m.group(1).strip()
        static = f.startswith("=")
        name = f[1:] if static else f
        if f.startswith("@"):
            return "N"
        inp = nd.inputs[name]
        if name in ("normal",):
            return "N"
        if name in ("tangent", "curve_direction"):
            return "T"
        value = case.inputs.get(name, inp.value)
        if static:
            if inp.type == "string":
                return str(value)
            return _glsl_value(inp.type, value)
        if name in swept:
            u = "u_" + name
            if u not in uniforms:
                uniforms[u] = name
                decls.append("uniform %s %s;" % (mxtypes.glsl_type(inp.type), u))
            return u
        return _glsl_value(inp.type, value)

    expr = re.sub(r"\{\{(.*?)\}\}", field, template)
    # static (string) inputs that are swept, like sheen's mode, are baked in: one shader per value
    parts = ["#version 400", lib_source(_lib_files(files))]
    parts += decls
    parts.append("""
uniform vec3 u_dirs[%(n)d];
layout(location = 0) out vec4 out_color;
float mg_eval(vec3 mg_L, vec3 mg_V, vec3 N, vec3 T)
{
    vec3 mg_P = vec3(0.0);
    float mg_occlusion = 1.0;
    BSDF b = %(expr)s;
    return b.response.x / max(abs(dot(N, mg_L)), 1.0e-6);
}
void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec3 a = u_dirs[p.x], b = u_dirs[p.y];
    vec3 N = vec3(0.0, 0.0, 1.0), T = vec3(1.0, 0.0, 0.0);
%(body)s
}
""" % {"n": len(grid_directions()), "expr": expr, "body": (
        # light a below the surface, viewer b above; swapped: light b, viewer a, normal towards a
        "    vec3 ab = vec3(a.xy, -a.z);\n"
        "    out_color = vec4(mg_eval(ab, b, N, T), mg_eval(b, ab, -N, T), 0.0, 1.0);"
        if case.transmit else
        "    out_color = vec4(mg_eval(a, b, N, T), mg_eval(b, a, N, T), 0.0, 1.0);")})
    return "\n".join(parts), uniforms


def _nodedef(category, library):
    cands = [n for n in library.nodedefs.values() if n.category == category]
    assert cands, category
    return cands[0]


def _static_key(case, settings):
    """Settings of static (compile-time) inputs, which need a program each."""
    return tuple(sorted((k, v) for k, v in settings.items() if isinstance(v, (str, bool))))


class Evaluator:
    def __init__(self):
        from mtlxgen.read.library import load_library
        from mtlxgen.draw.renderer import create_context
        self.library = load_library()
        self.ctx = create_context()
        self.dirs = grid_directions()
        n = len(self.dirs)
        self.fbo = self.ctx.framebuffer(color_attachments=[self.ctx.texture((n, n), 4, dtype="f4")])
        self.results = {}

    def close(self):
        self.ctx.release()

    def measure(self, case):
        """[(label, worst relative difference, f value there, largest f on the grid)] over the case's sweep."""
        if case.name in self.results:
            return self.results[case.name]
        rows = []
        groups = {}
        for label, settings in case.sweep:
            groups.setdefault(_static_key(case, settings), []).append((label, settings))
        for key, items in groups.items():
            c = RCase(case.name, case.category, case.sweep, case.reciprocal, case.why, case.template, case.files,
                      dict(case.inputs, **dict(key)), case.transmit)
            c.sweep = [(lb, {k: v for k, v in s.items() if not isinstance(v, (str, bool))}) for lb, s in items]
            frag, uniforms = build_shader(c, self.library)
            self.ctx.__enter__()
            prog = self.ctx.program(vertex_shader=VERTEX, fragment_shader=frag)
            try:
                prog["u_dirs"].write(np.ascontiguousarray(self.dirs, dtype="f4").tobytes())
                vao = self.ctx.vertex_array(prog, [])
                for label, settings in c.sweep:
                    for u, name in uniforms.items():
                        prog[u].value = settings[name]
                    self.fbo.use()
                    self.ctx.clear(0.0, 0.0, 0.0, 0.0)
                    vao.render(vertices=3)
                    n = len(self.dirs)
                    img = np.frombuffer(self.fbo.read(components=4, dtype="f4"), dtype="f4").reshape(n, n, 4)
                    rows.append((label,) + relative_error(img[..., 0], img[..., 1]))
                vao.release()
            finally:
                prog.release()
        self.results[case.name] = rows
        return rows


def relative_error(fab, fba):
    """(worst |f(l,v) - f(v,l)| / max of the two, the larger value there, the grid's largest value); pairs
    where both are below 1e-6 of the grid's largest value count as zero."""
    assert np.isfinite(fab).all() and np.isfinite(fba).all()
    big = np.maximum(np.abs(fab), np.abs(fba))
    floor = 1.0e-6 * max(float(big.max()), 1.0e-12)
    rel = np.where(big > floor, np.abs(fab - fba) / np.maximum(big, floor), 0.0)
    k = np.unravel_index(np.argmax(rel), rel.shape)
    return float(rel[k]), float(big[k]), float(big.max())


@pytest.fixture(scope="module")
def evaluator():
    e = Evaluator()
    yield e
    e.close()


def _params():
    return [pytest.param(c, id=c.name, marks=[pytest.mark.xfail(strict=True, reason=c.xfail)] if c.xfail else [])
            for c in CASES]


def silent(rows):
    """Settings where the BSDF gives (almost) nothing anywhere on the grid: no reciprocity is shown there."""
    return ["%s: largest f on the grid %.3g <= %g" % (r[0], r[3], RESPONDS) for r in rows if not r[3] > RESPONDS]


@pytest.mark.parametrize("case", [p for p in _params() if p.values[0].reciprocal])
def test_bsdf_reciprocal_by_design_is_reciprocal_on_the_grid(evaluator, case):
    """Models that promise reciprocity (the others are measured, and held to the page's figures, by the table test)."""
    rows = evaluator.measure(case)
    bad = silent(rows) + ["%s: relative difference %.2e (f = %.4g)" % r[:3] for r in rows if not r[1] <= REL_TOL]
    assert not bad, "%s is meant to be reciprocal (%s):\n  %s" % (case.name, case.why, "\n  ".join(bad))


def markdown_table(results):
    lines = ["| BSDF | settings | reciprocal by design? | worst relative difference | why |", "|---|---|---|---|---|"]
    for c in CASES:
        rows = results.get(c.name)
        if not rows:
            continue
        worst = max(rows, key=lambda r: r[1])
        lines.append("| %s | %d | %s | %.1e (%s) | %s |" % (c.name, len(rows), "yes" if c.reciprocal else "no",
                                                          worst[1], worst[0], c.why))
    return "\n".join(lines)


def same_figure(col, ours, theirs):
    """Does a printed figure agree with the page's? The settings count (column 1) exactly; a worst relative
    difference (column 3) within 10% (the page prints two digits), or, where the page's is below REL_TOL, also
    below REL_TOL: float noise, so which setting is worst is chance and its label is not compared (None)."""
    if col == 1:
        return ours == theirs
    if theirs <= REL_TOL:
        return None if ours <= REL_TOL else False
    return abs(ours - theirs) <= 0.1 * theirs


def test_reciprocity_table_is_the_documented_one(evaluator, capsys):
    """Measures every case, prints the table (pytest -s shows it) and asserts it is docs/materials.md's (the same rows,
    settings, verdicts and reasons, each figure as same_figure says), that every BSDF responds on the grid
    and that every model reciprocal by design is."""
    for c in CASES:
        evaluator.measure(c)
    table = markdown_table(evaluator.results)
    with capsys.disabled():
        print("\n" + table)
    bad = []
    for c in CASES:
        rows = evaluator.results[c.name]
        bad += ["%s, %s" % (c.name, b) for b in silent(rows)]
        if c.reciprocal:
            bad += ["%s, %s: %.2e, reciprocal by design" % (c.name, r[0], r[1]) for r in rows if not r[1] <= REL_TOL]
    bad += table_differences(table_rows(table, "| BSDF |"), page_table("| BSDF | settings |"), same_figure)
    assert not bad, ("the reciprocity table (python3 tests/nodes/test_reciprocity.py prints it) against docs/materials.md:"
                     "\n  " + "\n  ".join(bad))


if __name__ == "__main__":
    import time
    t0 = time.time()
    e = Evaluator()
    for c in CASES:
        t = time.time()
        rows = e.measure(c)
        print("%-40s %5.2fs worst %.2e" % (c.name, time.time() - t, max(r[1] for r in rows)), file=sys.stderr)
    print(markdown_table(e.results))
    print("%.1fs" % (time.time() - t0), file=sys.stderr)
