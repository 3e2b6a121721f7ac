"""USD stages as input (mtlxgen/read/usdstage.py, issue 15): stages built here with Pixar's pxr, each feature drawn
and compared with the same material written as a USD-vocabulary .mtlx document (identical pixels), plus
problems (FILE:PRIM_PATH.ATTRIBUTE), info, and a sweep over ../shared/corpus/usd (marked corpus)."""
import glob
import json
import os

import numpy as np
import pytest

from conftest import SHARED
from util import write_doc

from mtlxgen.base import images
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.read.usdstage import element_name

pxr = pytest.importorskip("pxr", reason="usd-core (a dependency of mtlxgen) is not installed")
from pxr import Gf, Sdf, Usd, UsdShade, UsdUtils  # noqa: E402

T = Sdf.ValueTypeNames
USD_CORPUS = os.path.join(SHARED, "corpus", "usd")


# ---------------------------------------------------------------- building stages

def _png(folder, name, pixels, size=16):
    """An 8-bit PNG: `pixels` is a function (u, v) -> channel values in 0..255 over a size x size grid."""
    v, u = np.meshgrid((np.arange(size) + 0.5) / size, (np.arange(size) + 0.5) / size, indexing="ij")
    px = np.stack(pixels(u, v), -1).astype(np.uint8)
    path = os.path.join(str(folder), name)
    images.write_image(path, px)
    return path


def _textures(folder):
    _png(folder, "albedo.png", lambda u, v: (u * 255, v * 255, 128 + 0 * u))
    _png(folder, "mask.png", lambda u, v: ((u > 0.5) * 200 + 30,))
    _png(folder, "nrm.png", lambda u, v: (128 + 60 * np.sin(9 * u), 128 + 60 * np.cos(7 * v), 255 + 0 * u))
    _png(folder, "leaf.png", lambda u, v: (180 + 0 * u, ((u - 0.5) ** 2 + (v - 0.5) ** 2 < 0.2) * 255))


def _shader(stage, path, sid, **inputs):
    s = UsdShade.Shader.Define(stage, path)
    s.CreateIdAttr(sid)
    for name, (t, value) in inputs.items():
        s.CreateInput(name, t).Set(value)
    return s


def _connect(shader, name, t, source, output, out_type=T.Float3):
    inp = shader.CreateInput(name, t)
    inp.ConnectToSource(source.ConnectableAPI() if hasattr(source, "ConnectableAPI") else source, output,
                        UsdShade.AttributeType.Output, out_type)
    return inp


def _surface(material, shader, context=None):
    out = material.CreateSurfaceOutput(context) if context else material.CreateSurfaceOutput()
    out.ConnectToSource(shader.ConnectableAPI(), "surface" if context is None else "out")


def _tiles(stage, root="/Root/Looks/Tiles"):
    """UsdPrimvarReader (varname st0) -> UsdTransform2d -> four UsdUVTextures: sRGB-by-auto albedo with wrap
    repeat/mirror, scale and bias; one channel `r` for roughness; a normal map (rgb into the float3 normal:
    scale 2, bias -1); a 2-channel leaf's `a` as opacity with opacityThreshold; specular workflow."""
    mat = UsdShade.Material.Define(stage, root)
    reader = _shader(stage, root + "/Reader", "UsdPrimvarReader_float2", varname=(T.Token, "st0"))
    xf = _shader(stage, root + "/Xf", "UsdTransform2d", scale=(T.Float2, Gf.Vec2f(2, 1.5)),
                 rotation=(T.Float, 30.0), translation=(T.Float2, Gf.Vec2f(0.125, 0)))
    _connect(xf, "in", T.Float2, reader, "result", T.Float2)
    albedo = _shader(stage, root + "/Albedo", "UsdUVTexture", file=(T.Asset, "albedo.png"),
                     wrapS=(T.Token, "repeat"), wrapT=(T.Token, "mirror"), sourceColorSpace=(T.Token, "auto"),
                     scale=(T.Float4, Gf.Vec4f(0.875, 0.75, 0.625, 1)), bias=(T.Float4, Gf.Vec4f(0.0625, 0, 0, 0)))
    mask = _shader(stage, root + "/Mask", "UsdUVTexture", file=(T.Asset, "mask.png"), wrapS=(T.Token, "repeat"),
                   wrapT=(T.Token, "black"), sourceColorSpace=(T.Token, "raw"))
    nrm = _shader(stage, root + "/Nrm", "UsdUVTexture", file=(T.Asset, "nrm.png"), sourceColorSpace=(T.Token, "raw"),
                  wrapS=(T.Token, "repeat"), wrapT=(T.Token, "repeat"),
                  scale=(T.Float4, Gf.Vec4f(2, 2, 2, 1)), bias=(T.Float4, Gf.Vec4f(-1, -1, -1, 0)))
    leaf = _shader(stage, root + "/Leaf", "UsdUVTexture", file=(T.Asset, "leaf.png"), wrapS=(T.Token, "clamp"),
                   wrapT=(T.Token, "clamp"))
    for tex in (albedo, mask, nrm, leaf):
        _connect(tex, "st", T.Float2, xf, "result", T.Float2)
    surf = _shader(stage, root + "/Surface", "UsdPreviewSurface", opacityThreshold=(T.Float, 0.5),
                   useSpecularWorkflow=(T.Int, 1), specularColor=(T.Color3f, Gf.Vec3f(0.25, 0.5, 0.125)))
    _connect(surf, "diffuseColor", T.Color3f, albedo, "rgb")
    _connect(surf, "roughness", T.Float, mask, "r", T.Float)
    _connect(surf, "normal", T.Normal3f, nrm, "rgb")
    _connect(surf, "opacity", T.Float, leaf, "a", T.Float)
    surf.CreateInput("specular", T.Float).Set(0.5)          # not a UsdPreviewSurface input: ignored
    _surface(mat, surf)
    return mat


TILES_MTLX = """
  <UsdPrimvarReader name="reader" type="vector2"><input name="varname" type="string" value="st0" /></UsdPrimvarReader>
  <UsdTransform2d name="xf" type="vector2">
    <input name="in" type="vector2" nodename="reader" output="result" />
    <input name="scale" type="vector2" value="2, 1.5" />
    <input name="rotation" type="float" value="30" />
    <input name="translation" type="vector2" value="0.125, 0" />
  </UsdTransform2d>
  <UsdUVTexture name="albedo" type="multioutput">
    <input name="file" type="filename" value="albedo.png" />
    <input name="st" type="vector2" nodename="xf" output="result" />
    <input name="wrapS" type="string" value="repeat" /><input name="wrapT" type="string" value="mirror" />
    <input name="sourceColorSpace" type="string" value="auto" />
    <input name="scale" type="color4" value="0.875, 0.75, 0.625, 1" />
    <input name="bias" type="color4" value="0.0625, 0, 0, 0" />
  </UsdUVTexture>
  <UsdUVTexture name="mask" type="multioutput">
    <input name="file" type="filename" value="mask.png" />
    <input name="st" type="vector2" nodename="xf" output="result" />
    <input name="wrapS" type="string" value="repeat" /><input name="wrapT" type="string" value="black" />
    <input name="sourceColorSpace" type="string" value="raw" />
  </UsdUVTexture>
  <UsdUVTexture name="nrm" type="multioutput">
    <input name="file" type="filename" value="nrm.png" />
    <input name="st" type="vector2" nodename="xf" output="result" />
    <input name="wrapS" type="string" value="repeat" /><input name="wrapT" type="string" value="repeat" />
    <input name="sourceColorSpace" type="string" value="raw" />
    <input name="scale" type="color4" value="2, 2, 2, 1" /><input name="bias" type="color4" value="-1, -1, -1, 0" />
  </UsdUVTexture>
  <UsdUVTexture name="leaf" type="multioutput">
    <input name="file" type="filename" value="leaf.png" />
    <input name="st" type="vector2" nodename="xf" output="result" />
    <input name="wrapS" type="string" value="clamp" /><input name="wrapT" type="string" value="clamp" />
  </UsdUVTexture>
  <convert name="nrm_vector" type="vector3"><input name="in" type="color3" nodename="nrm" output="rgb" /></convert>
  <UsdPreviewSurface name="surface" type="surfaceshader">
    <input name="diffuseColor" type="color3" nodename="albedo" output="rgb" />
    <input name="roughness" type="float" nodename="mask" output="r" />
    <input name="normal" type="vector3" nodename="nrm_vector" />
    <input name="opacity" type="float" nodename="leaf" output="a" />
    <input name="opacityThreshold" type="float" value="0.5" />
    <input name="useSpecularWorkflow" type="integer" value="1" />
    <input name="specularColor" type="color3" value="0.25, 0.5, 0.125" />
  </UsdPreviewSurface>
  <surfacematerial name="Tiles" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="surface" />
  </surfacematerial>"""


def _gold(stage, root="/Root/Looks/Gold"):
    """Interface inputs: the Material's `tint` and `rough`; a NodeGraph whose input `amount` reads the material's
    `rough`, doubled by a MaterialX node (ND_multiply_float) inside the graph, out to the roughness."""
    mat = UsdShade.Material.Define(stage, root)
    tint = mat.CreateInput("tint", T.Color3f)
    tint.Set(Gf.Vec3f(1, 0.75, 0.25))
    rough = mat.CreateInput("rough", T.Float)
    rough.Set(0.25)
    graph = UsdShade.NodeGraph.Define(stage, root + "/Graph")
    amount = graph.CreateInput("amount", T.Float)
    amount.ConnectToSource(rough)
    twice = _shader(stage, root + "/Graph/Twice", "ND_multiply_float", in2=(T.Float, 2.0))
    twice.CreateInput("in1", T.Float).ConnectToSource(amount)
    graph.CreateOutput("out", T.Float).ConnectToSource(twice.ConnectableAPI(), "out")
    surf = _shader(stage, root + "/Surface", "UsdPreviewSurface", metallic=(T.Float, 1.0))
    surf.CreateInput("diffuseColor", T.Color3f).ConnectToSource(tint)
    surf.CreateInput("roughness", T.Float).ConnectToSource(graph.ConnectableAPI(), "out")
    _surface(mat, surf)
    return mat


GOLD_MTLX = """
  <input name="tint" type="color3" value="1, 0.75, 0.25" />
  <input name="rough" type="float" value="0.25" />
  <nodegraph name="Graph">
    <input name="amount" type="float" interfacename="rough" />
    <multiply name="Twice" type="float">
      <input name="in1" type="float" interfacename="amount" /><input name="in2" type="float" value="2" />
    </multiply>
    <output name="out" type="float" nodename="Twice" />
  </nodegraph>
  <UsdPreviewSurface name="surface" type="surfaceshader">
    <input name="diffuseColor" type="color3" interfacename="tint" />
    <input name="metallic" type="float" value="1" />
    <input name="roughness" type="float" nodegraph="Graph" output="out" />
  </UsdPreviewSurface>
  <surfacematerial name="Gold" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="surface" />
  </surfacematerial>"""

