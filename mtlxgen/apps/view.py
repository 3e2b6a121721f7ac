"""mtlxgen view: a live window that draws a document's elements and redraws as the document is edited.

    Viewer        the state of one viewing session, drawn into any framebuffer: the document's elements and
                  their linked shaders, an orbit camera, the environment, lights and background, progressive
                  accumulation of environment samples (fis shaders draw their GGX-prefiltered variant while the
                  camera moves: one lookup a lobe), screenshots. Draws with render.Renderer (prepare/draw:
                  the same binding code as `mtlxgen render`) into a float framebuffer and presents it.
    Reloader      generation off the drawing thread: the document re-read, the shown element regenerated,
                  problems collected; the drawing thread compares the text and relinks only what changed. Then,
                  for a lit fis shader linked, its prefiltered variant (the generator's moving_shader: the same
                  element and options, --environment prefiltered), which the camera's moves draw once it is
                  there (the fis program until then).
    Watcher       watchdog on the document, its includes, textures, the light rig and the environment map.
    GlfwWindow    a window (glfw) feeding mouse and keys to the Viewer; OffscreenWindow: a framebuffer in a
                  headless context for --headless-frames without a display.

A document edit that changes only <input> values of the shown shader's public uniforms (the document's XML
compared with the one the drawn shader came from) sets the values on the linked program without generating
anything (Viewer._value_edit); the session reads the document again after that frame. Otherwise the shown element
is generated again, and a shader whose text differs from the one drawn only in its uniforms' initial values is
not relinked either: the new values are set on the linked program. Anything else is linked anew; a document with
problems keeps the last good shader drawn and shows its problems (terminal and title).

Our generator specializes each shader on the inputs at zero (OurGenerator.specialize: the reduced interface
keeping every other input a uniform; a zero-weight lobe is left out of the code), so it compiles and draws
faster; an input moved off zero (by an edit or the panel) is kept a uniform from then on.
"""
import copy
import os
import sys
import threading
import time
from mtlxgen.base.records import dataclass, field

import numpy as np

from mtlxgen.draw import renderer as render
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.apps.uniformvalues import (initial_values, initializers, set_uniform,  # noqa: F401 (view.X for callers)
                                        skeleton)

SETTABLE = ("float", "integer", "boolean", "color3", "color4", "vector2", "vector3", "vector4")   # value edits
SAMPLE_STEPS = (16, 64, 256, 1024, 4096)    # the sample counts the S key steps through (the converged estimate)
MOVING_SAMPLES = 8                          # samples per frame while the camera moves
EDIT_SAMPLES = 1                            # samples of the first frame after a change (an edit, a setting): one
                                            # sample a lobe filtered for one (a smooth, blurrier estimate), then the
                                            # accumulation refines it
FRAME_SAMPLES = 16                          # samples per accumulated frame while the camera is still

KEYS = [("Tab / Shift+Tab", "next / previous element"), ("E", "environment: fis / prefiltered"),
        ("S", "samples: %s" % " / ".join(str(s) for s in SAMPLE_STEPS)), ("L", "lights on / off"),
        ("B", "background on / off"), ("G", "geometry: sphere / plane / cube / shaderball"),
        ("C", "screenshot (PNG + EXR)"), ("T", "print the frame time"), ("R", "reload now"),
        ("F", "frame the view (reset the camera)"), ("P", "property panel on / off"), ("Q / Esc", "quit"),
        ("drag", "left: orbit; right, middle or Shift+left: pan; wheel: zoom")]


def key_help():
    return "\n".join("  %-16s %s" % k for k in KEYS)


# ------------------------------------------------------------------ camera

class OrbitCamera:
    """Yaw and pitch about a target at a distance; yaw = pitch = 0 looks down -z (render's camera)."""

    def __init__(self, target=(0.0, 0.0, 0.0), distance=render.EYE[2], fov_y=render.FOV_Y):
        self.home = (tuple(float(x) for x in target), float(distance))
        self.fov_y = fov_y
        self.reset()

    def reset(self):
        self.target = np.array(self.home[0])
        self.distance = self.home[1]
        self.yaw = self.pitch = 0.0

    def frame(self, centre, radius):
        """Home on a bounding sphere: the whole of it in view, no closer than render's camera to a unit one."""
        distance = max(render.EYE[2], 1.08 * radius / np.sin(np.radians(self.fov_y) / 2.0))
        self.home = (tuple(float(x) for x in centre), float(distance))
        self.reset()

    def eye(self):
        cp = np.cos(self.pitch)
        offset = np.array([np.sin(self.yaw) * cp, np.sin(self.pitch), np.cos(self.yaw) * cp]) * self.distance
        return self.target + offset

    def camera(self):
        near = max(self.distance * 0.01, 1e-3)
        return render.Camera(eye=tuple(float(x) for x in self.eye()), target=tuple(float(x) for x in self.target),
                             fov_y=self.fov_y, near=min(near, 0.1), far=max(100.0, self.distance * 50.0))

    def orbit(self, dx, dy):
        """dx, dy: drag in pixels over the window's height (a full height is half a turn)."""
        self.yaw -= dx * np.pi
        self.pitch = float(np.clip(self.pitch + dy * np.pi, -1.55, 1.55))

    def zoom(self, steps):
        self.distance = float(np.clip(self.distance * 0.9 ** steps, 1e-3, 1e4))

    def pan(self, dx, dy):
        view = render.look_at(self.eye(), self.target, (0, 1, 0))
        right, up = view[0, :3], view[1, :3]
        scale = 2.0 * self.distance * np.tan(np.radians(self.fov_y) / 2.0)
        self.target = self.target - right * dx * scale + up * dy * scale


# ------------------------------------------------------------------ shader text (uniformvalues.py)

# ------------------------------------------------------------------ generation

@dataclass
class Generated:
    """One element's shader as a generator wrote it. sources (our generator only): {(element, input): [(uniform,
    MaterialX type, (file, line))]}, the public uniforms each document input initialises (the uniforms' Origin:
    the element's name path and the input; the input's FILE:LINE, the file absolute), for value edits that skip
    the generator (Viewer._value_edit); empty where the generator does not say."""
    element: str
    stem: str
    vertex: str
    fragment: str
    manifest: dict = field(default_factory=dict)
    sources: dict = field(default_factory=dict)


def is_zero(value):
    """A value that a zero-weight specialization folds: 0, false, black / all-zero vectors."""
    if isinstance(value, (list, tuple)):
        return len(value) > 0 and all(is_zero(v) for v in value)
    if isinstance(value, bool):
        return not value
    return isinstance(value, (int, float)) and value == 0


# kept in the viewer's reduced shaders (it accumulates frames: interface.PROGRESSIVE; either name keeps both)
PROGRESSIVE_KEPT = "u_envSampleFrames"


