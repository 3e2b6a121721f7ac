"""UsdPreviewSurface seed rules (mtlxgen/nodes/usd.py, glsl_lib/usd/): each rule against MaterialX's
own nodegraphs, with the option on and off, on small documents and images written here."""
import os
import subprocess
import sys

import numpy as np
import pytest

from mtlxgen.base import images
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError, Warnings
from tests.util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _png(tmp_path, name, pixels, **metadata):
    """An 8-bit PNG of constant channels (values 0..255); string metadata such as wrapS goes in the file."""
    import OpenImageIO as oiio
    px = np.zeros((8, 8, len(pixels)), np.uint8)
    px[...] = pixels
    if not metadata:
        return images.write_image(os.path.join(str(tmp_path), name), px)
    spec = oiio.ImageSpec(8, 8, len(pixels), oiio.UINT8)
    for k, v in metadata.items():
        spec.attribute(k, v)
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), px)
    path = os.path.join(str(tmp_path), name)
    assert buf.write(path)
    return path


def _texture_doc(tmp_path, file, output="rgba", out_type="color4", tex_inputs="", st=""):
    body = """
  <nodegraph name="g">
    <texcoord name="uv" type="vector2" />
    <UsdTransform2d name="xf" type="vector2">
      <input name="in" type="vector2" nodename="uv" />%s
    </UsdTransform2d>
    <UsdUVTexture name="tex" type="multioutput">
      <input name="file" type="filename" value="%s" />
      <input name="st" type="vector2" nodename="xf" output="%s" />%s
    </UsdUVTexture>
    <output name="out" type="%s" nodename="tex" output="%s" />
  </nodegraph>""" % (st, os.path.basename(file), "result", tex_inputs, out_type, output)
    return write_doc(tmp_path, body)


def _render_centre(renderer, path, rules, element=None):
    shaders = pipeline.generate(path, elements=[element] if element else None, usd_seed_rules=rules)
    img = renderer.render(shaders[0])
    return img[60:68, 60:68].reshape(-1, 4).mean(0), shaders[0]


def _mx_texture_doc(tmp_path, file, output="rgb", out_type="color3"):
    """The same read in MaterialX's vocabulary (`out` output name, no seed-only inputs)."""
    return write_doc(tmp_path, """
  <nodegraph name="g">
    <UsdUVTexture name="tex" type="multioutput">
      <input name="file" type="filename" value="%s" />
    </UsdUVTexture>
    <output name="out" type="%s" nodename="tex" output="%s" />
  </nodegraph>""" % (os.path.basename(file), out_type, output), name="mx.mtlx")


def test_one_channel_texture_repeats_red_and_alpha_is_one(renderer, tmp_path):
    f = _png(tmp_path, "one.png", [128])
    on, _ = _render_centre(renderer, _texture_doc(tmp_path, f), True)
    assert np.allclose(on, [128 / 255] * 3 + [1.0], atol=2e-3), on
    off, _ = _render_centre(renderer, _mx_texture_doc(tmp_path, f), False)
    assert off[1] < 1e-3 and abs(off[0] - 128 / 255) < 2e-3, off      # MaterialX: rgb = (r, 0, 0)


def test_two_channel_texture_is_grey_plus_alpha(renderer, tmp_path):
    f = _png(tmp_path, "two.png", [200, 64])
    on, _ = _render_centre(renderer, _texture_doc(tmp_path, f), True)
    # (the harness's loader, OpenImageIO, associates a PNG's alpha on reading: rgb arrives as r * a)
    assert abs(on[0] - on[1]) < 1e-4 and abs(on[0] - on[2]) < 1e-4 and abs(on[3] - 64 / 255) < 2e-3, on
    off, _ = _render_centre(renderer, _mx_texture_doc(tmp_path, f), False)
    assert abs(off[1] - 64 / 255) < 2e-3 and off[2] < 1e-3, off        # MaterialX: rgb = (r, g, 0)


def test_two_channel_float_texture_values(renderer, tmp_path):
    f = os.path.join(str(tmp_path), "two.exr")
    px = np.zeros((8, 8, 2), np.float32)
    px[...] = [0.75, 0.25]
    images.write_image(f, px)
    on, shader = _render_centre(renderer, _texture_doc(tmp_path, f), True)
    assert np.allclose(on, [0.75, 0.75, 0.75, 0.25], atol=2e-3), on
    assert shader.manifest["textures"][0]["channels"] == 2
    assert shader.manifest["textures"][0]["colorspace"] == "raw"      # auto: not 8-bit


@pytest.mark.parametrize("source, expected", [("raw", 128 / 255), ("sRGB", ((128 / 255 + 0.055) / 1.055) ** 2.4),
                                              ("auto", ((128 / 255 + 0.055) / 1.055) ** 2.4)])
