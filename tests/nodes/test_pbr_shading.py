"""Closure shading: surface lighting in contexts, Oren-Nayar against MaterialX, displacement in the vertex stage."""
import re

import numpy as np
import pytest

from mtlxgen import pipeline
from util import assert_parity_with_materialx, write_doc

ON = """
  <oren_nayar_diffuse_bsdf name="diff" type="BSDF">
    <input name="color" type="color3" value="0.8, 0.5, 0.3" />
    <input name="roughness" type="float" value="%s" />
  </oren_nayar_diffuse_bsdf>
  <surface name="surf" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="diff" /></surface>
  <surfacematerial name="mat" type="material"><input name="surfaceshader" type="surfaceshader" nodename="surf" /></surfacematerial>"""


@pytest.mark.parametrize("roughness", [0.0, 0.4, 0.9])
def test_oren_nayar_surface_matches_materialx(tmp_path, renderer, reference, roughness):
    assert_parity_with_materialx(renderer, reference, write_doc(tmp_path, ON % roughness), "mat")


def test_closures_are_evaluated_once_per_context(tmp_path):
    s = pipeline.generate(write_doc(tmp_path, ON % 0.5), max_lights=1)[0]     # with its light loop
    main = s.fragment[s.fragment.index("void main()"):]
    assert main.count("mg_oren_nayar_reflection(") == 1      # in the light loop
    assert main.count("mg_oren_nayar_indirect(") == 1        # in the environment block
    assert main.index("for (int mg_i = 0;") < main.index("mg_oren_nayar_reflection(") < main.index("mg_oren_nayar_indirect(")


def test_mixed_closures_weigh_their_responses(tmp_path):
    from mtlxgen.draw.renderer import Renderer
    body = """
  <oren_nayar_diffuse_bsdf name="top" type="BSDF"><input name="color" type="color3" value="1, 0, 0" />
    <input name="weight" type="float" value="0.5" /></oren_nayar_diffuse_bsdf>
  <oren_nayar_diffuse_bsdf name="base" type="BSDF"><input name="color" type="color3" value="0, 1, 0" /></oren_nayar_diffuse_bsdf>
  <mix name="m" type="BSDF"><input name="fg" type="BSDF" nodename="top" /><input name="bg" type="BSDF" nodename="base" />
    <input name="mix" type="float" value="0.25" /></mix>
  <surface name="surf" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="m" /></surface>"""
    white = np.ones((32, 64, 3), dtype=np.float32)        # a white furnace: irradiance 1 everywhere
    with Renderer(size=64, environment=white) as r:
        img = r.render(pipeline.generate(write_doc(tmp_path, body))[0])
    covered = img[..., 3] > 0
    # Lambert (roughness 0) reflects its albedo under unit irradiance: 0.25 * 0.5 red, 0.75 green
    assert np.allclose(img[covered][:, :3], [0.125, 0.75, 0.0], atol=2e-3)


DISPLACED = ON % 0.0 + """
  <position name="p" type="vector3" />
  <displacement name="d" type="displacementshader">
    <input name="displacement" type="float" value="%s" />
  </displacement>
  <surfacematerial name="dmat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="surf" />
    <input name="displacementshader" type="displacementshader" nodename="d" />
  </surfacematerial>"""


def test_displacement_moves_vertices_along_the_normal(tmp_path, renderer):
    path = write_doc(tmp_path, DISPLACED % 0.2)
    plain, displaced = pipeline.generate(path, elements=["mat"])[0], pipeline.generate(path, elements=["dmat"])[0]
    assert "mg_displacement" in displaced.vertex and "mg_displacement" not in plain.vertex
    cover = lambda s: float((renderer.render(s)[..., 3] > 0).mean())
    # a sphere of radius 1.2 covers (1.2)^2 as much of the frame, give or take perspective
    ratio = cover(displaced) / cover(plain)
    assert 1.3 < ratio < 1.7


def test_vector_displacement_uses_the_tangent_frame(tmp_path):
    body = (ON % 0.0) + """
  <displacement name="d" type="displacementshader"><input name="displacement" type="vector3" value="0, 0, 0.1" /></displacement>
  <surfacematerial name="dmat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="surf" />
    <input name="displacementshader" type="displacementshader" nodename="d" />
  </surfacematerial>"""
    s = pipeline.generate(write_doc(tmp_path, body), elements=["dmat"])[0]
    assert "i_tangent" in s.vertex and "cross(i_normal, i_tangent)" in s.vertex


MIXED = """
  <oren_nayar_diffuse_bsdf name="red" type="BSDF"><input name="color" type="color3" value="1, 0, 0" /></oren_nayar_diffuse_bsdf>
  <oren_nayar_diffuse_bsdf name="green" type="BSDF"><input name="color" type="color3" value="0, 1, 0" /></oren_nayar_diffuse_bsdf>
  <mix name="m" type="BSDF"><input name="fg" type="BSDF" nodename="red" /><input name="bg" type="BSDF" nodename="green" />
    <input name="mix" type="float" value="%s" /></mix>
  <surface name="surf" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="m" /></surface>"""