class OurGenerator:
    """mtlxgen's pipeline as the viewer drives it: open() reads a document (a pipeline.Session), shader()
    generates one element. Another generator (a benchmark's MaterialX one) offers the same four methods.

    specialize (where no interface is asked for): each element's shader is generated with the reduced interface
    (reduce.py, fold.py) keeping every public input a uniform except those whose value is zero (0, false,
    black): a lobe of zero weight (coat, sheen, transmission, subsurface, thin film, emission ...) is left out
    of the code, so the shader compiles and draws faster. An input once kept stays kept (kept[element]): an
    edit that moves a folded input off zero regenerates with it kept, and it stays a uniform from then on, so
    dragging it back to zero and off again sets a value. keep() keeps one at once (the panel edits a folded
    input). The pictures are those of the complete interface (fold.py computes what the GPU would)."""

    def __init__(self, options=None, specialize=True):
        from mtlxgen.options import GenerateOptions
        # options.GenerateOptions (None: the defaults); a light rig given: max_lights, its shaders loop over lights.
        # The environment method is each open()'s (E toggles it).
        self.options = GenerateOptions.of(options)
        if self.options.interface == "reduced":     # the viewer refines progressively: the frame pair stays uniforms
            self.options = self.options.replace(keep=tuple(self.options.keep) + ((PROGRESSIVE_KEPT, None),))
        self.library_dirs = self.options.library_dirs
        self.specialize = specialize and self.options.interface == "complete"
        self.kept = {}                      # element -> uniforms kept for good (specialize)
        self._lock = threading.Lock()

    def open(self, path, environment):
        from mtlxgen import pipeline
        from mtlxgen.base.diagnostics import Warnings
        warnings = Warnings()
        session = pipeline.Session(path, self.options.replace(environment=environment), warnings=warnings)
        session.warning_list = warnings
        return session

    def elements(self, session):
        return list(session.elements)

    def keep(self, element, uniform):
        """Keep `uniform` of `element` a uniform from now on (the next shader() has it)."""
        with self._lock:
            self.kept.setdefault(element, set()).add(uniform)

    def shader(self, session, name):
        specialized = self.specialize and not session.interface.reduced
        # the complete interface calls nodegraph implementations as functions, as `generate` writes it
        g = session.graph(name, functions=not specialized and not session.interface.reduced)
        if specialized:
            s = self._specialized(session, name, g)
        else:
            s = session.shader(name, graph=g)
        s = session.drawable(name, s)     # a texture file that cannot be read: its default drawn, the file unopened
        notes = session.notes(name)
        if notes:                         # drawn all the same (a texture not found draws its default or fallback)
            s.manifest = dict(s.manifest, notes=["%s: %s" % n for n in notes])
        sources = {}
        for u in g.uniforms.values():       # inputs the document writes, in a .mtlx file (not a USD stage)
            o = u.origin
            if o is not None and o.authored and u.loc is not None and u.loc.where is None and u.loc.file:
                sources.setdefault((o.element, o.input), []).append(
                    (u.name, u.type, (os.path.abspath(u.loc.file), u.loc.line)))
        return Generated(name, s.stem, s.vertex, s.fragment, s.manifest, sources)

    def _specialized(self, session, name, g):
        """The reduced interface keeping every input but those at zero that were never kept (see the class)."""
        from mtlxgen.passes.reduce import LITERAL_TYPES, Interface
        with self._lock:
            kept = self.kept.setdefault(name, set())
            for n, u in g.uniforms.items():
                if u.type not in LITERAL_TYPES or u.value is None or not is_zero(u.value):
                    kept.add(n)
            keep = sorted(n for n in g.uniforms if n in kept)
        s = session.shader(name, Interface("reduced", [(n, None) for n in keep + [PROGRESSIVE_KEPT]]), graph=g)
        s.manifest["folded"] = sorted(n for n in g.uniforms if n not in kept)
        return s

    def files(self, session):
        """Files whose edits change what is drawn: the document, its includes and implementation files."""
        from mtlxgen.read import usdstage
        path = os.path.abspath(session.path)
        if usdstage.is_usd(path):
            return {path}
        out = {path}
        try:
            from mtlxgen.read import xmlreader
            from mtlxgen.base.resolve import search_paths
            stack = [xmlreader.read_file(path, search_paths(self.library_dirs))]
            while stack:
                el = stack.pop()
                out.add(os.path.abspath(el.loc.file))
                if el.tag == "implementation" and el.get("file"):
                    from mtlxgen.base.resolve import resolve_file
                    f = resolve_file(el.get("file"), el.loc.file, self.library_dirs)
                    if f:
                        out.add(f)
                stack.extend(el.children)
        except MtlxError:
            pass
        return out

    def warnings(self, session):
        return session.warning_list.lines()

    def moving_shader(self, session, name):
        """Element `name` generated as shader() does, with the split sum (environment "prefiltered"): the variant the
        viewer draws while the camera moves. The same uniforms as the fis shader() under the same kept inputs (the
        two methods differ in glsl_lib code only)."""
        from mtlxgen.base.diagnostics import Warnings
        variant = copy.copy(session)      # the document, libraries and elements read once: only the method differs
        variant.environment = "prefiltered"
        variant.options = session.options.replace(environment="prefiltered")
        variant.warnings = Warnings()     # (said with the fis shader's)
        return self.shader(variant, name)


@dataclass
class Reload:
    """What the reloader made of the document: its elements, the wanted element's shader, the problems."""
    session: object = None              # None: the document itself could not be read
    elements: list = field(default_factory=list)
    shaders: dict = field(default_factory=dict)     # element -> Generated
    problems: list = field(default_factory=list)    # FILE:LINE: problem lines
    notes: list = field(default_factory=list)       # problems of a shader drawn all the same (a texture not found)
    warnings: list = field(default_factory=list)
    files: set = field(default_factory=set)
    started: float = 0.0                # perf_counter when generation began
    changed_at: float = 0.0             # perf_counter of the file event that caused it (0: none)
    environment: str = "fis"
    tree: object = None                 # the document's own XML (xmlreader, includes not spliced) as the session
                                        # read it: the base a value edit is compared with (None: not known)
    data: bytes = None                  # the document's bytes it was parsed from


@dataclass
class Moving:
    """The prefiltered variant the reloader made of a fis shader (Reloader.request_moving)."""
    element: str
    fis: object                         # the fis Generated it was asked for
    generated: object = None            # its prefiltered Generated; None: the generator could not (fis drawn)


class Reloader:
    """Generates on a thread of its own so the window keeps drawing; one request at a time, the latest wins.
    Prefiltered variants (request_moving) are made when no reload waits, each element's latest request only."""

    def __init__(self, generator, path, wake=None):
        self.generator = generator
        self.path = path
        self.wake = wake                    # called (from this thread) when a result is ready
        self._lock = threading.Lock()
        self._wake = threading.Condition(self._lock)
        self._request = None
        self._moving = {}                   # element -> (session, the fis Generated): variants to make
        self._done = []
        self._busy = False                  # a reload being generated
        self._working = False               # anything being generated (a reload or a variant)
        self._stop = False
        self._thread = threading.Thread(target=self._run, name="mtlxgen-view-reload", daemon=True)
        self._thread.start()

    def request(self, element, environment, changed_at=0.0):
        with self._lock:
            self._request = (element, environment, changed_at)
            self._wake.notify_all()     # the thread, and idle() waiters

    def request_moving(self, element, session, fis):
        """Make the prefiltered variant of `fis` (element's Generated, from `session`) when no reload waits."""
        with self._lock:
            self._moving[element] = (session, fis)
            self._wake.notify_all()     # the thread, and idle() waiters

    def busy(self):
        """A reload waiting, being generated, or its result not yet taken (results()); variants do not count."""
        with self._lock:
            return self._busy or self._request is not None or any(isinstance(d, Reload) for d in self._done)

    def idle(self, timeout=None):
        """Wait until nothing waits or is being generated (reloads and variants); False on timeout."""
        end = None if timeout is None else time.monotonic() + timeout
        with self._lock:
            while self._working or self._request is not None or self._moving:
                left = None if end is None else end - time.monotonic()
                if left is not None and left <= 0:
                    return False
                self._wake.wait(left)
            return True

    def results(self):
        with self._lock:
            done, self._done = self._done, []
        return done

    def close(self):
        with self._lock:
            self._stop = True
            self._wake.notify_all()     # the thread, and idle() waiters
        self._thread.join(timeout=5)

    def _run(self):
        while True:
            with self._lock:
                while self._request is None and not self._moving and not self._stop:
                    self._wake.wait()
                if self._stop:
                    return
                moving = None
                if self._request is not None:               # a reload first: the variants are for what it drew
                    request, self._request = self._request, None
                    self._busy = True
                else:
                    element = next(iter(self._moving))
                    moving = (element,) + self._moving.pop(element)
                self._working = True
            try:
                result = self.generate(*request) if moving is None else self.generate_moving(*moving)
            except Exception as e:          # a bug of ours: shown as a problem, the window stays up
                if moving is not None:
                    result = Moving(moving[0], moving[2])
                else:
                    result = Reload(problems=["%s: internal error: %s: %s" % (self.path, type(e).__name__, e)])
            with self._lock:
                self._done.append(result)
                self._busy = self._working = False
                self._wake.notify_all()
            if self.wake is not None:
                self.wake()

    def generate_moving(self, element, session, fis):
        """Moving: the prefiltered variant of `fis`; none where the generator makes none or meets a problem (the
        document changed under it: a reload follows)."""
        make = getattr(self.generator, "moving_shader", None)
        if make is None:
            return Moving(element, fis)
        try:
            return Moving(element, fis, make(session, element))
        except MtlxError:
            return Moving(element, fis)

    def generate(self, element, environment, changed_at=0.0):
        r = Reload(started=time.perf_counter(), changed_at=changed_at, environment=environment)
        g = self.generator
        before = read_bytes(self.path)
        try:
            r.session = g.open(self.path, environment)
        except MtlxError as e:
            r.problems = e.lines()
            r.files = {os.path.abspath(self.path)}
            return r
        if before is not None and before == read_bytes(self.path):    # what the session read, for certain
            r.tree, r.data = parse_tree(before, self.path), before
        r.files = g.files(r.session)
        r.elements = g.elements(r.session)
        name = element if element in r.elements else (r.elements[0] if r.elements else None)
        if name is not None:
            try:
                r.shaders[name] = g.shader(r.session, name)
                r.notes = list(r.shaders[name].manifest.get("notes", ()))
            except MtlxError as e:
                r.problems += e.lines()
        r.warnings = g.warnings(r.session) if hasattr(g, "warnings") else []
        return r


