"""One self-contained HTML page from a golden check's output directory (results.json + images).

Per material that did not pass: the golden, the new render, the diff heat map and the FLIP map where
there is one, all embedded as base64 PNG, and why it failed; per material its metric values (a
passing material has no images: `golden check` keeps images of failures only); materials sorted worst first (errors,
failures by failing-pixel fraction, FLIP and mean difference, then missing goldens, then passes).
No external resources: the file can be attached to a CI run and opened anywhere.

results.json may come from elsewhere (a CI artefact), so it is not trusted: it is read as a regular file of at
most MAX_BYTES["json"] (files.check_regular: no device, FIFO or /proc file), must be UTF-8 JSON of the shape
golden check writes (check_schema: each field the report reads, with its type; a status one of error, fail,
missing, pass), and every text from it reaches the page through escape.html_text / html_attr. An image is
embedded only when its `files` entry names a regular file inside the results folder (symlinks resolved),
within the image size cap, that starts with PNG's signature and decodes (images.read_image); an entry naming
a file that is gone is shown as no image. Anything else is one `results.json:LINE: field: problem` line (line
0 but for JSON syntax) and no report. The page is written through files.write_atomic.
"""
import base64
import json
import math
import os

from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.escape import html_attr, html_text
from mtlxgen.base.files import (MAX_BYTES, check_regular, is_inside, quoted, read_bounded, regular_file_problem,
                                write_atomic)
from mtlxgen.base.images import read_image

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


RESULTS = "results.json"
STATUSES = tuple(RANK)
# metrics golden.measure records: numbers (finite), FLIP's mean or null where FLIP is unavailable, texts, a flag;
# where the first key of a group is present the report reads the others too
NUMBER_METRICS = ("mean", "max", "failing_pixels", "fraction", "pixels", "threshold", "hdr_fraction",
                  "hdr_max_relative")
METRIC_GROUPS = (("fraction", ("failing_pixels", "pixels", "threshold", "mean", "max")),
                 ("hdr_fraction", ("hdr_max_relative",)), ("parity", ("parity_passes",)))


class _Invalid(Exception):
    """A field of results.json outside the schema: where (a path like results[2].status) and why."""

    def __init__(self, where, why):
        super().__init__("%s: %s" % (where, why) if where else why)


def _shown(value):
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _need(obj, kind, where):
    types = {"an object": dict, "a list": list, "a text": str}
    if not isinstance(obj, types[kind]):
        raise _Invalid(where, "%s is not %s" % (_shown(obj), kind))
    return obj


def _keys(obj, keys, where):
    for key in keys:
        if key not in obj:
            raise _Invalid(where, "missing %r" % key)


def _field(where, key):
    return "%s.%s" % (where, key) if where else key


def _check_number(obj, key, where, nullable=False):
    v = obj[key]
    if not (_is_number(v) or (nullable and v is None)):
        raise _Invalid(_field(where, key), "%s is not a finite number%s" % (_shown(v), " or null" if nullable else ""))


def _check_texts(items, where):
    for i, item in enumerate(_need(items, "a list", where)):
        _need(item, "a text", "%s[%d]" % (where, i))


def _check_metrics(m, where):
    _need(m, "an object", where)
    for lead, others in METRIC_GROUPS:
        if lead in m:
            _keys(m, others, where)
    for key in NUMBER_METRICS:
        if key in m:
            _check_number(m, key, where)
    if "flip" in m:
        _check_number(m, "flip", where, nullable=True)
    for key in ("parity", "size_mismatch"):
        if key in m:
            _need(m[key], "a text", _field(where, key))
    if "parity_passes" in m and not isinstance(m["parity_passes"], bool):
        raise _Invalid(_field(where, "parity_passes"), "%s is not true or false" % _shown(m["parity_passes"]))


def _check_settings(s, where):
    _need(s, "an object", where)
    for key in ("size", "samples", "environment"):
        if key in s and not (s[key] is None or isinstance(s[key], str) or _is_number(s[key])):
            raise _Invalid(_field(where, key), "%s is not a text or a number" % _shown(s[key]))
    if "lights" in s and s["lights"] is not None:
        _need(s["lights"], "a list", _field(where, "lights"))