UNLIT_MTLX = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <texcoord name="uv" type="vector2" />
  <image name="picture" type="color3">
    <input name="file" type="filename" value="albedo.png" colorspace="srgb_texture" />
    <input name="texcoord" type="vector2" nodename="uv" />
  </image>
  <surface_unlit name="unlit" type="surfaceshader">
    <input name="emission_color" type="color3" nodename="picture" />
    <input name="emission" type="float" value="0.75" />
  </surface_unlit>
  <surfacematerial name="Unlit" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="unlit" />
  </surfacematerial>
</materialx>
"""


def _both(stage, root="/Root/Looks/Both"):
    """A MaterialX network (ND_* ids: an image whose file has colorSpace srgb_texture, into an unlit surface) on
    outputs:mtlx:surface beside a red UsdPreviewSurface on outputs:surface."""
    mat = UsdShade.Material.Define(stage, root)
    uv = _shader(stage, root + "/Uv", "ND_texcoord_vector2")
    pic = _shader(stage, root + "/Picture", "ND_image_color3", file=(T.Asset, "albedo.png"))
    pic.GetInput("file").GetAttr().SetColorSpace("srgb_texture")
    _connect(pic, "texcoord", T.Float2, uv, "out", T.Float2)
    unlit = _shader(stage, root + "/Unlit", "ND_surface_unlit", emission=(T.Float, 0.75))
    _connect(unlit, "emission_color", T.Color3f, pic, "out", T.Color3f)
    _surface(mat, unlit, "mtlx")
    red = _shader(stage, root + "/Preview", "UsdPreviewSurface", diffuseColor=(T.Color3f, Gf.Vec3f(0.8, 0.05, 0.05)))
    _surface(mat, red)
    return mat


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """One folder: textures, looks.usda (Tiles, Gold, Both, and /Root/Mx referencing unlit.mtlx), the .mtlx forms."""
    folder = tmp_path_factory.mktemp("usd_scene")
    _textures(folder)
    stage = Usd.Stage.CreateNew(str(folder / "looks.usda"))
    _tiles(stage)
    _gold(stage)
    _both(stage)
    mx = stage.DefinePrim("/Root/Mx", "Scope")
    mx.GetReferences().AddReference("./unlit.mtlx", "/MaterialX/Materials")
    stage.GetRootLayer().Save()
    (folder / "unlit.mtlx").write_text(UNLIT_MTLX)
    write_doc(folder, TILES_MTLX, name="tiles.mtlx")
    write_doc(folder, GOLD_MTLX, name="gold.mtlx")
    return folder


def _render(renderer, path, element, **kw):
    shaders = pipeline.generate(str(path), elements=[element], usd_seed_rules=True, **kw)
    return renderer.render(shaders[0]), shaders[0]


def _same(a, b, what):
    assert a.shape == b.shape
    assert np.isfinite(a).all() and a[..., 3].max() > 0, what + ": nothing drawn"
    diff = np.abs(a - b).max()
    assert diff == 0.0, "%s: renders differ by up to %g" % (what, diff)


# ---------------------------------------------------------------- the tests

def test_element_names_are_prim_paths():
    assert element_name("/Root/Looks/Wood") == "Root_Looks_Wood"
    assert element_name("/A") == "A"
    assert str(Loc("f.usda", where="/A/B.inputs:file")) == "f.usda:/A/B.inputs:file"
    assert str(Loc("f.mtlx", 12)) == "f.mtlx:12"        # every existing FILE:LINE unchanged


def test_stage_lists_every_material_by_prim_path(scene):
    doc = pipeline.load_document(str(scene / "looks.usda"))
    assert list(doc.usd.materials) == ["Root_Looks_Tiles", "Root_Looks_Gold", "Root_Looks_Both", "Root_Mx_Unlit"]
    assert doc.usd.by_prim["/Root/Looks/Gold"] == "Root_Looks_Gold"
    assert doc.usd.by_prim["/Root/Mx/Unlit"] == "Root_Mx_Unlit"      # where USD's MaterialX plugin puts it
    session = pipeline.Session(str(scene / "looks.usda"), elements=["/Root/Looks/Gold"])
    assert session.elements == ["Root_Looks_Gold"] and session.usd_seed_rules


def test_preview_surface_network_draws_as_its_mtlx_form(renderer, scene):
    """primvar reader (any varname: st0), UsdTransform2d, wrap modes, sRGB by auto, scale/bias, a single channel,
    a normal map into the float3 normal (through convert), opacityThreshold, useSpecularWorkflow."""
    ours, shader = _render(renderer, scene / "looks.usda", "/Root/Looks/Tiles")
    theirs, _ = _render(renderer, scene / "tiles.mtlx", "Tiles")
    _same(ours, theirs, "Tiles")
    alpha = ours[..., 3]
    assert (alpha == 0).any() and (alpha == 1).any(), "the cut-out leaves both holes and solid surface"
    assert shader.manifest["usd"] == {"prim": "/Root/Looks/Tiles", "render_context": "universal"}
    kinds = {os.path.basename(t["file"]): (t["usd_wrap"], t["colorspace"]) for t in shader.manifest["textures"]}
    assert kinds["albedo.png"] == (["repeat", "mirror"], "srgb_texture")
    assert kinds["mask.png"] == (["repeat", "black"], "raw")


def test_interface_inputs_of_material_and_nodegraph(renderer, scene):
    ours, shader = _render(renderer, scene / "looks.usda", "Root_Looks_Gold")
    theirs, _ = _render(renderer, scene / "gold.mtlx", "Gold")
    _same(ours, theirs, "Gold")
    values = {u["name"]: u["value"] for u in shader.manifest["uniforms"]}
    tint = [k for k in values if k.endswith("Root_Looks_Gold_tint")]
    assert tint and values[tint[0]] == [1.0, 0.75, 0.25], values        # the material's input: one public uniform


def test_render_context_chooses_the_surface(renderer, scene):
    mx, shader = _render(renderer, scene / "looks.usda", "Root_Looks_Both")
    assert shader.manifest["usd"]["render_context"] == "mtlx"
    ref, _ = _render(renderer, scene / "unlit.mtlx", "Unlit")
    _same(mx, ref, "mtlx context vs unlit.mtlx")
    universal, shader = _render(renderer, scene / "looks.usda", "Root_Looks_Both",
                                render_context="universal")
    assert shader.manifest["usd"]["render_context"] == "universal"
    centre = universal[60:68, 60:68, :3].reshape(-1, 3).mean(0)
    assert centre[0] > 3 * centre[1] and centre[0] > 3 * centre[2], centre       # the red preview surface
    # the referenced .mtlx, read by our own reader at the prim path the plugin gives it
    mtlx_ref, shader = _render(renderer, scene / "looks.usda", "/Root/Mx/Unlit")
    _same(mtlx_ref, ref, "referenced unlit.mtlx")
    assert shader.manifest["usd"]["mtlx_document"].endswith("unlit.mtlx")


def test_usdz_textures_are_read_from_inside_the_package(renderer, scene, tmp_path, monkeypatch):
    monkeypatch.setenv("MTLXGEN_CACHE", str(tmp_path / "cache"))
    src = tmp_path / "src"
    src.mkdir()
    _textures(src)
    stage = Usd.Stage.CreateNew(str(src / "tiles.usda"))
    _tiles(stage)
    stage.GetRootLayer().Save()
    package = str(tmp_path / "tiles.usdz")
    assert UsdUtils.CreateNewUsdzPackage(Sdf.AssetPath(str(src / "tiles.usda")), package)
    for png in glob.glob(str(src / "*.png")):
        os.remove(png)                                   # only the package holds them now
    ours, shader = _render(renderer, package, "Root_Looks_Tiles")
    files = [t["file"] for t in shader.manifest["textures"]]
    assert files and all(f.startswith(str(tmp_path / "cache")) and os.path.isfile(f) for f in files), files
    theirs, _ = _render(renderer, scene / "looks.usda", "Root_Looks_Tiles")
    _same(ours, theirs, "Tiles from the .usdz")


def test_udim_tiles(renderer, tmp_path):
    _png(tmp_path, "tile.1001.png", lambda u, v: (230 + 0 * u, 20 + 0 * u, 20 + 0 * u))
    _png(tmp_path, "tile.1002.png", lambda u, v: (20 + 0 * u, 20 + 0 * u, 230 + 0 * u))
    stage = Usd.Stage.CreateNew(str(tmp_path / "udim.usda"))
    mat = UsdShade.Material.Define(stage, "/M")
    reader = _shader(stage, "/M/Reader", "UsdPrimvarReader_float2", varname=(T.Token, "st"))
    # the camera sees u in [0.5, 1]: scaled by 2 and moved by -0.5, half of it falls on each tile
    xf = _shader(stage, "/M/Xf", "UsdTransform2d", scale=(T.Float2, Gf.Vec2f(2, 1)),
                 translation=(T.Float2, Gf.Vec2f(-0.5, 0)))
    _connect(xf, "in", T.Float2, reader, "result", T.Float2)
    tex = _shader(stage, "/M/Tex", "UsdUVTexture", file=(T.Asset, "tile.<UDIM>.png"), sourceColorSpace=(T.Token, "raw"))
    _connect(tex, "st", T.Float2, xf, "result", T.Float2)
    surf = _shader(stage, "/M/Surface", "UsdPreviewSurface")
    _connect(surf, "emissiveColor", T.Color3f, tex, "rgb")
    _surface(mat, surf)
    stage.GetRootLayer().Save()
    img, shader = _render(renderer, tmp_path / "udim.usda", "M")
    tiles = sorted(os.path.basename(t["file"]) for t in shader.manifest["textures"])
    assert tiles == ["tile.1001.png", "tile.1002.png"]
    rgb, drawn = img[..., :3], img[..., 3] > 0
    red = drawn & (rgb[..., 0] > 2 * rgb[..., 2])
    blue = drawn & (rgb[..., 2] > 2 * rgb[..., 0])
    assert red.sum() > 0.2 * drawn.sum() and blue.sum() > 0.2 * drawn.sum(), (red.sum(), blue.sum(), drawn.sum())


def test_missing_texture_names_layer_prim_attribute_and_fallback(renderer, tmp_path, capsys):
    stage = Usd.Stage.CreateNew(str(tmp_path / "missing.usda"))
    for name, textured in (("Broken", True), ("Plain", False)):
        mat = UsdShade.Material.Define(stage, "/Looks/" + name)
        surf = _shader(stage, "/Looks/%s/Surface" % name, "UsdPreviewSurface")
        if textured:
            tex = _shader(stage, "/Looks/Broken/Tex", "UsdUVTexture", file=(T.Asset, "gone/nothere.png"),
                          fallback=(T.Float4, Gf.Vec4f(0.25, 0.5, 0.75, 1)))
            _connect(surf, "diffuseColor", T.Color3f, tex, "rgb")
        else:
            surf.CreateInput("diffuseColor", T.Color3f).Set(Gf.Vec3f(0.25, 0.5, 0.75))
        _surface(mat, surf)
    stage.GetRootLayer().Save()
    path = str(tmp_path / "missing.usda")
    from mtlxgen.apps.cli import main
    rc = main(["generate", path, "-o", str(tmp_path / "out")])
    out, err = capsys.readouterr()
    # generate: the shader is valid (the fallback is its texture's stand-in): a warning, as for a .mtlx document
    assert rc == 0
    line = ("%s:/Looks/Broken/Tex.inputs:file: texture 'gone/nothere.png' not found (looked for %s); drawing the "
            "fallback (0.25, 0.5, 0.75, 1.0)" % (path, os.path.join(str(tmp_path), "gone", "nothere.png")))
    assert err.splitlines() == [line.replace(".inputs:file: ", ".inputs:file: warning: ", 1)]
    assert os.path.isfile(tmp_path / "out" / "Looks_Broken.frag")         # the element is still written
    assert main(["generate", path, "-o", str(tmp_path / "strict"), "--strict"]) == 1
    assert capsys.readouterr().err.splitlines() == [line + " (a warning; an error with --strict)"]
    assert main(["batch", path, "-o", str(tmp_path / "b"), "-j", "1", "--no-progress"]) == 1
    assert capsys.readouterr().err.splitlines() == [line]          # an error where it is drawn: said once
    assert sorted(os.listdir(tmp_path / "b")) == ["missing__Looks_Broken.png", "missing__Looks_Plain.png"]
    shaders, error = pipeline.generate(path, partial=True, unreadable_textures="error")
    assert len(shaders) == 2 and len(error.problems) == 1
    broken, plain = (renderer.render(s) for s in shaders)
    _same(broken, plain, "the fallback drawn in place of the missing file")


def _variant_stage(tmp_path):
    stage = Usd.Stage.CreateNew(str(tmp_path / "variants.usda"))
    mat = UsdShade.Material.Define(stage, "/Looks/Paint")
    surf = _shader(stage, "/Looks/Paint/Surface", "UsdPreviewSurface")
    surf.CreateInput("diffuseColor", T.Color3f)         # its values only in the variants (local ones would win)
    _surface(mat, surf)
    vset = mat.GetPrim().GetVariantSets().AddVariantSet("look")
    for name, colour in (("red", (0.75, 0, 0)), ("blue", (0, 0, 0.75))):
        vset.AddVariant(name)
        vset.SetVariantSelection(name)
        with vset.GetVariantEditContext():
            surf.GetInput("diffuseColor").Set(Gf.Vec3f(*colour))
    vset.SetVariantSelection("red")
    stage.GetRootLayer().Save()
    return str(tmp_path / "variants.usda")


def _diffuse(shader):
    return next(u["value"] for u in shader.manifest["uniforms"] if u["name"].endswith("diffuseColor"))


def test_variants_are_selected_before_reading(tmp_path):
    path = _variant_stage(tmp_path)
    assert _diffuse(pipeline.generate(path)[0]) == [0.75, 0.0, 0.0]
    blue = pipeline.generate(path, variants=(("look", "blue"),))[0]
    assert _diffuse(blue) == [0.0, 0.0, 0.75]
    with open(path) as f:
        assert 'string look = "red"' in f.read()            # selected in the session layer, the file untouched
    with pytest.raises(MtlxError) as e:
        pipeline.generate(path, variants=(("look", "green"),))
    assert e.value.lines() == ["%s:/Looks/Paint: variant set 'look' has no variant 'green' (variants: blue, red)" % path]
    with pytest.raises(MtlxError) as e:
        pipeline.generate(path, variants=(("finish", "matte"),))
    assert e.value.lines() == ["%s:0: no variant set 'finish' on the stage (variant sets: look)" % path]


def test_cli_options_and_batch(tmp_path, capsys):
    from mtlxgen.apps.cli import main
    path = _variant_stage(tmp_path)
    assert main(["generate", path, "-o", str(tmp_path / "g"), "--variant", "look=blue", "--element", "/Looks/Paint"]) == 0
    manifest = json.loads((tmp_path / "g" / "Looks_Paint.json").read_text())
    assert manifest["usd"]["prim"] == "/Looks/Paint"
    assert next(u["value"] for u in manifest["uniforms"] if u["name"].endswith("diffuseColor")) == [0.0, 0.0, 0.75]
    capsys.readouterr()
    assert main(["generate", path, "-o", str(tmp_path / "g"), "--element", "/Looks/Nope"]) == 1
    assert capsys.readouterr().err.splitlines() == ["%s:/Looks/Nope: no UsdShadeMaterial at this prim path" % path]
    doc = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples", "quick_start.mtlx")
    assert main(["info", doc, "--variant", "a=b"]) == 1
    assert "applies to USD stages" in capsys.readouterr().err
    assert main(["batch", path, "-o", str(tmp_path / "b"), "-j", "1", "--no-progress"]) == 0
    assert os.path.isfile(tmp_path / "b" / "variants__Looks_Paint.png")
    capsys.readouterr()
    assert main(["render", doc, "-o", str(tmp_path / "r"), "--size", "8", "--geometry", "stage"]) == 1
    assert capsys.readouterr().err.splitlines() == [
        "%s:0: --geometry stage draws a USD stage's meshes; this is a MaterialX document" % doc]


def test_problems_are_one_line_each_and_other_materials_still_drawn(tmp_path, capsys):
    stage = Usd.Stage.CreateNew(str(tmp_path / "bad.usda"))
    good = UsdShade.Material.Define(stage, "/L/Good")
    _surface(good, _shader(stage, "/L/Good/S", "UsdPreviewSurface"))
    unknown = UsdShade.Material.Define(stage, "/L/Unknown")
    _surface(unknown, _shader(stage, "/L/Unknown/S", "PxrSurface"))
    dangling = UsdShade.Material.Define(stage, "/L/Dangling")
    s = _shader(stage, "/L/Dangling/S", "UsdPreviewSurface")
    s.CreateInput("diffuseColor", T.Color3f).GetAttr().AddConnection(Sdf.Path("/L/Nope.outputs:rgb"))
    _surface(dangling, s)
    UsdShade.Material.Define(stage, "/L/Empty")
    stage.GetRootLayer().Save()
    path = str(tmp_path / "bad.usda")
    from mtlxgen.apps.cli import main
    assert main(["generate", path, "-o", str(tmp_path / "o")]) == 1
    err = capsys.readouterr().err
    assert "Traceback" not in err and "Warning" not in err
    assert sorted(err.splitlines()) == sorted([
        "%s:/L/Unknown/S: unknown shader info:id 'PxrSurface' (mtlxgen reads UsdPreviewSurface, UsdUVTexture, "
        "UsdPrimvarReader_<type>, UsdTransform2d and MaterialX nodedef names, ND_*)" % path,
        "%s:/L/Dangling/S.inputs:diffuseColor: connects to </L/Nope.outputs:rgb>, which is not an input or output "
        "of a shader, nodegraph or material on the stage" % path,
        "%s:/L/Empty: material has no connected surface output (outputs:mtlx:surface or outputs:surface)" % path])
    assert sorted(os.listdir(tmp_path / "o")) == ["L_Good.frag", "L_Good.json", "L_Good.vert"]
    broken = tmp_path / "broken.usda"
    broken.write_text('#usda 1.0\ndef Xform "A" {\n  float x = \n}\n')
    assert main(["info", str(broken)]) == 1
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("%s:0: cannot open the USD stage: " % broken), lines
    assert "Expected" in lines[0]


def test_info_lists_materials_shader_ids_and_what_is_unresolved(scene, tmp_path, capsys):
    from mtlxgen.apps.cli import main
    assert main(["info", str(scene / "looks.usda")]) == 0
    out = capsys.readouterr().out
    assert "Root_Looks_Tiles  </Root/Looks/Tiles>  universal surface" in out
    assert "Root_Looks_Both  </Root/Looks/Both>  mtlx surface (also: universal)" in out
    for prim, sid in (("/Root/Looks/Tiles/Reader", "UsdPrimvarReader_float2"), ("/Root/Looks/Tiles/Xf", "UsdTransform2d"),
                      ("/Root/Looks/Both/Picture", "ND_image_color3"), ("/Root/Looks/Gold/Graph/Twice", "ND_multiply_float")):
        assert any(line.split() == [prim, sid] for line in out.splitlines()), (prim, out)
    assert "Root_Mx_Unlit  </Root/Mx/Unlit>  from " in out
    assert "Surface.inputs:specular: input 'specular' is not an input of UsdPreviewSurface: ignored" in out
    stage = Usd.Stage.CreateNew(str(tmp_path / "m.usda"))
    mat = UsdShade.Material.Define(stage, "/M")
    tex = _shader(stage, "/M/T", "UsdUVTexture", file=(T.Asset, "x.png"))
    surf = _shader(stage, "/M/S", "UsdPreviewSurface")
    _connect(surf, "diffuseColor", T.Color3f, tex, "rgb")
    _surface(mat, surf)
    stage.GetRootLayer().Save()
    assert main(["info", str(tmp_path / "m.usda")]) == 1
    out = capsys.readouterr().out
    assert "    unresolved:\n      %s:/M/T.inputs:file: texture 'x.png' not found" % (tmp_path / "m.usda") in out


# ---------------------------------------------------------------- the corpus

CORPUS_STAGES = {
    # entry file: materials it holds (as composed with the default variants)
    "TextureTransformTest/TextureTransformTest.usd": 9,
    "TextureCoordinateTest/TextureCoordinateTest.usda": 5,
    "TextureCoordinateTest/TextureCoordinateTestMaterialX.usda": 5,
    "RoughnessTest/RoughnessTest.usdz": 6,
    "StandardShaderBall/standard_shader_ball_scene.usda": 17,
    "intent-vfx/assets/simpleAsset/simpleAsset.usd": 2,
    "intent-vfx/assets/teapot/teapot.usd": 1,
    "Teapot/Teapot.usd": 2,
}
# what the copy in ../shared lacks (its README): a missing texture, drawn as its fallback
KNOWN_NOTES = ("ground.ACEScg.exr",)


def _corpus_cases():
    if not os.path.isdir(USD_CORPUS):
        return [pytest.param(None, None, id="usd-corpus-absent",
                             marks=pytest.mark.skip(reason="needs ../shared/corpus/usd, absent on a clone"))]
    return [pytest.param(k, v, id=os.path.basename(k)) for k, v in CORPUS_STAGES.items()]


@pytest.mark.corpus
@pytest.mark.parametrize("entry,count", _corpus_cases())
def test_corpus_materials_generate_and_compile(entry, count, renderer, tmp_path, monkeypatch):
    monkeypatch.setenv("MTLXGEN_CACHE", str(tmp_path / "cache"))
    path = os.path.join(USD_CORPUS, entry)
    shaders, error = pipeline.generate(path, partial=True)
    problems = error.lines() if error else []
    assert all(any(k in line for k in KNOWN_NOTES) for line in problems), "\n".join(problems)
    assert len(shaders) == count, [s.element for s in shaders]
    ctx = renderer.ctx
    ctx.__enter__()
    for s in shaders:
        prog = ctx.program(vertex_shader=s.vertex, fragment_shader=s.fragment)      # raises where it does not link
        prog.release()
    # and on its own geometry, from its camera (or a framing one)
    from mtlxgen.apps import stagerender
    view = stagerender.read_view(path)
    assert not view.problems, view.problems
    img = stagerender.render_stage(renderer, view, {s.element: s for s in shaders}, stagerender.fallback_shader())
    assert np.isfinite(img).all() and (img[..., 3] > 0).mean() > 0.01, (view.camera, (img[..., 3] > 0).mean())


HOSTILE = """#usda 1.0
def Scope "L" {
  def Material "Loop" {
    token outputs:surface.connect = </L/Loop/S.outputs:surface>
    float inputs:loop.connect = </L/Loop.inputs:loop>
    def Shader "S" {
      uniform token info:id = "UsdPreviewSurface"
      float inputs:roughness.connect = </L/Loop.inputs:loop>
      token outputs:surface
    }
  }
  def Material "Cycle" {
    token outputs:surface.connect = </L/Cycle/S.outputs:surface>
    def Shader "S" {
      uniform token info:id = "UsdPreviewSurface"
      color3f inputs:diffuseColor.connect = </L/Cycle/M.outputs:out>
      token outputs:surface
    }
    def Shader "M" {
      uniform token info:id = "ND_multiply_color3"
      color3f inputs:in1.connect = </L/Cycle/M.outputs:out>
      color3f outputs:out
    }
  }
  def Material "SelfRef" {
    token outputs:surface.connect = </L/SelfRef.outputs:surface>
  }
  def Material "Values" {
    token outputs:surface.connect = </L/Values/S.outputs:surface>
    def Shader "S" {
      uniform token info:id = "UsdPreviewSurface"
      color3f[] inputs:diffuseColor = [(1, 0, 0)]
      token outputs:surface
    }
  }
  def Material "Inf" {
    token outputs:surface.connect = </L/Inf/S.outputs:surface>
    def Shader "S" {
      uniform token info:id = "UsdPreviewSurface"
      float inputs:roughness = inf
      token outputs:surface
    }
  }
  def Material "Undeclared" {
    token outputs:surface.connect = </L/Undeclared/S.outputs:surface>
    def Shader "S" {
      uniform token info:id = "UsdPreviewSurface"
      color3f inputs:diffuseColor.connect = </L/Undeclared/T.outputs:rgbx>
      token outputs:surface
    }
    def Shader "T" {
      uniform token info:id = "UsdUVTexture"
    }
  }
  def Material "Device" {
    token outputs:surface.connect = </L/Device/S.outputs:surface>
    def Shader "S" {
      uniform token info:id = "UsdPreviewSurface"
      color3f inputs:diffuseColor.connect = </L/Device/T.outputs:rgb>
      token outputs:surface
    }
    def Shader "T" {
      uniform token info:id = "UsdUVTexture"
      asset inputs:file = @/dev/zero@
      token inputs:wrapS = "sideways"
      float3 outputs:rgb
    }
  }
  def Material "Bogus" {
    token outputs:mtlx:surface.connect = </L/Bogus/S.outputs:out>
    def Shader "S" {
      uniform token info:id = "ND_surface_unlit"
      float inputs:bogus = 1
      token outputs:out
    }
  }
  def Material "Fine" {
    token outputs:surface.connect = </L/Fine/S.outputs:surface>
    def Shader "S" {
      uniform token info:id = "UsdPreviewSurface"
      token outputs:surface
    }
  }
}
"""


def test_hostile_stages_give_one_line_problems_never_a_traceback(tmp_path, capsys):
    """Loops through interface inputs, node cycles, a material reading a material, arrays and non-finite values,
    connections to undeclared outputs, a device as a texture, unknown inputs and tokens: each one line at its
    prim or attribute, status 1, and the one sound material still written."""
    from mtlxgen.apps.cli import main
    path = str(tmp_path / "hostile.usda")
    with open(path, "w") as f:
        f.write(HOSTILE)
    assert main(["generate", path, "-o", str(tmp_path / "o")]) == 1
    err = capsys.readouterr().err.splitlines()
    assert not [line for line in err if not line.startswith(path + ":/L/")], err
    expected = {
        "/L/Loop/S.inputs:roughness": "connections pass through more than 64 interface inputs",
        "/L/Cycle/M.inputs:in1": "cycle",
        "/L/SelfRef.outputs:surface": "connects to output 'surface' of material </L/SelfRef>",
        "/L/Values/S.inputs:diffuseColor": "an array (Vec3fArray) for a color3 input",
        "/L/Inf/S.inputs:roughness": "non-finite value 'inf'",
        "/L/Undeclared/S.inputs:diffuseColor": "</L/Undeclared/T> does not declare",
        "/L/Device/T.inputs:file": "texture '/dev/zero' is a system file (under /dev); drawing the fallback (0, 0, 0, 1)",
        "/L/Device/T.inputs:wrapS": "wrapS 'sideways' is not one of",
        "/L/Bogus/S.inputs:bogus": "has no input 'bogus'",
    }
    for where, text in expected.items():
        assert any(line.startswith("%s:%s: " % (path, where)) and text in line for line in err), (where, err)
    assert sorted(os.listdir(tmp_path / "o")) == ["L_Fine.frag", "L_Fine.json", "L_Fine.vert"]


@pytest.mark.parametrize("prim,element", [("/Looks/Leaf", "leaf"), ("/Looks/Stripes", "stripes"), ("/Looks/Gold", "gold")])
def test_example_stage_draws_what_its_mtlx_form_draws(renderer, prim, element):
    """examples/usd/preview_stage.usda (goldens in golden_images/) against examples/usd/usd_seed_rules.mtlx."""
    examples = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples", "usd")
    ours, _ = _render(renderer, os.path.join(examples, "preview_stage.usda"), prim)
    theirs, _ = _render(renderer, os.path.join(examples, "usd_seed_rules.mtlx"), element)
    _same(ours, theirs, prim)


def _quad(stage, path, x0, y0, size=0.9, st=False):
    from pxr import UsdGeom
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreatePointsAttr([(x0, y0, 0), (x0 + size, y0, 0), (x0 + size, y0 + size, 0), (x0, y0 + size, 0)])
    mesh.CreateFaceVertexCountsAttr([4])
    mesh.CreateFaceVertexIndicesAttr([0, 1, 2, 3])
    if st:      # indexed, face-varying: the corners' coordinates through an index list
        pv = UsdGeom.PrimvarsAPI(mesh).CreatePrimvar("st", T.TexCoord2fArray, UsdGeom.Tokens.faceVarying)
        pv.Set([(0, 0), (1, 0), (1, 1), (0, 1)])
        pv.SetIndices([0, 1, 2, 3])
    return mesh


def _emissive(stage, path, colour=None, texture=None):
    mat = UsdShade.Material.Define(stage, path)
    surf = _shader(stage, path + "/S", "UsdPreviewSurface", diffuseColor=(T.Color3f, Gf.Vec3f(0, 0, 0)),
                   roughness=(T.Float, 1.0))
    if texture:
        reader = _shader(stage, path + "/R", "UsdPrimvarReader_float2", varname=(T.Token, "st"))
        tex = _shader(stage, path + "/T", "UsdUVTexture", file=(T.Asset, texture), sourceColorSpace=(T.Token, "raw"))
        _connect(tex, "st", T.Float2, reader, "result", T.Float2)
        _connect(surf, "emissiveColor", T.Color3f, tex, "rgb")
    else:
        surf.CreateInput("emissiveColor", T.Color3f).Set(Gf.Vec3f(*colour))
    _surface(mat, surf)
    return mat


def test_stage_geometry_draws_meshes_with_their_materials(renderer, tmp_path):
    """Four quads seen by the stage's camera: a texture through an indexed face-varying st (the image upright:
    its top-left quarter at the quad's top-left), a red and a blue material, and an unbound quad in its
    displayColor. Without the camera a framing one sees all four."""
    from pxr import UsdGeom
    from mtlxgen.apps import stagerender
    # image quarters (row 0 on top): top-left red, top-right green, bottom-left blue, bottom-right white
    _png(tmp_path, "quarters.png", lambda u, v: (np.where((u < 0.5) & (v < 0.5) | (u >= 0.5) & (v >= 0.5), 255, 0),
                                                 np.where((u >= 0.5), 255, 0),
                                                 np.where((v >= 0.5), 255, 0)))
    stage = Usd.Stage.CreateNew(str(tmp_path / "quads.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    textured = _quad(stage, "/World/Textured", -1.0, 0.05, st=True)
    red, blue = _quad(stage, "/World/Red", 0.05, 0.05), _quad(stage, "/World/Blue", -1.0, -1.0)
    plain = _quad(stage, "/World/Plain", 0.05, -1.0)
    UsdGeom.PrimvarsAPI(plain).CreatePrimvar("displayColor", T.Color3fArray, UsdGeom.Tokens.constant).Set([(0, 0.8, 0)])
    looks = {"Tex": _emissive(stage, "/Looks/Tex", texture="quarters.png"),
             "Red": _emissive(stage, "/Looks/Red", (1, 0, 0)), "Blue": _emissive(stage, "/Looks/Blue", (0, 0, 1))}
    for mesh, look in ((textured, "Tex"), (red, "Red"), (blue, "Blue")):
        UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim()).Bind(looks[look])
    cam = UsdGeom.Camera.Define(stage, "/Cam")
    UsdGeom.Xformable(cam).AddTranslateOp().Set(Gf.Vec3d(0, 0, 5))
    stage.GetRootLayer().Save()
    path = str(tmp_path / "quads.usda")

    view = stagerender.read_view(path)
    assert view.camera == "/Cam" and len(view.meshes) == 4
    shaders = {s.element: s for s in pipeline.generate(path)}
    img = stagerender.render_stage(renderer, view, shaders, stagerender.fallback_shader())
    n = img.shape[0]

    def at(x, y):       # scene coordinates in the plane z = 0 -> the pixel the camera sees them at
        half = 20.955 / 2 / 50 * 5       # default aperture and focal length, 5 units away
        return img[int((0.5 - y / half / 2) * n), int((0.5 + x / half / 2) * n), :3]

    def near(c, want):
        return np.allclose(c / max(c.max(), 1e-6), want, atol=0.1) and c.max() > 0.2

    assert near(at(0.5, 0.5), (1, 0, 0)) and near(at(-0.5, -0.5), (0, 0, 1)), (at(0.5, 0.5), at(-0.5, -0.5))
    plain_px = at(0.5, -0.5)
    assert plain_px[1] > 2 * plain_px[0] and plain_px[1] > 2 * plain_px[2], plain_px       # its displayColor
    for (x, y), want in (((-0.8, 0.8), (1, 0, 0)), ((-0.25, 0.8), (0, 1, 0)), ((-0.8, 0.25), (0, 0, 1)),
                         ((-0.25, 0.25), (1, 1, 1))):
        assert near(at(x, y), want), ((x, y), at(x, y), want)
    assert img[0, 0, 3] == 0 and img[n // 2, n // 2, 3] == 0          # background, and the gap between the quads

    stage.RemovePrim("/Cam")
    stage.GetRootLayer().Save()
    framed = stagerender.read_view(path)
    assert framed.camera == "framing"
    img = stagerender.render_stage(renderer, framed, shaders, stagerender.fallback_shader())
    h = n // 2
    quarters = [img[:h, :h], img[:h, h:], img[h:, :h], img[h:, h:]]
    assert all((q[..., 3] > 0).mean() > 0.05 for q in quarters), [(q[..., 3] > 0).mean() for q in quarters]


def test_stage_geometry_subsets_purposes_and_up_axis(tmp_path):
    """A GeomSubset takes its faces to its own material; proxy and invisible meshes are not drawn; a Z-up stage is
    turned Y-up; an implicit sphere is tessellated."""
    from pxr import UsdGeom
    from mtlxgen.apps import stagerender
    stage = Usd.Stage.CreateNew(str(tmp_path / "subsets.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    mesh = UsdGeom.Mesh.Define(stage, "/World/Two")
    mesh.CreatePointsAttr([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (2, 0, 0), (2, 1, 0)])
    mesh.CreateFaceVertexCountsAttr([4, 4])
    mesh.CreateFaceVertexIndicesAttr([0, 1, 2, 3, 1, 4, 5, 2])
    red, blue = _emissive(stage, "/Looks/Red", (1, 0, 0)), _emissive(stage, "/Looks/Blue", (0, 0, 1))
    UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim()).Bind(red)
    subset = UsdShade.MaterialBindingAPI(mesh.GetPrim()).CreateMaterialBindSubset("right", [1])
    UsdShade.MaterialBindingAPI.Apply(subset.GetPrim()).Bind(blue)
    proxy = _quad(stage, "/World/Proxy", 0, 0)
    UsdGeom.Imageable(proxy).CreatePurposeAttr(UsdGeom.Tokens.proxy)
    hidden = _quad(stage, "/World/Hidden", 0, 0)
    UsdGeom.Imageable(hidden).MakeInvisible()
    UsdGeom.Sphere.Define(stage, "/World/Ball").CreateRadiusAttr(0.5)
    stage.GetRootLayer().Save()
    view = stagerender.read_view(str(tmp_path / "subsets.usda"))
    assert [m.prim for m in view.meshes] == ["/World/Two", "/World/Ball"] and view.camera == "framing"
    groups = {element: len(tris) // 3 for element, tris in view.meshes[0].groups}
    assert groups == {"Looks_Blue": 2, "Looks_Red": 2}           # two triangles a face
    z = view.meshes[0].world @ np.array([0.0, 0.0, 1.0, 0.0])
    assert np.allclose(z[:3], (0, 1, 0))                        # the stage's up is the lighting's up
    ball = view.meshes[1].attrs["i_position"]
    assert np.allclose(np.linalg.norm(ball, axis=1), 0.5, atol=1e-6)


def test_composition_errors_are_problems_at_their_prim(tmp_path, capsys):
    from mtlxgen.apps.cli import main
    path = tmp_path / "comp.usda"
    path.write_text('#usda 1.0\ndef "Ref" (references = @./missing.usda@) {}\ndef Material "M" {\n'
                    '  token outputs:surface.connect = </M/S.outputs:surface>\n  def Shader "S" {\n'
                    '    uniform token info:id = "UsdPreviewSurface"\n    token outputs:surface\n  }\n}\n')
    assert main(["generate", str(path), "-o", str(tmp_path / "o")]) == 1
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) == 1 and lines[0].startswith("%s:/Ref: composition: Could not open asset @" % path), lines
    assert "missing.usda" in lines[0]
    assert sorted(os.listdir(tmp_path / "o")) == ["M.frag", "M.json", "M.vert"]


# ---------------------------------------------------------------- primvars other than texture coordinates

def _primvar(mesh, name, type_name, values, interpolation="constant"):
    from pxr import UsdGeom
    UsdGeom.PrimvarsAPI(mesh).CreatePrimvar(name, type_name, interpolation).Set(values)


def _reader_look(stage, path, sid, varname, out_type, chain=(), fallback=None):
    """UsdPreviewSurface (black, rough) whose emissiveColor comes from a primvar reader `sid` reading `varname`,
    through MaterialX nodes `chain` [(id, input the previous output goes into, {other inputs})]."""
    mat = UsdShade.Material.Define(stage, path)
    surf = _shader(stage, path + "/S", "UsdPreviewSurface", diffuseColor=(T.Color3f, Gf.Vec3f(0, 0, 0)),
                   roughness=(T.Float, 1.0))
    reader = _shader(stage, path + "/Reader", sid, varname=(T.String, varname))
    if fallback is not None:
        reader.CreateInput("fallback", fallback[0]).Set(fallback[1])
    source, output, t = reader, "result", out_type
    for i, (nd, into, extra) in enumerate(chain):
        node = _shader(stage, "%s/N%d" % (path, i), nd, **extra)
        for name in (into if isinstance(into, tuple) else (into,)):
            _connect(node, name, t, source, output, t)
        source, output, t = node, "out", {"ND_convert_float_color3": T.Color3f, "ND_combine3_color3": T.Color3f,
                                          "ND_convert_integer_float": T.Float, "ND_multiply_float": T.Float,
                                          "ND_extract_vector4": T.Float}[nd]
    _connect(surf, "emissiveColor", T.Color3f, source, output, t)
    _surface(mat, surf)
    return mat


def _primvar_stage(tmp_path):
    """A 3 x 3 grid of quads before the camera, each drawing a primvar through its material's reader."""
    from pxr import UsdGeom
    stage = Usd.Stage.CreateNew(str(tmp_path / "primvars.usda"))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
    colour = _reader_look(stage, "/Looks/Colour", "UsdPrimvarReader_float3", "displayColor", T.Float3,
                          fallback=(T.Float3, Gf.Vec3f(0, 0, 1)))
    level = _reader_look(stage, "/Looks/Level", "UsdPrimvarReader_float", "level", T.Float,
                         [("ND_convert_float_color3", "in", {})])
    four = _reader_look(stage, "/Looks/Four", "UsdPrimvarReader_float4", "rgba", T.Float4)
    for i, c in enumerate("xyz"):         # extract x, y, z into a colour (a chain with three branches)
        _shader(stage, "/Looks/Four/E" + c, "ND_extract_vector4", index=(T.Int, i))
        _connect(UsdShade.Shader.Get(stage, "/Looks/Four/E" + c), "in", T.Float4,
                 UsdShade.Shader.Get(stage, "/Looks/Four/Reader"), "result", T.Float4)
    combine = _shader(stage, "/Looks/Four/Combine", "ND_combine3_color3")
    for i, c in enumerate("xyz"):
        _connect(combine, "in%d" % (i + 1), T.Float, UsdShade.Shader.Get(stage, "/Looks/Four/E" + c), "out", T.Float)
    _connect(UsdShade.Shader.Get(stage, "/Looks/Four/S"), "emissiveColor", T.Color3f, combine, "out", T.Color3f)
    count = _reader_look(stage, "/Looks/Count", "UsdPrimvarReader_int", "count", T.Int,
                         [("ND_convert_integer_float", "in", {}), ("ND_multiply_float", "in1", {"in2": (T.Float, 0.25)}),
                          ("ND_convert_float_color3", "in", {})])
    spaced = _reader_look(stage, "/Looks/Spaced", "UsdPrimvarReader_float3", "my:tint", T.Float3)
    mx = UsdShade.Material.Define(stage, "/Looks/Mx")         # MaterialX's geompropvalue reads it too
    prop = _shader(stage, "/Looks/Mx/Prop", "ND_geompropvalue_color3", geomprop=(T.String, "displayColor"))
    unlit = _shader(stage, "/Looks/Mx/Unlit", "ND_surface_unlit")
    _connect(unlit, "emission_color", T.Color3f, prop, "out", T.Color3f)
    _surface(mx, unlit, "mtlx")

    quads = {}
    for row, names in enumerate((("Red", "Bare", "Ramp"), ("Wrong", "Four", "Count"), ("Yellow", "Magenta", None))):
        for col, name in enumerate(names):
            if name:
                quads[name] = _quad(stage, "/World/" + name, -1.0 + 0.7 * col, 0.4 - 0.7 * row, size=0.6)
    _primvar(quads["Red"], "displayColor", T.Color3fArray, [(1, 0, 0)])
    _primvar(quads["Ramp"], "level", T.FloatArray, [0, 1, 1, 0], "vertex")          # dark left, bright right
    _primvar(quads["Wrong"], "displayColor", T.Color3fArray, [(1, 0, 0), (1, 0, 0)], "vertex")   # 2 for 4 points
    _primvar(quads["Four"], "rgba", T.Float4Array, [(0, 1, 0, 1)], "uniform")
    _primvar(quads["Count"], "count", T.IntArray, [2])
    _primvar(quads["Yellow"], "displayColor", T.Color3fArray, [(1, 1, 0)])
    _primvar(quads["Magenta"], "my:tint", T.Color3fArray, [(1, 0, 1)], "faceVarying")
    UsdGeom.PrimvarsAPI(quads["Magenta"]).GetPrimvar("my:tint").Set([(1, 0, 1)] * 4)
    looks = {"Red": colour, "Bare": colour, "Wrong": colour, "Ramp": level, "Four": four, "Count": count,
             "Yellow": mx, "Magenta": spaced}
    for name, look in looks.items():
        UsdShade.MaterialBindingAPI.Apply(quads[name].GetPrim()).Bind(look)
    cam = UsdGeom.Camera.Define(stage, "/Cam")
    UsdGeom.Xformable(cam).AddTranslateOp().Set(Gf.Vec3d(0, 0, 5))
    stage.GetRootLayer().Save()
    return str(tmp_path / "primvars.usda")


