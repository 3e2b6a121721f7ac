"""Texture nodes, colour management and UDIMs: small materials rendered by us and by MaterialX in our harness.

MaterialX converts file colour spaces only when a colour management system is registered (its viewer
does; the bare generator does not), so the colour-space tests use a reference that registers one.
"""
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import DATA_IMAGES, DATA_TESTSUITE, REFERENCE_SEARCH
from mtlxgen.draw import compare
from mtlxgen.base import images
from mtlxgen.base.diagnostics import MtlxError
from util import assert_parity_with_materialx, generate_one, write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
IMAGES = DATA_IMAGES
GRID = os.path.abspath(os.path.join(IMAGES, "grid.png"))
CLOTH = os.path.abspath(os.path.join(IMAGES, "cloth.png"))
HEIGHT = os.path.abspath(os.path.join(IMAGES, "plain_heightmap.png"))
BRICK_NORMAL = os.path.abspath(os.path.join(IMAGES, "brick_normal.jpg"))


@pytest.fixture(scope="module")
def reference_cm():
    from mtlxgen.apps.reference import MaterialXReference
    return MaterialXReference(REFERENCE_SEARCH, color_management=True)


@pytest.fixture(scope="module")
def checker(tmp_path_factory):
    """A 16x8 RGBA gradient-and-checker image, written as 8-bit sRGB PNG."""
    h, w = 8, 16
    y, x = np.mgrid[0:h, 0:w]
    img = np.zeros((h, w, 4), np.float32)
    img[..., 0] = x / (w - 1)
    img[..., 1] = y / (h - 1)
    img[..., 2] = ((x // 4 + y // 4) % 2) * 0.8
    img[..., 3] = 1.0
    return images.write_image(str(tmp_path_factory.mktemp("tex") / "checker.png"), img)


def _image_doc(tmp_path, file, out_type="color3", extra="", colorspace="lin_rec709", file_cs=None):
    cs = ' colorspace="%s"' % file_cs if file_cs else ""
    body = ('<image name="img" type="%s"><input name="file" type="filename" value="%s"%s />%s</image>\n'
            '<output name="out" type="%s" nodename="img" />' % (out_type, file, cs, extra, out_type))
    path = write_doc(tmp_path, body)
    if colorspace:
        text = open(path).read().replace('<materialx version="1.39">', '<materialx version="1.39" colorspace="%s">' % colorspace)
        open(path, "w").write(text)
    return path


@pytest.mark.parametrize("out_type", ["float", "vector2", "color3", "vector3", "color4", "vector4"])
def test_image_every_type_matches_materialx(renderer, reference, tmp_path, checker, out_type):
    assert_parity_with_materialx(renderer, reference, _image_doc(tmp_path, checker, out_type), "out")


@pytest.mark.parametrize("colorspace", ["srgb_texture", "g22_rec709", "g18_rec709", "rec709_display", "acescg",
                                        "g22_ap1", "adobergb", "lin_adobergb", "srgb_displayp3", "lin_displayp3"])
def test_file_colorspace_converts_to_lin_rec709_like_materialx(renderer, reference_cm, tmp_path, colorspace):
    path = _image_doc(tmp_path, CLOTH, "color4", file_cs=colorspace)
    assert_parity_with_materialx(renderer, reference_cm, path, "out")


def test_document_without_colorspace_reads_files_unconverted(renderer, tmp_path):
    shader = generate_one(_image_doc(tmp_path, CLOTH, "color3", colorspace=None, file_cs="srgb_texture"), "out")
    assert "mg_srgb_to_linear" not in shader.fragment
    assert shader.manifest["textures"][0]["colorspace"] == "srgb_texture"


def test_vector_images_are_never_colour_managed(tmp_path):
    shader = generate_one(_image_doc(tmp_path, GRID, "vector3", file_cs="srgb_texture"), "out")
    assert "mg_srgb_to_linear" not in shader.fragment


def test_address_modes_filter_and_default_go_to_the_manifest(renderer, reference, tmp_path, checker):
    extra = ('<input name="uaddressmode" type="string" value="mirror" />'
             '<input name="vaddressmode" type="string" value="constant" />'
             '<input name="filtertype" type="string" value="closest" />'
             '<input name="default" type="color3" value="1, 0, 0" />')
    path = _image_doc(tmp_path, checker, "color3", extra)
    tex = generate_one(path, "out").manifest["textures"][0]
    assert (tex["uaddressmode"], tex["vaddressmode"], tex["filtertype"]) == ("mirror", "constant", "closest")
    assert tex["default"] == [1.0, 0.0, 0.0]
    assert_parity_with_materialx(renderer, reference, path, "out")      # sampler state: the harness's own


def test_bad_address_mode_is_a_file_line_error(tmp_path, checker):
    path = _image_doc(tmp_path, checker, "color3", '<input name="uaddressmode" type="string" value="wrap" />')
    with pytest.raises(MtlxError) as e:
        generate_one(path, "out")
    assert "doc.mtlx:" in str(e.value) and "uaddressmode 'wrap'" in str(e.value)


def test_missing_file_renders_the_default_colour(renderer, tmp_path):
    """Documented fallback: a file that cannot be read is bound as a 1x1 texture of `default`."""
    path = _image_doc(tmp_path, os.path.join(str(tmp_path), "nowhere.png"), "color3",
                      '<input name="default" type="color3" value="0.8, 0.2, 0.1" />')
    shader = generate_one(path, "out")
    assert shader.manifest["textures"][0]["default"] == [0.8, 0.2, 0.1]
    img = renderer.render(shader)
    assert np.allclose(img[64, 64, :3], [0.8, 0.2, 0.1], atol=1e-3)


def test_missing_file_through_the_cli_is_no_traceback(tmp_path):
    path = _image_doc(tmp_path, "nowhere.png", "color3")
    proc = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), "generate", path, "-o", str(tmp_path / "o")],
                          capture_output=True, text=True)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr


def test_udim_tiles_get_one_sampler_each(renderer, tmp_path):
    colors = {1001: (1, 0, 0), 1002: (0, 1, 0), 1011: (0, 0, 1)}
    for tile, c in colors.items():
        images.write_image(str(tmp_path / ("t.%d.exr" % tile)), np.tile(np.array(c + (1,), np.float32), (4, 4, 1)))
    body = ('<texcoord name="tc" type="vector2" />'
            '<multiply name="uv" type="vector2"><input name="in1" type="vector2" nodename="tc" />'
            '<input name="in2" type="vector2" value="2, 2" /></multiply>'
            '<image name="img" type="color3"><input name="file" type="filename" value="t.<UDIM>.exr" />'
            '<input name="texcoord" type="vector2" nodename="uv" /><input name="default" type="color3" value="1, 1, 0" />'
            '</image><output name="out" type="color3" nodename="img" />')
    shader = generate_one(write_doc(tmp_path, body), "out")
    files = sorted(os.path.basename(t["file"]) for t in shader.manifest["textures"])
    assert files == ["t.1001.exr", "t.1002.exr", "t.1011.exr"]
    img = renderer.render(shader)
    # the sphere's front (u around 0.75 -> 1.5) shows tile column 1; lower half v < 0.5 -> row 0
    assert np.allclose(img[80, 64, :3], [0, 1, 0], atol=1e-3)     # u*2 in [1,2), v*2 < 1: tile 1002
    assert np.allclose(img[40, 64, :3], [1, 1, 0], atol=1e-3)     # tile 1012 absent: the default colour


def test_corpus_udim_file_parses_and_expands(tmp_path):
    from mtlxgen import pipeline
    udim = os.path.join(DATA_TESTSUITE, "stdlib", "texture", "udim.mtlx")
    doc = pipeline.load_document(udim)
    assert "<UDIM>" in doc.nodes["image_color"].inputs["file"].value