def _check_result(r, where):
    _need(r, "an object", where)
    _keys(r, ("name", "source", "element", "status", "message", "metrics", "timings", "files", "settings"), where)
    for key in ("name", "source", "element"):
        _need(r[key], "a text", _field(where, key))
    if not isinstance(r["status"], str) or r["status"] not in STATUSES:
        raise _Invalid(_field(where, "status"), "%s is not one of %s" % (_shown(r["status"]), ", ".join(STATUSES)))
    _check_texts(r["message"], _field(where, "message"))
    _check_metrics(r["metrics"], _field(where, "metrics"))
    for key in _need(r["timings"], "an object", _field(where, "timings")):
        _check_number(r["timings"], key, _field(where, "timings"))
    for key, name in _need(r["files"], "an object", _field(where, "files")).items():
        _need(name, "a text", _field(_field(where, "files"), key))
    _check_settings(r["settings"], _field(where, "settings"))


def check_schema(data):
    """Raise _Invalid unless `data` has the shape golden.check writes to results.json (the fields the report
    reads, with their types; other fields are ignored)."""
    _need(data, "an object", "")
    _keys(data, ("results",), "")
    for i, r in enumerate(_need(data["results"], "a list", "results")):
        _check_result(r, "results[%d]" % i)
    if data.get("notes") is not None:
        _check_texts(data["notes"], "notes")
    if data.get("golden_dir") is not None:
        _need(data["golden_dir"], "a text", "golden_dir")
    tol = data.get("tolerance")
    if tol is not None:
        _need(tol, "an object", "tolerance")
        for key, nullable in (("threshold", False), ("max_fraction", True), ("hdr_relative", False), ("flip", True)):
            if key in tol:
                _check_number(tol, key, "tolerance", nullable)


def load_results(out_dir):
    """results.json of a check output folder: a regular file of at most MAX_BYTES["json"], UTF-8 JSON in the
    shape check_schema accepts; MtlxError (one line naming the file) otherwise."""
    path = os.path.join(out_dir, RESULTS)
    loc = Loc(path, 0)
    if not os.path.lexists(path):
        raise MtlxError((loc, "no check results here (run `mtlxgen golden check -o %s` first)" % out_dir))
    check_regular(path, loc, "the check results file", max_bytes="json")
    raw = read_bounded(path, loc, "the check results file", MAX_BYTES["json"])
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as e:
        raise MtlxError((loc, "not UTF-8 text (byte %d)" % e.start)) from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as e:
        raise MtlxError((Loc(path, e.lineno), "not JSON: %s (column %d)" % (e.msg, e.colno))) from None
    except RecursionError:
        raise MtlxError((loc, "not JSON this report reads: nested too deeply")) from None
    text = json.dumps(data, ensure_ascii=False)
    try:        # JSON may spell a lone UTF-16 surrogate (\ud800; golden check: a file name not in UTF-8):
        text.encode("utf-8")
    except UnicodeEncodeError:      # shown as U+FFFD, as a UTF-8 page can hold it
        data = json.loads(text.encode("utf-8", "surrogatepass").decode("utf-8", "replace"))
    try:
        check_schema(data)
    except _Invalid as e:
        raise MtlxError((loc, str(e))) from None
    return data


def sort_key(r):
    m = r.get("metrics") or {}
    return (RANK.get(r["status"], 0), -float(m.get("fraction") or 0.0), -float(m.get("hdr_fraction") or 0.0),
            -float(m.get("flip") or 0.0), -float(m.get("mean") or 0.0), r["name"])


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _image_problem(out_dir, name):
    """(why the image file `name`, inside the results folder, may not be embedded, None) or ("gone", None) where
    it no longer exists (not embedded, not an error), or (None, its bytes): a regular PNG file that decodes."""
    path = os.path.join(out_dir, name)
    problem = regular_file_problem(path, "image")
    if problem is not None:
        return ("gone", None) if problem.startswith("missing") else ("%s is %s" % (quoted(name), problem), None)
    try:
        data = read_bounded(path, Loc(path, 0), "image", MAX_BYTES["image"])
        if not data.startswith(PNG_SIGNATURE):
            return "%s is not a PNG image" % quoted(name), None
        read_image(path)            # decodes: a PNG signature before anything else is not enough
    except MtlxError as e:
        return "%s is not a PNG image (%s)" % (quoted(name), e.problems[0][1]), None
    return None, data