def test_stage_meshes_bind_the_primvars_their_readers_name(renderer, tmp_path):
    """float3 (constant displayColor, a namespaced name through faceVarying), float (vertex), float4 (uniform) and
    int primvars reach the readers as vertex attributes; MaterialX's geompropvalue reads the same attribute; a mesh
    without the primvar, or with one that does not fit it (a one-line problem), draws the reader's fallback."""
    from mtlxgen.apps import stagerender
    path = _primvar_stage(tmp_path)
    view = stagerender.read_view(path)
    assert [(str(loc), text) for loc, text in view.problems] == [
        ("%s:/World/Wrong.primvars:displayColor" % path,
         "primvar not bound (its readers draw their fallback): it has 2 values for 4 points")]
    shaders = {s.element: s for s in pipeline.generate(path)}
    spaced = shaders["Looks_Spaced"].manifest["primvars"]
    assert len(spaced) == 1 and spaced[0]["varname"] == "my:tint" and spaced[0]["attribute"].startswith(
        "i_geomprop_my_tint_")                          # ':' is no GLSL: a hashed name
    img = stagerender.render_stage(renderer, view, shaders, stagerender.fallback_shader())
    n = img.shape[0]

    def at(x, y):
        half = 20.955 / 2 / 50 * 5
        return img[int((0.5 - y / half / 2) * n), int((0.5 + x / half / 2) * n), :3]

    def colour(col, row, dx=0.0):       # the centre of a grid cell (dx: across it, -0.3 .. 0.3)
        return at(-0.7 + 0.7 * col + dx, 0.7 - 0.7 * row)

    def near(c, want):
        return np.allclose(c / max(c.max(), 1e-6), want, atol=0.12) and c.max() > 0.2

    expected = {(0, 0): (1, 0, 0), (1, 0): (0, 0, 1), (0, 1): (0, 0, 1), (1, 1): (0, 1, 0), (2, 1): (1, 1, 1),
                (0, 2): (1, 1, 0), (1, 2): (1, 0, 1)}
    for (col, row), want in expected.items():
        assert near(colour(col, row), want), ((col, row), colour(col, row), want)
    assert abs(colour(2, 1).mean() - 0.5) < 0.1, colour(2, 1)                  # count 2 * 0.25
    left, right = colour(2, 0, -0.25).mean(), colour(2, 0, 0.25).mean()
    assert right > 0.7 and left < 0.3, (left, right)                             # level 0 -> 1 across the quad


