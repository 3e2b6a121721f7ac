"""mtlxgen three: the ES module's material, in three.js from npm, draws what `mtlxgen render` draws.

The example page each element gets (three from npm linked beside it, served over HTTP on 127.0.0.1 as ES
modules need) is opened in headless Chromium (Debian's, WebGL2 on SwiftShader, driven by playwright); its
canvas is compared with the renderer's image of the same element, camera, size and samples. The module's
API is also checked in Node without a browser. Without an installed three (MTLXGEN_THREE_DIR, or the cache
folder .ci/run installs it into: the tests never install it), chromium or playwright, the tests that need them
skip, saying why."""
import json
import os
import shutil
import subprocess

import numpy as np
import pytest

from mtlxgen.apps import cli, three
from mtlxgen.base import images
from mtlxgen import pipeline
from mtlxgen.draw import renderer as render
from webpages import CASES, SAMPLES, SIZE, Server, assert_parity, browser, npm_three, open_page  # noqa: F401
from webpages import path as _path



@pytest.fixture(scope="module")
def three_dir():
    return npm_three()


@pytest.fixture(scope="module")
def renderer():
    with render.Renderer(size=SIZE, env_samples=SAMPLES) as r:
        yield r


def write_module(out, doc, element, three=None, *extra):
    rc = cli.main(["three", _path(doc), "-o", str(out), "--element", element, "--size", str(SIZE),
                   "--samples", str(SAMPLES)] + list(extra))
    assert rc == 0
    if three:
        os.symlink(three, out / "three")
    stem = pipeline.generate(_path(doc), elements=[element])[0].stem
    return stem


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_three_example_draws_what_render_draws(browser, three_dir, renderer, tmp_path, case):
    name, doc, element = case
    stem = write_module(tmp_path, doc, element, three_dir)
    server = Server(tmp_path)
    try:
        opened = open_page(browser, server.url(stem + ".html"))
        got = opened.pixels()
        manifest = json.loads(opened.page.evaluate("JSON.stringify(window.mtlxgen.material.userData.mtlxgen.manifest)"))
        # textures as three holds them: raw colour (the shader converts), the manifest's wrap and filter
        for t in manifest["textures"]:
            state = opened.page.evaluate("""(name) => { const t = window.mtlxgen.material.uniforms[name].value;
                return [!!(t.isDataTexture && t.image.width === 1), t.colorSpace, t.wrapS, t.wrapT, t.minFilter]; }""",
                                         t["uniform"])
            wrap = {"periodic": 1000, "clamp": 1001, "mirror": 1002, "constant": 1001}     # THREE.*Wrapping
            assert state == [False, "", wrap[t["uaddressmode"]], wrap[t["vaddressmode"]], 1008], (t, state)
        assert not [r for r in opened.requests if not r.startswith(server.url(""))]
        opened.page.context.close()
    finally:
        server.close()
    shader = pipeline.generate(_path(doc), elements=[element])[0]
    want = images.to_srgb8(renderer.render(shader))
    assert_parity("three %s" % name, got, want)


def test_three_prefiltered_draws_what_render_draws(browser, three_dir, renderer, tmp_path):
    """--environment prefiltered: the example page passes the environment through the module's
    prefilterEnvironment (render's environment.Prefilter recipe on three's renderer) and draws what render draws
    with its prefiltered map, at the fis pages' line."""
    doc, element = "examples/quick_start.mtlx", "M_tiles"
    stem = write_module(tmp_path, doc, element, three_dir, "--environment", "prefiltered")
    module = (tmp_path / (stem + ".js")).read_text(encoding="utf-8")
    assert "export const prefilter = " in module and "mg_env_prefilter_texel" in module
    assert "element.prefilterEnvironment(THREE, renderer" in (tmp_path / (stem + ".html")).read_text(encoding="utf-8")
    server = Server(tmp_path)
    try:
        opened = open_page(browser, server.url(stem + ".html"))
        got = opened.pixels()
        bound = opened.page.evaluate("""() => { const t = window.mtlxgen.material.uniforms.u_envRadiance.value;
            return [t.mipmaps.length, t.wrapS, t.wrapT, t.minFilter]; }""")
        assert not [m for m in opened.console if "box-filtered" in m], opened.console
        opened.page.context.close()
    finally:
        server.close()
    assert bound == [10, 1000, 1001, 1008], bound      # 512 x 256: 10 levels; repeat u, clamp v, trilinear
    shader = pipeline.generate(_path(doc), elements=[element], environment="prefiltered")[0]
    want = images.to_srgb8(renderer.render(shader))
    assert_parity("three prefiltered %s" % element, got, want)


