"""Files from strangers, read without hanging or exhausting memory: a FIFO anywhere in a USD stage's composition
(sublayer, reference, payload, a variant's payload, a sublayer named by a variable expression, a value clip, a clip
template, a referenced .mtlx document, the root layer itself) is one line naming it and status 1, never a process
blocked in open(); huge or sparse files are refused on their size before any reader opens them; images whose
decoding would take gigabytes within the documented pixel limit (64 channels, a 16384 x 8192 texture or
environment) decode at most 4 channels into bounded memory (peaks measured on the subprocess); a damaged image
or a text file named as a texture is one line naming the file (and, in a stage, the attribute), with nothing of
the decoder's own stderr; a mesh that cannot be drawn says what is wrong with it."""
import os
import struct
import subprocess
import sys
import tempfile
import time
import zlib

import numpy as np
import pytest

from conftest import ROOT
from util import write_doc

from mtlxgen.base import images
from mtlxgen.draw import ies, renderer as render
from mtlxgen.apps.cli import main
from mtlxgen.base.diagnostics import MtlxError

pxr = pytest.importorskip("pxr", reason="usd-core (a dependency of mtlxgen) is not installed")
from pxr import Sdf, Usd, UsdGeom, UsdShade  # noqa: E402

T = Sdf.ValueTypeNames
CLI = os.path.join(ROOT, "cli.py")
MATERIAL = ('def Material "M"\n{\n    token outputs:surface.connect = </M/S.outputs:surface>\n'
            '    def Shader "S"\n    {\n        uniform token info:id = "UsdPreviewSurface"\n'
            '        token outputs:surface\n    }\n}\n')


# ---------------------------------------------------------------- running the CLI, measured

