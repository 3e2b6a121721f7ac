"""EDFs and VDFs MaterialX does not generate (mtlxgen/nodes/pbrlib_edf_vdf.py, mtlxgen/draw/ies.py):
IES parsing, conical falloff and Beer–Lambert absorption (over the u_vdfThickness path) checked by rendering."""
import os
import subprocess
import sys

import numpy as np
import pytest

from mtlxgen.draw import ies
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.draw.renderer import EYE, FOV_Y
from tests.conftest import TEST_SIZE
from tests.util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "tests", "data", "ies")
DOWNLIGHT = os.path.join(DATA, "downlight_symmetric.ies")
WALLWASH = os.path.join(DATA, "wallwash_bilateral.ies")


# ---------------------------------------------------------------- IES LM-63

def test_ies_downlight_parses_with_its_multiplier():
    p = ies.parse(DOWNLIGHT)
    assert p.keywords["LUMCAT"] == "MG-DL-1" and p.photometric_type == 1 and p.units == 2
    assert p.lumens_per_lamp == 1000 and p.multiplier == 2.0 and p.input_watts == 12
    assert list(p.vertical) == [0, 15, 30, 45, 60, 75, 90] and list(p.horizontal) == [0]
    assert p.candela.tolist() == [[1000, 960, 800, 500, 100, 0, 0]] and p.peak == 1000


def test_ies_wallwash_parses_tilt_commas_and_wrapped_lines():
    p = ies.parse(WALLWASH)
    assert "bilateral symmetry" in p.keywords["MORE"] and p.ballast_factor == 0.5
    assert list(p.vertical) == [0, 30, 60, 90, 120, 150, 180] and list(p.horizontal) == [0, 90, 180]
    # candela x multiplier 1.0 x ballast factor 0.5
    assert p.candela.tolist() == [[50, 50, 50, 25, 0, 0, 0], [100, 90, 60, 30, 5, 0, 0],
                                  [150, 125, 75, 40, 10, 0, 0]]


def test_ies_texture_interpolates_and_applies_symmetry():
    t = ies.texture(ies.parse(WALLWASH))
    assert t.shape == (ies.HEIGHT, ies.WIDTH, 1)
    row60 = round(60 / 180 * (ies.HEIGHT - 1))
    q = ies.WIDTH // 4
    assert np.allclose(t[row60, [0, q, 2 * q, 3 * q], 0], [50 / 150, 60 / 150, 75 / 150, 60 / 150])  # 270 mirrors 90
    # bilinear between (30, 0) = 50, (60, 0) = 50, (30, 90) = 90, (60, 90) = 60 at (45, 45)
    assert np.isclose(ies.intensity(ies.parse(WALLWASH), 45.0, 45.0), 0.25 * (50 + 50 + 90 + 60))
    d = ies.parse(DOWNLIGHT)
    assert np.isclose(ies.intensity(d, 22.5, 123.0), 880.0)              # halfway between 960 and 800
    assert np.isclose(ies.intensity(d, 120.0, 0.0), 0.0)                 # below the measured range: dark
    td = ies.texture(d)
    assert np.allclose(td[0, :, 0], 1.0) and np.allclose(td[:, 0, 0], td[:, 17, 0])   # symmetric about the axis


@pytest.mark.parametrize("text, line, message", [
    ("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 10\n0 90\n0\n5 x\n", 7, "'x' is not a number"),
    ("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 1 3 2 0 0 0\n1 1 10\n0 90\n0\n5 5\n", 3, "photometric type 3"),
    ("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90\n", 5, "ends before"),
    ("IESNA:LM-63-2002\n[TEST] no tilt\n", 2, "no TILT= line"),
])
def test_bad_ies_files_are_file_line_errors(tmp_path, text, line, message):
    path = os.path.join(str(tmp_path), "bad.ies")
    with open(path, "w") as f:
        f.write(text)
    with pytest.raises(MtlxError) as e:
        ies.parse(path)
    assert e.value.lines()[0].startswith("%s:%d: " % (path, line)) and message in e.value.lines()[0], e.value.lines()


# ---------------------------------------------------------------- rendering helpers