def test_three_fis_module_and_page_hold_no_prefilter(tmp_path):
    stem = write_module(tmp_path, "examples/quick_start.mtlx", "M_tiles")
    module = (tmp_path / (stem + ".js")).read_text(encoding="utf-8")
    assert "export const prefilter" not in module and "mg_env_prefilter_texel" not in module
    with open(os.path.join(os.path.dirname(os.path.dirname(three.__file__)), "web_assets", "three_example.html"), encoding="utf-8") as f:
        template = f.read()
    page = (tmp_path / (stem + ".html")).read_text(encoding="utf-8")
    assert three.ENV_LINE in template and three.ENV_LINE in page and "prefilterEnvironment" not in page


@pytest.mark.parametrize("doc, element", [("examples/unlit_checker.mtlx", "M_checker"),
                                          ("tests/data/targets/struct_uniform.mtlx", "out")],
                         ids=["unlit_checker", "struct_uniform"])
def test_three_unlit_is_render_to_the_byte(browser, three_dir, renderer, tmp_path, doc, element):
    """Unlit (no sampling): inside the sphere three's canvas holds render's bytes; a uniform of the document's
    own struct type is set member by member."""
    stem = write_module(tmp_path, doc, element, three_dir)
    server = Server(tmp_path)
    try:
        opened = open_page(browser, server.url(stem + ".html"))
        got = opened.pixels()
        opened.page.context.close()
    finally:
        server.close()
    want = images.to_srgb8(renderer.render(pipeline.generate(_path(doc), elements=[element])[0]))
    inside = (want[..., 3] == 255) & (got[..., 3] == 255)
    assert inside.sum() > 0.99 * (want[..., 3] == 255).sum() > 0.3 * SIZE * SIZE
    assert np.abs(got.astype(int) - want.astype(int))[inside].max() <= 1
    assert_parity("three %s" % element, got, want)


