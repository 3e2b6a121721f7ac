"""mtlxgen web: the self-contained WebGL2 page draws what `mtlxgen render` draws.

Headless Chromium (Debian's, WebGL2 on SwiftShader, driven by playwright) opens each page from file:// with
every other request refused; the canvas it drew (read back, and as the browser shows it) is compared with
the renderer's image of the same element, camera, size and sample count. Without chromium or playwright the
browser tests skip, saying why; the rest (mip chains against OpenGL's, WebGL's struct rule, the command's
errors) run anyway."""
import json
import os
import re

import numpy as np
import pytest

from mtlxgen.apps import cli, web
from mtlxgen.base import images
from mtlxgen import pipeline
from mtlxgen.draw import renderer as render
from mtlxgen.base.diagnostics import MtlxError
from webpages import CASES, ROOT, SAMPLES, SIZE, assert_parity, browser, open_page, over_black  # noqa: F401
from webpages import path as _path



@pytest.fixture(scope="module")
def renderer():
    with render.Renderer(size=SIZE, env_samples=SAMPLES) as r:
        yield r


def reference(renderer, doc, element):
    """`mtlxgen render`'s PNG bytes of the element (the default target) at SIZE and SAMPLES."""
    shader = pipeline.generate(_path(doc), elements=[element])[0]
    return images.to_srgb8(renderer.render(shader))


def write_page(tmp_path, doc, element, *extra):
    rc = cli.main(["web", _path(doc), "-o", str(tmp_path), "--element", element, "--size", str(SIZE),
                   "--samples", str(SAMPLES)] + list(extra))
    assert rc == 0
    pages = list(tmp_path.glob("*.html"))
    assert len(pages) == 1, pages
    return pages[0]


def open_offline(browser, page_path):
    """Open a page from file:// with every request that is not the page itself (or data:) refused."""
    opened = open_page(browser, page_path.as_uri(), offline=True)
    return opened, opened.refused


@pytest.mark.parametrize("case", CASES, ids=[c[0] for c in CASES])
def test_web_page_draws_what_render_draws(browser, renderer, tmp_path, case):
    name, doc, element = case
    page_path = write_page(tmp_path, doc, element)
    html = page_path.read_text(encoding="utf-8")
    # self-contained: no script, style, image or font from anywhere
    assert not re.search(r"""(?:src|href)\s*=\s*["']?(?:https?:|//|file:)""", html, re.I)
    assert "@import" not in html and "url(" not in html
    opened, refused = open_offline(browser, page_path)
    assert refused == [], "the page asked for %s" % refused
    want = reference(renderer, doc, element)
    got = opened.pixels()
    assert_parity("web %s" % name, got, want)
    # what the browser shows: the canvas over the page's black background
    shown = opened.screenshot(tmp_path / "shown.png")
    assert_parity("web %s shown" % name, shown, over_black(want))
    opened.page.context.close()


PREFILTERED = [c for c in CASES if c[0] in ("standard_surface", "open_pbr_surface")]


@pytest.mark.parametrize("case", PREFILTERED, ids=[c[0] for c in PREFILTERED])
def test_prefiltered_page_draws_what_render_draws(browser, renderer, tmp_path, case):
    """--environment prefiltered: the page GGX-prefilters the map on the GPU (environment.Prefilter's recipe,
    web_assets/prefilter.js) and draws what render draws with its prefiltered map, at the fis pages' line."""
    name, doc, element = case
    page_path = write_page(tmp_path, doc, element, "--environment", "prefiltered")
    html = page_path.read_text(encoding="utf-8")
    assert "prefilterRadiance" in html and "mg_env_prefilter_texel" in html
    opened, refused = open_offline(browser, page_path)
    assert refused == [], "the page asked for %s" % refused
    assert not [m for m in opened.console if "box-filtered" in m], opened.console
    shader = pipeline.generate(_path(doc), elements=[element], environment="prefiltered")[0]
    want = images.to_srgb8(renderer.render(shader))
    got = opened.pixels()
    assert_parity("web prefiltered %s" % name, got, want)
    opened.page.context.close()


def test_prefiltered_page_without_the_pass_is_off(browser, renderer, tmp_path):
    """The control for the test above: the same page binding the box chain (no prefilter pass) is visibly off
    render's prefiltered picture of standard_surface, so parity there says the pass ran as render's does."""
    from webpages import OVER_FRACTION, parity
    doc, element = "examples/quick_start.mtlx", "M_tiles"
    shader = pipeline.generate(_path(doc), elements=[element], environment="prefiltered", target="essl")[0]
    data = web.page_data(shader, web.environment_payload(), SIZE, SAMPLES)
    del data["prefilter"]
    page_path = tmp_path / "box.html"
    page_path.write_text(web.page_html(data), encoding="utf-8")
    opened, _ = open_offline(browser, page_path)
    got = opened.pixels()
    opened.page.context.close()
    want = images.to_srgb8(renderer.render(pipeline.generate(_path(doc), elements=[element], environment="prefiltered")[0]))
    mean, over = parity(got, want)
    assert over > 2 * OVER_FRACTION, (mean, over)