def test_sphere_draws_the_readers_fallback(renderer, tmp_path):
    """The sphere has no primvars but its texture coordinates: a displayColor reader draws its fallback (as the
    seed says and Storm draws a mesh that authors no displayColor), its flag uniform left at 0."""
    path = _primvar_stage(tmp_path)
    img, shader = _render(renderer, path, "/Looks/Colour")
    (entry,) = shader.manifest["primvars"]
    assert entry["varname"] == "displayColor" and entry["attribute"] == "i_geomprop_displayColor"
    assert shader.manifest["attributes"][entry["attribute"]] == "vec3"
    assert next(u["value"] for u in shader.manifest["uniforms"] if u["name"] == entry["uniform"]) == 0
    centre = img[56:72, 56:72, :3].reshape(-1, 3).mean(0)
    assert centre[2] > 4 * max(centre[0], centre[1]) and centre[2] > 0.5, centre
    grey, _ = _render(renderer, path, "/Looks/Level")             # no fallback authored: the seed's 0
    assert grey[56:72, 56:72, :3].max() < 0.2


# ---------------------------------------------------------------- the licensed copies in tests/data/usd

USD_DATA = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data", "usd")
STAGE_GOLDENS = os.path.join(USD_DATA, "renders")
# entry file: the textures it names that the copy leaves out (tests/data/usd/README.md)
DATA_STAGES = {
    "TextureTransformTest/TextureTransformTest.usd": (),
    "RoughnessTest/RoughnessTest.usdz": (),
    "Teapot/Teapot.usd": ("tea_set_01_diff_2k.jpg", "tea_set_01_arm_2k.jpg"),
    "TextureCoordinateTest/TextureCoordinateTest.usda": (),
}