def read_bytes(path):
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError:
        return None


def parse_tree(data, path):
    """The root XElement of a .mtlx document's own text (includes not spliced); None for USD or unreadable."""
    from mtlxgen.read import usdstage, xmlreader
    if data is None or usdstage.is_usd(path):
        return None
    try:
        return xmlreader.parse_text(data, os.path.abspath(path))
    except MtlxError:
        return None


def value_edits(old, new):
    """[((element, input), old <input>, new <input>)] whose value attribute differs, where the two documents are
    otherwise the same: the same elements, attributes and lines. (element, input): the input's name path as an
    Origin gives it (the name path of the element holding it, "" for the document's own inputs); None for one
    MaterialX does not read by that path (a later sibling repeating a name, an element without a name, what
    they hold). None where anything else differs, or where a value changed inside a nodedef or a nodegraph
    implementing one (a default or an implementation's value: read as constants too)."""
    out = []
    stack = [(old, new, False, ())]
    while stack:
        a, b, definition, names = stack.pop()
        if a.tag != b.tag or a.loc != b.loc or len(a.children) != len(b.children):
            return None
        if a.attrs != b.attrs:
            if a.tag != "input" or definition:
                return None
            if {k: v for k, v in a.attrs.items() if k != "value"} != {k: v for k, v in b.attrs.items() if k != "value"}:
                return None
            out.append(((("/".join(names[:-1]), names[-1]) if names else None), a, b))
        definition = definition or a.tag == "nodedef" or (a.tag == "nodegraph" and a.get("nodedef") is not None)
        seen = set()
        for x, y in zip(a.children, b.children):
            name = x.get("name")
            sub = names + (name,) if names is not None and name and name not in seen else None
            seen.add(name)
            stack.append((x, y, definition, sub))
    return out


def _same(a, b):
    """Equal values as parse_value and the manifest give them (a tuple and a list alike; a bool is not 1)."""
    a = tuple(a) if isinstance(a, (list, tuple)) else (a,)
    b = tuple(b) if isinstance(b, (list, tuple)) else (b,)
    return len(a) == len(b) and all(isinstance(x, bool) == isinstance(y, bool) and x == y for x, y in zip(a, b))


# ------------------------------------------------------------------ file watching

class Watcher:
    """watchdog on the folders of the watched files; changed() gives {path: perf_counter of its last event}."""

    def __init__(self, wake=None):
        from watchdog.observers import Observer
        self.wake = wake                    # called (from watchdog's thread) when a watched file changes
        self._observer = Observer()
        self._observer.daemon = True
        self._lock = threading.Lock()
        self._paths = set()
        self._dirs = {}
        self._changed = {}
        self._observer.start()

    def watch(self, paths):
        from watchdog.events import FileSystemEventHandler
        watcher = self

        class Handler(FileSystemEventHandler):
            def on_any_event(self, event):
                if event.is_directory or event.event_type in ("opened", "closed_no_write"):
                    return
                now = time.perf_counter()
                for p in (getattr(event, "src_path", None), getattr(event, "dest_path", None)):
                    if p:
                        p = os.path.abspath(os.fsdecode(p))
                        with watcher._lock:
                            hit = p in watcher._paths
                            if hit:         # closed after writing, or moved into place: the save is complete
                                watcher._changed[p] = (now, event.event_type in ("closed", "moved"))
                        if hit and watcher.wake is not None:
                            watcher.wake()

        paths = {os.path.abspath(p) for p in paths if p}
        with self._lock:
            self._paths = paths
        for d in sorted({os.path.dirname(p) for p in paths}):
            if d not in self._dirs and os.path.isdir(d):
                try:
                    self._dirs[d] = self._observer.schedule(Handler(), d, recursive=False)
                except OSError:
                    pass

    def changed(self, settle=0.02):
        """{path: time of its last event} of the paths whose save is complete: the last event closed the file
        after writing or moved it into place, or is at least `settle` seconds old (a save is often several
        events: truncated, written, closed)."""
        now = time.perf_counter()
        with self._lock:
            ready = {p: t for p, (t, done) in self._changed.items() if done or now - t >= settle}
            for p in ready:
                del self._changed[p]
        return ready

    def close(self):
        self._observer.stop()
        self._observer.join(timeout=5)


# ------------------------------------------------------------------ drawing

_FULLSCREEN_VS = """#version 400
out vec2 v_uv;
void main()
{
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    v_uv = p;
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
"""

# the environment seen behind the object: each pixel's view direction through the lat-long map as the shaders
# read it (u = atan(x, -z) / 2 pi + 0.5, v = -asin(y) / pi + 0.5 after the environment matrix; row 0 on top)
_BACKGROUND_FS = """#version 400
in vec2 v_uv;
out vec4 out_color;
uniform mat4 u_inverseViewProjection;
uniform mat4 u_envMatrix;
uniform sampler2D u_envRadiance;
void main()
{
    vec4 far = u_inverseViewProjection * vec4(v_uv * 2.0 - 1.0, 1.0, 1.0);
    vec4 near = u_inverseViewProjection * vec4(v_uv * 2.0 - 1.0, -1.0, 1.0);
    vec3 d = normalize(far.xyz / far.w - near.xyz / near.w);
    d = (u_envMatrix * vec4(d, 0.0)).xyz;
    vec2 uv = vec2(atan(d.x, -d.z) / 6.283185307179586 + 0.5, -asin(clamp(d.y, -1.0, 1.0)) / 3.141592653589793 + 0.5);
    out_color = vec4(textureLod(u_envRadiance, uv, 0.0).rgb, 1.0);
}
"""

_COPY_FS = """#version 400
in vec2 v_uv;
out vec4 out_color;
uniform sampler2D u_image;
void main()
{
    out_color = texture(u_image, v_uv);
}
"""

# the accumulated mean as the screen shows it: sRGB encoded (images.srgb_encode), over grey where transparent
_PRESENT_FS = """#version 400
in vec2 v_uv;
out vec4 out_color;
uniform sampler2D u_image;
uniform float u_scale;
vec3 srgb(vec3 c)
{
    c = max(c, vec3(0.0));
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main()
{
    vec4 c = texture(u_image, v_uv) * u_scale;
    float a = clamp(c.a, 0.0, 1.0);
    out_color = vec4(clamp(srgb(c.rgb) + vec3(0.18) * (1.0 - a), 0.0, 1.0), 1.0);
}
"""


