"""Strings from documents and stages are data in what `web` and `three` write, never code or markup.

A document whose names, interface input names, texture file names (real files, in folders whose names hold
`<!--`, `*` and `<`, a base name holding quotes, backticks, `${`, U+2028 and a line break), `colorspace`
attributes (holding `*/`, `</script>`, `<!--`, quotes, U+2028 and a line break) and a USD stage's `colorSpace`
metadata carry every character that ends a comment, a string, a script element or an HTML comment goes through
the CLI; the modules are imported in Node (no injected code runs at import, each value arrives intact), the
pages' embedded JSON parses, and no `</script>` or `<!--` of the document appears raw. One page is opened in
headless Chromium: no page error, no console output from injected code. The escaping functions themselves
(mtlxgen/base/escape.py) are checked on the same strings."""
import json
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

from mtlxgen.base import escape, images
from mtlxgen.apps import web

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STRIPES = os.path.join(ROOT, "examples", "usd", "stripes_r.png")

# every character that ends something in some context of the generated files
HOSTILE = ['*/', '</script>', '<!--', '-->', '`', '${x}', "'", '"', '\u2028', '\u2029', '\n', '\\', '&', '<', '>']
# names may hold neither '/' nor line breaks (the document reader refuses them): the rest
NAME = "<!--`${x}'\"*&<>\\"
# what a colour space attribute carries: a comment end followed by code, then the rest
CS = 'x*/;globalThis.PWNED=1;console.log("PWNED");/*</script><!--`${x}\'"\u2028\u2029\n-->\\'
# a texture path under the document's folder: folders "d<!--*" and "x<", so the path holds "*/" and "</script>"
TEX_PARTS = ["d<!--*", "x<", "script>'\"`${u}\u2028\n*.png"]
# the document's own file name (the shaders' header comment names it)
DOC_NAME = "h<!--`${x}'\"\u2028\n*\\.mtlx"


def _attr(text):
    from xml.sax.saxutils import quoteattr
    return quoteattr(text, {"\n": "&#10;", "\u2028": "&#x2028;", "\u2029": "&#x2029;"})


def hostile_document(folder):
    os.makedirs(os.path.join(folder, *TEX_PARTS[:-1]), exist_ok=True)
    shutil.copy(STRIPES, os.path.join(folder, *TEX_PARTS))
    tex = "/".join(TEX_PARTS)
    doc = os.path.join(folder, DOC_NAME)
    with open(doc, "w", encoding="utf-8") as f:
        f.write("""<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <nodegraph name=%(g)s>
    <input name=%(i)s type="color3" value="0.5, 0.5, 0.5" />
    <image name=%(n)s type="color3" colorspace=%(cs1)s>
      <input name="file" type="filename" value=%(tex)s colorspace=%(cs2)s />
    </image>
    <multiply name=%(m)s type="color3">
      <input name="in1" type="color3" nodename=%(n)s />
      <input name="in2" type="color3" interfacename=%(i)s />
    </multiply>
    <output name=%(o)s type="color3" nodename=%(m)s />
  </nodegraph>
  <image name=%(t)s type="color3" colorspace=%(cs3)s>
    <input name="file" type="filename" value=%(tex)s />
  </image>
  <output name=%(O)s type="color3" nodename=%(t)s />
</materialx>
""" % {"g": _attr("G" + NAME), "i": _attr("i" + NAME), "n": _attr("n" + NAME), "m": _attr("m" + NAME),
       "o": _attr("o" + NAME), "t": _attr("t" + NAME), "O": _attr("O" + NAME), "tex": _attr(tex),
       "cs1": _attr(CS + "1"), "cs2": _attr(CS + "2"), "cs3": _attr(CS + "3")})
    return doc


USD_CS = 'u*/;globalThis.PWNED=1;console.log("PWNED");/*</script><!--`${x}\'"\u2028\n'


def hostile_stage(folder):
    shutil.copy(STRIPES, os.path.join(folder, "tex.png"))
    path = os.path.join(folder, "s.usda")
    with open(path, "w", encoding="utf-8") as f:
        f.write("""#usda 1.0
def Material "M"
{
    token outputs:mtlx:surface.connect = </M/Surf.outputs:out>
    def Shader "Surf"
    {
        uniform token info:id = "ND_surface_unlit"
        color3f inputs:emission_color.connect = </M/Img.outputs:out>
        token outputs:out
    }
    def Shader "Img"
    {
        uniform token info:id = "ND_image_color3"
        asset inputs:file = @tex.png@ (
            colorSpace = %s
        )
        color3f outputs:out
    }
}
""" % json.dumps(USD_CS, ensure_ascii=False))     # USD strings take \" and \n escapes; U+2028 as it is
    return path