def _sphere_geometry(size=TEST_SIZE):
    """Per pixel centre: (hit mask, N, V) of the harness's unit sphere seen from EYE with FOV_Y."""
    f = 1.0 / np.tan(np.radians(FOV_Y) / 2)
    y, x = np.mgrid[0:size, 0:size]
    ndc_x = (x + 0.5) / size * 2 - 1
    ndc_y = 1 - (y + 0.5) / size * 2
    d = np.stack([ndc_x / f, ndc_y / f, -np.ones_like(ndc_x, dtype=float)], -1)
    d /= np.linalg.norm(d, axis=-1, keepdims=True)
    o = np.array(EYE)
    b = (d @ o)
    c = o @ o - 1.0
    disc = b * b - c
    hit = disc > 0
    t = -b - np.sqrt(np.maximum(disc, 0))
    p = o + t[..., None] * d
    return hit, p, -d


def _render(renderer, body, element, name="doc.mtlx", tmp_path=None):
    path = write_doc(tmp_path, body, name=name)
    shader = pipeline.generate(path, elements=[element])[0]
    return renderer.render(shader), shader


# ---------------------------------------------------------------- conical_edf

@pytest.mark.parametrize("inner, outer", [(20.0, 50.0), (40.0, 0.0)])
def test_conical_edf_falloff_matches_the_cone(renderer, tmp_path, inner, outer):
    img, _ = _render(renderer, """
  <conical_edf name="cone" type="EDF">
    <input name="color" type="color3" value="1, 0.5, 0.25" />
    <input name="inner_angle" type="float" value="%g" />
    <input name="outer_angle" type="float" value="%g" />
  </conical_edf>
  <surface name="s" type="surfaceshader"><input name="edf" type="EDF" nodename="cone" /></surface>""" % (inner, outer),
        "s", tmp_path=tmp_path)
    hit, N, V = _sphere_geometry()
    cos_t = np.sum(N * V, -1)
    ci, co = np.cos(np.radians(inner)), np.cos(np.radians(outer))
    if outer > inner:
        s = np.clip((cos_t - co) / (ci - co), 0, 1)
        expected = s * s * (3 - 2 * s)
    else:
        expected = (cos_t >= ci).astype(float)
    inside = hit & (img[..., 3] > 0.99)
    # away from the hard edge (one pixel either side) the tessellated sphere agrees to a few percent
    if outer <= inner:
        inside &= np.abs(np.degrees(np.arccos(np.clip(cos_t, -1, 1))) - inner) > 3.0
    err = np.abs(img[..., 0] - expected)[inside]
    assert inside.sum() > 5000 and np.percentile(err, 99) < 0.03, (np.percentile(err, 99), err.max())
    assert np.allclose(img[..., 1][inside], 0.5 * img[..., 0][inside], atol=1e-4)      # colour scales it


# ---------------------------------------------------------------- measured_edf

def test_measured_edf_reads_the_ies_profile(renderer, tmp_path):
    img, shader = _render(renderer, """
  <measured_edf name="lum" type="EDF">
    <input name="file" type="filename" value="%s" />
  </measured_edf>
  <surface name="s" type="surfaceshader"><input name="edf" type="EDF" nodename="lum" /></surface>""" % DOWNLIGHT,
        "s", tmp_path=tmp_path)
    tex = shader.manifest["textures"]
    assert len(tex) == 1 and tex[0]["file"] == DOWNLIGHT
    hit, N, V = _sphere_geometry()
    theta = np.degrees(np.arccos(np.clip(np.sum(N * V, -1), -1, 1)))
    expected = ies.intensity(ies.parse(DOWNLIGHT), theta, 0.0) / 1000.0
    inside = hit & (img[..., 3] > 0.99)
    err = np.abs(img[..., 0] - expected)[inside]
    assert np.percentile(err, 99) < 0.03, np.percentile(err, 99)
    assert abs(img[64, 64, 0] - 1.0) < 0.01                        # on the axis: the peak


# ---------------------------------------------------------------- VDFs