def test_module_api_in_node(three_dir, tmp_path):
    """Without a browser: createMaterial's uniforms hold the manifest's values, onBeforeRender sets the
    matrices from the object and camera, prepareGeometry shares three's buffers under our names."""
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed")
    stem = write_module(tmp_path, "examples/usd/usd_seed_rules.mtlx", "leaf")
    script = tmp_path / "check.mjs"
    script.write_text("""
import * as THREE from %s;
import * as element from %s;
console.warn = () => {};      // TextureLoader has no Image in Node: the textures keep their default colours
const m = element.createMaterial(THREE, { envSamples: 48 });
const mesh = new THREE.Mesh(element.prepareGeometry(THREE, new THREE.SphereGeometry(1, 16, 8)), m);
mesh.position.set(1, 2, 3);
mesh.updateMatrixWorld();
const camera = new THREE.PerspectiveCamera(45, 1, 0.1, 100);
camera.position.set(0, 0, 5);
camera.updateMatrixWorld();
m.onBeforeRender(null, null, camera, mesh.geometry, mesh);
const g = mesh.geometry.attributes;
const out = {
  raw: m.isRawShaderMaterial, glsl3: m.glslVersion === THREE.GLSL3, side: m.side === THREE.DoubleSide,
  version: /^#version/.test(m.fragmentShader), structTernary: /BSDF \\w+ = \\([^;]*\\? /.test(m.fragmentShader),
  uniforms: Object.fromEntries(element.manifest.uniforms.map((u) => {
    const v = m.uniforms[u.name].value;
    return [u.name, v && v.toArray ? v.toArray() : v];
  })),
  samples: m.uniforms.u_envRadianceSamples.value,
  envMatrix: m.uniforms.u_envMatrix.value.toArray(),
  world: m.uniforms.u_worldMatrix.value.toArray(),
  viewPosition: m.uniforms.u_viewPosition.value.toArray(),
  shared: g.i_position === g.position && g.i_normal === g.normal && g.i_texcoord_0 === g.uv && g.i_tangent === g.tangent,
  bitangent: g.i_bitangent.itemSize,
  sampler: m.uniforms.leaf_tex_file.value.isDataTexture,
  sphere: element.createSphere(THREE).attributes.position.count,
};
console.log(JSON.stringify(out));
""" % (json.dumps(os.path.join(three_dir, "build", "three.module.js")), json.dumps(str(tmp_path / (stem + ".js")))))
    r = subprocess.run([node, str(script)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout.strip().splitlines()[-1])
    manifest = json.loads((tmp_path / (stem + ".js")).read_text().split("export const manifest = ", 1)[1]
                          .split(";\n", 1)[0])
    assert out["raw"] and out["glsl3"] and out["side"] and not out["version"] and not out["structTernary"]
    for u in manifest["uniforms"]:
        assert np.allclose(np.ravel(out["uniforms"][u["name"]]).astype(float), np.ravel(u["value"]).astype(float)), u
    assert out["samples"] == 48
    assert out["envMatrix"] == [-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, 1]
    assert out["world"][12:15] == [1, 2, 3] and out["viewPosition"] == [0, 0, 5]
    assert out["shared"] and out["bitangent"] == 3 and out["sampler"]
    assert out["sphere"] == 129 * 65


def test_textures_written_beside_the_module(tmp_path):
    """Texture files are decoded and their pixels written afresh to OUT/textures/ (8-bit sources as PNG, the same
    8-bit values), never copied; one that does not decode is refused as render refuses it (one line at the input
    naming it, the element not written, nothing of the file anywhere); the module's manifest names the written
    files relative to itself."""
    (tmp_path / "doc").mkdir()
    (tmp_path / "doc" / "fake.png").write_text("secret, not an image")
    shutil.copy(_path("examples/usd/stripes_r.png"), tmp_path / "doc" / "stripes.png")
    shutil.copy(_path("tests/data/materialx/resources/Images/onyx_roughness.jpg"), tmp_path / "doc" / "rough.jpg")
    doc = tmp_path / "doc" / "m.mtlx"
    doc.write_text("""<?xml version="1.0"?>
<materialx version="1.39">
  <image name="a" type="color3"><input name="file" type="filename" value="fake.png" /></image>
  <image name="b" type="color3"><input name="file" type="filename" value="stripes.png" />
    <input name="uaddressmode" type="string" value="mirror" /></image>
  <image name="c" type="float"><input name="file" type="filename" value="rough.jpg" /></image>
  <add name="ab" type="color3"><input name="in1" type="color3" nodename="a" /><input name="in2" type="color3" nodename="b" /></add>
  <add name="abc" type="color3"><input name="in1" type="color3" nodename="ab" /><input name="in2" type="float" nodename="c" /></add>
  <output name="out" type="color3" nodename="abc" />
</materialx>
""")
    refused = tmp_path / "refused"
    assert cli.main(["three", str(doc), "-o", str(refused)]) == 1
    assert not list(refused.glob("out*.js")) and b"secret" not in b"".join(
        p.read_bytes() for p in refused.rglob("*") if p.is_file())
    doc.write_text(doc.read_text().replace('value="fake.png"', 'value="stripes.png"'))
    out = tmp_path / "out"
    assert cli.main(["three", str(doc), "-o", str(out)]) == 0
    copies = sorted(p.name for p in (out / "textures").iterdir())
    assert len(copies) == 2 and copies[0].startswith("rough-") and copies[0].endswith(".png")
    assert copies[1].startswith("stripes-") and copies[1].endswith(".png")
    for copy, source in zip(copies, ("rough.jpg", "stripes.png")):      # the decoded pixels, exactly
        got, want = images.read_image(str(out / "textures" / copy)), images.read_image(str(tmp_path / "doc" / source))
        assert got.shape == want.shape and np.array_equal(got, want), copy
    jpeg = (tmp_path / "doc" / "rough.jpg").read_bytes()
    assert (out / "textures" / copies[0]).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and jpeg[:2] == b"\xff\xd8"
    module = next(out.glob("*.js"), None)
    text = [p for p in out.glob("*.js") if p.name != "mtlxgen_three.js"][0].read_text()
    manifest = json.loads(text.split("export const manifest = ", 1)[1].split(";\n", 1)[0])
    urls = {t["source"]: t["url"] for t in manifest["textures"]}
    assert urls == {"stripes.png": "textures/" + copies[1], "rough.jpg": "textures/" + copies[0]}
    assert all("file" not in t for t in manifest["textures"])       # no absolute paths of the author's machine
    assert module is not None and "secret" not in "".join(p.read_text(errors="replace") for p in out.rglob("*.js"))
    assert (out / "environment.exr").is_file() and (out / "mtlxgen_three.js").is_file()


def test_environment_written_is_render_sky(tmp_path):
    """environment.exr holds the built-in sky as render lights with it, 32-bit float."""
    assert cli.main(["three", _path("examples/usd/usd_seed_rules.mtlx"), "-o", str(tmp_path), "--element", "gold"]) == 0
    env = images.read_image(str(tmp_path / "environment.exr"))
    assert np.array_equal(env, render.builtin_sky())


def test_outputs_replace_symlinks_never_follow_them(tmp_path):
    """Every file three writes (module, page, runtime, environment, textures) goes through a temporary file and a
    rename: a symlink already at an output path is replaced by the file, and what it pointed to is untouched."""
    out = tmp_path / "out"
    args = ["three", _path("examples/usd/usd_seed_rules.mtlx"), "-o", str(out), "--element", "leaf"]
    assert cli.main(args) == 0
    written = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    assert set(written) >= {"leaf.js", "leaf.html", "mtlxgen_three.js", "environment.exr"}
    assert any(w.startswith("textures/") for w in written)
    first = {w: (out / w).read_bytes() for w in written}
    shutil.copytree(out, tmp_path / "first")
    (tmp_path / "victims").mkdir()
    for i, w in enumerate(written):
        victim = tmp_path / "victims" / str(i)
        victim.write_text("victim %d" % i)
        os.remove(out / w)
        os.symlink(str(victim), out / w)
    assert cli.main(args) == 0
    for i, w in enumerate(written):
        assert (tmp_path / "victims" / str(i)).read_text() == "victim %d" % i, w
        assert not os.path.islink(out / w), w
        if w.endswith((".png", ".exr")):        # OpenEXR headers carry the time of writing: compare the pixels
            assert np.array_equal(images.read_image(str(out / w)), images.read_image(str(tmp_path / "first" / w))), w
        else:
            assert (out / w).read_bytes() == first[w], w


def test_texture_folder_that_is_a_symlink_is_refused(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (tmp_path / "elsewhere").mkdir()
    os.symlink(str(tmp_path / "elsewhere"), out / "textures")
    rc = cli.main(["three", _path("examples/usd/usd_seed_rules.mtlx"), "-o", str(out), "--element", "leaf"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 1 and len(err) == 1 and err[0].startswith(str(out / "textures") + ":0: is a symbolic link"), err
    assert os.listdir(tmp_path / "elsewhere") == []


def _deep_textures(folder):
    """A 16-bit grey + alpha PNG and a float RGB OpenEXR carrying a metadata text, in `folder`."""
    import OpenImageIO as oiio
    rng = np.random.RandomState(7)
    ga = (rng.rand(6, 5, 2) * 65535).astype(np.uint16)
    spec = oiio.ImageSpec(5, 6, 2, oiio.UINT16)
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), ga)
    assert buf.write(os.path.join(folder, "ga16.png"))
    rgb = (rng.rand(4, 3, 3) * 8).astype(np.float32)
    spec = oiio.ImageSpec(3, 4, 3, oiio.FLOAT)
    spec.attribute("ImageDescription", "METADATA-NOT-FOR-OUTPUT")
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), rgb)
    assert buf.write(os.path.join(folder, "hdr.exr"))
    return os.path.join(folder, "ga16.png"), os.path.join(folder, "hdr.exr")