def embedded_images(data, out_dir):
    """{(result index, key): data URI} of the images the report shows (IMAGES) that exist. Every `files` entry
    must name a file inside the results folder (symlinks resolved); those shown must be regular PNG files
    (size-capped, decoded). MtlxError at results.json otherwise."""
    loc = Loc(os.path.join(out_dir, RESULTS), 0)
    shown = {key for key, _ in IMAGES}
    uris = {}
    for i, r in enumerate(data.get("results", [])):
        for key, name in sorted((r.get("files") or {}).items()):
            where = "results[%d].files.%s" % (i, key)
            if os.path.isabs(name) or not is_inside(os.path.join(out_dir, name), [os.path.realpath(out_dir)]):
                raise MtlxError((loc, "%s: %s is outside the results folder" % (where, quoted(name))))
            if key not in shown:
                continue
            problem, png = _image_problem(out_dir, name)
            if problem == "gone":
                continue
            if problem is not None:
                raise MtlxError((loc, "%s: %s" % (where, problem)))
            uris[(i, key)] = "data:image/png;base64," + base64.b64encode(png).decode("ascii")
    return uris


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


def render_html(data, out_dir, title="mtlxgen golden check", images=None):
    """The page for results `data` (as load_results returns them); images: embedded_images(data, out_dir),
    computed where not given. Every text from the results goes through escape.html_text / html_attr."""
    if images is None:
        images = embedded_images(data, out_dir)
    order = sorted(range(len(data.get("results", []))), key=lambda i: sort_key(data["results"][i]))
    results = [data["results"][i] for i in order]
    counts = {k: sum(1 for r in results if r["status"] == k) for k in ("fail", "error", "missing", "pass")}
    esc, attr = html_text, html_attr
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
    for i, r in zip(order, results):
        status = r["status"]
        parts.append('<section class="material %s" id="%s" data-status="%s">' % (attr(status), attr(r["name"]),
                                                                                attr(status)))
        parts.append('<h2><span class="badge %s">%s</span>%s</h2>' % (attr(status), esc(status.upper()),
                                                                      esc(r["name"])))
        parts.append('<p class="src">%s : %s</p>' % (esc(r["source"]), esc(r["element"])))
        if r.get("message"):
            parts.append('<ul class="why">%s</ul>' % "".join("<li>%s</li>" % esc(line) for line in r["message"]))
        if status == "pass":
            parts.append('<p class="passed">within tolerance; no images kept for passing materials</p>')
        figures = []
        for key, caption in IMAGES:
            uri = images.get((i, key))
            if uri is not None:
                figures.append('<figure><img class="%s" alt="%s" src="%s"><figcaption>%s</figcaption></figure>'
                               % (attr(key), attr("%s: %s" % (caption, r["name"])), attr(uri), esc(caption)))
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
    """Write the report for a check output directory (through a temporary file and a rename: a symlink at
    the output is replaced, never followed); returns the HTML file's path."""
    data = load_results(out_dir)
    html_path = html_path or os.path.join(out_dir, "report.html")
    text = render_html(data, out_dir, title)
    os.makedirs(os.path.dirname(os.path.abspath(html_path)), exist_ok=True)
    write_atomic(html_path, text)
    return html_path


# ---------------------------------------------------------------- shards (golden check --shard K/N)

def _shard_info(data, loc):
    """results.json's "shard" object ({"index": K, "count": N, "elements": all the shards' elements}) or None."""
    s = data.get("shard")
    if s is None:
        return None
    ok = isinstance(s, dict) and all(isinstance(s.get(k), int) and not isinstance(s.get(k), bool)
                                     for k in ("index", "count", "elements"))
    if not ok or not 1 <= s["index"] <= s["count"] or s["elements"] < 0:
        raise MtlxError((loc, "shard: %s is not {\"index\": K, \"count\": N, \"elements\": E} with 1 <= K <= N"
                         % _shown(s)))
    return s