def test_source_colorspace_picks_the_transfer_curve(renderer, tmp_path, source, expected):
    f = _png(tmp_path, "rgb.png", [128, 128, 128])
    doc = _texture_doc(tmp_path, f, tex_inputs='\n      <input name="sourceColorSpace" type="string" value="%s" />' % source)
    on, shader = _render_centre(renderer, doc, True)
    assert np.allclose(on[:3], expected, atol=2e-3), (source, on)
    tex = shader.manifest["textures"][0]
    assert tex["colorspace"] == ("raw" if source == "raw" else "srgb_texture") and tex["channels"] == 3


def test_auto_reads_one_channel_8_bit_files_raw(renderer, tmp_path):
    f = _png(tmp_path, "one.png", [128])
    on, shader = _render_centre(renderer, _texture_doc(tmp_path, f), True)
    assert abs(on[0] - 128 / 255) < 2e-3
    assert shader.manifest["textures"][0]["colorspace"] == "raw"


def test_scale_and_bias_apply_after_the_read(renderer, tmp_path):
    f = _png(tmp_path, "one.png", [51])
    doc = _texture_doc(tmp_path, f, tex_inputs='\n      <input name="scale" type="color4" value="-1, 2, 1, 1" />'
                                               '\n      <input name="bias" type="color4" value="1, 0, 0.25, 0" />')
    on, _ = _render_centre(renderer, doc, True)
    assert np.allclose(on, [1 - 0.2, 0.4, 0.45, 1.0], atol=2e-3), on


@pytest.mark.parametrize("wrap, expected", [("black", 0.0), ("clamp", 0.6), ("repeat", 0.6), ("mirror", 0.6),
                                            ("useMetadata", 0.0)])
def test_wrap_modes_outside_the_unit_square(renderer, tmp_path, wrap, expected):
    f = _png(tmp_path, "one.png", [153])
    doc = _texture_doc(tmp_path, f, st='\n      <input name="translation" type="vector2" value="3.0, -2.0" />',
                       tex_inputs='\n      <input name="wrapS" type="string" value="%s" />'
                                  '\n      <input name="wrapT" type="string" value="%s" />' % (wrap, wrap))
    on, _ = _render_centre(renderer, doc, True)
    assert abs(on[0] - expected) < 2e-3, (wrap, on)
    assert abs(on[3] - (0.0 if expected == 0.0 else 1.0)) < 2e-3     # black is transparent black


def test_use_metadata_reads_the_files_wrap_tokens(renderer, tmp_path):
    f = _png(tmp_path, "meta.png", [153], wrapS="clamp", wrapT="mirror")
    doc = _texture_doc(tmp_path, f, st='\n      <input name="translation" type="vector2" value="3.0, -2.0" />')
    on, shader = _render_centre(renderer, doc, True)
    assert abs(on[0] - 0.6) < 2e-3, on
    assert shader.manifest["textures"][0]["usd_wrap"] == ["clamp", "mirror"]


def test_black_wrap_is_not_a_materialx_address_mode(tmp_path):
    f = _png(tmp_path, "one.png", [153])
    doc = write_doc(tmp_path, """
  <UsdUVTexture name="tex" type="multioutput">
    <input name="file" type="filename" value="%s" />
    <input name="wrapS" type="string" value="black" />
  </UsdUVTexture>
  <output name="o" type="color3" nodename="tex" output="rgb" />""" % os.path.basename(f))
    assert "mg_usd_uvtexture" in pipeline.generate(doc, usd_seed_rules=True)[0].fragment
    with pytest.raises(MtlxError, match="uaddressmode 'black'"):
        pipeline.generate(doc, usd_seed_rules=False)


def test_result_output_name_is_accepted_only_with_the_rules(tmp_path):
    f = _png(tmp_path, "one.png", [153])
    doc = _texture_doc(tmp_path, f)
    seen = Warnings()
    pipeline.generate(doc, usd_seed_rules=True, warnings=seen)
    assert not seen, seen.lines()
    # without the rules, as MaterialX 1.39.5 reads it (issue 16): an output name a node lacks reads its first
    # output (a warning: UsdTransform2d's 'out' for 'result'), and MaterialX's UsdUVTexture has no 'rgba', so the
    # color4 graph output would read its first output, the float 'r' (MaterialX's GLSL for that does not compile)
    with pytest.raises(MtlxError, match="has type color4 but is connected to a value of type float"):
        pipeline.generate(doc, usd_seed_rules=False, warnings=seen)
    assert any("node 'xf' has no output 'result'" in line for line in seen.lines()), seen.lines()


def test_unreadable_file_gives_the_fallback(renderer, tmp_path):
    doc = write_doc(tmp_path, """
  <UsdUVTexture name="tex" type="multioutput">
    <input name="file" type="filename" value="missing.png" />
    <input name="fallback" type="color4" value="0.25, 0.5, 0.75, 1" />
  </UsdUVTexture>
  <output name="o" type="color3" nodename="tex" output="rgb" />""")
    on, _ = _render_centre(renderer, doc, True)
    assert np.allclose(on[:3], [0.25, 0.5, 0.75], atol=2e-3)


def _surface_doc(tmp_path, inputs, name="srf.mtlx"):
    return write_doc(tmp_path, """
  <UsdPreviewSurface name="srf" type="surfaceshader">%s
  </UsdPreviewSurface>
  <surfacematerial name="mat" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="srf" />
  </surfacematerial>""" % "".join('\n    <input name="%s" type="%s" value="%s" />' % i for i in inputs), name=name)


