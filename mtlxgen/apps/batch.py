"""Batch rendering: many materials, all cores, per-material timings.

A job is one .mtlx file and the elements to render from it, plus the RenderSettings to render them
with. Jobs run in a process pool ("spawn" start method, so no process ever inherits a GL context);
each worker opens one headless GL context per distinct settings and keeps it for its lifetime.
With workers=1 (or a single small job) everything runs in this process, with the same per-process
renderer cache, so repeated calls (tests) pay for a context only once. With a scheduler (cluster.py) the same
jobs run as tasks of a Dask distributed cluster: run_job is the one per-element function of all three ways.

A `post` function (module level, so that it travels to a worker) runs where the element was rendered, on each
Item drawn: it may compare it with a golden, turn it into what is written, and drop the float image, so that
only what the client writes comes back (golden check: a passing element returns its metrics alone).

Every rendered element comes back as an Item: the linear RGBA float32 image (row 0 on top), or the
error lines that stopped it, and its timings (document load, generation, program link, draw).
"""
import concurrent.futures
import inspect
import multiprocessing
import os
import sys
import threading
import time
from mtlxgen.base.records import dataclass, field

import numpy as np

from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.files import regular_file_problem

BUILTIN_SKY = "builtin_sky"
CHUNK = 16          # elements per pool task: big files are split so the pool stays balanced
KEPT_TEXTURES = 64  # image files a renderer keeps decoded between jobs (a library of thousands: memory stays flat)


@dataclass(frozen=True)
class RenderSettings:
    """What a render depends on besides the material. `environment` is BUILTIN_SKY or an image path."""
    size: int = 128
    environment: str = BUILTIN_SKY
    env_samples: int = 64

    def to_dict(self):
        """The record kept with each golden: these fields plus the fixed scene of the harness."""
        from mtlxgen.draw import renderer as render
        sphere_args = inspect.signature(render.sphere).parameters
        return {"size": self.size, "environment": self.environment, "samples": self.env_samples,
                "lights": [],
                "geometry": {"shape": "uv_sphere", "radius": 1.0,
                             "segments": [sphere_args["n_lon"].default, sphere_args["n_lat"].default]},
                "camera": {"eye": list(render.EYE), "target": [0.0, 0.0, 0.0], "fov_y": render.FOV_Y}}

    @classmethod
    def from_dict(cls, d):
        d = d or {}
        return cls(size=int(d.get("size", cls.size)), environment=d.get("environment") or BUILTIN_SKY,
                   env_samples=int(d.get("samples", cls.env_samples)))


@dataclass(frozen=True)
class Job:
    path: str
    elements: tuple = ()            # empty: every renderable element of the file
    settings: RenderSettings = RenderSettings()


@dataclass
class Item:
    path: str
    element: str
    settings: RenderSettings
    image: np.ndarray = None        # linear RGBA float32, row 0 on top; None when it failed
    error: list = field(default_factory=list)
    warnings: list = field(default_factory=list)    # `FILE:LINE: warning: ...` lines (slips MaterialX reads on)
    timings: dict = field(default_factory=dict)
    pid: int = 0
    gl_renderer: str = ""
    outcome: dict = None            # what the run's `post` function made of the drawn image (it may drop `image`)

    @property
    def ok(self):
        """Drawn (its image, or what `post` made of it, is here)."""
        return self.image is not None or self.outcome is not None


# ---------------------------------------------------------------- per-process state

_RENDERERS = {}


def renderer_for(settings):
    """This thread's renderer for these settings (created on first use, kept until exit). Per thread: a GL
    context is current in one thread at a time, and a Dask worker may run tasks in several."""
    key = (settings, threading.get_ident())
    r = _RENDERERS.get(key)
    if r is None:
        from mtlxgen.draw import renderer as render
        env = None
        if settings.environment and settings.environment != BUILTIN_SKY:
            env = render.load_environment(settings.environment)
        r = render.Renderer(size=settings.size, environment=env, env_samples=settings.env_samples)
        _RENDERERS[key] = r
    return r


def list_elements(path, library_dirs=()):
    """Renderable element name paths of a file, in document order (raises MtlxError)."""
    from mtlxgen.graph import build as graph
    from mtlxgen import pipeline
    return graph.renderable_elements(pipeline.load_document(path, library_dirs))