def merge_shards(dirs, out_dir):
    """Merge the outputs of `golden check --shard K/N` runs (or of any checks of disjoint elements) into out_dir:
    one results.json (results in shard order, notes each once) and the failures' images copied beside it.
    Each results.json is read as load_results reads it (its schema checked) and its files as the report embeds
    them (embedded_images: inside its folder, PNGs that decode). Refused, one line naming the file: an element
    reported by two shards, shards of different counts or of different element sets (another commit), a shard
    twice, shard and plain outputs mixed, out_dir one of the shards. Missing shards (of the N) are a note and
    "complete": False in what is returned (the merged results.json's data plus "complete")."""
    out_real = os.path.realpath(out_dir)
    loaded, seen, infos = [], {}, []
    for d in dirs:
        loc = Loc(os.path.join(d, RESULTS), 0)
        if os.path.realpath(d) == out_real:
            raise MtlxError((loc, "the merged output folder is this shard's folder; give another with -o"))
        data = load_results(d)
        embedded_images(data, d)            # every files entry inside the folder, the images shown PNGs
        info = _shard_info(data, loc)
        for i, r in enumerate(data["results"]):
            if r["name"] in seen:
                raise MtlxError((loc, "results[%d]: %s (%s:%s) is also in %s; merge each shard once, of one check"
                                 % (i, r["name"], r["source"], r["element"], seen[r["name"]])))
            seen[r["name"]] = loc.file
        loaded.append((d, loc, data))
        infos.append((loc, info))
    sharded = [(loc, s) for loc, s in infos if s is not None]
    notes, complete = [], True
    if sharded:
        if len(sharded) != len(infos):
            loc = next(loc for loc, s in infos if s is None)
            raise MtlxError((loc, "not the output of a `golden check --shard K/N` run, merged with shards"))
        first_loc, first = sharded[0]
        indices = {}
        for loc, s in sharded:
            if s["count"] != first["count"] or s["elements"] != first["elements"]:
                raise MtlxError((loc, "shard %d/%d of %d elements, merged with shard %d/%d of %d elements (%s): "
                                 "shards of one check of one commit merge" % (s["index"], s["count"], s["elements"],
                                                                             first["index"], first["count"],
                                                                             first["elements"], first_loc.file)))
            if s["index"] in indices:
                raise MtlxError((loc, "shard %d/%d is also %s" % (s["index"], s["count"], indices[s["index"]])))
            indices[s["index"]] = loc.file
        missing = [k for k in range(1, first["count"] + 1) if k not in indices]
        if missing:
            complete = False
            notes.append("shard%s %s of %d not merged: %d of %d shards' elements are in this report"
                         % ("" if len(missing) == 1 else "s", ", ".join(str(k) for k in missing[:20]) +
                            (", ..." if len(missing) > 20 else ""), first["count"], first["count"] - len(missing),
                            first["count"]))
    tolerances = [data.get("tolerance") for _, _, data in loaded if data.get("tolerance") is not None]
    if any(t != tolerances[0] for t in tolerances):
        notes.append("the shards were checked with different tolerances (the first shard's is shown)")
    for _, _, data in loaded:
        notes += [n for n in data.get("notes") or [] if n not in notes]
    os.makedirs(out_dir, exist_ok=True)
    results = []
    for d, loc, data in loaded:
        for r in data["results"]:
            kept = {}
            for key, name in sorted(r["files"].items()):
                src = os.path.join(d, name)
                if regular_file_problem(src, "image") is not None:      # gone (a check keeps only failures')
                    continue
                write_atomic(os.path.join(out_dir, name), read_bounded(src, Loc(src, 0), "image", MAX_BYTES["image"]))
                kept[key] = name
            results.append(dict(r, files=kept))
    merged = {"golden_dir": loaded[0][2].get("golden_dir"), "tolerance": tolerances[0] if tolerances else None,
              "notes": notes, "results": results,
              "shards": [{"from": d, **(s or {})} for (d, _, _), (_, s) in zip(loaded, infos)]}
    write_atomic(os.path.join(out_dir, RESULTS), json.dumps(merged, indent=1, sort_keys=True) + "\n")
    return dict(merged, complete=complete)
