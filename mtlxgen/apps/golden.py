"""Golden-image regression: render materials, compare them with stored goldens, or rewrite the goldens.

Layout of a golden directory (default ./golden_images):

    index.json                      one entry per golden: source file, element, render settings
    <file stem>__<element>.png      the golden, sRGB 8-bit RGBA (alpha linear), as `render` writes it
    <file stem>__<element>.exr      the linear render (half float), only where HDR matters: when some
                                    RGB value lies outside [0, 1] and the PNG therefore clips it

Element paths name goldens with "/" replaced by "_" (NG_waves/waves -> math_outputs__NG_waves_waves).
Sources are stored relative to the golden directory's parent (the project root).

The metric (defaults below, overridable per run and per golden with a "tolerance" object in the
index): per pixel the max-channel difference over R, G, B and A in 8-bit sRGB steps
(compare.diff_map); a pixel fails when it exceeds THRESHOLD; a golden fails when more than
MAX_FRACTION of its pixels fail. With an EXR golden the linear values must also agree: a pixel fails
when its largest relative difference exceeds HDR_RELATIVE. NVIDIA's FLIP (the `flip-evaluator`
package) is computed as a perceptual score for every golden that differs at all; it gates only when
a FLIP limit is set. The scoreboard's parity verdict (compare.parity) is recorded alongside.
"""
import hashlib
import json
import os
from mtlxgen.base.records import asdict, dataclass

import numpy as np

from mtlxgen.apps import batch
from mtlxgen.draw import compare
from mtlxgen.apps.batch import RenderSettings
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.files import MAX_BYTES, check_regular, is_inside, read_bounded, regular_file_problem, write_atomic
from mtlxgen.base.images import read_image, to_srgb8, write_image
from mtlxgen.options import GenerateOptions
from mtlxgen.apps.report import _shown

INDEX_NAME = "index.json"
INDEX_VERSION = 1
DEFAULT_DIR = "golden_images"
DEFAULT_OUT = os.path.join("out", "golden")

THRESHOLD = 2            # 8-bit sRGB steps a pixel may differ by (max over channels) before it fails
MAX_FRACTION = 0.0       # share of pixels allowed to fail: none, so one changed pixel is caught
HDR_RELATIVE = 0.01      # EXR goldens: relative difference |new - golden| / max(1, |golden|) per channel
FLIP_LIMIT = None        # mean FLIP error allowed (None: FLIP is reported, not gated)
HDR_EPS = 1e-3


@dataclass(frozen=True)
class Tolerance:
    threshold: int = THRESHOLD
    max_fraction: float = MAX_FRACTION
    hdr_relative: float = HDR_RELATIVE
    flip: float = FLIP_LIMIT

    def merged(self, overrides):
        """This tolerance with the fields named in an index entry's "tolerance" object replaced."""
        if not overrides:
            return self
        d = asdict(self)
        d.update({k: v for k, v in overrides.items() if k in d})
        return Tolerance(**d)


def golden_name(path, element):
    """FILE__ELEMENT: the element's part as generate names its files (emit.file_stem: '/' as '_', and safe
    and bounded for any name a document holds); FILE alone for no element (a document that cannot be read).
    A file name with a line break or another control character (which the index refuses), or one that is not
    UTF-8 (held with surrogates, which no image library or JSON reader takes), is made safe as element names are."""
    from mtlxgen.emit.emitter import file_stem
    stem = os.path.splitext(os.path.basename(path))[0]
    if not stem.isprintable():
        stem = file_stem(stem)
    return "%s__%s" % (stem, file_stem(element)) if element else stem     # (no element: a file-wide problem)


def is_hdr(img):
    rgb = img[..., :3]
    return bool(np.any(rgb > 1.0 + HDR_EPS) or np.any(rgb < -HDR_EPS))


# ---------------------------------------------------------------- FLIP

def flip_module():
    """(flip_evaluator module, None) or (None, why it is unavailable)."""
    try:
        import flip_evaluator
        flip_evaluator.evaluate  # noqa: B018  (an old or broken install lacks it)
        return flip_evaluator, None
    except Exception as e:
        return None, ("FLIP score unavailable: cannot import flip_evaluator (pip install flip-evaluator): %s"
                      % (str(e).strip() or type(e).__name__))