def error_lines(e, path, element=""):
    """The lines of a failure: a problem's own FILE:LINE lines; anything else is a bug of ours, one line naming the
    document (and element) it met."""
    if isinstance(e, MtlxError):
        return list(e.lines())
    what = " ".join(("%s: %s" % (type(e).__name__, e)).split())      # one line, whatever the message holds
    return ["%s:0: %sinternal error: %s (set MTLXGEN_DEBUG=1 for details)"
            % (path, "%s: " % element if element else "", what)]


def failed_items(job, element, error):
    """The Items of a job that could not run (of its one `element`, or of all its elements): error an exception
    (error_lines) or a sentence said of each."""
    lines = (lambda el: ["%s:0: %s%s" % (job.path, "%s: " % el if el else "", error)]) if isinstance(error, str) \
        else (lambda el: error_lines(error, job.path, el))
    return [Item(job.path, el, job.settings, error=lines(el)) for el in ((element,) if element else
                                                                         job.elements or ("",))]


def run_job(job, options=None, post=None, post_args=None):
    """Render one job in this process. Never raises for bad input: failures become Items with errors.
    options: how shaders are generated (options.GenerateOptions; None: the defaults), the same for every job of a
    run; options.strict: warnings are errors (the element is not drawn). post(item, arg): run on each drawn
    item, arg = post_args[(absolute path, element)] (module docstring)."""
    items = _draw_job(job, options)
    if post is not None:
        for item in items:
            if item.image is not None:
                try:
                    post(item, (post_args or {}).get((os.path.abspath(item.path), item.element)))
                except Exception as e:      # (a bug of ours: the element's failure, one line naming it)
                    item.image, item.outcome, item.error = None, None, error_lines(e, item.path, item.element)
    return items


def srgb8_drawn(item, _=None):
    """A post step (batch's): the drawn image as the sRGB 8-bit pixels its PNG holds (outcome["srgb8"]), made where
    it was drawn; a quarter of the float image's bytes come back."""
    from mtlxgen.base.images import to_srgb8
    item.outcome, item.image = {"srgb8": to_srgb8(item.image)}, None


def _draw_job(job, options):
    from mtlxgen.read import library
    from mtlxgen import pipeline
    from mtlxgen.options import GenerateOptions
    items = []
    try:
        options = GenerateOptions.of(options)
        library.load_library(options.library_dirs)   # once per process (memoized): not a material's cost
        t0 = time.perf_counter()
        session = pipeline.Session(job.path, options, job.elements)
        names = session.elements
    except Exception as e:  # the file as a whole
        return [Item(job.path, el, job.settings, error=error_lines(e, job.path, el), pid=os.getpid())
                for el in (job.elements or ("",))]
    load_s = time.perf_counter() - t0
    try:
        r = renderer_for(job.settings)
        gl = r.ctx.info.get("GL_RENDERER", "")
    except Exception as e:
        return [Item(job.path, n, job.settings, error=error_lines(e, job.path, n), pid=os.getpid()) for n in names]
    for name in names:
        item = Item(job.path, name, job.settings, pid=os.getpid(), gl_renderer=gl)
        t1 = time.perf_counter()
        try:
            shader = session.drawable(name, session.shader(name))     # an unreadable texture: its default
            t2 = time.perf_counter()
            try:
                item.image, gl_times = r.render_timed(shader.vertex, shader.fragment, shader.manifest)
            except MtlxError as e:      # a texture that does not decode: said at the input naming it
                raise pipeline.at_inputs(shader, e) from None
            # drawn, but with problems to report (a USD stage's: a texture not found, its fallback drawn)
            item.error = MtlxError(session.notes() + session.notes(name)).lines() if hasattr(session, "notes") else []
            item.timings = {"load_s": load_s, "generate_s": t2 - t1, **gl_times,
                            "total_s": time.perf_counter() - t1 + load_s / len(names)}
        except Exception as e:
            item.error = error_lines(e, job.path, name)
            item.timings = {"load_s": load_s, "total_s": time.perf_counter() - t1}
        if not options.strict:          # strict: they are the item's errors
            item.warnings = session.warning_lines(name)
        items.append(item)
    r.trim_images(KEPT_TEXTURES)
    return items