def test_textures_of_more_than_8_bits_are_written_as_float_exr(tmp_path):
    """Sources deeper than 8 bits keep their values: a 32-bit float OpenEXR of the decoded pixels (grey + alpha
    as R, G and a zero B), no metadata of the source."""
    from mtlxgen.apps import three
    ga16, hdr = _deep_textures(str(tmp_path))
    textures = three.TextureFiles(str(tmp_path / "out"))
    url_ga, url_hdr = textures.url(ga16), textures.url(hdr)
    assert url_ga.startswith("textures/ga16-") and url_ga.endswith(".exr") and url_hdr.endswith(".exr")
    got = images.read_image(str(tmp_path / "out" / url_ga))
    want = images.read_image(ga16)
    assert got.shape == (6, 5, 3) and np.array_equal(got[..., :2], want) and not got[..., 2].any()
    assert np.array_equal(images.read_image(str(tmp_path / "out" / url_hdr)), images.read_image(hdr))
    assert b"METADATA-NOT-FOR-OUTPUT" not in (tmp_path / "out" / url_hdr).read_bytes()
    assert textures.url(ga16) == url_ga and len(os.listdir(tmp_path / "out" / "textures")) == 2   # each once


def test_written_exr_textures_load_in_threes_exr_loader(three_dir, tmp_path):
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed")
    from mtlxgen.apps import three
    ga16, hdr = _deep_textures(str(tmp_path))
    textures = three.TextureFiles(str(tmp_path / "out"))
    script = tmp_path / "exr.mjs"
    script.write_text("""
import * as THREE from %s;
import { EXRLoader } from %s;
import * as fs from "fs";
const b = fs.readFileSync(process.argv[2]);
const r = new EXRLoader().setDataType(THREE.FloatType).parse(b.buffer.slice(b.byteOffset, b.byteOffset + b.length));
console.log(JSON.stringify({ width: r.width, height: r.height, rgba: r.format === THREE.RGBAFormat, data: Array.from(r.data) }));
""" % (json.dumps(os.path.join(three_dir, "build", "three.module.js")),
       json.dumps(os.path.join(three_dir, "examples", "jsm", "loaders", "EXRLoader.js"))))
    for source in (ga16, hdr):
        written = str(tmp_path / "out" / textures.url(source))
        r = subprocess.run([node, str(script), written], capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, r.stderr
        out = json.loads(r.stdout)
        want = images.read_image(source)
        h, w, c = want.shape
        assert out["rgba"] and (out["width"], out["height"]) == (w, h)
        data = np.array(out["data"], dtype=np.float32).reshape(h, w, 4)[::-1]      # three's rows: bottom first
        assert np.array_equal(data[..., :c], want), source