@pytest.mark.parametrize("body", [
    '<normalmap name="n" type="vector3"><input name="in" type="vector3" value="0.7, 0.3, 0.8" />'
    '<input name="scale" type="float" value="1.5" /></normalmap><output name="out" type="vector3" nodename="n" />',
    '<normalmap name="n" type="vector3"><input name="in" type="vector3" value="0.7, 0.3, 0.8" />'
    '<input name="scale" type="vector2" value="0.5, 2" /></normalmap><output name="out" type="vector3" nodename="n" />',
    '<image name="h" type="float"><input name="file" type="filename" value="%s" /></image>'
    '<bump name="b" type="vector3"><input name="height" type="float" nodename="h" />'
    '<input name="scale" type="float" value="0.5" /></bump><output name="out" type="vector3" nodename="b" />' % HEIGHT,
    '<image name="i" type="color3"><input name="file" type="filename" value="%s" /></image>'
    '<extract name="e" type="float"><input name="in" type="color3" nodename="i" /><input name="index" type="integer" value="1" /></extract>'
    '<heighttonormal name="h" type="vector3"><input name="in" type="float" nodename="e" /></heighttonormal>'
    '<output name="out" type="vector3" nodename="h" />' % GRID,
    '<triplanarprojection name="t" type="color3"><input name="filex" type="filename" value="%s" />'
    '<input name="filey" type="filename" value="%s" /><input name="filez" type="filename" value="%s" />'
    '<input name="blend" type="float" value="0.5" /></triplanarprojection><output name="out" type="color3" nodename="t" />'
    % (GRID, CLOTH, GRID),
    '<tiledimage name="t" type="color3"><input name="file" type="filename" value="%s" />'
    '<input name="uvtiling" type="vector2" value="3, 2" /><input name="uvoffset" type="vector2" value="0.2, 0.1" />'
    '<input name="realworldimagesize" type="vector2" value="2, 2" /><input name="realworldtilesize" type="vector2" value="1, 4" />'
    '<input name="framerange" type="string" value="1-10" /></tiledimage><output name="out" type="color3" nodename="t" />' % GRID,
    '<image name="i" type="color3"><input name="file" type="filename" value="%s" /></image>'
    '<blur name="b" type="color3"><input name="in" type="color3" nodename="i" /><input name="size" type="float" value="0.5" />'
    '</blur><output name="out" type="color3" nodename="b" />' % GRID,
    '<image name="i" type="vector3"><input name="file" type="filename" value="%s" /></image>'
    '<normalmap name="n" type="vector3"><input name="in" type="vector3" nodename="i" /></normalmap>'
    '<output name="out" type="vector3" nodename="n" />' % HEIGHT,
], ids=["normalmap", "normalmap_vector2", "bump", "heighttonormal", "triplanar", "tiledimage", "blur", "normalmap_black_texels"])
def test_texture_nodes_match_materialx(renderer, reference, tmp_path, body):
    assert_parity_with_materialx(renderer, reference, write_doc(tmp_path, body), "out")


@pytest.mark.parametrize("node", ["g18_rec709", "g22_rec709", "rec709_display", "acescg", "g22_ap1", "srgb_texture",
                                  "lin_adobergb", "adobergb", "srgb_displayp3", "lin_displayp3"])
def test_cmlib_nodes_match_materialx(renderer, reference, tmp_path, node):
    body = ('<{n}_to_lin_rec709 name="a" type="color3"><input name="in" type="color3" value="0.3, 0.6, 0.9" />'
            '</{n}_to_lin_rec709><output name="out" type="color3" nodename="a" />'
            '<{n}_to_lin_rec709 name="b" type="color4"><input name="in" type="color4" value="0.8, 0.2, 0.02, 0.5" />'
            '</{n}_to_lin_rec709><output name="out4" type="color4" nodename="b" />').format(n=node)
    path = write_doc(tmp_path, body)
    assert_parity_with_materialx(renderer, reference, path, "out")
    assert_parity_with_materialx(renderer, reference, path, "out4")