@pytest.fixture(scope="module")
def stage_renderer():
    from mtlxgen.draw.renderer import Renderer
    with Renderer(size=256) as r:
        yield r


@pytest.mark.parametrize("entry", sorted(DATA_STAGES))
def test_licensed_copies_draw_their_stage_goldens(stage_renderer, entry, update_goldens, tmp_path, monkeypatch):
    """Each copied asset on its own geometry, from its camera or a framing one, against tests/data/usd/renders
    (`pytest --update-goldens` rewrites them); golden_images/ holds a sphere per material."""
    from mtlxgen.apps import golden, stagerender
    from util import FAILURES
    monkeypatch.setenv("MTLXGEN_CACHE", str(tmp_path / "cache"))
    path = os.path.join(USD_DATA, entry)
    shaders, error = pipeline.generate(path, partial=True, unreadable_textures="error")
    problems = error.lines() if error else []
    left_out = DATA_STAGES[entry]
    assert len(problems) == len(left_out) and all(any(f in line and "not found" in line for line in problems)
                                                  for f in left_out), problems
    view = stagerender.read_view(path)
    assert not view.problems, view.problems
    img = stagerender.render_stage(stage_renderer, view, {s.element: s for s in shaders}, stagerender.fallback_shader())
    drawn = img[..., 3] > 0
    assert drawn.mean() > 0.02
    if entry.startswith("Teapot"):      # its Ceramic material reads the mesh's displayColor: lime green (0.325, 0.825, 0)
        rgb = img[drawn][:, :3].mean(0)
        assert rgb[1] > 1.5 * rgb[0] and rgb[0] > 2 * rgb[2], rgb
    name = os.path.splitext(os.path.basename(entry))[0] + "__stage.png"
    stored = os.path.join(STAGE_GOLDENS, name)
    if update_goldens:
        os.makedirs(STAGE_GOLDENS, exist_ok=True)
        images.write_image(stored, images.to_srgb8(img))
        return
    metrics, diff, _ = golden.measure(img, golden.read_png8(stored), None, golden.Tolerance(), flip=False)
    passes, why = golden.verdict(metrics, golden.Tolerance())
    if not passes:
        os.makedirs(FAILURES, exist_ok=True)
        new = os.path.join(FAILURES, name.replace(".png", ".new.png"))
        images.write_image(new, images.to_srgb8(img))
        raise AssertionError("%s: %s (new render: %s; if intended: pytest --update-goldens)" % (name, why, new))