@dataclass
class Loaded:
    """An element as drawn: its generated text, the linked program, and values set from the panel."""
    generated: Generated
    prepared: object
    stale: bool = False                 # the document changed since: regenerate before it is shown again
    overrides: dict = field(default_factory=dict)    # uniform -> value set by the property panel
    values: dict = field(default_factory=dict)       # uniform -> the document's value on the program (manifest's,
                                                     # then those value edits set)
    edited: set = field(default_factory=set)         # uniforms value edits set since the text was generated
    moving: object = None               # the prefiltered variant drawn while the camera moves (Viewer.moving_prepared)
    moving_generated: object = None     # its Generated, from the reloader (Viewer.apply_moving)
    moving_asked: object = None         # the Generated whose variant was asked for (asked once each)

    def release(self):
        self.prepared.release()
        if self.moving is not None:
            self.moving.release()
            self.moving = None

    def folded(self, uniform):
        """A public input the specialized shader has as a constant (editing it regenerates)."""
        return uniform in self.generated.manifest.get("folded", ())


def manifest_values(g):
    """{uniform: value} of a Generated's manifest uniforms (vectors as tuples of floats) whose initial value in
    the text is that value: the document's value as it is, nothing made of it on the way (a value edit sets
    these only)."""
    text = initial_values(g.fragment)
    out = {}
    for u in g.manifest.get("uniforms", ()):
        v = u.get("value")
        v = tuple(v) if isinstance(v, list) else v
        if u.get("name") in text and _same(v, text[u["name"]]):
            out[u["name"]] = v
    return out


