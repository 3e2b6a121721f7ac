"""Headless Chromium for tests/apps/test_web.py and tests/apps/test_three.py: Debian's /usr/bin/chromium (WebGL2 on
SwiftShader) driven by Python's playwright, never a downloaded browser; pages' pixels read back from their
canvas and compared with `mtlxgen render`'s at the parity line (mean <= 2/255, <= 1% of pixels over 8/255)."""
import base64
import functools
import http.server
import os
import shutil
import threading

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIZE, SAMPLES = 128, 32             # both the page (or three's example) and render draw at these

# the materials issue 13 names, drawn by test_web and test_three: (test id, document, element)
CASES = [
    ("standard_surface", "examples/quick_start.mtlx", "M_tiles"),
    ("open_pbr_surface", "examples/openpbr/open_pbr_released_names.mtlx", "coated_red_mat"),
    ("gltf_pbr", "tests/data/materialx/resources/Materials/Examples/GltfPbr/gltf_pbr_default.mtlx", "Default"),
    ("UsdPreviewSurface_textured_cutout", "examples/usd/usd_seed_rules.mtlx", "leaf"),
    ("textured_standard_surface", "tests/data/web/textured.mtlx", "M_textured"),
    ("enterprise_pbr", "examples/enterprise/enterprise_car_paint.mtlx", "M_car_paint"),
]


def path(rel):
    return os.path.join(ROOT, rel)


CHROMIUM = os.environ.get("MTLXGEN_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
# WebGL2 without a GPU: ANGLE on SwiftShader; no network, no first-run or component traffic
FLAGS = ["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-background-networking",
         "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-default-apps",
         "--force-color-profile=srgb"]
PAGE_TIMEOUT_MS = 180_000          # SwiftShader compiles a large fragment shader in tens of seconds on a busy core
MEAN_LIMIT = 2.0                   # 8-bit steps
OVER_STEPS, OVER_FRACTION = 8, 0.01


def chromium_skip_reason():
    if not (os.path.isfile(CHROMIUM) and os.access(CHROMIUM, os.X_OK)):
        return "no Chromium at %s (Debian: apt-get install chromium)" % CHROMIUM
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "Python playwright is not installed (pip install playwright; it drives Debian's chromium)"
    return None


@pytest.fixture(scope="module")
def browser():
    reason = chromium_skip_reason()
    if reason:
        pytest.skip(reason)
    from playwright.sync_api import sync_playwright
    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS, headless=True)
        try:
            gl = _webgl2_probe(b)
            if gl is not True:
                pytest.skip("Chromium at %s gives no WebGL2 with EXT_color_buffer_float here: %s" % (CHROMIUM, gl))
            yield b
        finally:
            b.close()


def _webgl2_probe(b):
    page = b.new_page()
    try:
        page.set_content("<canvas></canvas>")
        return page.evaluate("""() => { const gl = document.querySelector('canvas').getContext('webgl2');
            if (!gl) return 'no webgl2 context';
            return gl.getExtension('EXT_color_buffer_float') ? true : 'no EXT_color_buffer_float'; }""")
    finally:
        page.close()