# ---------------------------------------------------------------- hex tiling

def _hextile_doc(tmp_path, node, out_type, file, **inputs):
    types = {"rotationrange": "vector2", "scalerange": "vector2", "offsetrange": "vector2", "flip_g": "boolean",
             "lumacoeffs": "color3", "tiling": "vector2"}
    body = "".join('<input name="%s" type="%s" value="%s" />' % (k, types.get(k, "float"), v) for k, v in inputs.items())
    return write_doc(tmp_path, '<%s name="h" type="%s"><input name="file" type="filename" value="%s" />%s</%s>'
                               '<output name="out" type="%s" nodename="h" />' % (node, out_type, file, body, node, out_type))


# Every per-tile draw fixed (each range one value wide), so the tiles' transforms and blend weights, not the random
# numbers, are compared: the spec names the ranges, not the generator (ours is the paper's sine hash).
@pytest.mark.parametrize("out_type, inputs", [
    ("color3", dict(rotationrange="30, 30", scalerange="1.5, 1.5", offsetrange="0.05, 0.05", tiling="3, 2")),
    ("color4", dict(rotation=0.4, rotationrange="75, 75", scale=0.6, scalerange="0.7, 0.7", offset=0.3,
                    offsetrange="0.2, 0.2", falloff=0.8, falloffcontrast=1.0, tiling="4, 4")),
    ("color3", dict(rotationrange="120, 120", scalerange="2, 2", offsetrange="0.5, 0.5", falloff=0.1,
                    falloffcontrast=0.0, lumacoeffs="0.2126, 0.7152, 0.0722", tiling="2, 2")),
], ids=["defaults", "weights", "sharp_falloff"])
def test_hextiledimage_tiles_match_materialx(renderer, reference, tmp_path, out_type, inputs):
    path = _hextile_doc(tmp_path, "hextiledimage", out_type, CLOTH, **inputs)
    assert_parity_with_materialx(renderer, reference, path, "out")


# normals blend as height slopes (xy / |z|, the paper's derivatives); the height map read as a normal map has
# texels with z below 0 and all-zero ones
@pytest.mark.parametrize("file", [BRICK_NORMAL, HEIGHT], ids=["normal_map", "height_map"])
def test_hextilednormalmap_tiles_match_materialx_without_rotation(renderer, reference, tmp_path, file):
    path = _hextile_doc(tmp_path, "hextilednormalmap", "vector3", file, rotationrange="0, 0", scalerange="1.3, 1.3",
                        offsetrange="0.25, 0.25", falloff=0.7, strength=0.6, flip_g="true", tiling="3, 3")
    assert_parity_with_materialx(renderer, reference, path, "out")


def test_hextilednormalmap_turns_normals_with_their_tile(renderer, tmp_path):
    """A tile drawn at t = R(90 deg) uv turns its height gradients by R^T: a normal map leaning towards -x in
    the texture leans towards +y (the bitangent) on the surface. (MaterialX turns them by R, towards -y.)"""
    tilted = images.write_image(str(tmp_path / "tilted.exr"), np.tile(np.array([0.25, 0.5, 1.0], np.float32), (4, 4, 1)))
    hex_path = _hextile_doc(tmp_path, "hextilednormalmap", "vector3", tilted, rotationrange="90, 90",
                            scale=0.0, offset=0.0)
    ours = renderer.render(generate_one(hex_path, "out"))
    leaning = {}
    for name, encoded in (("plus_y", "0.5, 0.75, 1.0"), ("minus_y", "0.5, 0.25, 1.0")):
        plain = write_doc(tmp_path, '<normalmap name="n" type="vector3"><input name="in" type="vector3" value="%s" />'
                                    '</normalmap><output name="out" type="vector3" nodename="n" />' % encoded, name + ".mtlx")
        leaning[name] = renderer.render(generate_one(plain, "out"))
    assert compare.parity(ours, leaning["plus_y"]).passes
    assert not compare.parity(ours, leaning["minus_y"]).passes
