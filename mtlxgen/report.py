"""One self-contained HTML page from a golden check's output directory (results.json + images).

Per material that did not pass: the golden, the new render, the diff heat map and the FLIP map where
there is one, all embedded as base64 PNG, and why it failed; per material its metric values (a
passing material has no images: `golden check` keeps images of failures only); materials sorted worst first (errors,
failures by failing-pixel fraction, FLIP and mean difference, then missing goldens, then passes).
No external resources: the file can be attached to a CI run and opened anywhere.
"""
import base64
import html
import json
import os

from .diagnostics import Loc, MtlxError

RANK = {"error": 0, "fail": 1, "missing": 2, "pass": 3}
IMAGES = (("golden", "golden"), ("new", "new render"), ("diff", "difference"), ("flip", "FLIP error"))

CSS = """
body { font: 14px/1.4 system-ui, sans-serif; margin: 24px; background: #f4f4f6; color: #222; }
h1 { font-size: 20px; margin: 0 0 4px; }
.summary span { display: inline-block; margin-right: 14px; }
.notes { color: #8a5a00; }
section.material { background: #fff; border-radius: 6px; margin: 14px 0; padding: 12px 16px;
  border-left: 6px solid #4a4; box-shadow: 0 1px 2px rgba(0,0,0,.15); }
section.fail, section.error { border-left-color: #d33; }
section.missing { border-left-color: #e90; }
h2 { font-size: 16px; margin: 0; }
.badge { font-size: 12px; padding: 1px 6px; border-radius: 3px; color: #fff; background: #4a4; margin-right: 6px; }
.badge.fail, .badge.error { background: #d33; } .badge.missing { background: #e90; }
.passed { color: #4a4; margin: 2px 0; }
.src { color: #666; margin: 2px 0 8px; font-family: monospace; }
.why { color: #b00; margin: 4px 0 8px; padding-left: 18px; font-family: monospace; white-space: pre-wrap; }
.images { display: flex; gap: 12px; flex-wrap: wrap; }
figure { margin: 0; text-align: center; font-size: 12px; color: #555; }
figure img { width: 256px; height: 256px; image-rendering: pixelated; display: block;
  background: repeating-conic-gradient(#ccc 0% 25%, #eee 0% 50%) 50% / 16px 16px; }
.placeholder { width: 256px; height: 256px; display: flex; align-items: center; justify-content: center;
  background: #eee; color: #888; }
table.metrics { border-collapse: collapse; margin-top: 8px; font-size: 13px; }
table.metrics td { padding: 1px 10px 1px 0; } table.metrics td:first-child { color: #666; }
"""

SCRIPT = """
window.addEventListener('load', function () {
  var sections = document.querySelectorAll('section.material'), shown = 0;
  Array.prototype.forEach.call(sections, function (s) {
    var ok = Array.prototype.some.call(s.querySelectorAll('img'), function (i) {
      return i.complete && i.naturalWidth > 0; });
    s.setAttribute('data-image-shown', ok ? 'yes' : 'no');
    if (ok) shown++;
  });
  document.body.setAttribute('data-materials', String(sections.length));
  document.body.setAttribute('data-materials-with-image', String(shown));
  document.body.setAttribute('data-not-passing',
    String(document.querySelectorAll('section.material:not(.pass)').length));
});
"""


def load_results(out_dir):
    path = os.path.join(out_dir, "results.json")
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise MtlxError((Loc(path, 0), "cannot read check results (run `mtlxgen golden check -o %s` first): %s"
                         % (out_dir, e)))


def sort_key(r):
    m = r.get("metrics") or {}
    return (RANK.get(r["status"], 0), -float(m.get("fraction") or 0.0), -float(m.get("hdr_fraction") or 0.0),
            -float(m.get("flip") or 0.0), -float(m.get("mean") or 0.0), r["name"])


def _data_uri(path):
    with open(path, "rb") as f:
        return "data:image/png;base64," + base64.b64encode(f.read()).decode("ascii")