def find_materials(paths, problems=None):
    """.mtlx documents and USD stages named by PATHS: files as given; directories searched (sorted, hidden ones
    skipped) for .mtlx files and for the USD stages (.usd, .usda, .usdc, .usdz) among them that hold materials
    and that no other stage found there composes (usdstage.scene_files: a payload, reference or sublayer is
    drawn as part of the stage that uses it); FILE:ELEMENT kept as is (split_spec parts them).

    Symbolic links to folders are not followed (a link loop, or a link to /, cannot make the walk endless or
    take it out of the tree). An entry that cannot be read as a file (a dangling symbolic link, a link loop, a
    FIFO, a device, a file over its size cap) or a folder that cannot be listed is left out, each a (Loc, message)
    problem appended to `problems` (`PATH:0: skipped: WHY`): nothing hands it to a reader (a FIFO would block
    it). Without a `problems` list they are raised, all together, as an MtlxError after the walk. Raises
    MtlxError at once for a path that does not exist."""
    from mtlxgen.read.usdstage import is_usd, scene_files
    skipped = []

    def readable(path):
        why = regular_file_problem(path, "usd" if is_usd(path) else "text")
        if why is not None and (Loc(path, 0), "skipped: %s" % why) not in skipped:    # (named twice: said once)
            skipped.append((Loc(path, 0), "skipped: %s" % why))
        return why is None

    def unlisted(e):
        skipped.append((Loc(e.filename or "?", 0), "skipped: a folder that cannot be listed (%s)" % (e.strerror or e)))

    files = []
    for p in paths:
        if os.path.isdir(p):
            found = []
            for base, dirs, names in os.walk(p, onerror=unlisted):      # links to folders: not followed
                dirs[:] = sorted(d for d in dirs if not d.startswith("."))
                found += [f for f in (os.path.join(base, n) for n in sorted(names)
                                      if n.endswith(".mtlx") or is_usd(n)) if readable(f)]
            stages = set(scene_files([f for f in found if is_usd(f)]))
            files += [f for f in found if not is_usd(f) or f in stages]
        elif os.path.lexists(p):
            if readable(p):
                files.append(p)
        elif ":" in p and os.path.lexists(p.rsplit(":", 1)[0]):
            if readable(p.rsplit(":", 1)[0]):
                files.append(p)          # FILE.mtlx:ELEMENT
        else:
            raise MtlxError((Loc(p, 0), "no such file or directory"))
    if problems is not None:
        problems.extend(skipped)
    elif skipped:
        raise MtlxError(skipped)
    return files


def split_spec(spec):
    """(file, element or None) of a find_materials entry: FILE, or FILE:ELEMENT where no file has the whole name."""
    if os.path.lexists(spec) or ":" not in spec:
        return spec, None
    path, element = spec.rsplit(":", 1)
    return path, element


def _split(jobs, library_dirs):
    """Jobs with an explicit element list, at most CHUNK elements each (so the pool can balance)."""
    out = []
    for job in jobs:
        names = list(job.elements)
        if not names:
            try:
                names = list_elements(job.path, library_dirs)
            except Exception:
                out.append(job)         # run_job reports the error
                continue
        for i in range(0, max(len(names), 1), CHUNK):
            out.append(Job(job.path, tuple(names[i:i + CHUNK]), job.settings))
    return out


def default_workers():
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:
        return max(1, os.cpu_count() or 1)