def test_fis_page_holds_no_prefilter_code(tmp_path):
    """Only pages of prefiltered shaders carry the prefilter pass; a fis page's viewer is viewer.js as it is."""
    fis = write_page(tmp_path / "fis", "examples/quick_start.mtlx", "M_tiles").read_text(encoding="utf-8")
    pre = write_page(tmp_path / "pre", "examples/quick_start.mtlx", "M_tiles", "--environment", "prefiltered")
    pre = pre.read_text(encoding="utf-8")
    assert "prefilterRadiance" not in fis and "/*PREFILTER*/" not in fis and '"prefilter"' not in fis
    with open(os.path.join(ROOT, "mtlxgen", "web_assets", "viewer.js"), encoding="utf-8") as f:
        viewer = f.read()
    assert viewer.replace(web.PREFILTER_MARK, "") in fis
    assert "prefilterRadiance" in pre and '"prefilter"' in pre


UNLIT = [("examples/unlit_checker.mtlx", "M_checker"),
         ("tests/data/targets/struct_uniform.mtlx", "out")]      # a uniform of the document's own struct type


@pytest.mark.parametrize("doc, element", UNLIT, ids=["unlit_checker", "struct_uniform"])
def test_unlit_page_is_render_to_the_byte(browser, renderer, tmp_path, doc, element):
    """No sampling in an unlit shader: inside the sphere the page holds render's bytes (to rounding)."""
    page_path = write_page(tmp_path, doc, element)
    opened, _ = open_offline(browser, page_path)
    got = opened.pixels()
    opened.page.context.close()
    want = reference(renderer, doc, element)
    assert (want[..., 3] == 255).sum() > 0.3 * SIZE * SIZE
    inside = (want[..., 3] == 255) & (got[..., 3] == 255)       # edge pixels: the rasterizers' coverage differs
    assert inside.sum() > 0.99 * (want[..., 3] == 255).sum()
    assert np.abs(got.astype(int) - want.astype(int))[inside].max() <= 1
    assert_parity("web %s" % element, got, want)


def test_orbit_and_zoom(browser, tmp_path):
    """Dragging turns the view, a double click brings back render's exact view, the wheel zooms in."""
    page_path = write_page(tmp_path, "examples/usd/usd_seed_rules.mtlx", "gold")
    opened, _ = open_offline(browser, page_path)
    page = opened.page
    first = opened.pixels()
    box = page.locator("#view").bounding_box()
    cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2

    def frames():
        return page.evaluate("window.mtlxgen.frames")

    n = frames()
    page.mouse.move(cx, cy)
    page.mouse.down()
    page.mouse.move(cx + 30, cy + 10, steps=3)
    page.mouse.up()
    page.wait_for_function("window.mtlxgen.frames > %d" % n)
    assert page.evaluate("window.mtlxgen.orbit.azimuth") < 0
    turned = opened.pixels()
    assert np.abs(turned.astype(int) - first.astype(int)).max() > 40      # the sun's highlight moved

    n = frames()
    page.mouse.dblclick(cx, cy)
    page.wait_for_function("window.mtlxgen.frames > %d && window.mtlxgen.orbit.azimuth === 0" % n)
    page.wait_for_timeout(400)          # the drag's full-sample redraw, if still pending, lands first
    page.evaluate("window.mtlxgen.draw()")
    assert np.array_equal(opened.pixels(), first)

    n = frames()
    page.mouse.move(cx, cy)
    page.mouse.wheel(0, -400)
    page.wait_for_function("window.mtlxgen.frames > %d" % n)
    assert page.evaluate("window.mtlxgen.orbit.radius") < 3.0
    zoomed = opened.pixels()
    assert (zoomed[..., 3] > 0).sum() > 1.3 * (first[..., 3] > 0).sum()
    opened.page.context.close()


def test_environment_file_is_the_one_drawn(browser, renderer, tmp_path):
    """--env: the page lights with that image (here a white furnace), as render does."""
    env_path = _path("examples/enterprise/white_furnace.hdr")
    page_path = write_page(tmp_path, "examples/usd/usd_seed_rules.mtlx", "gold", "--env", env_path)
    opened, _ = open_offline(browser, page_path)
    env = render.load_environment(env_path)
    with render.Renderer(size=SIZE, env_samples=SAMPLES, environment=env) as r:
        want = images.to_srgb8(r.render(pipeline.generate(_path("examples/usd/usd_seed_rules.mtlx"), elements=["gold"])[0]))
    assert_parity("web gold --env furnace", opened.pixels(), want)
    sky = reference(renderer, "examples/usd/usd_seed_rules.mtlx", "gold")
    assert np.abs(sky.astype(int) - want.astype(int))[..., :3].mean() > 10     # not the sky's picture
    opened.page.context.close()