class Opened:
    """A page after it drew (window.mtlxgen.ready) or failed (window.mtlxgen.error)."""

    def __init__(self, page, requests, console):
        self.page, self.requests, self.console = page, requests, console

    def pixels(self):
        """The canvas's RGBA8, rows top first, as the page reads it back (gl.readPixels)."""
        data = base64.b64decode(self.page.evaluate("window.mtlxgen.pixels()"))
        n = int(round((len(data) // 4) ** 0.5))
        return np.frombuffer(data, np.uint8).reshape(n, n, 4).copy()

    def screenshot(self, path):
        """What the browser shows of the canvas (composited over the page's black), RGB8; the PNG goes to path."""
        import OpenImageIO as oiio
        self.page.locator("#view").screenshot(path=str(path), animations="disabled", scale="css")
        return np.asarray(oiio.ImageBuf(str(path)).get_pixels(oiio.UINT8))[..., :3]


def open_page(browser, url, offline=False):
    """Open url in a fresh page (device scale 1); fail with the page's own message where it reports one.
    offline: refuse every request but the page itself and data: URLs (Opened.refused lists them)."""
    context = browser.new_context(device_scale_factor=1, viewport={"width": 800, "height": 800})
    page = context.new_page()
    requests, console, refused = [], [], []
    if offline:
        def route(r):
            if r.request.url.startswith("data:") or r.request.url == url:
                return r.continue_()
            refused.append(r.request.url)
            return r.abort()
        context.route("**/*", route)
    page.on("request", lambda r: requests.append(r.url))
    page.on("console", lambda m: console.append(m.text))
    page.on("pageerror", lambda e: console.append("pageerror: %s" % e))
    page.goto(url)
    page.wait_for_function("window.mtlxgen && (window.mtlxgen.ready || window.mtlxgen.error)",
                           timeout=PAGE_TIMEOUT_MS)
    error = page.evaluate("window.mtlxgen.error")
    if error:
        context.close()
        pytest.fail("%s reports: %s\nconsole: %s" % (url, error[:4000], "\n".join(console)[:2000]))
    opened = Opened(page, requests, console)
    opened.refused = refused
    return opened


def parity(got, want):
    """(mean |difference| in 8-bit steps over RGB, share of pixels with a channel (alpha too) over OVER_STEPS)."""
    d = np.abs(got.astype(np.int16) - want.astype(np.int16))
    return float(d[..., :3].mean()), float((d.max(-1) > OVER_STEPS).mean())


def assert_parity(name, got, want):
    mean, over = parity(got, want)
    print("%-24s mean %.3f/255, %.3f%% of pixels > %d/255" % (name, mean, 100 * over, OVER_STEPS))
    assert got.shape == want.shape, (got.shape, want.shape)
    assert mean <= MEAN_LIMIT and over <= OVER_FRACTION, \
        "%s: mean %.3f/255 (limit %.1f), %.3f%% of pixels over %d/255 (limit %.0f%%)" % (
            name, mean, MEAN_LIMIT, 100 * over, OVER_STEPS, 100 * OVER_FRACTION)
    return mean, over


def over_black(rgba8):
    """An RGBA8 image (straight alpha) as a page shows it over its black background."""
    a = rgba8[..., 3:4].astype(np.float64) / 255.0
    return np.clip(np.round(rgba8[..., :3] * a), 0, 255).astype(np.uint8)


class Server:
    """A folder served over HTTP on 127.0.0.1 (ES modules do not load from file:// pages)."""

    def __init__(self, folder):
        class Quiet(http.server.SimpleHTTPRequestHandler):
            def log_message(self, *args):
                pass
        self.httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(Quiet, directory=str(folder)))
        self.thread = threading.Thread(target=self.httpd.serve_forever, daemon=True)
        self.thread.start()

    def url(self, name):
        return "http://127.0.0.1:%d/%s" % (self.httpd.server_address[1], name)

    def close(self):
        self.httpd.shutdown()
        self.httpd.server_close()


def three_cache():
    """The folder .ci/run installs three.js into with npm (`npm install --prefix FOLDER three`)."""
    return os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "mtlxgen", "npm")


def npm_three():
    """node_modules/three as npm installed it: MTLXGEN_THREE_DIR, else the cache folder .ci/run installs it into.
    The tests never install it themselves (they never reach the network): without it they skip, saying how to
    install it."""
    given = os.environ.get("MTLXGEN_THREE_DIR")
    if given:
        if not os.path.isfile(os.path.join(given, "build", "three.module.js")):
            pytest.skip("MTLXGEN_THREE_DIR=%s holds no build/three.module.js" % given)
        return given
    cache = three_cache()
    three = os.path.join(cache, "node_modules", "three")
    if os.path.isfile(os.path.join(three, "build", "three.module.js")):
        return three
    pytest.skip("three.js is not installed: `npm install --prefix %s three` (as .ci/run does), or set "
                "MTLXGEN_THREE_DIR to a node_modules/three" % cache)