def render_jobs(jobs, workers=None, progress=None, options=None, post=None, post_args=None, scheduler=None):
    """Render all jobs; returns [Item] in job order. `progress`: a Progress, True/False, or None (auto).
    options (an options.GenerateOptions: library_dirs, strict, ...), post and post_args: run_job's. scheduler: a
    Dask scheduler address (cluster.py: tcp://HOST:PORT, or local:N) to run the jobs on instead of `workers`
    processes here; raises MtlxError (one line) when the cluster cannot run them or goes away."""
    from mtlxgen.options import GenerateOptions
    options = GenerateOptions.of(options)           # checked here, before any worker starts
    tasks = _split(jobs, options.library_dirs)
    total = sum(len(t.elements) or 1 for t in tasks)
    bar = progress if isinstance(progress, Progress) else Progress(total, "render", enabled=progress)
    post_args = post_args or {}

    def args_of(task):          # the post arguments of this task's elements alone (not the whole run's)
        if not post_args:
            return None
        here = os.path.abspath(task.path)
        return {(here, el): post_args[(here, el)] for el in task.elements if (here, el) in post_args}

    def done(i, items):
        results[i] = items
        bar.advance(len(items), os.path.basename(tasks[i].path), failed=sum(1 for it in items if not it.ok))

    results = [None] * len(tasks)
    if scheduler is not None:
        from mtlxgen.apps import cluster
        cluster.run_tasks(scheduler, tasks, done, bar, run_job, failed_items, options, post, args_of)
        bar.close()
        return [item for chunk in results for item in chunk]
    workers = default_workers() if workers is None else max(1, int(workers))
    workers = min(workers, len(tasks)) or 1
    if workers == 1:
        for i, task in enumerate(tasks):
            bar.running = 1
            done(i, run_job(task, options, post, args_of(task)))
    else:
        ctx = multiprocessing.get_context("spawn")
        with concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=ctx) as pool:
            futures = {pool.submit(run_job, task, options, post, args_of(task)): i
                       for i, task in enumerate(tasks)}
            left = len(futures)
            for fut in concurrent.futures.as_completed(futures):
                i = futures[fut]
                left -= 1
                bar.running = min(workers, left)
                try:
                    items = fut.result()
                except Exception as e:  # a worker died (GL crash, out of memory)
                    items = failed_items(tasks[i], "", e)
                done(i, items)
    bar.running = 0
    bar.close()
    return [item for chunk in results for item in chunk]


def timing_table(rows):
    """Plain-text timing table of (label, timings dict, ok) rows, slowest first, with a total line."""
    rows = sorted(rows, key=lambda row: -row[1].get("total_s", 0.0))
    lines = ["%9s %9s %9s %9s  %s" % ("total ms", "gen ms", "link ms", "draw ms", "material")]
    for label, t, ok in rows:
        ms = lambda k: ("%9.1f" % (1000 * t[k])) if k in t else "%9s" % "-"
        lines.append("%s %s %s %s  %s%s" % (ms("total_s"), ms("generate_s"), ms("link_s"), ms("draw_s"), label,
                                            "" if ok else "  (failed)"))
    lines.append("%9.1f  in all, %d materials" % (1000 * sum(t.get("total_s", 0.0) for _, t, _ in rows), len(rows)))
    return "\n".join(lines)


# ---------------------------------------------------------------- progress bar

class Progress:
    """A progress bar on stderr: redrawn in place on a terminal, a line per ~10% otherwise; elements done of
    all, tasks running (set `running`) and elements failed.

    enabled=None shows it when there are at least 8 steps (a "long run")."""

    def __init__(self, total, label="", stream=None, enabled=None, width=30):
        self.total, self.label, self.width = max(int(total), 0), label, width
        self.stream = stream or sys.stderr
        self.enabled = (self.total >= 8) if enabled is None else bool(enabled)
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.done, self.t0, self._last_tenth = 0, time.perf_counter(), -1
        self.running, self.failed = 0, 0
        self._drawn = False

    def _counts(self):
        return "%d/%d%s%s" % (self.done, self.total, " running %d" % self.running if self.running else "",
                              " failed %d" % self.failed if self.failed else "")

    def advance(self, n=1, what="", failed=0):
        self.done += n
        self.failed += failed
        self.draw(what)

    def draw(self, what=""):
        if not self.enabled or not self.total:
            return
        frac = min(self.done / self.total, 1.0)
        elapsed = time.perf_counter() - self.t0
        if self.tty:
            fill = int(round(frac * self.width))
            line = "\r%s [%s%s] %s %5.1fs %s" % (self.label, "#" * fill, "." * (self.width - fill), self._counts(),
                                                elapsed, what[:30])
            self.stream.write(line.ljust(100)[:100])
            self._drawn = True
        else:
            tenth = int(frac * 10)
            if tenth == self._last_tenth:
                return
            self._last_tenth = tenth
            self.stream.write("%s: %s (%d%%) %.1fs\n" % (self.label, self._counts(), 100 * frac, elapsed))
        self.stream.flush()

    def close(self):
        if self.enabled and self.tty and self._drawn:
            self.stream.write("\n")
            self.stream.flush()