def _project_essl_shaders():
    import glob
    out = []
    for doc in sorted(glob.glob(_path("examples/**/*.mtlx"), recursive=True)
                      + glob.glob(_path("tests/data/**/*.mtlx"), recursive=True)):
        try:
            shaders, _ = pipeline.generate(doc, partial=True, target="essl")
        except Exception:           # documents that are meant to fail (tests of errors)
            continue
        out += [("%s:%s" % (os.path.relpath(doc, ROOT), s.element), s) for s in shaders]
    return out


def test_every_project_element_is_valid_webgl(browser):
    """WebGL's validator (ANGLE, stricter than GLSL ES 3.00) compiles and links every element of examples/ and
    tests/data as the pages and modules carry it."""
    shaders = _project_essl_shaders()
    assert len(shaders) > 100
    page = browser.new_page()
    try:
        page.set_content("<canvas></canvas>")
        failures = []
        for name, s in shaders:
            log = page.evaluate("""([v, f]) => {
                const gl = document.querySelector('canvas').getContext('webgl2'), p = gl.createProgram();
                for (const [type, src] of [[gl.VERTEX_SHADER, v], [gl.FRAGMENT_SHADER, f]]) {
                    const sh = gl.createShader(type);
                    gl.shaderSource(sh, src);
                    gl.compileShader(sh);
                    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) return gl.getShaderInfoLog(sh);
                    gl.attachShader(p, sh);
                }
                gl.linkProgram(p);
                return gl.getProgramParameter(p, gl.LINK_STATUS) ? '' : 'link: ' + gl.getProgramInfoLog(p);
            }""", [s.vertex, s.fragment])
            if log:
                failures.append("%s: %s" % (name, log.strip().splitlines()[0]))
        assert not failures, "%d of %d refused:\n%s" % (len(failures), len(shaders), "\n".join(failures[:20]))
    finally:
        page.close()


# ---------------------------------------------------------------- without a browser

@pytest.mark.parametrize("shape", [(8, 16, 3), (5, 10, 3), (3, 7, 4), (6, 13, 1), (1, 9, 2), (256, 512, 3)])
def test_mip_chain_is_what_opengl_builds(renderer, shape):
    """The levels a page uploads are the ones render's GL build_mipmaps makes (odd sizes too)."""
    rng = np.random.default_rng(sum(shape))
    img = rng.random(shape).astype(np.float32) * 4.0
    levels = web.mip_chain(img)
    tex = renderer._float_texture(img, mipmaps=True, top_first=True)
    try:
        assert len(levels) == int(np.floor(np.log2(max(shape[:2])))) + 1
        for i, level in enumerate(levels):
            h, w, c = level.shape
            gl = np.frombuffer(tex.read(level=i), dtype="f4").reshape(h, w, c)
            np.testing.assert_allclose(level, gl, rtol=1e-5, atol=1e-6, err_msg="level %d" % i)
    finally:
        tex.release()


def test_page_text_from_a_document_is_inert():
    """An element's name is text in the page: escaped in HTML, a JSON string in the data, never a placeholder."""
    data = {"element": "</script><b>{{DATA}}", "size": 8}
    html = web.page_html(data)
    assert "</script><b>" not in html and html.count('id="mtlxgen-data"') == 1
    assert "&lt;/script&gt;&lt;b&gt;{{DATA}}" in html
    assert json.loads(re.search(r'id="mtlxgen-data">(.*?)</script>', html, re.S).group(1)) == data


def test_page_data_holds_the_manifest_values(tmp_path):
    shader = pipeline.generate(_path("examples/usd/usd_seed_rules.mtlx"), elements=["leaf"], target="essl")[0]
    data = web.page_data(shader, web.environment_payload(), SIZE, SAMPLES)
    assert data["uniforms"] == shader.manifest["uniforms"]
    assert {a["name"] for a in data["application"]} >= {"u_envRadiance", "u_viewProjectionMatrix"}
    assert data["samples"] == SAMPLES and data["size"] == SIZE
    assert data["environment"]["mips"] == 10 and len(data["environment"]["radiance"]["levels"]) == 10
    (sampler, index), = data["textures"]["samplers"].items()
    image = data["textures"]["images"][index]
    assert sampler == "leaf_tex_file" and image["channels"] == 2 and image["source"] == "leaf_ga.png"
    assert not re.search(r"\bBSDF \w+ = \([^;]*\? ", data["fragment"])


# ---------------------------------------------------------------- errors: one line, status 1

def _run(capsys, *argv):
    rc = cli.main(list(argv))
    err = capsys.readouterr().err.strip().splitlines()
    return rc, err