def cli(*argv):
    """`python cli.py ARGV` (the command line itself, in a fresh process)."""
    r = subprocess.run([sys.executable, os.path.join(ROOT, "cli.py"), *argv], capture_output=True, text=True,
                       timeout=600, cwd=ROOT)
    return r.returncode, r.stdout, r.stderr


@pytest.fixture(scope="module")
def hostile(tmp_path_factory):
    folder = str(tmp_path_factory.mktemp("hostile"))
    doc = hostile_document(folder)
    out = {}
    for command in ("web", "three"):
        out[command] = os.path.join(folder, "out_" + command)
        rc, stdout, stderr = cli(command, doc, "-o", out[command], "--size", "16", "--samples", "1")
        assert rc == 0, stderr
    return doc, out


def element_names():
    return {"G%s/o%s" % (NAME, NAME), "O" + NAME}


def modules(folder):
    return sorted(p for p in (os.path.join(folder, n) for n in os.listdir(folder))
                  if p.endswith(".js") and not p.endswith("mtlxgen_three.js"))


# ---------------------------------------------------------------- three: the modules

def _without_strings(text):
    """JavaScript text with its double-quoted string literals (the only ones generated text holds) removed."""
    return re.sub(r'"(?:[^"\\\n\r\u2028\u2029]|\\.)*"', '""', text)


def test_three_module_comment_holds_no_document_text_raw(hostile):
    doc, out = hostile
    js = modules(out["three"])
    assert len(js) == 2
    for path in js:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        head, sep, rest = text.partition("*/")
        assert sep and rest.startswith("\nimport * as runtime from './mtlxgen_three.js';"), \
            "the doc comment ends early: %r" % head[-200:]
        assert text.isascii() and "\u2028" not in text and "\u2029" not in text
        # what the document wrote appears inside string literals only
        code = _without_strings(text)
        assert "PWNED" not in code and "${x}" not in code and "<!--" not in code and "</script" not in code
        assert "</script" not in text.lower() and "<!--" not in text