_GLASS = """
  <dielectric_bsdf name="glass" type="BSDF">
    <input name="scatter_mode" type="string" value="T" />
  </dielectric_bsdf>
  <absorption_vdf name="medium" type="VDF">
    <input name="absorption" type="vector3" value="%s" />
  </absorption_vdf>
  <layer name="glass_in_medium" type="BSDF">
    <input name="top" type="BSDF" nodename="glass" />
    <input name="base" type="VDF" nodename="medium" />
  </layer>
  <surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="glass_in_medium" /></surface>"""


def test_absorption_vdf_attenuates_transmission_by_beer_lambert(renderer, tmp_path):
    sigma = np.array([0.1, 0.5, 1.2])
    clear, _ = _render(renderer, _GLASS % "0, 0, 0", "s", "clear.mtlx", tmp_path)
    tinted, shader = _render(renderer, _GLASS % ", ".join(map(str, sigma)), "s", "tinted.mtlx", tmp_path)
    # over the default path length of one scene unit, everywhere on the surface (centre and rim alike)
    inside = (clear[..., 3] > 0.99) & (clear[..., :3].min(-1) > 0.02)
    ratio = tinted[inside][:, :3] / clear[inside][:, :3]
    assert np.allclose(ratio, np.exp(-sigma)[None, :], rtol=0.02), ratio.mean(0)
    # the path length is the thickness uniform, public: an application sets it
    decl = "uniform float u_vdfThickness = 1.0;"
    assert decl in shader.fragment
    thick = renderer.render((shader.vertex, shader.fragment.replace(decl, decl.replace("1.0", "2.5"))))
    ratio = thick[inside][:, :3] / clear[inside][:, :3]
    assert np.allclose(ratio, np.exp(-2.5 * sigma)[None, :], rtol=0.02), ratio.mean(0)


def test_vdf_leaves_reflection_alone(renderer, tmp_path):
    body = _GLASS.replace('value="T"', 'value="R"')
    a, _ = _render(renderer, body % "0, 0, 0", "s", "a.mtlx", tmp_path)
    b, _ = _render(renderer, body % "2, 2, 2", "s", "b.mtlx", tmp_path)
    assert np.allclose(a, b, atol=1e-6)


def test_anisotropic_vdf_extinction_and_inscatter(renderer, tmp_path):
    body = _GLASS.replace('<absorption_vdf name="medium" type="VDF">\n    <input name="absorption" type="vector3" value="%s" />\n  </absorption_vdf>',
                          '<anisotropic_vdf name="medium" type="VDF">\n    <input name="absorption" type="vector3" value="%s" />\n'
                          '    <input name="scattering" type="vector3" value="%s" />\n  </anisotropic_vdf>')
    dark, _ = _render(renderer, body % ("0.5, 0.5, 0.5", "0, 0, 0"), "s", "dark.mtlx", tmp_path)
    absorbing, _ = _render(renderer, _GLASS % "0.5, 0.5, 0.5", "s", "abs.mtlx", tmp_path)
    assert np.allclose(dark, absorbing, atol=1e-5)                # no scattering: the absorption_vdf
    milky, _ = _render(renderer, body % ("0, 0, 0", "3, 3, 3"), "s", "milky.mtlx", tmp_path)
    assert milky[64, 64, :3].mean() > 0.05                        # in-scattered light replaces what is lost