@pytest.mark.parametrize("argv, message", [
    (["--size", "0"], "argument --size: 0 is out of range"),
    (["--samples", "0"], "argument --samples: 0 is out of range"),
    (["--samples", "many"], "argument --samples: 'many' is not a whole number"),
    (["--env", "/nonexistent.hdr"], "argument --env: /nonexistent.hdr: no such file"),
])
def test_bad_options(capsys, tmp_path, argv, message):
    for command in ("web", "three"):
        rc, err = _run(capsys, command, _path("examples/quick_start.mtlx"), "-o", str(tmp_path), *argv)
        assert rc == 1 and len(err) == 1 and message in err[0], err


def test_missing_document(capsys, tmp_path):
    rc, err = _run(capsys, "web", str(tmp_path / "nope.mtlx"), "-o", str(tmp_path / "out"))
    assert rc == 1 and err == ["%s:0: no such file" % (tmp_path / "nope.mtlx")]


def test_environment_too_big(capsys, tmp_path, monkeypatch):
    monkeypatch.setattr(web, "MAX_ENV_PIXELS", 100)
    env = _path("examples/enterprise/white_furnace.hdr")
    rc, err = _run(capsys, "web", _path("examples/quick_start.mtlx"), "-o", str(tmp_path), "--env", env)
    assert rc == 1 and len(err) == 1
    assert err[0].startswith(env + ":0: environment of ") and "larger than a web page embeds" in err[0]
    assert not list(tmp_path.glob("*.html"))


def test_texture_too_big_fails_that_element_only(capsys, tmp_path, monkeypatch):
    monkeypatch.setattr(web, "MAX_TEXTURE_PIXELS", 100)
    rc, err = _run(capsys, "web", _path("examples/usd/usd_seed_rules.mtlx"), "-o", str(tmp_path), "--size", "8",
                   "--samples", "1")
    assert rc == 1 and len(err) == 2
    assert all("texture of " in line and "larger than a web page embeds" in line for line in err)
    assert sorted(p.name for p in tmp_path.glob("*.html")) == ["gold.html"]


def test_device_texture_refused(capsys, tmp_path):
    doc = tmp_path / "dev.mtlx"
    doc.write_text("""<?xml version="1.0"?>
<materialx version="1.39">
  <image name="img" type="color3"><input name="file" type="filename" value="/dev/zero" /></image>
  <output name="out" type="color3" nodename="img" />
</materialx>
""")
    for command in ("web", "three"):
        rc, err = _run(capsys, command, str(doc), "-o", str(tmp_path / command))
        assert rc == 1 and err == ["%s:3: texture '/dev/zero' is a system file (under /dev); the image's default is "
                                   "drawn" % doc], err


def test_texture_that_does_not_decode_is_an_error_at_its_input(tmp_path, capsys):
    """A texture file that does not decode is refused as render refuses it: one line at the input naming the file
    (the decoder's words), the element not written, exit 1 (it drew the default colour in silence)."""
    (tmp_path / "fake.png").write_text("not an image")
    doc = tmp_path / "fake.mtlx"
    doc.write_text("""<?xml version="1.0"?>
<materialx version="1.39">
  <image name="img" type="color3"><input name="file" type="filename" value="fake.png" />
    <input name="default" type="color3" value="0.25, 0.5, 0.75" /></image>
  <output name="out" type="color3" nodename="img" />
</materialx>
""")
    shader = pipeline.generate(str(doc), target="essl")[0]
    with pytest.raises(MtlxError) as e:
        web.texture_payload(shader.manifest)
    assert e.value.lines()[0].startswith("%s:0: " % (tmp_path / "fake.png")), e.value.lines()
    for command in ("web", "three", "render"):
        rc, err = _run(capsys, command, str(doc), "-o", str(tmp_path / command))
        assert rc == 1 and len(err) == 1 and err[0].startswith(
            "%s:3: texture '%s': " % (doc, tmp_path / "fake.png")), err
        assert not os.path.exists(tmp_path / command / ("out.html" if command == "web" else
                                                         "out.js" if command == "three" else "out.png"))


def test_page_replaces_a_symlink_never_follows_it(tmp_path):
    """The page is written through a temporary file and a rename: a symlink at OUT/STEM.html is replaced."""
    victim = tmp_path / "victim.txt"
    victim.write_text("keep me")
    out = tmp_path / "out"
    out.mkdir()
    os.symlink(str(victim), out / "gold.html")
    assert cli.main(["web", _path("examples/usd/usd_seed_rules.mtlx"), "-o", str(out), "--element", "gold",
                     "--size", "8", "--samples", "1"]) == 0
    assert victim.read_text() == "keep me"
    assert not os.path.islink(out / "gold.html") and "mtlxgen-data" in (out / "gold.html").read_text()