def test_three_module_syntax_and_import_in_node(hostile, tmp_path):
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed")
    doc, out = hostile
    script = tmp_path / "import.mjs"
    script.write_text("""
const said = [];
for (const k of ["log", "warn", "error", "info", "debug"]) console[k] = (...a) => said.push(a.join(" "));
const m = await import(process.argv[2]);
process.stdout.write(JSON.stringify({ said, pwned: globalThis.PWNED === undefined ? null : globalThis.PWNED,
                                      element: m.element, manifest: m.manifest }));
""")
    got = {}
    for path in modules(out["three"]):
        check = subprocess.run([node, "--check", path], capture_output=True, text=True, timeout=60)
        assert check.returncode == 0, check.stderr
        r = subprocess.run([node, str(script), path], capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, r.stderr
        result = json.loads(r.stdout)
        assert result["said"] == [] and result["pwned"] is None, result["said"]
        got[result["element"]] = result["manifest"]
    assert set(got) == element_names()
    # every value arrives as the document wrote it
    colorspaces = {t["colorspace"] for m in got.values() for t in m["textures"]}
    assert colorspaces == {CS + "2", CS + "3"}
    assert {t["source"] for m in got.values() for t in m["textures"]} == {TEX_PARTS[-1]}
    assert all(t["url"] and t["url"].startswith("textures/") for m in got.values() for t in m["textures"])


def test_three_example_page_holds_no_document_markup(hostile):
    doc, out = hostile
    pages = sorted(p for p in os.listdir(out["three"]) if p.endswith(".html"))
    assert len(pages) == 2
    names = set()
    for page in pages:
        with open(os.path.join(out["three"], page), encoding="utf-8") as f:
            text = f.read()
        assert text.lower().count("</script") == 2 and text.count("<!--") == 1     # the template's own
        title = re.search(r"<title>(.*?) \(mtlxgen, three\.js\)</title>", text, re.S).group(1)
        assert "<" not in title and '"' not in title and "'" not in title
        import html
        names.add(html.unescape(title))
        module = re.search(r'const element = await import\((.*?)\);', text).group(1)
        assert json.loads(module) == "./%s.js" % page[:-5]
    assert names == element_names()


def test_usd_colorspace_metadata_is_data_in_the_module(tmp_path):
    node = shutil.which("node")
    stage = hostile_stage(str(tmp_path))
    out = tmp_path / "out"
    rc, stdout, stderr = cli("three", stage, "-o", str(out))
    assert rc == 0, stderr
    text = (out / "M.js").read_text(encoding="utf-8")
    assert text.partition("*/")[2].startswith("\nimport * as runtime")
    assert "PWNED" not in _without_strings(text)
    if node is None:
        pytest.skip("node is not installed")
    script = tmp_path / "import.mjs"
    script.write_text("""
const said = [];
for (const k of ["log", "warn", "error", "info", "debug"]) console[k] = (...a) => said.push(a.join(" "));
const m = await import(process.argv[2]);
process.stdout.write(JSON.stringify({ said, pwned: globalThis.PWNED === undefined ? null : 1, manifest: m.manifest }));
""")
    r = subprocess.run([node, str(script), str(out / "M.js")], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout)
    assert result["said"] == [] and result["pwned"] is None
    assert [t["colorspace"] for t in result["manifest"]["textures"]] == [USD_CS]


# ---------------------------------------------------------------- web: the pages

def page_json(text):
    m = re.search(r'<script type="application/json" id="mtlxgen-data">(.*?)</script>', text, re.S)
    return json.loads(m.group(1))


def test_web_page_json_parses_and_holds_the_names(hostile):
    doc, out = hostile
    pages = sorted(os.listdir(out["web"]))
    assert len(pages) == 2
    elements = set()
    for page in pages:
        with open(os.path.join(out["web"], page), encoding="utf-8") as f:
            text = f.read()
        assert text.lower().count("</script") == 2 and "<!--" not in text
        data = page_json(text)
        elements.add(data["element"])
        assert data["stem"] == page[:-5]
        assert [img["source"] for img in data["textures"]["images"]] == [TEX_PARTS[-1]]
        for stage in ("vertex", "fragment"):        # GLSL comments: one printable ASCII line, no backslash
            for line in data[stage].splitlines():
                comment = line.partition("//")[2]
                assert comment.isascii() and comment.isprintable() and "\\" not in comment, (stage, line)
        import html
        title = re.search(r"<title>(.*?) \(mtlxgen\)</title>", text, re.S).group(1)
        assert "<" not in title and html.unescape(title) == data["element"]
    assert elements == element_names()


def test_page_json_with_an_html_comment_opener_is_valid_json():
    """`<!--`, `-->`, `</script>` and U+2028 in any string of the page's data: the block parses as JSON, to
    the same value, and none of them appears raw."""
    data = {"element": "a<!--b-->c</script>d\u2028e\u2029&", "size": 8, "list": ["<!--", "</SCRIPT>"]}
    text = web.page_html(data)
    assert page_json(text) == data
    assert "<!--" not in text and "-->" not in text.split("</script>")[0] and text.lower().count("</script") == 2


def test_web_page_loads_in_chromium_without_running_document_text(hostile):
    from webpages import chromium_skip_reason, CHROMIUM, FLAGS
    reason = chromium_skip_reason()
    if reason:
        pytest.skip(reason)
    from playwright.sync_api import sync_playwright
    doc, out = hostile
    page_file = os.path.join(out["web"], sorted(os.listdir(out["web"]))[-1])
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS, headless=True)
        try:
            page = browser.new_page()
            said, errors = [], []
            page.on("console", lambda m: said.append(m.text))
            page.on("pageerror", lambda e: errors.append(str(e)))
            page.goto("file://" + page_file)
            page.wait_for_function("window.mtlxgen && (window.mtlxgen.ready || window.mtlxgen.error)", timeout=180_000)
            state = page.evaluate("({error: window.mtlxgen.error, pwned: window.PWNED === undefined ? null : 1,"
                                  " title: document.title, scripts: document.scripts.length})")
        finally:
            browser.close()
    assert errors == [] and not [s for s in said if "PWNED" in s], (errors, said)
    assert state["error"] is None and state["pwned"] is None and state["scripts"] == 2, state
    assert state["title"] == "O%s (mtlxgen)" % NAME


# ---------------------------------------------------------------- the escaping functions

@pytest.mark.parametrize("s", HOSTILE + ["".join(HOSTILE), CS, NAME])
def test_escape_functions(s):
    for f in (escape.html_text, escape.html_attr):
        e = f(s)
        assert not set(e) & set("<>\"'") and re.sub(r"&(amp|lt|gt|quot|#x27);", "", e).count("&") == 0
        import html
        assert html.unescape(e) == s
    for f in (escape.js_string, escape.json_in_script):
        e = f(s)
        assert json.loads(e) == s and e.isascii()
        assert not set(e) & set("<>&\n\r") and "\u2028" not in e
    c = escape.js_comment(s)
    assert json.loads(c) == s and "*/" not in c and c.isascii() and "\n" not in c and "<" not in c
    c = escape.js_comment({"k": [s, 1.5, None]})
    assert json.loads(c) == {"k": [s, 1.5, None]} and "*/" not in c and "\n" not in c
    g = escape.glsl_comment(s)
    assert g.isascii() and g.isprintable() and "*/" not in g and "\\" not in g and "\n" not in g