def flip_score(golden8, new8):
    """Mean LDR FLIP error of two sRGB 8-bit images and its magma heat map (uint8 RGB).

    Returns (mean, heat map) or (None, None) when flip_evaluator cannot be imported."""
    flip, _ = flip_module()
    if flip is None:
        return None, None
    ref = np.ascontiguousarray(golden8[..., :3], dtype=np.float32) / 255.0
    test = np.ascontiguousarray(new8[..., :3], dtype=np.float32) / 255.0
    err, mean, _ = flip.evaluate(ref, test, "LDR", applyMagma=True)
    heat = (np.clip(np.asarray(err, dtype=np.float32), 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8)
    return float(mean), heat


# ---------------------------------------------------------------- metric

def measure(new, golden8, golden_exr=None, tolerance=Tolerance(), flip=True):
    """Compare a linear render with a golden (sRGB 8-bit, plus its linear EXR if it has one).

    Returns (metrics dict, diff map of 8-bit steps, FLIP heat map or None)."""
    new8 = to_srgb8(new)
    if new8.shape[:2] != golden8.shape[:2]:
        return {"size_mismatch": "render %dx%d, golden %dx%d" % (new8.shape[1], new8.shape[0], golden8.shape[1],
                                                                  golden8.shape[0])}, None, None
    channels = min(new8.shape[-1], golden8.shape[-1])
    d = compare.diff_map(new8, golden8, channels)
    over = d > tolerance.threshold
    p = compare.parity(new8, golden8)
    m = {"mean": round(float(d.mean()), 4), "max": int(d.max()), "failing_pixels": int(over.sum()),
         "fraction": float(over.mean()), "pixels": int(d.size), "threshold": tolerance.threshold,
         "parity": str(p), "parity_passes": bool(p.passes)}
    if golden_exr is not None and golden_exr.shape[:2] == new.shape[:2]:
        c = min(new.shape[-1], golden_exr.shape[-1])
        stored = new[..., :c].astype(np.float16).astype(np.float32)    # the precision the EXR keeps
        ref = golden_exr[..., :c]
        rel = (np.abs(stored - ref) / np.maximum(1.0, np.abs(ref))).max(-1)
        m["hdr_fraction"] = float((rel > tolerance.hdr_relative).mean())
        m["hdr_max_relative"] = round(float(rel.max()), 6)
    heat = None
    if flip:
        if m["max"] == 0:
            m["flip"] = 0.0                    # identical pixels: FLIP is zero by definition
        else:
            m["flip"], heat = flip_score(golden8, new8)
    return m, d, heat


def verdict(metrics, tolerance):
    """(passes, [reasons it fails])."""
    if "size_mismatch" in metrics:
        return False, ["size differs: %s" % metrics["size_mismatch"]]
    why = []
    if metrics["fraction"] > tolerance.max_fraction:
        why.append("%d %s (%.3f%%) by more than %d/255 (max %d/255; allowed %.3f%%)"
                   % (metrics["failing_pixels"], "pixel differs" if metrics["failing_pixels"] == 1 else "pixels differ",
                      100 * metrics["fraction"], tolerance.threshold, metrics["max"], 100 * tolerance.max_fraction))
    if metrics.get("hdr_fraction", 0.0) > tolerance.max_fraction:
        why.append("linear EXR: %.3f%% of pixels differ by more than %g relative (max %g)"
                   % (100 * metrics["hdr_fraction"], tolerance.hdr_relative, metrics["hdr_max_relative"]))
    if tolerance.flip is not None and metrics.get("flip") is not None and metrics["flip"] > tolerance.flip:
        why.append("FLIP %.5f above %.5f" % (metrics["flip"], tolerance.flip))
    return not why, why


def heat_map(d, golden8, threshold):
    """Diff visualisation (uint8 RGB): the golden dimmed to grey; differing pixels from dark red
    (1 step) to yellow (32+ steps); pixels over the threshold at least bright red."""
    grey = golden8[..., :3].astype(np.float32).mean(-1) * 0.3
    out = np.stack([grey] * 3, -1)
    t = np.clip(d / 32.0, 0.0, 1.0)
    color = np.stack([96 + 159 * np.minimum(1.0, 3 * t), 255 * np.clip(1.5 * t - 0.5, 0, 1),
                      255 * np.clip(3 * t - 2, 0, 1)], -1)
    color[d > threshold, 0] = 255
    out = np.where((d > 0)[..., None], color, out)
    failing = np.argwhere(d > threshold)
    if 0 < len(failing) <= 64:           # a few isolated pixels: ring each so a reviewer can find it
        h, w = d.shape
        for y, x in failing:
            y0, y1, x0, x1 = max(y - 4, 0), min(y + 4, h - 1), max(x - 4, 0), min(x + 4, w - 1)
            for ys, xs in ((slice(y0, y1 + 1), x0), (slice(y0, y1 + 1), x1), (y0, slice(x0, x1 + 1)),
                           (y1, slice(x0, x1 + 1))):
                out[ys, xs] = np.where((d[ys, xs] > 0)[..., None], out[ys, xs], (0.0, 255.0, 255.0))
    return (np.clip(out, 0, 255) + 0.5).astype(np.uint8)


def read_png8(path):
    """A golden PNG's stored bytes as uint8 HxWxC (colour not multiplied by alpha on the way in)."""
    import OpenImageIO as oiio
    check_regular(path, Loc(path, 0), "golden image", "image")
    config = oiio.ImageSpec()
    config.attribute("oiio:UnassociatedAlpha", 1)
    buf = oiio.ImageBuf(path, 0, 0, config)
    px = None if buf.has_error else buf.get_pixels(oiio.UINT8)
    if px is None or buf.has_error:
        raise MtlxError((Loc(path, 0), "cannot read golden image: %s" % buf.geterror().strip()))
    px = np.asarray(px, dtype=np.uint8)
    return px[..., None] if px.ndim == 2 else px


# ---------------------------------------------------------------- index

MAX_SIZE = 8192            # as the command line's --size
MAX_SAMPLES = 65536         # as web's --samples


def _plain_name(value):
    """A file's name alone, as update writes them: no folder (so never outside the golden or output folder)."""
    return (isinstance(value, str) and value not in ("", ".", "..") and value.isprintable()
            and "/" not in value and "\\" not in value and os.sep not in value)


def _count(value, low, high):
    return isinstance(value, int) and not isinstance(value, bool) and low <= value <= high


def _fraction(value, low=0.0, high=float("inf")):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and low <= value <= high


def _entry_problems(name, entry):
    """Why an index entry is not one update writes (' .FIELD: why' each): the index comes with the project
    (a pull request), and its names become paths that are read and written, its settings a render's."""
    if not _plain_name(name):
        return [": not a file name (a golden's name names its images in the golden and output folders)"]
    if not isinstance(entry, dict):
        return [": %s is not an object" % _shown(entry)]
    out = []
    for key in ("source", "element", "png"):
        if not isinstance(entry.get(key), str) or (key != "element" and not entry[key]):
            out.append(".%s: %s is not a%s text" % (key, _shown(entry.get(key)), "" if key == "element" else
                                                    " non-empty"))
    for key in ("png", "exr"):
        value = entry.get(key)
        if isinstance(value, str) and not _plain_name(value):
            out.append(".%s: %s is not a file name in the golden folder" % (key, _shown(value)))
    if entry.get("exr") is not None and not isinstance(entry["exr"], str):
        out.append(".exr: %s is not a text or null" % _shown(entry["exr"]))
    settings = entry.get("settings")
    if settings is not None and not isinstance(settings, dict):
        out.append(".settings: %s is not an object" % _shown(settings))
    elif settings:
        if "size" in settings and not _count(settings["size"], 1, MAX_SIZE):
            out.append(".settings.size: %s is not a whole number from 1 to %d" % (_shown(settings["size"]), MAX_SIZE))
        if "samples" in settings and not _count(settings["samples"], 1, MAX_SAMPLES):
            out.append(".settings.samples: %s is not a whole number from 1 to %d"
                       % (_shown(settings["samples"]), MAX_SAMPLES))
        env = settings.get("environment")
        if env is not None and (not isinstance(env, str) or not env.isprintable()):
            out.append(".settings.environment: %s is not a file name or null" % _shown(env))
        for key, kind in (("lights", list), ("geometry", dict), ("camera", dict)):
            if settings.get(key) is not None and not isinstance(settings[key], kind):
                out.append(".settings.%s: %s is not %s" % (key, _shown(settings[key]),
                                                           "a list" if kind is list else "an object"))
    tol = entry.get("tolerance")
    if tol is not None and not isinstance(tol, dict):
        out.append(".tolerance: %s is not an object" % _shown(tol))
    elif tol:
        for key, ok, what in (("threshold", lambda v: _fraction(v, 0, 255), "a number from 0 to 255"),
                              ("max_fraction", lambda v: _fraction(v, 0, 1), "a number from 0 to 1"),
                              ("hdr_relative", _fraction, "a number from 0"),
                              ("flip", lambda v: v is None or _fraction(v, 0, 1), "a number from 0 to 1 or null")):
            if key in tol and not ok(tol[key]):
                out.append(".tolerance.%s: %s is not %s" % (key, _shown(tol[key]), what))
    if entry.get("gl_renderer") is not None and not isinstance(entry["gl_renderer"], str):
        out.append(".gl_renderer: %s is not a text" % _shown(entry["gl_renderer"]))
    return out


class Index:
    """golden_images/index.json: {"version": 1, "goldens": {name: entry}}; an entry outside the shape update
    writes is one line per field (_entry_problems) and the index is refused."""

    def __init__(self, golden_dir=DEFAULT_DIR):
        self.dir = os.path.abspath(golden_dir)
        self.root = os.path.dirname(self.dir)
        self.path = os.path.join(self.dir, INDEX_NAME)
        self.goldens = self._read()

    def _read(self):
        if not os.path.lexists(self.path):
            return {}
        loc = Loc(self.path, 1)
        try:
            data = json.loads(read_bounded(self.path, loc, "golden index", MAX_BYTES["json"]))
        except ValueError as e:
            raise MtlxError((loc, "cannot read golden index: %s" % e)) from None
        if not isinstance(data, dict) or not isinstance(data.get("goldens", {}), dict):
            raise MtlxError((Loc(self.path, 1), "golden index must be an object with a 'goldens' object"))
        goldens = data.get("goldens", {})
        problems = [(Loc(self.path, 0), "goldens[%s]%s" % (_shown(name), why))
                    for name, entry in sorted(goldens.items()) for why in _entry_problems(name, entry)]
        if problems:
            raise MtlxError(problems)
        return goldens

    def rel(self, path):
        return os.path.relpath(os.path.abspath(path), self.root).replace(os.sep, "/")

    def source(self, entry):
        return os.path.normpath(os.path.join(self.root, entry["source"]))

    def portable_settings(self, settings):
        """Recorded settings with an environment file under the project written relative to it, so the
        index holds in any checkout."""
        d = dict(settings)
        env = d.get("environment")
        if env and os.path.isabs(env) and os.path.exists(env):
            rel = self.rel(env)
            if not rel.startswith(".."):
                d["environment"] = rel
        return d

    def settings(self, entry):
        """RenderSettings of an index entry (a relative environment resolved against the project)."""
        d = dict((entry or {}).get("settings") or {})
        env = d.get("environment")
        if env and not os.path.isabs(env) and os.path.exists(os.path.join(self.root, env)):
            d["environment"] = os.path.normpath(os.path.join(self.root, env))
        return RenderSettings.from_dict(d)

    def file(self, name):
        return os.path.join(self.dir, name)

    def save(self, changed, removed=()):
        """Re-read the index, apply these entries, write it atomically (sorted, stable formatting)."""
        goldens = self._read()
        goldens.update(changed)
        for name in removed:
            goldens.pop(name, None)
        os.makedirs(self.dir, exist_ok=True)
        _write(self.path, json.dumps({"version": INDEX_VERSION, "goldens": goldens}, indent=1, sort_keys=True) + "\n")
        self.goldens = goldens


@dataclass
class Target:
    path: str          # absolute .mtlx path
    element: str
    name: str
    entry: dict = None  # the index entry, None when there is no golden yet
    error: list = None  # why the target could not even be listed


def targets(index, paths=None, library_dirs=()):
    """What to check or update: every golden in the index, or every renderable element in PATHS
    (files, directories searched for .mtlx documents and USD stages (batch.find_materials), or FILE:ELEMENT).
    A document that cannot be read (a dangling symbolic link, a FIFO, ...; or one that does not open) is a
    target with an error, so that it is reported and fails the run, and the others are still done."""
    if not paths:
        out = []
        for name, e in sorted(index.goldens.items()):
            path = index.source(e)
            why = regular_file_problem(path) if os.path.lexists(path) else None    # (gone: check says so)
            out.append(Target(path, e["element"], name, e, None if why is None else [
                "%s:0: the source of golden %s is %s" % (index.rel(path), name, why)]))
        return out
    out, seen, skipped = [], {}, []
    for spec in batch.find_materials(paths, skipped):
        path, element = batch.split_spec(spec)
        path, elements = os.path.abspath(path), None if element is None else [element]
        if elements is None:
            try:
                elements = batch.list_elements(path, library_dirs)
            except Exception as e:      # (a bug of ours: one line naming the document)
                out.append(Target(path, "", golden_name(path, ""), None, batch.error_lines(e, path)))
                continue
        for element in elements:
            name = golden_name(path, element)
            entry = index.goldens.get(name)
            if name in seen and seen[name] != path:
                out.append(Target(path, element, name, None,
                                  ["%s:1: golden name %s is also used by %s; rename one of the files"
                                   % (path, name, seen[name])]))
                continue
            seen[name] = path
            if entry is not None and index.source(entry) != path:
                out.append(Target(path, element, name, None,
                                  ["%s:1: golden %s belongs to %s, not this file; rename one of them"
                                   % (path, name, entry["source"])]))
                continue
            out.append(Target(path, element, name, entry))
    for loc, message in skipped:
        path = os.path.abspath(loc.file)
        out.append(Target(path, "", golden_name(path, ""), None, MtlxError((loc, message)).lines()))
    return out


def _nothing_to_do(index, paths, verb):
    """Checking (or updating) nothing is a mistake, not a pass: say where we looked."""
    if paths:
        return MtlxError((Loc(paths[0], 0), "nothing to %s: no .mtlx file or USD stage with a renderable element in %s" % (verb, ", ".join(paths))))
    return MtlxError((Loc(index.path, 0), "nothing to %s: %s; run in the project directory, or give --goldens DIR "
                      "or the .mtlx PATHS" % (verb, "the index lists no goldens" if os.path.exists(index.path)
                                              else "no golden index here")))


def _jobs(tgts, settings_for):
    """Group targets into batch jobs (one per file and settings)."""
    groups = {}
    for t in tgts:
        if t.error is None:
            groups.setdefault((t.path, settings_for(t)), []).append(t.element)
    return [batch.Job(path, tuple(elements), settings) for (path, settings), elements in groups.items()]


# ---------------------------------------------------------------- check

@dataclass
class CheckRun:
    results: list      # dicts, in target order (see _result)
    out_dir: str
    notes: list        # e.g. FLIP unavailable, renderer differs from the goldens'

    @property
    def ok(self):
        return all(r["status"] == "pass" for r in self.results)

    def counts(self):
        c = {"pass": 0, "fail": 0, "missing": 0, "error": 0}
        for r in self.results:
            c[r["status"]] += 1
        return c


def _result(t, index, status, message=(), metrics=None, timings=None, files=None, settings=None):
    return {"name": t.name, "source": index.rel(t.path), "element": t.element, "status": status,
            "message": list(message), "metrics": metrics or {}, "timings": timings or {},
            "files": files or {}, "settings": settings or {}}


def check(paths=None, golden_dir=DEFAULT_DIR, out_dir=DEFAULT_OUT, tolerance=Tolerance(), workers=None,
          progress=None, flip=True, warnings=None, options=None, scheduler=None, shard=None):
    """Render and compare. Writes results.json to out_dir and, per material that does not pass,
    NAME.new.png, NAME.golden.png, NAME.diff.png (and NAME.flip.png, NAME.new.exr where they apply)
    side by side; a passing material leaves no images (stale ones from an earlier run are removed).
    Raises MtlxError when there is nothing to check. warnings: a list that receives the warning lines of
    the documents checked, each once; options: how shaders are generated (options.GenerateOptions: library_dirs,
    strict: warnings are errors, the material's status error; target, ...): a golden is an image, so every target
    must draw it. scheduler: a Dask scheduler to draw and compare on (cluster.py; None: `workers`
    processes here). shard: (K, N), check the K-th (1 to N) of N shards of the elements alone (shard_of); one
    may be empty."""
    options = GenerateOptions.of(options)
    index = Index(golden_dir)
    every = tgts = targets(index, paths, options.library_dirs)
    if not tgts:
        raise _nothing_to_do(index, paths, "check")
    if shard is not None:
        tgts = [t for t in tgts if shard_of(index, t, shard[1]) == shard[0] - 1]
    notes = []
    if flip:
        mod, why = flip_module()
        if mod is None:
            notes.append(why)
    settings_for = lambda t: index.settings(t.entry) if t.entry else RenderSettings()
    tgts_render = [t for t in tgts if t.error is None and t.entry is not None]
    plan = {(t.path, t.element): {"png": index.file(t.entry["png"]),
                                  "exr": index.file(t.entry["exr"]) if t.entry.get("exr") else None,
                                  "tolerance": asdict(tolerance.merged(t.entry.get("tolerance"))), "flip": flip,
                                  "keep_images": _scene_changed(t.entry.get("settings", {}))}
            for t in tgts_render}
    items = batch.render_jobs(_jobs(tgts_render, settings_for), workers=workers, progress=progress,
                              options=options, post=compare_drawn,
                              post_args=plan, scheduler=scheduler)
    _collect_warnings(items, warnings)
    by_key = {(os.path.abspath(it.path), it.element): it for it in items}
    os.makedirs(out_dir, exist_ok=True)
    results, renderers = [], set()
    for t in tgts:
        if t.error is not None:
            results.append(_result(t, index, "error", t.error))
            continue
        if t.entry is not None and not os.path.exists(t.path):
            results.append(_result(t, index, "error", [
                "%s:0: the source of golden %s is gone; restore it, or delete the golden's entry from %s"
                % (index.rel(t.path), t.name, index.rel(index.path))]))
            continue
        if t.entry is None:
            results.append(_result(t, index, "missing", [
                "no golden %s in %s; create it with: mtlxgen golden update %s:%s"
                % (t.name, index.rel(index.dir), index.rel(t.path), t.element)]))
            continue
        it = by_key.get((t.path, t.element))
        settings = t.entry.get("settings", {})
        if it is None or not it.ok:
            results.append(_result(t, index, "error", it.error if it else ["not rendered"],
                                   timings=it.timings if it else None, settings=settings))
            continue
        if it.gl_renderer and t.entry.get("gl_renderer") and it.gl_renderer != t.entry["gl_renderer"]:
            renderers.add((it.gl_renderer, t.entry["gl_renderer"]))
        files = {"new": t.name + ".new.png", "golden": t.name + ".golden.png", "diff": t.name + ".diff.png"}
        golden_png = index.file(t.entry["png"])
        message = []
        if _scene_changed(settings):
            message.append("the harness scene (geometry/camera/lights) differs from the one this golden was "
                           "made with; review and run mtlxgen golden update")
        done = it.outcome           # compare_drawn's, where the element was drawn
        if "error" in done:
            results.append(_result(t, index, "error", done["error"], timings=it.timings, settings=settings))
            continue
        metrics, why = done["metrics"], done["why"]
        passes = done["passes"] and not message
        if passes:
            _remove_stale(out_dir, t.name)
            results.append(_result(t, index, "pass", (), metrics, it.timings, {}, settings))
            continue
        try:
            _write_image(os.path.join(out_dir, files["new"]), done["new8"])
            if done["new_linear"] is not None:
                files["new_exr"] = t.name + ".new.exr"
                _write_image(os.path.join(out_dir, files["new_exr"]), done["new_linear"])
            if is_inside(golden_png, [os.path.realpath(index.dir)]):   # its bytes; linked from elsewhere: pixels
                _write(os.path.join(out_dir, files["golden"]),
                       read_bounded(golden_png, Loc(golden_png, 0), "golden image", MAX_BYTES["image"]))
            else:
                _write_image(os.path.join(out_dir, files["golden"]), done["golden8"])
            if done["diff"] is not None:
                _write_image(os.path.join(out_dir, files["diff"]), done["diff"])
            else:
                files.pop("diff")
            if done["flip_map"] is not None:
                files["flip"] = t.name + ".flip.png"
                _write_image(os.path.join(out_dir, files["flip"]), done["flip_map"])
        except MtlxError as e:          # its images could not be written: a failure all the same, said why
            results.append(_result(t, index, "fail", message + why + e.lines(), metrics, it.timings, {}, settings))
            continue
        results.append(_result(t, index, "fail", message + why, metrics, it.timings, files, settings))
    for new_gl, old_gl in sorted(renderers):
        notes.append("goldens were made with the GL renderer '%s', this run used '%s': small differences "
                     "are expected across drivers" % (old_gl, new_gl))
    run = CheckRun(results, os.path.abspath(out_dir), notes)
    data = {"golden_dir": index.dir, "tolerance": asdict(tolerance), "notes": notes, "results": results}
    if shard is not None:
        data["shard"] = {"index": shard[0], "count": shard[1], "elements": len(every)}
    _write(os.path.join(out_dir, "results.json"), json.dumps(data, indent=1, sort_keys=True) + "\n")
    return run


def compare_drawn(item, plan):
    """batch.run_job's post step of check, run where the element was drawn: its image compared with its golden
    (plan: the golden's files, the tolerance, flip, keep_images). item.outcome: {"error": lines} (a golden that
    cannot be read), else the metrics, passes, why, and for a failure (or keep_images) what check writes: new8,
    new_linear (the linear render, where there is an EXR golden or it is HDR), golden8, diff, flip_map. The float
    image is dropped: a passing element sends back its metrics alone."""
    tol = Tolerance(**plan["tolerance"])
    try:
        golden8 = read_png8(plan["png"])
        golden_exr = read_image(plan["exr"]) if plan["exr"] else None
    except MtlxError as e:
        item.outcome, item.image = {"error": e.lines()}, None
        return
    metrics, d, flip_heat = measure(item.image, golden8, golden_exr, tol, plan["flip"])
    passes, why = verdict(metrics, tol)
    out = {"metrics": metrics, "passes": passes, "why": why}
    if not passes or plan["keep_images"]:
        out.update(new8=to_srgb8(item.image), golden8=golden8, flip_map=flip_heat,
                   new_linear=item.image if golden_exr is not None or is_hdr(item.image) else None,
                   diff=heat_map(d, golden8, tol.threshold) if d is not None else None)
    item.outcome, item.image = out, None


def shard_of(index, target, count):
    """The shard (0 .. count-1) of a target: a stable hash (sha256) of its identity, its source relative to the
    project and its element, so a shard keeps its elements as documents are added or removed elsewhere."""
    identity = "%s\n%s" % (index.rel(target.path), target.element)
    digest = hashlib.sha256(identity.encode("utf-8", "surrogatepass")).digest()
    return int.from_bytes(digest[:8], "big") % count


def _write(path, data):
    """files.write_atomic; the file system's refusal (a folder at the path, no space left) one line naming path."""
    try:
        return write_atomic(path, data)
    except OSError as e:
        raise MtlxError((Loc(path, 0), "cannot write: %s" % (e.strerror or e))) from None


def _write_image(path, img):
    """images.write_image (a temporary file and a rename), its file system's refusal one line naming path."""
    try:
        return write_image(path, img)
    except OSError as e:
        raise MtlxError((Loc(path, 0), "cannot write image: %s" % (e.strerror or e))) from None


def _collect_warnings(items, warnings):
    if warnings is not None:
        for it in items:
            warnings.extend(line for line in it.warnings if line not in warnings)


def _remove_stale(out_dir, name):
    """A passing material's images from an earlier failing run would sit beside the new report, unexplained."""
    for suffix in (".new.png", ".new.exr", ".golden.png", ".diff.png", ".flip.png"):
        path = os.path.join(out_dir, name + suffix)
        if os.path.islink(path) or os.path.isfile(path):
            os.remove(path)


def _scene_changed(recorded):
    """True when a golden's recorded scene (not the per-golden settings) differs from today's harness."""
    if not recorded:
        return False
    now = RenderSettings.from_dict(recorded).to_dict()
    return any(recorded.get(k) != now[k] for k in ("geometry", "camera", "lights") if k in recorded)


# ---------------------------------------------------------------- update

def update(paths=None, golden_dir=DEFAULT_DIR, settings=None, workers=None, progress=None, warnings=None, options=None,
           scheduler=None):
    """Render and (re)write goldens. `settings` (RenderSettings) overrides what each golden recorded;
    new goldens get RenderSettings() by default. Returns [(name, status, message lines)] with status
    created, updated, unchanged or error; the index is saved once at the end. Raises MtlxError when
    there is nothing to update. warnings, options, scheduler: as for check(); nothing is written before every
    element is drawn (a scheduler lost on the way: MtlxError, and the goldens as they were)."""
    options = GenerateOptions.of(options)
    index = Index(golden_dir)
    tgts = targets(index, paths, options.library_dirs)
    if not tgts:
        raise _nothing_to_do(index, paths, "update")

    def settings_for(t):
        if settings is not None:
            return settings
        return index.settings(t.entry) if t.entry else RenderSettings()

    plan = {}
    for t in tgts:
        if t.error is None:
            entry = {"source": index.rel(t.path), "element": t.element, "png": t.name + ".png",
                     "settings": index.portable_settings(settings_for(t).to_dict())}
            if t.entry and t.entry.get("tolerance"):
                entry["tolerance"] = t.entry["tolerance"]
            plan[(t.path, t.element)] = {"entry": entry, "old": t.entry, "exr_name": t.name + ".exr",
                                         "png": index.file(entry["png"]), "exr": index.file(t.name + ".exr")}
    items = batch.render_jobs(_jobs(tgts, settings_for), workers=workers, progress=progress,
                              options=options, post=prepare_golden,
                              post_args=plan, scheduler=scheduler)
    _collect_warnings(items, warnings)
    by_key = {(os.path.abspath(it.path), it.element): it for it in items}
    os.makedirs(index.dir, exist_ok=True)
    out, changed = [], {}
    for t in tgts:
        it = by_key.get((t.path, t.element))
        if t.error is not None or it is None or not it.ok:
            out.append((t.name, "error", t.error or (it.error if it else ["not rendered"])))
            continue
        done = it.outcome               # prepare_golden's, where the element was drawn
        entry = done["entry"]
        png, exr = plan[(t.path, t.element)]["png"], plan[(t.path, t.element)]["exr"]
        if done["same"]:
            out.append((t.name, "unchanged", []))
            continue
        try:
            _write_image(png, done["img8"])
            if entry["exr"]:
                _write_image(exr, done["linear"])
            elif os.path.lexists(exr):
                os.remove(exr)
        except (MtlxError, OSError) as e:     # (this golden is not written: its entry stays as it was)
            out.append((t.name, "error", e.lines() if isinstance(e, MtlxError) else
                        ["%s:0: cannot remove the old linear golden: %s" % (exr, e.strerror or e)]))
            continue
        changed[t.name] = entry
        out.append((t.name, "updated" if t.entry else "created", ["%s" % os.path.relpath(png)]))
    if changed:
        index.save(changed)
    return out


def prepare_golden(item, plan):
    """batch.run_job's post step of update, run where the element was drawn: its index entry completed (exr,
    gl_renderer), whether the stored golden already holds it (same entry, same pixels), and what update writes
    where it does not (img8, and the linear image of an HDR render). The float image is dropped."""
    hdr = is_hdr(item.image)
    img8 = to_srgb8(item.image)
    entry = dict(plan["entry"], exr=plan["exr_name"] if hdr else None, gl_renderer=item.gl_renderer)
    old, png, exr = plan["old"], plan["png"], plan["exr"]
    try:        # an old golden that cannot be read (a dangling link, a FIFO, a broken file) is written anew
        same = (old is not None and os.path.exists(png)
                and {k: old.get(k) for k in entry} == entry and np.array_equal(read_png8(png), img8)
                and (entry["exr"] is None or (os.path.exists(exr) and np.array_equal(
                    read_image(exr), item.image.astype(np.float16).astype(np.float32)))))
    except MtlxError:
        same = False
    item.outcome = {"entry": entry, "same": same, "img8": None if same else img8,
                    "linear": item.image if hdr and not same else None}
    item.image = None