def test_roughness_channels_are_read_from_the_usdz_as_authored(renderer, tmp_path, monkeypatch):
    """RoughnessTest reads roughness from the r, g and b channels of one texture inside the .usdz, each through
    the sourceColorSpace its UsdUVTexture names: every textured sphere draws what its constant twin draws once the
    twin holds that channel's texel read the same way. Where that is not the twin's own value (the file keeps
    sRGB-encoded numbers, one reader reads them raw) the two differ, as the seed's rules say they must."""
    import OpenImageIO as oiio
    monkeypatch.setenv("MTLXGEN_CACHE", str(tmp_path / "cache"))
    package = os.path.join(USD_DATA, "RoughnessTest", "RoughnessTest.usdz")
    zipped = Sdf.ZipFile.Open(package)
    (tga,) = [n for n in zipped.GetFileNames() if n.endswith("roughness.tga")]
    (tmp_path / "r.tga").write_bytes(bytes(zipped.GetFile(tga)))
    texel = oiio.ImageBuf(str(tmp_path / "r.tga")).get_pixels(oiio.UINT8)[..., :3].reshape(-1, 3)
    assert (texel == texel[0]).all()                 # one value per channel
    stage = Usd.Stage.Open(package)
    cases = []
    for tex, twin in (("Tex000", "Const000"), ("Tex033", "Const033"), ("Tex066", "Const066")):
        surface = UsdShade.Shader.Get(stage, "/Roughness/Materials/%s/Principled_BSDF" % tex)
        (source,) = surface.GetInput("roughness").GetConnectedSources()[0]
        reader = UsdShade.Shader(source.source.GetPrim())
        assert reader.GetInput("file").Get().path.endswith("roughness.tga")
        value = float(texel[0]["rgb".index(source.sourceName)]) / 255.0
        if reader.GetInput("sourceColorSpace").Get() == "sRGB":
            value = value / 12.92 if value <= 0.04045 else ((value + 0.055) / 1.055) ** 2.4
        own = UsdShade.Shader.Get(stage, "/Roughness/Materials/%s/Principled_BSDF" % twin).GetInput("roughness").Get()
        cases.append((tex, twin, value, own))
    assert any(abs(v - own) > 0.1 for _, _, v, own in cases) and any(abs(v - own) < 0.02 for _, _, v, own in cases)
    over = tmp_path / "twins.usda"              # the package sublayered, the constants overridden
    lines = ['#usda 1.0', '(subLayers = [@%s@])' % package, 'over "Roughness" {', 'over "Materials" {']
    for _, twin, value, _ in cases:
        lines += ['over "%s" {' % twin, 'over "Principled_BSDF" {', "float inputs:roughness = %r" % value, "}", "}"]
    over.write_text("\n".join(lines + ["}", "}"]) + "\n")

    def draw(path, element):
        return images.to_srgb8(renderer.render(pipeline.generate(str(path), elements=[element])[0])).astype(int)

    for tex, twin, value, own in cases:
        textured = draw(package, "Roughness_Materials_" + tex)
        assert np.abs(textured - draw(over, "Roughness_Materials_" + twin)).max() <= 2, (tex, value)
        if abs(value - own) > 0.1:
            assert np.abs(textured - draw(package, "Roughness_Materials_" + twin)).max() > 20, (tex, value, own)


# ---------------------------------------------------------------- directories: batch and golden sweeps

def test_directory_sweeps_find_stages_not_the_layers_they_compose(tmp_path, capsys):
    """batch and golden find USD stages in directories beside .mtlx documents: a stage's payloads, references and
    sublayers (the Teapot's) are drawn as part of it, not again on their own, and a layer without materials (its
    geometry) is no stage to draw."""
    import shutil
    from mtlxgen.apps import batch, golden
    from mtlxgen.apps.batch import RenderSettings
    from mtlxgen.apps.cli import main
    root = tmp_path / "scenes"
    shutil.copytree(os.path.join(USD_DATA, "Teapot"), root / "Teapot")
    examples = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "examples", "usd")
    for name in ("preview_stage.usda", "usd_seed_rules.mtlx", "leaf_ga.png", "stripes_r.png"):
        shutil.copy(os.path.join(examples, name), root / name)
    geometry_only = Usd.Stage.CreateNew(str(root / "ground.usda"))
    _quad(geometry_only, "/Ground", 0, 0)
    geometry_only.GetRootLayer().Save()
    layers = sorted(os.path.relpath(p, root) for p in glob.glob(str(root / "**" / "*.usd*"), recursive=True))
    assert len(layers) == 7                        # ground, preview_stage, and the Teapot's five layers
    found = [os.path.relpath(p, root) for p in batch.find_materials([str(root)])]
    assert found == ["preview_stage.usda", "usd_seed_rules.mtlx", os.path.join("Teapot", "Teapot.usd")], found

    # golden update and check of the directory: the stages' materials among the goldens
    goldens = tmp_path / "goldens"
    made = [str(root / "preview_stage.usda"), str(root / "usd_seed_rules.mtlx")]
    done = golden.update(made, str(goldens), settings=RenderSettings(size=24), workers=1, progress=False)
    assert [s for _, s, _ in done] == ["created"] * sum(len(batch.list_elements(p)) for p in made), done
    run = golden.check([str(root)], str(goldens), str(tmp_path / "check"), workers=1, progress=False, flip=False)
    status = {r["name"]: r["status"] for r in run.results}
    stage_names = [n for n in status if n.startswith("preview_stage__")]
    assert len(stage_names) == 4 and all(status[n] == "pass" for n in stage_names), status
    assert {status[n] for n in status if n.startswith("Teapot__")} == {"missing"}, status   # no golden made for them

    # batch of the directory: every stage element drawn once (the Teapot's missing textures said once, status 1)
    assert main(["batch", str(root), "-o", str(tmp_path / "b"), "-j", "1", "--size", "16", "--no-progress"]) == 1
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and all("tea_set_01_" in line and "not found" in line for line in err), err
    pngs = sorted(n for n in os.listdir(tmp_path / "b") if n.endswith(".png"))
    assert [n for n in pngs if n.startswith("Teapot__")] == ["Teapot__Teapot_Materials_Ceramic.png",
                                                             "Teapot__Teapot_Materials_PorcelainFlowers.png"]
    assert len([n for n in pngs if n.startswith("preview_stage__")]) == 4
    assert not [n for n in pngs if n.startswith(("Teapot_Materials", "Teapot_Payload", "ground"))], pngs