def test_json_in_script_keeps_structure():
    value = {"a": [1, 2.5, True, None, "x<y>&z"], "b": {"c": "\u2028"}}
    for kw in ({}, {"separators": (", ", ": ")}, {"indent": 1}):
        assert json.loads(escape.json_in_script(value, **kw)) == value


# ---------------------------------------------------------------- textures: decoded, never copied

def _png_with_secrets(path, secret):
    """A small RGBA PNG with a tEXt chunk holding `secret` before IEND and `secret` appended after it."""
    import struct
    import zlib
    img = (np.arange(4 * 4 * 4, dtype=np.uint16).reshape(4, 4, 4) * 4 % 256).astype(np.uint8)
    images.write_image(path, img)
    data = open(path, "rb").read()
    end = data.rindex(b"IEND") - 4
    body = b"Comment\0" + secret
    chunk = struct.pack(">I", len(body)) + b"tEXt" + body + struct.pack(">I", zlib.crc32(b"tEXt" + body))
    with open(path, "wb") as f:
        f.write(data[:end] + chunk + data[end:] + secret)
    return img


def _jpeg_with_secret(path, secret):
    import OpenImageIO as oiio
    spec = oiio.ImageSpec(8, 8, 3, oiio.UINT8)
    spec.attribute("ImageDescription", secret.decode())
    spec.attribute("Copyright", secret.decode())
    buf = oiio.ImageBuf(spec)
    buf.set_pixels(oiio.ROI(), np.full((8, 8, 3), 77, np.uint8))
    assert buf.write(path)
    with open(path, "ab") as f:
        f.write(secret)


def test_three_reencodes_textures_from_outside_the_document_folder(tmp_path):
    secret = b"SECRET-0b5e77-not-for-the-output"
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "doc").mkdir()
    png = str(tmp_path / "elsewhere" / "t.png")
    jpg = str(tmp_path / "elsewhere" / "t.jpg")
    _png_with_secrets(png, secret)
    _jpeg_with_secret(jpg, secret)
    assert secret in open(png, "rb").read() and secret in open(jpg, "rb").read()
    doc = tmp_path / "doc" / "m.mtlx"
    doc.write_text("""<?xml version="1.0"?>
<materialx version="1.39">
  <image name="a" type="color4"><input name="file" type="filename" value="../elsewhere/t.png" /></image>
  <image name="b" type="color4"><input name="file" type="filename" value="%s" /></image>
  <add name="ab" type="color4"><input name="in1" type="color4" nodename="a" /><input name="in2" type="color4" nodename="b" /></add>
  <output name="out" type="color4" nodename="ab" />
</materialx>
""" % jpg)
    out = tmp_path / "out"
    rc, stdout, stderr = cli("three", str(doc), "-o", str(out))
    assert rc == 0, stderr
    sources = {open(png, "rb").read(), open(jpg, "rb").read()}
    written = [p for p in out.rglob("*") if p.is_file()]
    for p in written:
        data = p.read_bytes()
        assert secret not in data, p
        assert data not in sources, p
    textures = sorted((out / "textures").iterdir())
    assert [t.suffix for t in textures] == [".png", ".png"]
    for src in (png, jpg):         # each file's pixels, as decoded, in a PNG of its own
        assert sum(_same_pixels(src, str(t)) for t in textures) == 1, src
    # the web page decodes too: neither the secret nor the file's bytes are embedded
    rc, stdout, stderr = cli("web", str(doc), "-o", str(tmp_path / "web"), "--size", "8", "--samples", "1")
    assert rc == 0, stderr
    (page,) = (tmp_path / "web").glob("*.html")
    text = page.read_text(encoding="utf-8")
    import base64
    assert secret.decode() not in text
    for img in page_json(text)["textures"]["images"]:
        for level in img["levels"]:
            assert secret not in base64.b64decode(level)
    for src in sources:
        assert base64.b64encode(src).decode()[:40] not in text


def _same_pixels(a, b):
    x, y = images.read_image(a), images.read_image(b)
    return x.shape == y.shape and np.array_equal(x, y)