def test_metallic_uses_albedo_for_f0_and_f90_not_a_conductor(renderer, tmp_path):
    doc = _surface_doc(tmp_path, [("diffuseColor", "color3", "0.9, 0.1, 0.05"), ("metallic", "float", "1"),
                                  ("roughness", "float", "0.3")])
    on = pipeline.generate(doc, usd_seed_rules=True)[0]
    off = pipeline.generate(doc, usd_seed_rules=False)[0]
    assert "mg_conductor" not in on.fragment and "mg_conductor" in off.fragment
    a, b = renderer.render(on), renderer.render(off)
    # at grazing angles the seed's metal stays the albedo's colour; MaterialX's conductor turns white
    y, x = np.mgrid[0:128, 0:128]
    r = np.hypot(x - 63.5, y - 63.5)
    rim = (r > 44) & (r < 47) & (a[..., 3] > 0.99)

    def whiteness(img):
        return float(np.mean(img[rim][:, 1] / np.maximum(img[rim][:, 0], 1e-6)))
    assert whiteness(a) < whiteness(b), (whiteness(a), whiteness(b))


@pytest.mark.parametrize("opacity, threshold, alpha", [(0.3, 0.5, 0.0), (0.3, 0.2, 1.0), (0.3, 0.0, 0.3),
                                                       (0.5, 0.5, 1.0)])
def test_opacity_threshold_cuts_out(renderer, tmp_path, opacity, threshold, alpha):
    doc = _surface_doc(tmp_path, [("opacity", "float", opacity), ("opacityThreshold", "float", threshold)])
    img = renderer.render(pipeline.generate(doc, usd_seed_rules=True)[0])
    assert abs(img[64, 64, 3] - alpha) < 2e-3, img[64, 64]


def test_opacity_is_alpha_not_refraction_with_the_rules(tmp_path):
    doc = _surface_doc(tmp_path, [("opacity", "float", "0.5")])
    assert "mg_dielectric_transmission" not in pipeline.generate(doc, usd_seed_rules=True)[0].fragment
    assert "mg_dielectric_transmission" in pipeline.generate(doc, usd_seed_rules=False)[0].fragment


def test_rules_default_on_for_documents_from_usd(tmp_path):
    # USD's own vocabulary (sourceColorSpace, which MaterialX's UsdUVTexture lacks) marks a document from USD
    usd = _surface_doc(tmp_path, [("metallic", "float", "1")], name="usd.mtlx")
    usd_text = open(usd).read().replace("</materialx>", """  <UsdUVTexture name="tex" type="multioutput">
    <input name="file" type="filename" value="missing.png" />
    <input name="sourceColorSpace" type="string" value="raw" />
  </UsdUVTexture>
</materialx>""")
    open(usd, "w").write(usd_text)
    assert "mg_conductor" not in pipeline.generate(usd)[0].fragment
    # MaterialX's vocabulary only (like MaterialX's Examples/UsdPreviewSurface): MaterialX's nodegraphs
    mx = _surface_doc(tmp_path, [("metallic", "float", "1")], name="mx.mtlx")
    assert "mg_conductor" in pipeline.generate(mx)[0].fragment
    plain = write_doc(tmp_path, '<output name="o" type="float" value="1" />', name="plain.mtlx")
    from mtlxgen.read.document import load
    from mtlxgen.nodes.usd import comes_from_usd, uses_usd_nodes
    assert comes_from_usd(load(usd)) and not comes_from_usd(load(mx)) and not comes_from_usd(load(plain))
    assert uses_usd_nodes(load(mx)) and not uses_usd_nodes(load(plain))
    assert comes_from_usd(load(os.path.join(ROOT, "examples", "usd", "usd_seed_rules.mtlx")))


def _cli(*args):
    return subprocess.run([sys.executable, os.path.join(ROOT, "cli.py")] + list(args), capture_output=True, text=True)


def test_cli_switches_the_rules(tmp_path):
    doc = _surface_doc(tmp_path, [("metallic", "float", "1")])
    out = str(tmp_path / "out")
    for flag, conductor in (("--usd-seed-rules", False), ("--no-usd-seed-rules", True), (None, True)):
        r = _cli(*[a for a in ("generate", doc, "-o", out, flag) if a])
        assert r.returncode == 0, r.stderr
        assert ("mg_conductor" in open(os.path.join(out, "mat.frag")).read()) == conductor, flag


def test_bad_source_colorspace_is_one_file_line_error(tmp_path):
    f = _png(tmp_path, "one.png", [153])
    doc = _texture_doc(tmp_path, f, tex_inputs='\n      <input name="sourceColorSpace" type="string" value="linear" />')
    r = _cli("generate", doc, "-o", str(tmp_path / "out"))
    assert r.returncode == 1 and "Traceback" not in r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "doc.mtlx:" in lines[0] and "sourceColorSpace 'linear'" in lines[0], r.stderr