def test_volume_mix_add_multiply_and_shader_mixes_generate_and_render(renderer, tmp_path):
    body = """
  <absorption_vdf name="a" type="VDF"><input name="absorption" type="vector3" value="1, 0.5, 0.2" /></absorption_vdf>
  <anisotropic_vdf name="b" type="VDF">
    <input name="scattering" type="vector3" value="0.5, 0.5, 0.5" />
    <input name="anisotropy" type="float" value="0.4" />
  </anisotropic_vdf>
  <mix name="m" type="VDF"><input name="fg" type="VDF" nodename="a" /><input name="bg" type="VDF" nodename="b" /><input name="mix" type="float" value="0.3" /></mix>
  <add name="s" type="VDF"><input name="in1" type="VDF" nodename="m" /><input name="in2" type="VDF" nodename="a" /></add>
  <multiply name="k" type="VDF"><input name="in1" type="VDF" nodename="s" /><input name="in2" type="color3" value="0.5, 1, 1" /></multiply>
  <uniform_edf name="e" type="EDF"><input name="color" type="color3" value="0.2, 0.1, 0" /></uniform_edf>
  <volume name="v1" type="volumeshader"><input name="vdf" type="VDF" nodename="k" /><input name="edf" type="EDF" nodename="e" /></volume>
  <volume name="v2" type="volumeshader"><input name="vdf" type="VDF" nodename="a" /></volume>
  <mix name="vm" type="volumeshader"><input name="fg" type="volumeshader" nodename="v1" /><input name="bg" type="volumeshader" nodename="v2" /><input name="mix" type="float" value="0.5" /></mix>
  <volumematerial name="vol" type="material"><input name="volumeshader" type="volumeshader" nodename="vm" /></volumematerial>
  <displacement name="d1" type="displacementshader"><input name="displacement" type="float" value="0.1" /></displacement>
  <displacement name="d2" type="displacementshader"><input name="displacement" type="float" value="-0.1" /></displacement>
  <mix name="dm" type="displacementshader"><input name="fg" type="displacementshader" nodename="d1" /><input name="bg" type="displacementshader" nodename="d2" /><input name="mix" type="float" value="0.5" /></mix>
  <surface_unlit name="u" type="surfaceshader" />
  <surfacematerial name="disp" type="material"><input name="surfaceshader" type="surfaceshader" nodename="u" /><input name="displacementshader" type="displacementshader" nodename="dm" /></surfacematerial>"""
    vol, shader = _render(renderer, body, "vol", "vol.mtlx", tmp_path)
    assert "mg_absorption_vdf" in shader.fragment and "mg_mix_volumeshader" in shader.fragment
    # the volume's transparency: mix of the two transmittances over the unit path length
    v2 = np.exp(-np.array([1, 0.5, 0.2]))
    assert abs(vol[64, 64, 3] - (1 - 0.5 * (v2.mean() + _v1_transparency().mean()))) < 0.01
    disp, shader = _render(renderer, body, "disp", "disp.mtlx", tmp_path)
    assert "mg_mix_displacementshader" in shader.vertex
    # offsets of +0.1 and -0.1 mixed half and half: the sphere keeps radius 1
    ref, _ = _render(renderer, '<surface_unlit name="u" type="surfaceshader" /><surfacematerial name="m" type="material">'
                     '<input name="surfaceshader" type="surfaceshader" nodename="u" /></surfacematerial>', "m", "ref.mtlx",
                     tmp_path)
    assert np.array_equal(disp[..., 3] > 0.5, ref[..., 3] > 0.5)


def _v1_transparency():
    """Throughput of k = multiply(add(mix(a, b, 0.3), a), ...) over the unit path length."""
    a = np.exp(-np.array([1, 0.5, 0.2]))
    b = np.exp(-np.array([0.5, 0.5, 0.5]))
    m = 0.3 * a + 0.7 * b
    return m * a                                                   # add multiplies throughputs; multiply keeps them


def test_measured_edf_with_a_broken_ies_file_is_one_line_at_its_input(tmp_path):
    """A profile that does not read is refused as a texture that does not decode: one line at the input naming
    the file and the IES reader's line, nothing drawn (it drew a dark sphere in silence)."""
    bad = os.path.join(str(tmp_path), "bad.ies")
    with open(bad, "w") as f:
        f.write("not an ies file\n")
    path = write_doc(tmp_path, """
  <measured_edf name="lum" type="EDF"><input name="file" type="filename" value="bad.ies" /></measured_edf>
  <surface name="s" type="surfaceshader"><input name="edf" type="EDF" nodename="lum" /></surface>""")
    r = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "render", path, "-o", str(tmp_path / "o"),
                        "--size", "32"], capture_output=True, text=True)
    assert r.returncode == 1 and "Traceback" not in r.stderr, r.stderr
    assert r.stderr.splitlines() == ["%s:4: texture '%s' line 1: no TILT= line: not an IES LM-63 file" % (path, bad)]
    assert not os.path.exists(tmp_path / "o" / "s.exr")