# ---------------------------------------------------------------- MaterialX's own UsdPreviewSurface nodegraph

# Each case is one network, built as a USD stage (drawn by the seed's rules) and written as a MaterialX-vocabulary
# .mtlx document (ND_UsdPreviewSurface_surfaceshader, ND_UsdUVTexture_23, ND_UsdTransform2d: MaterialX's graphs),
# MaterialX's own GLSL drawn in our harness. Where the seed and MaterialX's graphs agree the renders are at parity
# (compare.parity); where they differ by design the renders differ (asserted, so the list stays true):
#   metallic   the seed: F0 = F90 = diffuseColor (a Schlick lobe); MaterialX: a conductor_bsdf with artistic IOR
#   opacity    the seed: alpha (the surface fades, what is behind shows); MaterialX: a mix with dielectric transmission
#   channels1  a 1-channel file: the seed gives rgb = (r, r, r); MaterialX's image reads (r, 0, 0)
# Not compared here: wrap clamp / mirror / black (MaterialX's image leaves them to sampler state, which this harness
# does not set: its draws always repeat), and primvar readers (MaterialX 1.39's generator refuses its own
# UsdPrimvarReader graphs: "No 'geomprop' parameter found"; its forms read `texcoord`, what the seed's float2 reader
# reads on the sphere; other readers draw their fallback, MaterialX's read the vertex attribute).
TEXTURE_INPUTS = {"scale": T.Float4, "bias": T.Float4}
PARITY_CASES = {
    # name: (UsdPreviewSurface inputs, textures: [(file, wrap, sourceColorSpace, {input: value}, {surface input:
    #        texture output})] read through one primvar reader and UsdTransform2d, MaterialX reference fixture, agrees)
    "Constant": ({"diffuseColor": (0.7, 0.3, 0.1), "roughness": 0.35, "ior": 1.6, "emissiveColor": (0.05, 0.02, 0.0)},
                 None, "reference", True),
    "SpecularCoat": ({"diffuseColor": (0.1, 0.3, 0.6), "useSpecularWorkflow": 1, "specularColor": (0.5, 0.4, 0.2),
                      "roughness": 0.5, "clearcoat": 1.0, "clearcoatRoughness": 0.1}, None, "reference", True),
    "TextureRaw": ({}, [("rgb.png", "repeat", "raw", {"scale": (0.9, 0.8, 0.7, 1), "bias": (0.05, 0, 0.1, 0)},
                         {"diffuseColor": "rgb", "roughness": "g"}),
                        ("nrm.png", "repeat", "raw", {"scale": (2, 2, 2, 1), "bias": (-1, -1, -1, 0)}, {"normal": "rgb"})],
                   "reference", True),
    # auto on an 8-bit RGB file is sRGB; MaterialX with colour management, the file's colorspace srgb_texture
    "TextureAuto": ({}, [("rgb.png", "repeat", "auto", {}, {"diffuseColor": "rgb"})], "cms_reference", True),
    "Metallic": ({"diffuseColor": (1.0, 0.76, 0.33), "metallic": 1.0, "roughness": 0.3}, None, "reference", False),
    "Opacity": ({"diffuseColor": (0.2, 0.6, 0.2), "opacity": 0.4}, None, "reference", False),
    "OneChannel": ({}, [("one.png", "repeat", "raw", {}, {"diffuseColor": "rgb"})], "reference", False),
}
_SURFACE_TYPES = {"diffuseColor": "color3", "emissiveColor": "color3", "specularColor": "color3", "normal": "vector3",
                  "useSpecularWorkflow": "integer"}


def _mx_value(value):
    return ", ".join(repr(float(v)) for v in value) if isinstance(value, tuple) else repr(value)


def _parity_files(folder):
    """parity.usda with a material per case, and NAME.mtlx: the same networks in MaterialX's vocabulary."""
    _png(folder, "rgb.png", lambda u, v: (u * 255, v * 255, 128 + 100 * np.sin(20 * u)))
    _png(folder, "nrm.png", lambda u, v: (128 + 60 * np.sin(9 * u), 128 + 60 * np.cos(7 * v), 255 + 0 * u))
    _png(folder, "one.png", lambda u, v: ((u > 0.5) * 200 + 30,))
    usd_types = {"color3": T.Color3f, "vector3": T.Normal3f, "integer": T.Int, "float": T.Float}
    stage = Usd.Stage.CreateNew(str(folder / "parity.usda"))
    for name, (inputs, texture, _, _) in PARITY_CASES.items():
        root = "/P/" + name
        mat = UsdShade.Material.Define(stage, root)
        surf = _shader(stage, root + "/Surface", "UsdPreviewSurface")
        mx_inputs, mx_nodes = [], ""
        for key, value in inputs.items():
            t = _SURFACE_TYPES.get(key, "float")
            surf.CreateInput(key, usd_types[t]).Set(Gf.Vec3f(*value) if isinstance(value, tuple) else value)
            mx_inputs.append('<input name="%s" type="%s" value="%s" />' % (key, t, _mx_value(value)))
        if texture:
            reader = _shader(stage, root + "/Reader", "UsdPrimvarReader_float2", varname=(T.Token, "st"))
            xf = _shader(stage, root + "/Xf", "UsdTransform2d", scale=(T.Float2, Gf.Vec2f(2, 1.5)),
                         rotation=(T.Float, 30.0), translation=(T.Float2, Gf.Vec2f(0.125, 0.25)))
            _connect(xf, "in", T.Float2, reader, "result", T.Float2)
            mx_nodes = ('<texcoord name="uv" type="vector2" />'
                        '<UsdTransform2d name="xf" type="vector2"><input name="in" type="vector2" nodename="uv" />'
                        '<input name="scale" type="vector2" value="2, 1.5" /><input name="rotation" type="float" '
                        'value="30" /><input name="translation" type="vector2" value="0.125, 0.25" /></UsdTransform2d>')
        for i, (file, wrap, source, extra, outputs) in enumerate(texture or ()):
            tex = _shader(stage, "%s/Tex%d" % (root, i), "UsdUVTexture", file=(T.Asset, file), wrapS=(T.Token, wrap),
                          wrapT=(T.Token, wrap), sourceColorSpace=(T.Token, source),
                          **{k: (TEXTURE_INPUTS[k], Gf.Vec4f(*v)) for k, v in extra.items()})
            _connect(tex, "st", T.Float2, xf, "result", T.Float2)
            colorspace = ' colorspace="srgb_texture"' if source in ("sRGB", "auto") else ""
            mx_wrap = "periodic" if wrap == "repeat" else wrap
            mx_nodes += ('<UsdUVTexture name="tex%d" type="multioutput"><input name="file" type="filename" value="%s"%s />'
                         '<input name="st" type="vector2" nodename="xf" /><input name="wrapS" type="string" value="%s" />'
                         '<input name="wrapT" type="string" value="%s" />%s</UsdUVTexture>'
                         % (i, file, colorspace, mx_wrap, mx_wrap, "".join(
                             '<input name="%s" type="color4" value="%s" />' % (k, _mx_value(v)) for k, v in extra.items())))
            for key, output in outputs.items():
                t = _SURFACE_TYPES.get(key, "float")
                _connect(surf, key, usd_types[t], tex, output, T.Float if t == "float" else T.Float3)
                if t == "vector3":
                    mx_nodes += ('<convert name="to_%s" type="vector3"><input name="in" type="color3" nodename="tex%d" '
                                 'output="%s" /></convert>' % (key, i, output))
                    mx_inputs.append('<input name="%s" type="vector3" nodename="to_%s" />' % (key, key))
                else:
                    mx_inputs.append('<input name="%s" type="%s" nodename="tex%d" output="%s" />' % (key, t, i, output))
        _surface(mat, surf)
        write_doc(folder, '%s<UsdPreviewSurface name="surface" type="surfaceshader">%s</UsdPreviewSurface>'
                          '<surfacematerial name="%s" type="material"><input name="surfaceshader" type="surfaceshader" '
                          'nodename="surface" /></surfacematerial>' % (mx_nodes, "".join(mx_inputs), name),
                  name=name + ".mtlx")
        text = (folder / (name + ".mtlx")).read_text()
        (folder / (name + ".mtlx")).write_text(text.replace('<materialx version="1.39">',
                                                            '<materialx version="1.39" colorspace="lin_rec709">'))
    stage.GetRootLayer().Save()
    return folder / "parity.usda"


@pytest.fixture(scope="module")
def parity_stage(tmp_path_factory):
    return _parity_files(tmp_path_factory.mktemp("usd_parity"))


@pytest.mark.parametrize("name", list(PARITY_CASES))
def test_stage_against_materialx_usd_preview_surface(renderer, request, parity_stage, name):
    from mtlxgen.draw import compare
    from util import save_side_by_side
    _, _, fixture, agrees = PARITY_CASES[name]
    reference = request.getfixturevalue(fixture)
    ours, _ = _render(renderer, parity_stage, "/P/" + name)
    vs, fs, tex, _ = reference.generate(str(parity_stage.parent / (name + ".mtlx")), name)
    theirs, _ = renderer.render_timed(vs, fs, {}, tex)
    assert ours[..., 3].max() > 0 and theirs[..., 3].max() > 0
    p = compare.parity(ours, theirs)
    if p.passes != agrees:
        where = save_side_by_side("usd_stage_parity_" + name, ours, theirs)
        raise AssertionError("%s: %s, %s (side by side: %s)" % (
            name, "expected parity with MaterialX's graph" if agrees else "expected the by-design difference", p, where))