def run_measured(args, timeout=120, address_space=None):
    """(exit status, stdout, stderr, peak resident MB) of `python cli.py ARGS` in a subprocess of its own (its
    own rusage, from wait4), under an address-space limit where given, so that a regression cannot take the
    machine's memory. A run past `timeout` is killed and fails the test (a hang)."""
    def limit():
        if address_space:
            import resource
            resource.setrlimit(resource.RLIMIT_AS, (address_space, address_space))
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        proc = subprocess.Popen([sys.executable, CLI] + [str(a) for a in args], stdout=out, stderr=err,
                                preexec_fn=limit, cwd=ROOT)
        deadline = time.monotonic() + timeout
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() > deadline:
                proc.kill()
                os.wait4(proc.pid, 0)
                pytest.fail("%s did not finish in %d s (blocked?)" % (" ".join(map(str, args)), timeout))
            time.sleep(0.05)
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        return (proc.returncode, out.read().decode(errors="replace"), err.read().decode(errors="replace"),
                usage.ru_maxrss // 1024)


def one_line(err):
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err and "internal error" not in err, err
    return lines[0]


# ---------------------------------------------------------------- FIFOs in a stage's composition

@pytest.mark.parametrize("kind,text", [
    ("sublayer", '(\n    subLayers = [@./fifo.usda@]\n)\n'),
    ("reference", 'def Xform "A" (\n    references = @./fifo.usda@\n)\n{\n}\n'),
    ("payload", 'def Xform "A" (\n    payload = @./fifo.usda@\n)\n{\n}\n'),
])
def test_fifo_in_composition_is_one_line(tmp_path, kind, text):
    """USD would open the FIFO itself while composing and block forever: every layer is checked before it is
    opened, and the FIFO is named at the layer (and prim) naming it."""
    os.mkfifo(tmp_path / "fifo.usda")
    stage = tmp_path / "stage.usda"
    stage.write_text("#usda 1.0\n" + text + MATERIAL)
    rc, _, err, _ = run_measured(["generate", stage, "-o", tmp_path / "o"], timeout=60)
    line = one_line(err)
    assert rc == 1 and line.startswith(str(stage) + (":0: " if kind == "sublayer" else ":/A: ")), line
    assert "%s './fifo.usda' (%s) is a FIFO" % (kind, tmp_path / "fifo.usda") in line, line


_LOAD_EACH = """
import sys
from mtlxgen.read import usdstage
from mtlxgen.base.diagnostics import MtlxError
for path in sys.argv[1:]:
    try:
        doc = usdstage.load(path)
        print("\\n".join(MtlxError(doc.usd.problems).lines()) or "loaded " + path)
    except MtlxError as e:
        print("\\n".join(e.lines()))
print("scene_files", usdstage.scene_files(sys.argv[1:]))
"""


def test_fifos_everywhere_usd_opens_files(tmp_path):
    """A variant's payload, a sublayer named by a variable expression (evaluated as composition does, here with
    the referenced layer's own variables), a value clip, a clip template's files, a referenced .mtlx document and
    the root layer itself: each a line naming the FIFO. scene_files (batch's sweep) keeps such files unopened."""
    os.mkfifo(tmp_path / "fifo.usda")
    os.mkfifo(tmp_path / "fifo.mtlx")
    os.mkfifo(tmp_path / "root_fifo.usda")
    (tmp_path / "clips").mkdir()
    (tmp_path / "clips" / "c.001.usda").write_text("#usda 1.0\n")
    os.mkfifo(tmp_path / "clips" / "c.002.usda")
    (tmp_path / "vars.usda").write_text('#usda 1.0\n(\n    defaultPrim = "R"\n    expressionVariables = {\n'
                                        '        string X = "fifo"\n    }\n'
                                        '    subLayers = [@`"./${X}.usda"`@]\n)\ndef Xform "R"\n{\n}\n')
    stages = {
        "variant": 'def Xform "V" (\n    variantSets = "v"\n    variants = {\n        string v = "a"\n    }\n)\n{\n'
                   '    variantSet "v" = {\n        "a" {\n        }\n        "b" (\n'
                   '            payload = @./fifo.usda@\n        ) {\n        }\n    }\n}\n',
        "expression": 'def Xform "E" (\n    references = @./vars.usda@\n)\n{\n}\n',
        "clip": 'def Xform "C" (\n    clips = {\n        dictionary default = {\n'
                '            asset[] assetPaths = [@./fifo.usda@]\n            string primPath = "/C"\n        }\n'
                '    }\n)\n{\n}\n',
        "template": 'def Xform "C" (\n    clips = {\n        dictionary default = {\n'
                    '            string templateAssetPath = "./clips/c.###.usda"\n'
                    '            double templateStartTime = 1\n            double templateEndTime = 2\n'
                    '            double templateStride = 1\n            string primPath = "/C"\n        }\n'
                    '    }\n)\n{\n}\n',
        "mtlx": 'def Xform "X" (\n    references = @./fifo.mtlx@\n)\n{\n}\n',
    }
    paths = []
    for name, text in stages.items():
        (tmp_path / (name + ".usda")).write_text("#usda 1.0\n" + text + MATERIAL)
        paths.append(str(tmp_path / (name + ".usda")))
    paths.append(str(tmp_path / "root_fifo.usda"))
    proc = subprocess.run([sys.executable, "-c", _LOAD_EACH] + paths, capture_output=True, text=True, timeout=60,
                          cwd=ROOT)
    lines = proc.stdout.splitlines()
    d = str(tmp_path)
    assert lines[:5] == [
        "%s/variant.usda:/V{v=b}: payload './fifo.usda' (%s/fifo.usda) is a FIFO" % (d, d),
        "%s/vars.usda:0: sublayer '`\"./${X}.usda\"`' (%s/fifo.usda) is a FIFO" % (d, d),
        "%s/clip.usda:/C: value clip './fifo.usda' of clip set 'default' is a FIFO" % d,
        "%s/template.usda:/C: value clip '%s/clips/c.002.usda' of clip set 'default' is a FIFO" % (d, d),
        "%s/mtlx.usda:/X: references MaterialX document './fifo.mtlx', which is a FIFO" % d], proc.stdout
    assert lines[5] == "%s/root_fifo.usda:0: USD stage is a FIFO" % d, proc.stdout
    assert lines[6].startswith("scene_files [") and "root_fifo.usda" in lines[6], proc.stdout
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr


def test_clip_template_of_a_billion_clips_is_refused(tmp_path):
    """USD would generate every clip path of a template before drawing anything."""
    stage = tmp_path / "t.usda"
    stage.write_text('#usda 1.0\ndef Xform "C" (\n    clips = {\n        dictionary default = {\n'
                     '            string templateAssetPath = "./c.###.usda"\n            double templateStartTime = 1\n'
                     '            double templateEndTime = 1000000000\n            double templateStride = 1\n'
                     '            string primPath = "/C"\n        }\n    }\n)\n{\n}\n' + MATERIAL)
    from mtlxgen.read import usdstage
    with pytest.raises(MtlxError) as e:
        usdstage.load(str(stage))
    assert e.value.lines() == ["%s:/C: clip set 'default': its template names 1000000000 value clips, more than %d"
                               % (stage, usdstage.MAX_TEMPLATE_CLIPS)]


def test_stage_layers_are_the_ones_composition_uses(tmp_path):
    """The layers opened before composing are exactly those the stage then uses (nothing opened twice, nothing
    missed): sublayers, references and expression-named sublayers, with the referencing stack's variables
    overriding the referenced layer's own."""
    from mtlxgen.read import usdstage
    for name in "abc":
        (tmp_path / ("%s.usda" % name)).write_text('#usda 1.0\ndef Xform "From%s"\n{\n}\n' % name.upper())
    (tmp_path / "ref.usda").write_text('#usda 1.0\n(\n    defaultPrim = "R"\n    expressionVariables = {\n'
                                       '        string X = "b"\n    }\n    subLayers = [@`"./${X}.usda"`@]\n)\n'
                                       'def Xform "R"\n{\n}\n')
    for name, variables, expected in (("plain", "", "b"), ("override", '    expressionVariables = {\n'
                                                           '        string X = "a"\n    }\n', "a")):
        path = tmp_path / (name + ".usda")
        path.write_text('#usda 1.0\n(\n%s    subLayers = [@./c.usda@]\n)\ndef Xform "Top" (\n'
                        '    references = @./ref.usda@\n)\n{\n}\n' % variables)
        stage, layers = usdstage._open(str(path))
        opened = sorted(os.path.basename(layer.identifier) for layer in layers)
        used = sorted(os.path.basename(layer.identifier) for layer in stage.GetUsedLayers() if not layer.anonymous)
        assert opened == used == sorted([name + ".usda", "c.usda", "ref.usda", expected + ".usda"])


# ---------------------------------------------------------------- sizes checked before reading

def _sparse(path, size=2 ** 30 + 1):
    with open(path, "wb") as f:
        f.truncate(size)          # costs no disk; every format reader would read it to its end
    return str(path)


def test_sparse_files_are_refused_on_their_size(tmp_path, capsys):
    big_png = _sparse(tmp_path / "big.png")
    big_exr = _sparse(tmp_path / "big.exr")
    start = time.monotonic()
    doc = write_doc(tmp_path, '<image name="img" type="color3"><input name="file" type="filename" value="big.png" />'
                              '</image><output name="out" type="color3" nodename="img" />')
    assert main(["render", doc, "-o", str(tmp_path / "o"), "--size", "16"]) == 1
    line = one_line(capsys.readouterr().err)
    assert "big.png" in line and "is larger than 512 MB (1,073,741,825 bytes)" in line, line
    assert main(["render", doc, "-o", str(tmp_path / "o"), "--size", "16", "--env", big_exr]) == 1
    assert capsys.readouterr().err.splitlines() == ["%s:0: environment file is larger than 512 MB (1,073,741,825 bytes)" % big_exr]
    with pytest.raises(MtlxError) as e:
        ies.parse(_sparse(tmp_path / "big.ies"))
    assert e.value.lines() == ["%s/big.ies:0: IES file is larger than 32 MB (1,073,741,825 bytes)" % tmp_path]
    assert images.image_header(big_png) is None and images.image_problem(big_png).startswith("larger than 512 MB")
    # a USD layer (cap 1 GB) and a stage's texture
    _sparse(tmp_path / "big.usda", 2 ** 30 + 2 ** 20)
    stage = tmp_path / "s.usda"
    stage.write_text('#usda 1.0\n(\n    subLayers = [@./big.usda@]\n)\n' + MATERIAL)
    assert main(["generate", str(stage), "-o", str(tmp_path / "g")]) == 1
    assert capsys.readouterr().err.splitlines() == [
        "%s:0: sublayer './big.usda' (%s/big.usda) is larger than 1024 MB (1025 MB)" % (stage, tmp_path)]
    from mtlxgen.read import usdstage
    doc = usdstage.load(_texture_stage(tmp_path, "big.png"))
    (m,) = doc.usd.materials.values()
    assert [msg for _, msg in m.notes] == ["texture 'big.png' is larger than 512 MB (1,073,741,825 bytes); drawing the fallback "
                                           "(0, 0, 0, 1)"]
    assert time.monotonic() - start < 30


def _texture_stage(folder, file_value):
    """A stage whose material reads `file_value` through a UsdUVTexture into its diffuse colour."""
    path = os.path.join(str(folder), "tex_%d.usda" % len(os.listdir(str(folder))))
    stage = Usd.Stage.CreateNew(path)
    mat = UsdShade.Material.Define(stage, "/M")
    surf = UsdShade.Shader.Define(stage, "/M/S")
    surf.CreateIdAttr("UsdPreviewSurface")
    tex = UsdShade.Shader.Define(stage, "/M/Tex")
    tex.CreateIdAttr("UsdUVTexture")
    tex.CreateInput("file", T.Asset).Set(file_value)
    surf.CreateInput("diffuseColor", T.Color3f).ConnectToSource(tex.ConnectableAPI(), "rgb")
    mat.CreateSurfaceOutput().ConnectToSource(surf.ConnectableAPI(), "surface")
    stage.GetRootLayer().Save()
    return path


# ---------------------------------------------------------------- damaged images and text files as textures

def _png_bytes(width, height, rgb):
    """A PNG of one colour, written directly (no OpenImageIO: fast for any size, a few hundred KB for 16k)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)
    comp = zlib.compressobj(1)
    parts = [comp.compress(b"\0" + bytes(rgb) * width)]
    rest = b"\2" + bytes(3 * width)             # filter "up": each row as the one above it
    for start in range(1, height, 64):
        parts.append(comp.compress(rest * min(64, height - start)))
    parts.append(comp.flush())
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", b"".join(parts)) + chunk(b"IEND", b""))


def test_truncated_png_is_one_line_without_libpng_output(tmp_path, capfd):
    """libpng writes its own complaints on stderr: they are caught, and the texture is an error in render (its
    header reads, its pixels do not)."""
    data = _png_bytes(64, 64, (10, 200, 30))
    (tmp_path / "cut.png").write_bytes(data[:len(data) * 2 // 3])
    doc = write_doc(tmp_path, '<image name="img" type="color3"><input name="file" type="filename" value="cut.png" />'
                              '</image><output name="out" type="color3" nodename="img" />')
    assert main(["render", doc, "-o", str(tmp_path / "o"), "--size", "16"]) == 1
    err = capfd.readouterr().err
    assert "libpng" not in err
    line = one_line(err)        # at the input naming the file where the pipeline knows it, else at the file
    assert "%s/cut.png" % tmp_path in line and "does not decode as an image (" in line, line
    # as an environment: one line, no escaped line breaks of OpenImageIO's several-line message
    assert main(["render", doc, "-o", str(tmp_path / "o"), "--size", "16", "--env", str(tmp_path / "cut.png")]) == 1
    line = one_line(capfd.readouterr().err)
    assert line.startswith("%s/cut.png:0: environment file does not decode as an image (" % tmp_path)
    assert "\\n" not in line and "libpng" not in line


def test_text_file_as_a_stage_texture_names_the_attribute(tmp_path):
    """A text file named as a texture: the stage's attribute and "is not an image", once, and no OpenImageIO
    message left pending at exit."""
    notes = tmp_path / "notes.png"
    notes.write_text("root:x:0:0:root:/root:/bin/bash\n")
    stage = _texture_stage(tmp_path, str(notes))
    rc, _, err, _ = run_measured(["render", stage, "-o", tmp_path / "o", "--size", "16"], timeout=90)
    line = one_line(err)
    assert rc == 1 and line.startswith("%s:/M/Tex.inputs:file: texture '%s' is not an image (" % (stage, notes)), line
    assert "drawing the fallback" in line and "pending" not in err


# ---------------------------------------------------------------- memory within the pixel limit

def _exr_64_channels(path, size=2048):
    import OpenImageIO as oiio
    spec = oiio.ImageSpec(size, size, 64, oiio.HALF)
    spec.attribute("compression", "zip")
    out = oiio.ImageOutput.create(path)
    assert out.open(path, spec)
    band = np.full((64, size, 64), 0.25, dtype=np.float16)
    for y in range(0, size, 64):
        assert out.write_scanlines(y, y + 64, 0, band)
    out.close()
    return path


def test_64_channel_texture_decodes_four_channels(tmp_path):
    """A 550 KB EXR of 2048 x 2048 pixels in 64 channels: all 64 decoded as floats took 2.7 GB; 4 are read."""
    _exr_64_channels(str(tmp_path / "c64.exr"))
    doc = write_doc(tmp_path, '<image name="img" type="color3"><input name="file" type="filename" value="c64.exr" />'
                              '</image><output name="out" type="color3" nodename="img" />')
    rc, _, err, peak = run_measured(["render", doc, "-o", tmp_path / "o", "--size", "32"], address_space=4 * 10 ** 9)
    assert rc == 0 and err == "", err
    assert peak < 1000, "peak %d MB" % peak
    assert np.allclose(images.read_image(str(tmp_path / "o" / "out.exr"))[16, 16, :3], 0.25, atol=1e-3)


def test_16k_texture_and_environment_render_in_bounded_memory(tmp_path):
    """A 400 KB PNG of 16384 x 8192 pixels, the documented limit: as a texture it took 3.6 to 4.9 GB; as the
    environment float64 arrays of ~10 GB and exit 3 (MemoryError). Both draw now, box-filtered to 8192 x 4096 as
    they are read (the decoding budget), in under 2.5 GB."""
    (tmp_path / "big.png").write_bytes(_png_bytes(16384, 8192, (128, 64, 32)))
    doc = write_doc(tmp_path, '<image name="img" type="color3"><input name="file" type="filename" value="big.png" />'
                              '</image><output name="out" type="color3" nodename="img" />')
    rc, _, err, peak = run_measured(["render", doc, "-o", tmp_path / "t", "--size", "32"], address_space=6 * 10 ** 9)
    assert rc == 0 and err == "", err
    assert peak < 2000, "texture: peak %d MB" % peak
    assert np.allclose(images.read_image(str(tmp_path / "t" / "out.exr"))[16, 16, :3],
                       np.array([128, 64, 32]) / 255.0, atol=2e-3)
    lit = write_doc(tmp_path, '<standard_surface name="s" type="surfaceshader"><input name="specular" type="float" '
                              'value="0" /></standard_surface><surfacematerial name="m" type="material"><input '
                              'name="surfaceshader" type="surfaceshader" nodename="s" /></surfacematerial>', "lit.mtlx")
    rc, _, err, peak = run_measured(["render", lit, "-o", tmp_path / "e", "--size", "32",
                                     "--env", tmp_path / "big.png"], address_space=6 * 10 ** 9)
    assert rc == 0 and err == "", err
    assert peak < 2500, "environment: peak %d MB" % peak
    centre = images.read_image(str(tmp_path / "e" / "m.exr"))[16, 16, :3]
    assert np.all(np.isfinite(centre)) and centre[0] > centre[1] > centre[2] > 0     # lit by the warm map


def test_decoding_budget_reduces_or_refuses_on_the_header(tmp_path):
    """The budget is checked on the header: a plain read is refused, a renderer's read box-filters by the smallest
    power of two that fits, whole pixels averaged over the image's edges."""
    rng = np.random.default_rng(7)
    px = rng.random((37, 53, 3)).astype(np.float32)
    path = str(tmp_path / "r.exr")
    images.write_image(path, px)
    full = images.read_image(path)
    with pytest.raises(MtlxError) as e:
        images.read_image(path, budget=full.nbytes - 1)
    assert "more than the 0 MB a read may take" in e.value.lines()[0]
    half = images.read_image(path, budget=full.nbytes // 3, reduce=True)
    assert half.shape == (19, 27, 3)
    assert np.allclose(half[3, 5], full[6:8, 10:12].mean((0, 1)), atol=1e-6)
    assert np.allclose(half[18, 26], full[36, 52], atol=1e-6)              # the corner: one pixel of its own
    quarter = images.read_image(path, budget=half.nbytes // 2, reduce=True)
    assert quarter.shape == (10, 14, 3) and np.allclose(quarter[9, 13], full[36:, 52:].mean((0, 1)), atol=1e-6)


def test_irradiance_projection_is_bounded_and_matches_the_definition():
    """The separable projection equals the per-texel sum of radiance x basis x solid angle."""
    env = np.random.default_rng(3).random((37, 70, 3)).astype(np.float32) * 4
    d, sa = render._latlong_directions(70, 37)
    direct = np.einsum("hwk,hwc,hw->kc", render._sh9(d), env.astype(np.float64), sa)
    assert np.allclose(render.sh9_projection(env), direct, rtol=0, atol=1e-12)


# ---------------------------------------------------------------- meshes that cannot be drawn

def test_meshes_that_cannot_be_drawn_say_why(tmp_path):
    from mtlxgen.apps import stagerender
    path = str(tmp_path / "meshes.usda")
    stage = Usd.Stage.CreateNew(path)
    UsdShade.Material.Define(stage, "/M")
    bad = UsdGeom.Mesh.Define(stage, "/World/Bad")
    bad.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (0, 1, 0)])
    bad.CreateFaceVertexCountsAttr([3])
    bad.CreateFaceVertexIndicesAttr([0, 1, 7])
    empty = UsdGeom.Mesh.Define(stage, "/World/Empty")
    empty.CreateFaceVertexCountsAttr([3])
    empty.CreateFaceVertexIndicesAttr([0, 1, 2])
    stage.GetRootLayer().Save()
    with pytest.raises(MtlxError) as e:
        stagerender.read_view(path)
    assert e.value.lines() == [
        "%s:/World/Bad: mesh not drawn: faceVertexIndices out of range: 7 is not one of its 3 points" % path,
        "%s:/World/Empty: mesh not drawn: it has no points" % path]


def test_renderer_keeps_a_texture_error_until_the_file_is_forgotten(tmp_path):
    """A texture that does not decode is an error at every bind (not a default drawn in silence after the first);
    forgetting the file (the viewer's reload) reads it again; closing a renderer on a borrowed context releases
    its textures, not the errors kept beside them."""
    bad = tmp_path / "bad.png"
    bad.write_text("not an image")
    ctx = render.create_context()
    try:
        r = render.Renderer(size=8, ctx=ctx)
        for _ in range(2):
            with pytest.raises(MtlxError) as e:
                r.image_texture(str(bad))
            assert e.value.lines()[0].startswith("%s:0: file is not an image (" % bad)
        assert r.image_texture(str(tmp_path / "absent.png")) is None         # missing: the sampler's default
        images.write_image(str(bad), np.full((2, 2, 3), 0.5, dtype=np.float32))
        with pytest.raises(MtlxError):
            r.image_texture(str(bad))           # mended on disk: still the error, until the file is forgotten
        r.forget_texture(str(bad))
        assert r.image_texture(str(bad)).size == (2, 2)
        r.close()
    finally:
        ctx.release()