def _metric_rows(r):
    m, t, rows = r.get("metrics") or {}, r.get("timings") or {}, []
    if "fraction" in m:
        rows.append(("failing pixels", "%d of %d (%.3f%%) over %d/255" % (m["failing_pixels"], m["pixels"],
                                                                         100 * m["fraction"], m["threshold"])))
        rows.append(("mean / max difference", "%.3f / %d (8-bit steps)" % (m["mean"], m["max"])))
    if "hdr_fraction" in m:
        rows.append(("linear EXR", "%.3f%% over relative limit, max relative %g" % (100 * m["hdr_fraction"],
                                                                                   m["hdr_max_relative"])))
    if "flip" in m:
        rows.append(("FLIP (mean)", "unavailable" if m["flip"] is None else "%.5f" % m["flip"]))
    if "parity" in m:
        rows.append(("scoreboard parity", "%s (%s)" % ("pass" if m["parity_passes"] else "fail", m["parity"])))
    if t:
        rows.append(("time", ", ".join("%s %.1f ms" % (k[:-2], 1000 * v) for k, v in sorted(t.items()))))
    s = r.get("settings") or {}
    if s:
        rows.append(("settings", "%spx, env %s, %s samples, %d lights" % (s.get("size"), s.get("environment"),
                                                                       s.get("samples"), len(s.get("lights") or []))))
    return rows


def render_html(data, out_dir, title="mtlxgen golden check"):
    results = sorted(data.get("results", []), key=sort_key)
    counts = {k: sum(1 for r in results if r["status"] == k) for k in ("fail", "error", "missing", "pass")}
    esc = html.escape
    tol = data.get("tolerance") or {}
    parts = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
             "<title>%s</title>" % esc(title), "<style>%s</style>" % CSS, "</head><body>",
             "<h1>%s</h1>" % esc(title),
             '<p class="summary">%s</p>' % "".join('<span class="count-%s">%d %s</span>' % (k, v, k)
                                                  for k, v in counts.items()),
             "<p>A pixel fails when a channel differs by more than %s/255 (sRGB 8-bit); a material fails when "
             "%s. FLIP: NVIDIA's perceptual error, 0 identical to 1.</p>"
             % (esc(str(tol.get("threshold", "?"))), "any of its pixels fails" if not tol.get("max_fraction") else
                esc("more than %g%% of its pixels fail" % (100 * float(tol["max_fraction"]))))]
    for note in data.get("notes") or []:
        parts.append('<p class="notes">%s</p>' % esc(note))
    for r in results:
        status = r["status"]
        parts.append('<section class="material %s" id="%s" data-status="%s">' % (status, esc(r["name"]), status))
        parts.append('<h2><span class="badge %s">%s</span>%s</h2>' % (status, status.upper(), esc(r["name"])))
        parts.append('<p class="src">%s : %s</p>' % (esc(r["source"]), esc(r["element"])))
        if r.get("message"):
            parts.append('<ul class="why">%s</ul>' % "".join("<li>%s</li>" % esc(line) for line in r["message"]))
        if status == "pass":
            parts.append('<p class="passed">within tolerance; no images kept for passing materials</p>')
        figures = []
        for key, caption in IMAGES:
            name = (r.get("files") or {}).get(key)
            if name and os.path.exists(os.path.join(out_dir, name)):
                figures.append('<figure><img class="%s" alt="%s: %s" src="%s"><figcaption>%s</figcaption></figure>'
                               % (key, esc(caption), esc(r["name"]), _data_uri(os.path.join(out_dir, name)),
                                  esc(caption)))
        if not figures and status != "pass":
            figures.append('<figure><div class="placeholder">%s</div><figcaption>&nbsp;</figcaption></figure>'
                           % ("no golden yet" if status == "missing" else "not rendered"))
        if figures:
            parts.append('<div class="images">%s</div>' % "".join(figures))
        rows = _metric_rows(r)
        if rows:
            parts.append('<table class="metrics">%s</table>' % "".join(
                "<tr><td>%s</td><td>%s</td></tr>" % (esc(k), esc(v)) for k, v in rows))
        parts.append("</section>")
    parts += ["<script>%s</script>" % SCRIPT, "</body></html>", ""]
    return "\n".join(parts)


def write_report(out_dir, html_path=None, title="mtlxgen golden check"):
    """Write the report for a check output directory; returns the HTML file's path."""
    data = load_results(out_dir)
    html_path = html_path or os.path.join(out_dir, "report.html")
    text = render_html(data, out_dir, title)
    os.makedirs(os.path.dirname(os.path.abspath(html_path)), exist_ok=True)
    with open(html_path, "w", encoding="utf-8") as f:
        f.write(text)
    return html_path