def test_primvars_bound_per_mesh_are_bounded(tmp_path):
    """A material reading more primvars than a mesh binds (stagerender.MAX_VERTEX_PRIMVARS) gets the first ones; each
    other one is a problem line and its reader draws the fallback; a value a 32-bit attribute cannot hold is one too."""
    from mtlxgen.apps import stagerender
    n = stagerender.MAX_VERTEX_PRIMVARS + 1
    stage = Usd.Stage.CreateNew(str(tmp_path / "many.usda"))
    mat = UsdShade.Material.Define(stage, "/Looks/Many")
    total = None
    for i in range(n):
        reader = _shader(stage, "/Looks/Many/R%d" % i, "UsdPrimvarReader_float", varname=(T.String, "p%d" % i))
        if total is None:
            total = reader
            continue
        add = _shader(stage, "/Looks/Many/Add%d" % i, "ND_add_float")
        _connect(add, "in1", T.Float, total, "result" if total.GetShaderId().startswith("Usd") else "out", T.Float)
        _connect(add, "in2", T.Float, reader, "result", T.Float)
        total = add
    surf = _shader(stage, "/Looks/Many/S", "UsdPreviewSurface")
    _connect(surf, "roughness", T.Float, total, "out", T.Float)
    _surface(mat, surf)
    quad = _quad(stage, "/World/Quad", 0, 0)
    for i in range(n):
        _primvar(quad, "p%d" % i, T.FloatArray, [0.01 * i])
    odd = _quad(stage, "/World/Odd", 2, 0)
    _primvar(odd, "p0", T.DoubleArray, [1e300])
    for mesh in (quad, odd):
        UsdShade.MaterialBindingAPI.Apply(mesh.GetPrim()).Bind(mat)
    stage.GetRootLayer().Save()
    path = str(tmp_path / "many.usda")
    view = stagerender.read_view(path)
    bound = view.meshes[0].primvars
    assert sorted(bound) == sorted("p%d" % i for i in range(n - 1)), sorted(bound)
    assert [(str(loc), text) for loc, text in view.problems] == [
        ("%s:/World/Quad.primvars:p%d" % (path, n - 1), "primvar not bound (its readers draw their fallback): the "
         "mesh's materials read more than %d primvars as vertex attributes" % (n - 1)),
        ("%s:/World/Odd.primvars:p0" % path, "primvar not bound (its readers draw their fallback): its values are "
         "not finite 32-bit numbers")]
    assert view.meshes[0].primvars["p3"].dtype == np.float32 and not view.meshes[1].primvars


@pytest.mark.parametrize("first", ["st", "uv2"])
def test_two_texture_coordinate_sets_on_one_mesh(renderer, tmp_path, first):
    """A material reading a texture through `st` and another through `uv2` on a mesh holding both: each reader
    reads its own set (whichever the mesh binds as its texture coordinates); on the sphere both read the sphere's."""
    from mtlxgen.apps import stagerender
    _png(tmp_path, "ramp.png", lambda u, v: (u * 255, u * 255, u * 255))
    _png(tmp_path, "white.png", lambda u, v: (255 + 0 * u, 255 + 0 * u, 255 + 0 * u))
    stage = Usd.Stage.CreateNew(str(tmp_path / "sets.usda"))
    mat = UsdShade.Material.Define(stage, "/Looks/Two")
    surf = _shader(stage, "/Looks/Two/S", "UsdPreviewSurface", diffuseColor=(T.Color3f, Gf.Vec3f(0, 0, 0)),
                   roughness=(T.Float, 1.0))
    product = _shader(stage, "/Looks/Two/Times", "ND_multiply_color3")
    for i, (varname, png) in enumerate(((first, "white.png"), ({"st": "uv2", "uv2": "st"}[first], "ramp.png"))):
        reader = _shader(stage, "/Looks/Two/R%d" % i, "UsdPrimvarReader_float2", varname=(T.Token, varname))
        tex = _shader(stage, "/Looks/Two/T%d" % i, "UsdUVTexture", file=(T.Asset, png), sourceColorSpace=(T.Token, "raw"))
        _connect(tex, "st", T.Float2, reader, "result", T.Float2)
        _connect(product, "in%d" % (i + 1), T.Color3f, tex, "rgb")
    _connect(surf, "emissiveColor", T.Color3f, product, "out")
    _surface(mat, surf)
    ramp_set = {"st": "uv2", "uv2": "st"}[first]           # the set the ramp is read through: along u across the quad
    quad = _quad(stage, "/World/Quad", -0.9, -0.9, size=1.8)
    _primvar(quad, ramp_set, T.TexCoord2fArray, [(0, 0), (1, 0), (1, 1), (0, 1)], "vertex")
    _primvar(quad, first, T.TexCoord2fArray, [(0.5, 0.5)] * 4, "vertex")    # the white texture, read at its middle
    UsdShade.MaterialBindingAPI.Apply(quad.GetPrim()).Bind(mat)
    from pxr import UsdGeom
    UsdGeom.Xformable(UsdGeom.Camera.Define(stage, "/Cam")).AddTranslateOp().Set(Gf.Vec3d(0, 0, 5))
    stage.GetRootLayer().Save()
    path = str(tmp_path / "sets.usda")
    shaders = {s.element: s for s in pipeline.generate(path)}
    assert sorted(p["varname"] for p in shaders["Looks_Two"].manifest["primvars"]) == ["st", "uv2"]
    img = stagerender.render_stage(renderer, stagerender.read_view(path), shaders, stagerender.fallback_shader())
    n = img.shape[0]
    row = img[n // 2, :, :3].mean(-1)
    left, right = row[int(0.2 * n)], row[int(0.8 * n)]
    assert right > 0.6 and left < 0.35 * right, (left, right)        # the ramp across, through its own set


@pytest.mark.skipif(not __import__("shutil").which("glslangValidator"), reason="glslangValidator not installed "
                    "(Debian glslang-tools; .ci/run installs it)")
def test_stage_shaders_are_valid_to_the_reference_compiler(tmp_path, monkeypatch):
    """The shaders of the copied stages and of the primvar stage (flag uniforms, flat int attributes, hashed
    attribute names) pass Khronos' glslangValidator, not only Mesa."""
    from emit.test_glsl_validity import check_documents
    monkeypatch.setenv("MTLXGEN_CACHE", str(tmp_path / "cache"))
    paths = [os.path.join(USD_DATA, entry) for entry in sorted(DATA_STAGES)] + [_primvar_stage(tmp_path)]
    count, errors = check_documents(paths, str(tmp_path))
    assert count >= len(paths) and not errors, errors[:10]


# ---------------------------------------------------------------- displacement

BUMPY_MTLX = """
  <UsdUVTexture name="height" type="multioutput">
    <input name="file" type="filename" value="mask.png" />
    <input name="sourceColorSpace" type="string" value="raw" />
    <input name="scale" type="color4" value="0.25, 0.25, 0.25, 1" />
  </UsdUVTexture>
  <UsdPreviewSurface name="surface" type="surfaceshader">
    <input name="diffuseColor" type="color3" value="0.6, 0.3, 0.2" />
    <input name="displacement" type="float" nodename="height" output="r" />
  </UsdPreviewSurface>
  <displacement name="bump" type="displacementshader">
    <input name="displacement" type="float" nodename="height" output="r" />
  </displacement>
  <surfacematerial name="Bumpy" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="surface" />
    <input name="displacementshader" type="displacementshader" nodename="bump" />
  </surfacematerial>
"""


def _bumpy(stage, root, amount):
    mat = UsdShade.Material.Define(stage, root)
    height = _shader(stage, root + "/Height", "UsdUVTexture", file=(T.Asset, "mask.png"),
                     sourceColorSpace=(T.Token, "raw"), scale=(T.Float4, Gf.Vec4f(0.25, 0.25, 0.25, 1)))
    surf = _shader(stage, root + "/Surface", "UsdPreviewSurface", diffuseColor=(T.Color3f, Gf.Vec3f(0.6, 0.3, 0.2)))
    if amount == "texture":
        _connect(surf, "displacement", T.Float, height, "r", T.Float)
    elif amount is not None:
        surf.CreateInput("displacement", T.Float).Set(amount)
    _surface(mat, surf)
    mat.CreateDisplacementOutput().ConnectToSource(surf.ConnectableAPI(), "displacement")
    return mat


def test_preview_surface_displacement_moves_the_surface_as_its_mtlx_form(renderer, tmp_path):
    """A Material's outputs:displacement connected to its UsdPreviewSurface moves the surface along the normal by
    the shader's `displacement` input (here a texture's channel): the vertex stage reads it, and the picture is
    the .mtlx form's (a displacement node on the surfacematerial) pixel for pixel. Without outputs:displacement,
    or with no displacement authored, nothing moves."""
    _textures(tmp_path)
    stage = Usd.Stage.CreateNew(str(tmp_path / "bumpy.usda"))
    _bumpy(stage, "/Root/Bumpy", "texture")
    _bumpy(stage, "/Root/Flat", None)
    _bumpy(stage, "/Root/Pushed", 0.2)
    mx = UsdShade.Material.Define(stage, "/Root/MxPushed")          # a MaterialX network's displacement
    mx_surface = _shader(stage, "/Root/MxPushed/Surface", "ND_UsdPreviewSurface_surfaceshader",
                         diffuseColor=(T.Color3f, Gf.Vec3f(0.6, 0.3, 0.2)))
    mx_disp = _shader(stage, "/Root/MxPushed/Disp", "ND_displacement_float", displacement=(T.Float, 0.2))
    _surface(mx, mx_surface, "mtlx")
    mx.CreateDisplacementOutput("mtlx").ConnectToSource(mx_disp.ConnectableAPI(), "out")
    plain = UsdShade.Material.Define(stage, "/Root/Plain")
    _surface(plain, _shader(stage, "/Root/Plain/Surface", "UsdPreviewSurface",
                            diffuseColor=(T.Color3f, Gf.Vec3f(0.6, 0.3, 0.2))))
    stage.GetRootLayer().Save()
    write_doc(tmp_path, BUMPY_MTLX, name="bumpy.mtlx")
    ours, shader = _render(renderer, tmp_path / "bumpy.usda", "/Root/Bumpy")
    theirs, _ = _render(renderer, tmp_path / "bumpy.mtlx", "Bumpy")
    _same(ours, theirs, "Bumpy")
    assert "mg_displacement" in shader.vertex and "sampler2D" in shader.vertex
    flat, flat_shader = _render(renderer, tmp_path / "bumpy.usda", "/Root/Flat")
    plain_img, _ = _render(renderer, tmp_path / "bumpy.usda", "/Root/Plain")
    _same(flat, plain_img, "no displacement authored")
    assert "mg_displacement" not in flat_shader.vertex
    pushed, _ = _render(renderer, tmp_path / "bumpy.usda", "/Root/Pushed")
    # a constant 0.2 along the normal makes the unit sphere one of radius 1.2: it covers more of the image
    assert (pushed[..., 3] > 0).sum() > (plain_img[..., 3] > 0).sum() * 1.2
    assert np.abs(ours - plain_img).max() > 0.01, "the texture's displacement changes the picture"
    mx_pushed, mx_shader = _render(renderer, tmp_path / "bumpy.usda", "/Root/MxPushed")
    assert "mg_displacement" in mx_shader.vertex
    assert abs(int((mx_pushed[..., 3] > 0).sum()) - int((pushed[..., 3] > 0).sum())) <= 2