class Viewer:
    """One viewing session (see the module's docstring). Drive it with frame(); feed it mouse and keys."""
    keys = KEYS                       # (key, what it does), for the key help (the property panel shows it)

    def __init__(self, ctx, path, size=(512, 512), element=None, generator=None, environment_method="fis",
                 env_file=None, lights_file=None, geometry="sphere", samples=256, background=True,
                 output_dir=".", watch=True, out=None, progressive=True, frame_samples=FRAME_SAMPLES,
                 keep_program=True):
        self.ctx = ctx
        self.path = os.path.abspath(path)
        self.display_path = path
        self.out = out or sys.stderr
        self.size = tuple(size)
        from mtlxgen.base.interface import LIGHTS_LIMIT
        from mtlxgen.options import GenerateOptions
        # with a rig, shaders take as many lights as a rig may hold (the rig file is watched and may grow); the
        # loop runs over the bound ones only, so the bound costs the array's size, not time
        self.generator = generator or OurGenerator(GenerateOptions(max_lights=LIGHTS_LIMIT if lights_file else 0))
        self.environment_method = environment_method
        self.env_file = os.path.abspath(env_file) if env_file else None
        self.lights_file = os.path.abspath(lights_file) if lights_file else None
        self.samples = samples
        self.frame_samples = frame_samples
        self.keep_program = keep_program    # False: relink on every change, values too (as MaterialXView does)
        self.progressive = progressive
        self.moving_prefiltered = True      # draw the GGX-prefiltered variant while the camera moves (fis shaders)
        self.background = background
        self.lights_on = True
        self.output_dir = output_dir
        self.show_panel = True
        self.rig = []
        self.rig_problems = []
        env = render.load_environment(self.env_file) if self.env_file else None
        self.renderer = render.Renderer(size=1, environment=env, ctx=ctx)
        self.geometry_name = geometry
        self.camera = OrbitCamera()
        self.set_geometry(geometry)
        self.elements = []
        self.element = element
        self.loaded = {}                    # element -> Loaded
        self.session = None                 # the generator's handle on the last document read without problems
        self.problems = []                  # lines shown while the document has problems
        self.warnings = []
        self.generation = 0                 # reloads applied
        self.shown_generation = 0           # the reload whose result the last frame drew
        self.last_reload = None             # (seconds from the file's change to the applied result, what happened)
        self.base = None                    # the document's XML as the drawn shaders were generated from it
        self.base_data = None               # and its bytes
        self.behind = False                 # value edits set since the session was read (it still has the old ones)
        self._catch_up = False              # read the document again after the next frame (value edits set)
        self.frame_time = 0.0
        self.frames = 0
        self.moving = False
        self._moved = False
        self._camera_moved = False
        self._quick = EDIT_SAMPLES          # samples of the quick frame drawn now (moving)
        self._preview = False               # the frame in the buffer is a quick one of few samples
        self.wake = None                    # called from other threads when there is something to draw
        self.accumulated = 0                # frames in the accumulation buffer
        self._programs = {name: ctx.program(vertex_shader=_FULLSCREEN_VS, fragment_shader=fs)
                          for name, fs in (("background", _BACKGROUND_FS), ("copy", _COPY_FS),
                                           ("present", _PRESENT_FS))}
        self._quads = {name: ctx.vertex_array(p, []) for name, p in self._programs.items()}
        self._targets = None
        self._make_targets()
        self._load_rig(say=False)
        self.reloader = Reloader(self.generator, self.path, wake=self._wake)
        self.watcher = None
        if watch:
            try:
                self.watcher = Watcher(wake=self._wake)
            except ImportError:
                self.say("%s:0: note: file watching needs watchdog (pip install 'mtlxgen[view]'): "
                         "press R to reload" % self.display_path)
        self._reload_now(element)
        self._moved = False                 # the first frames accumulate at once

    def _wake(self):
        if self.wake is not None:
            self.wake()

    # -------------------------------------------------------------- messages

    def say(self, line):
        print(line, file=self.out, flush=True)

    # -------------------------------------------------------------- setup

    def _make_targets(self):
        if self._targets:
            for t in self._targets.values():
                for a in t.color_attachments + ([t.depth_attachment] if t.depth_attachment else []):
                    a.release()
                t.release()
        w, h = self.size
        ctx = self.ctx
        self._targets = {
            "frame": ctx.framebuffer(color_attachments=[ctx.texture((w, h), 4, dtype="f4")],
                                     depth_attachment=ctx.depth_renderbuffer((w, h))),
            "sum": ctx.framebuffer(color_attachments=[ctx.texture((w, h), 4, dtype="f4")]),
        }
        self.accumulated = 0

    def resize(self, width, height):
        if (width, height) != self.size and width > 0 and height > 0:
            self.size = (int(width), int(height))
            self._make_targets()

    def set_geometry(self, name):
        from mtlxgen.draw import geometry as geom
        attrs, index = geom.geometry(name)
        self.renderer.set_geometry(attrs, index)
        for loaded in getattr(self, "loaded", {}).values():     # vertex arrays are per mesh
            if loaded.prepared.vao is not None:
                loaded.prepared.vao.release()
                loaded.prepared.vao = None
        self.geometry_name = name
        centre, radius = geom.bounds(attrs)
        if name == "sphere":
            self.camera.home = ((0.0, 0.0, 0.0), render.EYE[2])     # render's camera exactly
            self.camera.reset()
        else:
            self.camera.frame(centre, radius)
        self.changed()

    def _load_rig(self, say=True):
        """Read the light rig; its problems are said here when `say` (a reload of the rig), else by the first
        apply(), which says every problem (said here too, each was printed twice)."""
        if not self.lights_file:
            return
        from mtlxgen.draw.lights import load_light_rig
        try:
            self.rig = load_light_rig(self.lights_file)
            self.rig_problems = []
        except MtlxError as e:
            self.rig_problems = e.lines()
            for line in self.rig_problems if say else ():
                self.say(line)
        self.changed()

    # -------------------------------------------------------------- reloading

    def _reload_now(self, element=None, changed_at=0.0):
        """Generate synchronously (the first load, and tests that want no thread in between)."""
        self.apply(self.reloader.generate(element or self.element, self.environment_method, changed_at))

    def request_reload(self, changed_at=0.0):
        self.reloader.request(self.element, self.environment_method, changed_at)

    def apply(self, r):
        """Take a reload's result: relink what changed, keep the last good shader where there are problems."""
        self.generation += 1
        what = []
        if r.session is not None:
            self.session = r.session
            self.elements = r.elements
            self.behind = False
            for loaded in self.loaded.values():
                loaded.stale = True
        if self.element not in self.elements and self.elements:
            self.element = self.elements[0]
        for name, g in r.shaders.items():
            what.append(self._install(name, g))
        problems = r.problems + r.notes + self.rig_problems
        good = (r.session is not None and not r.problems and not self.rig_problems and self.element in r.shaders
                and r.tree is not None)     # notes: drawn all the same, and value edits go on skipping generation
        self.base, self.base_data = (r.tree, r.data) if good else (None, None)
        if problems != self.problems:
            for line in problems:
                self.say(line)
            if self.problems and not problems:
                self.say("%s: no problems: drawing %s" % (self.display_path, self.element))
        for line in r.warnings:
            if line not in self.warnings:
                self.say(line)
        self.warnings = list(r.warnings)
        self.problems = problems
        self._files = set(r.files) | {os.path.abspath(self.path)}
        self._rewatch()
        if r.changed_at:
            self.last_reload = (time.perf_counter() - r.changed_at, ", ".join(w for w in what if w) or "problems")
        self.changed()
        self.set_title()

    def _install(self, name, g):
        """Link `g` for element `name` unless the drawn program differs from it only in initial values."""
        old = self.loaded.get(name)
        changed = None
        if old is not None and self.keep_program and old.generated.vertex == g.vertex \
                and self._same_bindings(old.generated, g) \
                and skeleton(old.generated.fragment) == skeleton(g.fragment):
            before, after = initializers(old.generated.fragment), initializers(g.fragment)
            names = {k for k, v in after.items() if before.get(k) != v or k in old.edited}   # the program's
            changed = initial_values(g.fragment, names)
            if len(changed) != len(names):          # a value a program cannot be given (a struct): link anew
                changed = None
        if changed is not None:
            for k, v in changed.items():
                old.overrides.pop(k, None)
                set_uniform(old.prepared.prog, k, v)
            old.generated, old.stale = g, False
            old.prepared.manifest = g.manifest
            old.values, old.edited = manifest_values(g), set()
            return "%s: %d value%s set" % (name, len(changed), "" if len(changed) == 1 else "s") if changed else ""
        try:
            prepared = self.renderer.prepare(g.vertex, g.fragment, g.manifest)
        except Exception as e:          # the driver refused it: a bug of ours or of the driver; keep the old one
            lines = str(e).strip().splitlines()
            self.problems = ["%s:0: %s: the shader did not link: %s" % (self.display_path, name,
                                                                       lines[-1] if lines else type(e).__name__)]
            self.say(self.problems[0])
            return ""
        overrides = {}
        if old is not None:
            # the panel's values stay where the document's did not change (or the input was a constant: a
            # specialized shader's folded input the panel set, now kept)
            before, after = initial_values(old.generated.fragment), initial_values(g.fragment)
            overrides = {k: v for k, v in old.overrides.items() if before.get(k) == after.get(k) or k not in before}
            old.release()
        for k, v in overrides.items():
            set_uniform(prepared.prog, k, v)
        self.loaded[name] = Loaded(g, prepared, overrides=overrides, values=manifest_values(g))
        self._ask_moving(name, self.loaded[name])
        return "%s: linked" % name

    @staticmethod
    def _sampled(loaded):
        """A lit fis shader: the environment sampled (its program reads u_envRadianceSamples)."""
        return loaded.generated.manifest.get("environment") == "fis" and "u_envRadianceSamples" in loaded.prepared.prog

    def _ask_moving(self, name, loaded):
        """Have the reloader generate the prefiltered variant of a lit fis shader, once per text linked."""
        if self.moving_prefiltered and self.session is not None and self._sampled(loaded) \
                and loaded.moving_asked is not loaded.generated and hasattr(self.generator, "moving_shader"):
            loaded.moving_asked = loaded.generated
            self.reloader.request_moving(name, self.session, loaded.generated)

    def apply_moving(self, m):
        """Take a prefiltered variant: kept for its element where the shader drawn is still the one it was made
        for (or differs from it in initial values only) and it declares the same uniforms; linked at the next
        moving frame (moving_prepared). Nothing redrawn."""
        loaded = self.loaded.get(m.element)
        if loaded is None or m.generated is None:
            return
        g = loaded.generated
        same = m.fis is g or (m.fis.vertex == g.vertex and self._same_bindings(m.fis, g)
                              and skeleton(m.fis.fragment) == skeleton(g.fragment))
        names = lambda x: sorted(u.get("name") for u in x.manifest.get("uniforms", ()))
        if not same or names(m.generated) != names(g) or not self._same_bindings(m.generated, g):
            return
        if loaded.moving is not None:
            loaded.moving.release()
            loaded.moving = None
        loaded.moving_generated = m.generated

    def unfold(self, uniform, value):
        """The panel set an input the specialized shader folded: kept a uniform from now on, the element
        generated again (the panel's value set on the new program)."""
        loaded = self.loaded.get(self.element)
        if loaded is None or not hasattr(self.generator, "keep"):
            return False
        self.generator.keep(self.element, uniform)
        loaded.overrides[uniform] = value
        loaded.stale = True
        self.changed()
        return True

    def _rewatch(self):
        """Watch the document's files, the textures of the elements linked so far, the rig and the map."""
        if self.watcher is not None:
            watched = set(getattr(self, "_files", ())) | {os.path.abspath(self.path)} | self.texture_files()
            self.watcher.watch(watched | {f for f in (self.lights_file, self.env_file) if f})

    @staticmethod
    def _same_bindings(a, b):
        key = lambda g: [(t.get("uniform"), t.get("file"), t.get("default")) for t in g.manifest.get("textures", [])]
        return key(a) == key(b)

    def texture_files(self):
        out = set()
        for loaded in self.loaded.values():
            for _, path, _ in loaded.prepared.samplers:
                if path:
                    out.add(os.path.abspath(path))
        return out

    def poll(self):
        """Take finished reloads and file changes (called by frame())."""
        for r in self.reloader.results():
            if isinstance(r, Moving):
                self.apply_moving(r)
            else:
                self.apply(r)
        if self.watcher is None:
            return
        changed = self.watcher.changed()
        if not changed:
            return
        first = min(changed.values())
        textures = self.texture_files()
        regenerate = False
        for path in changed:
            if path in textures:
                self.renderer.forget_texture(path)
                self.say("%s: texture reloaded" % path)
                self.last_reload = (time.perf_counter() - changed[path], "texture")
                self.changed()
            if path == self.lights_file:
                self._load_rig()
                self.set_title()
            if path == self.env_file:
                try:
                    self.renderer.set_environment(render.load_environment(self.env_file))
                except MtlxError as e:
                    for line in e.lines():
                        self.say(line)
                self.changed()
            if path not in textures and path not in (self.lights_file, self.env_file):
                regenerate = True
        if regenerate and set(changed) == {self.path}:
            data = read_bytes(self.path)
            if data is not None and data == self.base_data and not self.reloader.busy():
                return                      # the same bytes as drawn (a save's trailing event, a touch)
            if self._value_edit(first, data):
                return
        if regenerate:
            self.request_reload(first)

    def _value_edit(self, changed_at, data):
        """A document edit that changed only input values of public uniforms of the shown element's shader: the
        values set on the linked program, no generation (the session is read again after the next frame).
        Each edited input's uniforms are those whose Origin names it (its element's name path and its name),
        the uniform's FILE:LINE that of the input. False (nothing done) where in doubt: anything but <input>
        values changed, an input MaterialX does not read by its name path (a repeated name), one that feeds no
        uniform of the shown shader or feeds it otherwise than as its value (its current value is not the
        uniform's), a folded input of a specialized shader, a type a program cannot be set to, a value that does
        not read cleanly, a reload in flight, problems shown."""
        from mtlxgen.base import mxtypes
        loaded = self.loaded.get(self.element)
        if self.base is None or loaded is None or loaded.stale or not loaded.generated.sources \
                or self.problems or self.reloader.busy() or not self.keep_program:
            return False
        new = parse_tree(data, self.path)
        if new is None:
            return False
        edits = value_edits(self.base, new)
        if edits is None:
            return False
        if not edits:                   # the same elements, attributes and lines (a comment, spaces): the same
            self.base_data = data       # shaders, nothing to do
            return True
        changes = {}
        for where, a, b in edits:
            t = b.get("type")
            if where is None or a.get("value") is None or b.get("value") is None or t not in SETTABLE:
                return False
            # the uniforms the input's Origin names, confirmed at the input's FILE:LINE
            targets = loaded.generated.sources.get(where, ())
            at = (os.path.abspath(a.loc.file), a.loc.line)
            if not targets or any(loc != at for _, _, loc in targets):
                return False
            try:
                before, after = mxtypes.parse_value(t, a.get("value")), mxtypes.parse_value(t, b.get("value"))
            except Exception:
                return False
            for uniform, utype, _ in targets:
                if utype != t or uniform not in loaded.values or loaded.folded(uniform) \
                        or not _same(loaded.values[uniform], before):
                    return False
                changes[uniform] = after
        self.base, self.base_data = new, data
        for k, v in changes.items():
            loaded.overrides.pop(k, None)
            loaded.values[k] = v
            loaded.edited.add(k)
            set_uniform(loaded.prepared.prog, k, v)
        for name, other in self.loaded.items():      # other elements may read the same inputs: regenerated
            if name != self.element:
                other.stale = True
        self.behind = self._catch_up = True
        self.generation += 1
        self.last_reload = (time.perf_counter() - changed_at, "%s: %d value%s set, not generated" % (
            self.element, len(changes), "" if len(changes) == 1 else "s"))
        self.changed()
        return True

    def current(self):
        """The Loaded element to draw (regenerated first if the document changed since it was linked)."""
        name = self.element
        if name is None:
            return None
        loaded = self.loaded.get(name)
        if (loaded is None or loaded.stale) and self.behind:
            self._reload_now()                  # the session has the values before the value edits: read again
            loaded = self.loaded.get(name)
        if (loaded is None or loaded.stale) and self.session is not None and name in self.elements:
            try:
                self._install(name, self.generator.shader(self.session, name))
                self._rewatch()
            except MtlxError as e:
                if e.lines() != self.problems:
                    self.problems = e.lines()
                    for line in self.problems:
                        self.say(line)
                    self.set_title()
                if name in self.loaded:
                    self.loaded[name].stale = False
            loaded = self.loaded.get(name)
        return loaded

    # -------------------------------------------------------------- actions (keys)

    def cycle_element(self, step=1):
        if not self.elements:
            return
        i = self.elements.index(self.element) if self.element in self.elements else 0
        self.element = self.elements[(i + step) % len(self.elements)]
        self.changed()
        self.set_title()

    def toggle_environment(self):
        self.environment_method = "prefiltered" if self.environment_method == "fis" else "fis"
        self.say("environment: %s" % self.environment_method)
        for loaded in self.loaded.values():
            loaded.stale = True
        self._reload_now()

    def cycle_samples(self):
        i = SAMPLE_STEPS.index(self.samples) if self.samples in SAMPLE_STEPS else -1
        self.samples = SAMPLE_STEPS[(i + 1) % len(SAMPLE_STEPS)]
        self.changed()
        self.say("samples: %d" % self.samples)
        self.set_title()

    def toggle_lights(self):
        self.lights_on = not self.lights_on
        if not self.lights_file:
            self.say("lights: no light rig given (--lights RIG.mtlx)")
        self.changed()
        self.set_title()

    def toggle_background(self):
        self.background = not self.background
        self.changed()
        self.set_title()

    def cycle_geometry(self):
        from mtlxgen.draw.geometry import BUILTIN
        i = BUILTIN.index(self.geometry_name) if self.geometry_name in BUILTIN else -1
        self.set_geometry(BUILTIN[(i + 1) % len(BUILTIN)])
        self.set_title()

    def print_frame_time(self):
        ms = self.frame_time * 1000.0
        self.say("frame %.1f ms (%.1f fps), %s" % (ms, 1000.0 / ms if ms > 0 else 0.0, self.sample_status()))

    def moved(self):
        """The camera moved this frame: draw with few samples (MOVING_SAMPLES), start accumulating again once
        still."""
        self._moved = self._camera_moved = True

    def changed(self):
        """What is drawn changed (an edit, a setting): a quick frame of EDIT_SAMPLES first, then the
        accumulation."""
        self._moved = True

    # -------------------------------------------------------------- drawing

    def plan(self, loaded):
        """(samples per frame, frames to accumulate) for the element drawn now."""
        lit = loaded is not None and "u_envRadianceSamples" in loaded.prepared.prog
        if not lit:
            return 1, 1
        if self.moving:
            return self._quick, 1
        if not self.progressive:
            return self.samples, 1
        n = min(self.frame_samples, self.samples)
        return n, max(self.samples // n, 1)

    def sample_status(self):
        loaded = self.loaded.get(self.element)
        if loaded is None or "u_envRadianceSamples" not in loaded.prepared.prog:
            return "no environment samples"
        n, frames = self.plan(loaded)
        if loaded.generated.manifest.get("environment") == "prefiltered":
            return "prefiltered environment"
        done = min(self.accumulated, frames)
        return "%d/%d samples%s" % (done * n, n * frames, " (converged)" if done >= frames else "")

    def converged(self):
        """Nothing left to draw: every frame of the estimate accumulated (not a quick frame, nothing pending)."""
        loaded = self.loaded.get(self.element)
        if loaded is None:
            return True
        if self._moved or self._preview:
            return False
        moving, self.moving = self.moving, False
        try:
            return self.accumulated >= self.plan(loaded)[1]
        finally:
            self.moving = moving

    def frame(self, target=None):
        """Draw one frame: take reloads, add one accumulation step if not converged, present into `target`."""
        t0 = time.perf_counter()
        self.poll()
        self.moving, self._moved = self._moved, False
        self._quick = MOVING_SAMPLES if self._camera_moved else EDIT_SAMPLES
        self._camera_moved = False
        if self.moving:
            self.accumulated = 0
        loaded = self.current()
        drew = False
        if loaded is not None:
            n, frames = self.plan(loaded)
            if self._preview and not self.moving:       # still again: the quick frame is not part of the mean
                self.accumulated, self._preview = 0, False
            if self.accumulated < frames:
                self._draw_once(loaded, n, frames)
                self.shown_generation = self.generation
                self._preview = self.moving and frames == 1 and n == self._quick and \
                    "u_envRadianceSamples" in loaded.prepared.prog
                drew = True
        elif self.accumulated == 0:
            self._targets["sum"].clear(0.0, 0.0, 0.0, 0.0)
            self.accumulated = 1
        if target is not None:
            self.present(target)
        self.frames += 1
        if self._catch_up and drew:         # value edits shown: the session reads the document again, off the
            self._catch_up = False          # drawing thread (the panel, other elements)
            self.request_reload()
        if drew:                        # the time of a frame that drew (a converged picture is only presented)
            self.ctx.finish()
            self.frame_time = time.perf_counter() - t0

    def _draw_once(self, loaded, n, frames):
        ctx, frame, total = self.ctx, self._targets["frame"], self._targets["sum"]
        camera = self.camera.camera()
        frame.use()
        frame.clear(0.0, 0.0, 0.0, 0.0)
        if self.background:
            self._draw_background(camera)
        lights = (self.rig if self.lights_on else [])
        k = self.accumulated
        if self.background:
            # the surface over the environment: its colour is already weighted by its opacity (MaterialX's
            # surface closure), so "over" is premultiplied; a cut-out shows the environment, not a hole
            ctx.enable(self.renderer.mgl.BLEND)
            ctx.blend_func = self.renderer.mgl.ONE, self.renderer.mgl.ONE_MINUS_SRC_ALPHA
        prepared = loaded.prepared
        if self.moving and self._quick == MOVING_SAMPLES and self.moving_prefiltered:
            prepared = self.moving_prepared(loaded) or prepared
        self.renderer.draw(prepared, target=frame, camera=camera, clear=False, env_samples=n,
                           sample_frame=(k, frames) if frames > 1 else (0, 1), lights=lights)
        ctx.disable(self.renderer.mgl.BLEND)
        ctx.disable(self.renderer.mgl.DEPTH_TEST)
        total.use()
        if k == 0:
            ctx.disable(self.renderer.mgl.BLEND)
        else:
            ctx.enable(self.renderer.mgl.BLEND)
            ctx.blend_func = self.renderer.mgl.ONE, self.renderer.mgl.ONE
        frame.color_attachments[0].use(0)
        self._programs["copy"]["u_image"].value = 0
        self._quads["copy"].render(self.renderer.mgl.TRIANGLES, vertices=3)
        ctx.disable(self.renderer.mgl.BLEND)
        self.accumulated = k + 1

    def moving_prepared(self, loaded):
        """The prefiltered variant of a lit fis shader (the generator's moving_shader, generated off the drawing
        thread by the reloader: the same element and options, environment "prefiltered"), linked at the first
        camera move once it is there and kept with the element's program, its uniforms given the program's values
        before each draw (panel and value edits included). None where the element is unlit or already prefiltered,
        or while its variant is not there yet (the fis program draws the moving frames)."""
        if not self._sampled(loaded):
            return None
        if loaded.moving is None:
            g = loaded.moving_generated
            if g is None:
                self._ask_moving(self.element, loaded)
                return None
            try:
                loaded.moving = self.renderer.prepare(g.vertex, g.fragment, g.manifest)
            except Exception:           # the driver refused it: the fis program draws the moving frames
                self.moving_prefiltered = False
                return None
        src, dst = loaded.prepared.prog, loaded.moving.prog
        mgl = self.renderer.mgl
        for name in dst:
            u = dst[name]
            if isinstance(u, mgl.Uniform) and name in src and getattr(u, "gl_type", None) not in render._SAMPLER_TYPES:
                try:
                    u.value = src[name].value
                except Exception:       # a member moderngl cannot read back: bind() sets what the draw needs
                    pass
        return loaded.moving

    def _draw_background(self, camera):
        prog = self._programs["background"]
        w, h = self.size
        inv = np.linalg.inv(camera.view_projection(w / float(h)))
        prog["u_inverseViewProjection"].write(np.ascontiguousarray(inv.T, dtype="f4").tobytes())
        env_matrix = np.array(self.renderer.scene.env_matrix or render.ENV_MATRIX)
        prog["u_envMatrix"].write(np.ascontiguousarray(env_matrix.T, dtype="f4").tobytes())
        self.renderer.env.use(0)
        prog["u_envRadiance"].value = 0
        self.ctx.disable(self.renderer.mgl.DEPTH_TEST)
        self._quads["background"].render(self.renderer.mgl.TRIANGLES, vertices=3)

    def present(self, target):
        """The accumulated mean, sRGB encoded, into `target` (a window's framebuffer)."""
        target.use()
        self.ctx.disable(self.renderer.mgl.DEPTH_TEST)
        self.ctx.disable(self.renderer.mgl.BLEND)
        prog = self._programs["present"]
        self._targets["sum"].color_attachments[0].use(0)
        prog["u_image"].value = 0
        prog["u_scale"].value = 1.0 / max(self.accumulated, 1)
        self._quads["present"].render(self.renderer.mgl.TRIANGLES, vertices=3)

    def image(self):
        """The accumulated mean: linear RGBA float32, row 0 on top (what a screenshot writes)."""
        w, h = self.size
        raw = self._targets["sum"].read(components=4, dtype="f4")
        return np.frombuffer(raw, dtype="f4").reshape(h, w, 4)[::-1] / float(max(self.accumulated, 1))

    def screenshot(self, path=None):
        """PNG (sRGB) and EXR (linear) of the accumulated image; `render`'s naming (DIR/STEM.png, .exr) unless
        a file is named (FILE.png and FILE.exr beside it, or FILE.exr and FILE.png). Returns the paths: none where
        the shown element was never drawn (a document with problems from the start), said on one line; a black
        picture would pass for a render."""
        from mtlxgen.base.images import write_image
        if self.loaded.get(self.element) is None:
            self.say("%s:0: no screenshot: nothing is drawn%s" % (self.display_path, " (the document has problems)"
                                                                  if self.problems else ""))
            return []
        if path is None:
            loaded = self.loaded.get(self.element)
            stem = loaded.generated.stem if loaded is not None else "view"
            base = os.path.join(self.output_dir, stem)
        else:
            base, ext = os.path.splitext(path)
            if ext.lower() not in (".png", ".exr"):
                base = path
        img = self.image()
        out = [write_image(base + ".png", img), write_image(base + ".exr", img)]
        return out

    # -------------------------------------------------------------- title

    def title(self):
        parts = ["mtlxgen view: %s" % os.path.basename(self.display_path)]
        if self.element:
            parts.append("%s (%d/%d)" % (self.element, (self.elements.index(self.element) + 1)
                                         if self.element in self.elements else 0, len(self.elements)))
        parts.append("%s, %s" % (self.environment_method, self.sample_status()))
        if self.lights_file:
            parts.append("lights %s" % ("on" if self.lights_on else "off"))
        if self.problems:
            parts.append("PROBLEM: " + self.problems[0] + (" (+%d more)" % (len(self.problems) - 1)
                                                            if len(self.problems) > 1 else ""))
        else:
            parts.append("keys: Tab element, E env, S samples, L lights, B background, G geometry, C screenshot, "
                         "T time, P panel, Q quit")
        return " | ".join(parts)

    def set_title(self):
        pass                 # a window replaces this

    def close(self):
        if self.watcher is not None:
            self.watcher.close()
        self.reloader.close()
        for loaded in self.loaded.values():
            loaded.release()
        self.loaded = {}
        for q in self._quads.values():
            q.release()
        for p in self._programs.values():
            p.release()
        for t in self._targets.values():
            for a in t.color_attachments:
                a.release()
            if t.depth_attachment:
                t.depth_attachment.release()
            t.release()
        self.renderer.close()


# ------------------------------------------------------------------ windows

class OffscreenWindow:
    """A framebuffer in a headless context: what --headless-frames draws into without a display."""

    def __init__(self, size, title=""):
        self.ctx = render.create_context()
        self._size = tuple(size)
        self.screen = self.ctx.framebuffer(color_attachments=[self.ctx.texture(self._size, 4)])
        self.title = title
        self.viewer = None

    def framebuffer_size(self):
        return self._size

    def should_close(self):
        return False

    def set_title(self, title):
        self.title = title

    def poll(self, wait=0.0):
        pass

    def swap(self):
        self.ctx.finish()

    def close(self):
        self.screen.release()
        self.ctx.release()


class GlfwWindow:
    """A glfw window with an OpenGL 4 core context; mouse and keys go to the viewer (and the panel first)."""

    def __init__(self, size, title="mtlxgen view", visible=True):
        import glfw
        import moderngl
        self.glfw = glfw
        if not glfw.init():
            raise RuntimeError("glfw could not start: %s" % (glfw.get_error()[1] or "no display?"))
        self.window = None
        for major, minor in ((4, 5), (4, 1), (4, 0)):
            glfw.default_window_hints()
            glfw.window_hint(glfw.CONTEXT_VERSION_MAJOR, major)
            glfw.window_hint(glfw.CONTEXT_VERSION_MINOR, minor)
            glfw.window_hint(glfw.OPENGL_PROFILE, glfw.OPENGL_CORE_PROFILE)
            glfw.window_hint(glfw.OPENGL_FORWARD_COMPAT, True)
            glfw.window_hint(glfw.VISIBLE, bool(visible))
            self.window = glfw.create_window(int(size[0]), int(size[1]), title, None, None)
            if self.window:
                break
        if not self.window:
            glfw.terminate()
            raise RuntimeError("glfw could not open an OpenGL 4 window")
        glfw.make_context_current(self.window)
        glfw.swap_interval(0)
        self.ctx = moderngl.create_context(require=400)
        self.screen = self.ctx.detect_framebuffer()
        self.viewer = None
        self.panel = None
        self._last = None
        self._buttons = set()
        glfw.set_cursor_pos_callback(self.window, self._on_cursor)
        glfw.set_mouse_button_callback(self.window, self._on_button)
        glfw.set_scroll_callback(self.window, self._on_scroll)
        glfw.set_key_callback(self.window, self._on_key)
        glfw.set_char_callback(self.window, self._on_char)

    def framebuffer_size(self):
        return self.glfw.get_framebuffer_size(self.window)

    def should_close(self):
        return self.glfw.window_should_close(self.window)

    def set_title(self, title):
        self.glfw.set_window_title(self.window, title)

    def poll(self, wait=0.0):
        if wait > 0:
            self.glfw.wait_events_timeout(wait)
        else:
            self.glfw.poll_events()

    def swap(self):
        self.glfw.swap_buffers(self.window)

    def wake(self):
        """Wake the loop from another thread (a file changed, a reload finished)."""
        self.glfw.post_empty_event()

    def close(self):
        self.glfw.destroy_window(self.window)
        self.glfw.terminate()

    # input
    def _panel_wants(self, what):
        return self.panel is not None and self.panel.wants(what)

    def _on_cursor(self, window, x, y):
        if self.panel is not None:
            self.panel.mouse_pos(x, y)
        last, self._last = self._last, (x, y)
        if last is None or not self._buttons or self.viewer is None or self._panel_wants("mouse"):
            return
        h = max(self.glfw.get_window_size(self.window)[1], 1)
        dx, dy = (x - last[0]) / h, (y - last[1]) / h
        glfw = self.glfw
        shift = glfw.get_key(window, glfw.KEY_LEFT_SHIFT) == glfw.PRESS or \
            glfw.get_key(window, glfw.KEY_RIGHT_SHIFT) == glfw.PRESS
        if glfw.MOUSE_BUTTON_LEFT in self._buttons and not shift:
            self.viewer.camera.orbit(dx, dy)
        else:
            self.viewer.camera.pan(dx, dy)
        self.viewer.moved()

    def _on_button(self, window, button, action, mods):
        if self.panel is not None:
            self.panel.mouse_button(button, action == self.glfw.PRESS)
        if action == self.glfw.PRESS and not self._panel_wants("mouse"):
            self._buttons.add(button)
        elif action == self.glfw.RELEASE:
            self._buttons.discard(button)

    def _on_scroll(self, window, dx, dy):
        if self.panel is not None:
            self.panel.scroll(dx, dy)
        if self.viewer is not None and not self._panel_wants("mouse"):
            self.viewer.camera.zoom(dy)
            self.viewer.moved()

    def _on_char(self, window, codepoint):
        if self.panel is not None:
            self.panel.char(codepoint)

    def _on_key(self, window, key, scancode, action, mods):
        glfw = self.glfw
        if self.panel is not None:
            self.panel.key(key, action, mods)
        if action != glfw.PRESS or self.viewer is None or self._panel_wants("keyboard"):
            return
        name = glfw.get_key_name(key, scancode)
        special = {glfw.KEY_TAB: "tab", glfw.KEY_ESCAPE: "escape", glfw.KEY_F1: "f1"}.get(key)
        handle_key(self.viewer, (special or name or "").lower(), bool(mods & glfw.MOD_SHIFT), self)


def handle_key(viewer, key, shift=False, window=None):
    """One key press (names as KEYS gives them, lower case). Returns False for keys that mean nothing."""
    actions = {
        "tab": lambda: viewer.cycle_element(-1 if shift else 1),
        "e": viewer.toggle_environment, "s": viewer.cycle_samples, "l": viewer.toggle_lights,
        "b": viewer.toggle_background, "g": viewer.cycle_geometry, "t": viewer.print_frame_time,
        "r": lambda: viewer.request_reload(time.perf_counter()),
        "f": lambda: (viewer.camera.reset(), viewer.moved()),
        "c": lambda: [viewer.say("screenshot: %s" % p) for p in viewer.screenshot()],
        "p": lambda: setattr(viewer, "show_panel", not viewer.show_panel),
        "f1": lambda: viewer.say("keys:\n" + key_help()),
    }
    if key in ("q", "escape"):
        if window is not None and hasattr(window, "glfw"):
            window.glfw.set_window_should_close(window.window, True)
        return True
    action = actions.get(key)
    if action is None:
        return False
    action()
    return True


# ------------------------------------------------------------------ the command

def open_window(size, headless):
    """A glfw window where a display is (a visible one, or one under Xvfb); with --headless-frames and no
    display, an offscreen framebuffer. Raises MtlxError (one line) where neither can be had."""
    if headless and not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
        return OffscreenWindow(size)
    try:
        return GlfwWindow(size)
    except ImportError:
        if headless:
            return OffscreenWindow(size)
        raise MtlxError((Loc("mtlxgen view", 0), "the viewer needs glfw (pip install 'mtlxgen[view]')")) from None
    except Exception as e:
        if headless:
            return OffscreenWindow(size)
        raise MtlxError((Loc("mtlxgen view", 0), "no window: %s (no display? run it under Xvfb: xvfb-run -a "
                                                 "mtlxgen view ..., or use --headless-frames)" % e)) from None


def run(args):
    """`mtlxgen view` (cli.py parses the options)."""
    size = tuple(args.size)
    headless = args.headless_frames is not None
    window = open_window(size, headless)
    from mtlxgen.base.interface import LIGHTS_LIMIT
    # no --interface asked: the zero-weight specialization (OurGenerator); --interface complete turns it off
    asked = getattr(args, "interface", None) is not None or getattr(args, "keep", None) or getattr(args, "keep_file",
                                                                                                   None)
    generator = OurGenerator(args.generate_options.replace(max_lights=LIGHTS_LIMIT if args.lights else 0),
                             specialize=not asked)
    viewer = None
    try:
        viewer = Viewer(window.ctx, args.file, size=window.framebuffer_size() if not headless else size,
                        element=args.element, generator=generator, environment_method=args.environment,
                        env_file=args.env, lights_file=args.lights, geometry=args.geometry, samples=args.samples,
                        background=args.background, output_dir=args.output, watch=not args.no_watch,
                        progressive=not args.no_progressive, frame_samples=min(args.frame_samples, args.samples))
        if args.element and args.element not in viewer.elements and viewer.session is not None:
            raise MtlxError((Loc(args.file, 0), "no renderable element '%s' (elements: %s)"
                             % (args.element, ", ".join(viewer.elements) or "none")))
        window.viewer = viewer
        viewer.wake = getattr(window, "wake", None)
        viewer.set_title = lambda: window.set_title(viewer.title())
        viewer.set_title()
        panel = None
        if not args.no_panel and isinstance(window, GlfwWindow):
            panel = _open_panel(viewer, window)
        if not headless:
            viewer.say("mtlxgen view: %s; keys:\n%s" % (args.file, key_help()))
        frames = 0
        while not window.should_close():
            viewer.resize(*window.framebuffer_size())
            idle = viewer.converged() and not viewer.reloader.busy() and not headless
            window.poll(0.25 if idle else 0.0)     # events, file changes and reloads wake it sooner
            viewer.frame(window.screen)
            if panel is not None and viewer.show_panel:
                panel.draw(window.screen)
            window.swap()
            frames += 1
            if headless and frames >= args.headless_frames:
                break
        # pictures only of what was drawn (a black one would pass for a render); the problems that stopped the
        # drawing are said already, one line each
        drawn = viewer.loaded.get(viewer.element) is not None
        if drawn and args.screenshot:
            for p in viewer.screenshot(args.screenshot):
                print(p)
        if drawn and args.capture_window:
            print(capture(window, args.capture_window))
        if headless and viewer.problems:
            raise MtlxError([])
        if headless and not drawn:
            return 1
        return 0
    finally:
        if viewer is not None:
            viewer.close()
        window.close()


def capture(window, path):
    """What the window shows (the presented picture, the panel): an 8-bit PNG of its framebuffer."""
    from mtlxgen.base.images import write_image
    w, h = window.framebuffer_size()
    raw = window.screen.read(viewport=(0, 0, w, h), components=3)
    img = np.frombuffer(raw, dtype=np.uint8).reshape(h, w, 3)[::-1]
    return write_image(path, np.ascontiguousarray(img))


def _open_panel(viewer, window):
    try:
        from mtlxgen.apps.viewpanel import Panel
    except ImportError as e:
        viewer.say("%s:0: note: the property panel needs imgui-bundle (pip install 'mtlxgen[view]'): %s"
                   % (viewer.display_path, e))
        return None
    panel = Panel(viewer, window)
    window.panel = panel
    return panel