def test_closure_lobes_are_evaluated_only_where_their_mix_factor_lets_them_matter(tmp_path):
    """A lobe that samples the environment (a dielectric's indirect lobe: a loop of filtered lookups) is computed under
    an `if` (fg unless the factor is 0, bg unless it is 1); a cheap lobe (Oren-Nayar's: one irradiance read) is
    computed always, then made the empty closure where its weight is zero: GPU compilers handle that better than a
    branch per lobe (docs/measuring.md, guards and sample loops)."""
    glossy = MIXED.replace('<oren_nayar_diffuse_bsdf name="red" type="BSDF"><input name="color" type="color3" '
                           'value="1, 0, 0" /></oren_nayar_diffuse_bsdf>',
                           '<dielectric_bsdf name="red" type="BSDF"><input name="roughness" type="vector2" '
                           'value="0.3, 0.3" /></dielectric_bsdf>')
    s = pipeline.generate(write_doc(tmp_path, glossy % 0.0))[0]
    main = s.fragment[s.fragment.index("void main()"):]
    assert re.search(r"if \(m_mix != 0\.0 && red_weight >= 1\.0e-6\)\n\s+\w+ = mg_dielectric_indirect\(", main)
    assert re.search(r"\w+ = mg_oren_nayar_indirect\([^;]*\);\n\s+if \(!\(green_weight >= 1\.0e-6\)\)", main)
    assert not re.search(r"if \(m_mix != 1\.0[^)]*\)\n\s+\w+ = mg_oren_nayar_indirect\(", main)


@pytest.mark.parametrize("factor", [0.0, 0.3, 1.0])
def test_guarded_lobes_render_as_unguarded_ones(tmp_path, renderer, reference, factor):
    assert_parity_with_materialx(renderer, reference, write_doc(tmp_path, MIXED % factor), "surf")


@pytest.mark.parametrize("factor, held", [(1.5, 1.0), (-0.5, 0.0)])
def test_guarded_lobes_outside_the_unit_range_render_as_the_held_factor(tmp_path, renderer, reference, factor, held):
    # a BSDF mix holds its factor to [0, 1] (tests/nodes/test_closure_weights.py); MaterialX's lone mix extrapolates,
    # so ours is compared with MaterialX's at the held factor
    from mtlxgen.draw import compare
    from util import generate_one
    ours = renderer.render(generate_one(write_doc(tmp_path, MIXED % factor, name="out.mtlx"), "surf"))
    vs, fs, tex, _ = reference.generate(write_doc(tmp_path, MIXED % held, name="held.mtlx"), "surf")
    theirs, _ = renderer.render_timed(vs, fs, {}, tex)
    assert compare.parity(ours, theirs).passes


THROUGH = """
  <dielectric_bsdf name="glass" type="BSDF">
    <input name="ior" type="float" value="%s" />
    <input name="roughness" type="vector2" value="0, 0" />
    <input name="scatter_mode" type="string" value="T" />
  </dielectric_bsdf>
  <surface name="surf" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="glass" />
    <input name="thin_walled" type="boolean" value="%s" /></surface>"""


def test_thin_walled_surface_is_seen_straight_through(tmp_path):
    # a thin-walled surface is a shell (MaterialX Specification 1.39 surface; OpenPBR: no refraction): the
    # environment behind it is seen undeflected, as through an interface of IOR 1, only dimmed by the Fresnel
    # reflection (grey for a dielectric); a solid sphere of IOR 1.5 refracts (and mirrors) it
    from mtlxgen.draw.renderer import Renderer
    v, u = np.mgrid[0:64, 0:128]
    env = np.stack([(u + 0.5) / 128, (v + 0.5) / 64, np.full(u.shape, 0.5)], -1).astype(np.float32)

    def draw(ior, thin):
        path = write_doc(tmp_path, THROUGH % (ior, thin), name="glass_%s_%s.mtlx" % (ior, thin))
        with Renderer(size=64, environment=env) as r:
            return r.render(pipeline.generate(path)[0])

    def chroma(img):
        rgb = img[..., :3].astype(np.float64)
        return rgb / np.maximum(rgb.sum(-1, keepdims=True), 1e-6)

    air, thin, solid = draw(1.0, "false"), draw(1.5, "true"), draw(1.5, "false")
    inner = (air[..., 3] > 0.99) & (thin[..., 3] > 0.99)
    inner &= np.roll(inner, 3, 0) & np.roll(inner, -3, 0) & np.roll(inner, 3, 1) & np.roll(inner, -3, 1)
    assert inner.sum() > 1000
    assert np.abs(chroma(thin) - chroma(air))[inner].max() < 0.01
    assert (thin[..., :3].sum(-1) < air[..., :3].sum(-1))[inner].mean() > 0.99      # the interface reflects some
    assert np.abs(chroma(solid) - chroma(air))[inner].max() > 0.05


def test_open_pbr_thin_walled_reaches_the_surface(tmp_path):
    body = """
  <open_pbr_surface name="s" type="surfaceshader">
    <input name="transmission_weight" type="float" value="1" />
    <input name="geometry_thin_walled" type="boolean" value="%s" />
  </open_pbr_surface>"""
    for flag in ("true", "false"):
        frag = pipeline.generate(write_doc(tmp_path, body % flag, name=flag + ".mtlx"))[0].fragment
        # the public uniform of the material's input decides the surface's transmission
        assert "uniform bool s_geometry_thin_walled = %s;" % flag in frag
        # (through open_pbr_surface's function: the uniform passed as its parameter, the parameter read by the surface)
        call = re.search(r"\n    mg_ND_open_pbr_surface_surfaceshader\(([^;]*)\);", frag).group(1).split(", ")
        signature = re.search(r"void mg_ND_open_pbr_surface_surfaceshader\(([^)]*)\)", frag).group(1).split(", ")
        param = signature[call.index("s_geometry_thin_walled")].split()[-1]
        assert "bool mg_thin_walled = %s;" % param in frag
