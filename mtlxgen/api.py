"""mtlxgen's Python API: MaterialX documents to GLSL shaders, and pictures of them, from Python.

    import mtlxgen

    for shader in mtlxgen.generate("material.mtlx"):          # a path, a string of XML, or a USD stage
        print(shader.name, len(shader.fragment), shader.manifest["uniforms"][:1])
        shader.write("out")                                   # out/NAME.vert, .frag, .json
    image = mtlxgen.render("material.mtlx", size=256)       # linear RGBA float32, row 0 on top

    with mtlxgen.Session() as session:                        # one GL context and library for many documents
        for path in paths:
            image = session.render(session.generate(path)[0])

Problems in a document raise mtlxgen.DocumentError, which carries every `FILE:LINE: problem` (its `problems`, and
str() of it one a line). Slips MaterialX reads past are warnings: each goes through Python's `warnings` module as
a mtlxgen.DocumentWarning (filter them, or turn them into errors, as any warning) and the list generate returns
holds them as lines in `.warnings`. The command line (`mtlxgen generate`, `render`, `web`, `three`) is built on
this module's generation: what the API returns is what the commands write.
"""
from __future__ import annotations

import os
import warnings as _warnings
from collections import namedtuple
from collections.abc import Iterable, Sequence
from mtlxgen.base.records import dataclass, fields

from mtlxgen.base.diagnostics import Loc, MtlxError, Warnings
from mtlxgen.emit.emitter import Shader

__all__ = ["generate", "render", "Session", "Shader", "Shaders", "Options", "DocumentError", "DocumentWarning",
           "Problem"]

PathLike = str | os.PathLike[str]
STRING_SOURCE = "<string>"      # the file name problems in a document given as a string of XML are reported at


class Problem(namedtuple("Problem", "loc message")):
    """One problem in a document: where (`loc`: file and line, or a USD stage's prim path) and what (`message`)."""
    __slots__ = ()

    @property
    def file(self) -> str:
        return self.loc.file

    @property
    def line(self) -> int:
        """The line in `file` (0: the file as a whole, or a USD stage's prim: see `loc.where`)."""
        return self.loc.line

    def __str__(self) -> str:
        return MtlxError([tuple(self)]).lines()[0]


class DocumentError(MtlxError):
    """A document (or a texture it names) that cannot be turned into shaders or drawn. `problems` holds every
    Problem found, each `FILE:LINE: what is wrong` as str() shows it; str() of the error is all of them, one a
    line. `warnings` holds the warnings met before the problems (Problem too)."""

    def __init__(self, problems, warnings=()):
        super().__init__([Problem(*p) for p in ([problems] if isinstance(problems, tuple) else problems)],
                         [Problem(*w) for w in warnings])

    @classmethod
    def of(cls, error: MtlxError) -> "DocumentError":
        return error if isinstance(error, cls) else cls(error.problems, error.warnings)


class DocumentWarning(UserWarning):
    """A slip MaterialX reads past (a value with text after its number, an input its nodedef lacks): the document is
    read as MaterialX reads it. The message is the `FILE:LINE: warning: ...` line; `problem` its Problem."""

    def __init__(self, line: str, problem: Problem | None = None):
        super().__init__(line)
        self.problem = problem


class Shaders(list):
    """The shaders generate returns (a list of Shader, one per renderable element, in document order), with the
    warnings met making them as `FILE:LINE: warning: ...` lines in `.warnings`."""
    warnings: list

    def __init__(self, shaders=(), warnings=()):
        super().__init__(shaders)
        self.warnings = list(warnings)


@dataclass(frozen=True)
class Options:
    """How shaders are generated beyond the target and interface (each a command-line option of the same name).

    library_dirs: extra folders of .mtlx definitions (--library); environment: "fis" (filtered importance sampling
    of u_envRadiance, u_envRadianceSamples samples) or "prefiltered" (one mip lookup per lobe); max_lights: direct
    lights the shaders loop over in u_lightData[] (0: environment light only); strict: warnings are errors; keep:
    inputs the reduced interface keeps uniforms (their complete-interface uniform names, or NODE/INPUT);
    usd_seed_rules: USD's preview nodes by the UsdPreviewSurface seed's rules (None: on for documents from USD);
    variants: USD stages, (variant set, variant) pairs to select; render_context: USD stages, "mtlx" or
    "universal"."""
    library_dirs: Sequence[str] = ()
    environment: str = "fis"
    max_lights: int = 0
    strict: bool = False
    keep: Sequence[str] = ()
    usd_seed_rules: bool | None = None
    variants: Sequence[tuple] = ()
    render_context: str | None = None

    @classmethod
    def of(cls, options) -> "Options":
        """Options from None, an Options, or a dict of its fields (an unknown name is a TypeError)."""
        if options is None:
            return cls()
        if isinstance(options, cls):
            return options
        if isinstance(options, dict):
            unknown = set(options) - {f.name for f in fields(cls)}
            if unknown:
                raise TypeError("unknown option(s) %s; options are %s"
                                % (", ".join(sorted(unknown)), ", ".join(f.name for f in fields(cls))))
            return cls(**options)
        raise TypeError("options must be a mtlxgen.Options or a dict, not %s" % type(options).__name__)


# ---------------------------------------------------------------- sources

def _is_xml_text(source) -> bool:
    return isinstance(source, str) and source.lstrip("\ufeff \t\r\n").startswith("<")


class _Source:
    """A document to read: a path as it is, or a string of XML written to a file of its own for the reading (its
    problems and warnings reported at <string>:LINE; relative file names in it resolve against no folder of the
    caller's: name textures by absolute path, or pass a file)."""

    def __init__(self, source):
        self.folder = None
        if _is_xml_text(source):
            import tempfile
            self.folder = tempfile.mkdtemp(prefix="mtlxgen-")
            self.path = os.path.join(self.folder, "document.mtlx")
            with open(self.path, "w", encoding="utf-8") as f:
                f.write(source)
        elif isinstance(source, (str, os.PathLike)):
            self.path = os.fspath(source)
        else:
            raise TypeError("source must be a path, a string of XML or a USD stage's path, not %s"
                            % type(source).__name__)

    def loc(self, loc):
        if self.folder is not None and loc.file == self.path:
            return Loc(STRING_SOURCE, loc.line, loc.where)
        return loc

    def items(self, items):
        return [(self.loc(loc), message) for loc, message in items]

    def error(self, e: MtlxError) -> DocumentError:
        return DocumentError(self.items(e.problems), self.items(e.warnings))

    def close(self):
        if self.folder is not None:
            import shutil
            shutil.rmtree(self.folder, ignore_errors=True)
            self.folder = None


def generate_options(target="glsl", interface="complete", options=None, **settings):
    """The options.GenerateOptions of the public calls' target, interface and Options (or dict of its fields), with
    `settings` (GenerateOptions fields: unreadable_textures, max_lights, ...) on top: where the public options become
    the internal ones, each bad value a ValueError (TypeError) of its own."""
    from mtlxgen.options import GenerateOptions
    opts = Options.of(options)
    if isinstance(interface, str) and interface not in ("complete", "reduced"):
        raise ValueError("interface must be 'complete' or 'reduced', not %r" % (interface,))
    public = dict(target=target, interface=interface, library_dirs=tuple(opts.library_dirs),
                  environment=opts.environment, max_lights=opts.max_lights, strict=opts.strict,
                  usd_seed_rules=opts.usd_seed_rules, variants=tuple(opts.variants),
                  render_context=opts.render_context)
    if isinstance(interface, str):
        public["keep"] = tuple(opts.keep)
    return GenerateOptions(**public).replace(**settings) if settings else GenerateOptions(**public)


def generate_partial(source, elements=None, options=None, warnings=None, **settings):
    """(shaders that worked, DocumentError or None): every element tried, the problems of those that failed
    collected. What generate and the command line share. options: an options.GenerateOptions (None: the defaults),
    `settings` its fields as keywords on top (pipeline.generate); warnings: a diagnostics.Warnings that receives the
    warnings (as (Loc, message), <string> for a string's)."""
    from mtlxgen import pipeline
    from mtlxgen.options import GenerateOptions
    opts = GenerateOptions.of(options, **settings)
    src = _Source(source)
    found = Warnings()
    try:
        shaders, error = pipeline.generate(src.path, opts, list(elements) if elements else None, partial=True,
                                           warnings=found)
        return shaders, (src.error(error) if error is not None else None)
    except MtlxError as e:
        raise src.error(e) from None
    finally:
        if warnings is not None:
            warnings.extend(src.items(found.items))
        src.close()


def _elements(element) -> list | None:
    if element is None:
        return None
    if isinstance(element, str):
        return [element]
    return list(element)


def _generate_all(source, element, target, interface, options, unreadable_textures="warning"):
    """Shaders of every element asked for (generate_partial), each warning issued as a DocumentWarning at the public
    call's caller; DocumentError where any element fails."""
    found = Warnings()
    opts = generate_options(target, interface, options, unreadable_textures=unreadable_textures)
    shaders, error = generate_partial(source, _elements(element), opts, warnings=found)
    lines = found.lines()
    for line, item in zip(lines, found.items):      # stacklevel 3: the caller of generate or Session.*
        _warnings.warn(DocumentWarning(line, Problem(*item)), stacklevel=3)
    if error is not None:
        raise error
    return Shaders(shaders, lines)


# ---------------------------------------------------------------- the public calls

def generate(source: PathLike | str, element: str | Iterable[str] | None = None, *, target: str = "glsl",
             interface: str = "complete", options: Options | dict | None = None) -> Shaders:
    """The shaders of a document's renderable elements (or of `element`: a name path, a USD material's prim path or
    name, or several of them).

    source: a .mtlx file's path, a string of MaterialX XML, or a USD stage's path (.usd, .usda, .usdc, .usdz).
    target: "glsl" (desktop GLSL 4.00), "essl" (WebGL2's GLSL ES 3.00) or "vulkan" (GLSL 4.50 for SPIR-V).
    interface: "complete" (every public input a uniform) or "reduced" (unconnected inputs become constants;
    Options.keep keeps some uniforms).
    options: an Options (or a dict of its fields).

    Returns a Shaders list of Shader (name, vertex, fragment, manifest; write(folder) writes NAME.vert, .frag and
    .json). Raises DocumentError with every problem of every element where any element fails (generate_partial
    gives the others too); warnings go through the `warnings` module as DocumentWarning and are in `.warnings`.
    A texture file that cannot be read is a warning (the shader is valid; its default colour is drawn)."""
    return _generate_all(source, element, target, interface, options)


def render(shader_or_source: Shader | PathLike | str, element: str | None = None, *, size: int = 256,
           environment=None, samples: int = 64, options: Options | dict | None = None):
    """A picture of a shader (or of a document's element: its first renderable one unless `element` names one) on
    `render`'s sphere, lit by `environment`, as a numpy array: linear RGBA float32, shape (size, size, 4), row 0 on
    top; what `mtlxgen render` writes to NAME.exr.

    environment: None (the built-in sky), a lat-long HDR/EXR path, or an (h, w, 3) float array. samples:
    u_envRadianceSamples (render's 64). options: how a document is generated (Options). A texture file that cannot
    be read raises DocumentError here, as the command does (a picture without it would be wrong)."""
    with Session(size=size, environment=environment, samples=samples, options=options) as session:
        return session.render(shader_or_source, element)


class Session:
    """Generation and drawing for many documents: one OpenGL context (made at the first render), one environment,
    the libraries read once. A context manager; close() releases the GL context.

    target, interface, options: as generate takes them, for every document; size, environment, samples: as render
    takes them, for every picture (each render call may give others)."""

    def __init__(self, *, target: str = "glsl", interface: str = "complete",
                 options: Options | dict | None = None, size: int = 256, environment=None, samples: int = 64):
        self.target, self.interface, self.options = target, interface, Options.of(options)
        self.size, self.environment, self.samples = int(size), environment, int(samples)
        self._renderer = None
        self._renderer_env = None

    def generate(self, source: PathLike | str, element: str | Iterable[str] | None = None) -> Shaders:
        """generate(source, element) with this session's target, interface and options."""
        return _generate_all(source, element, self.target, self.interface, self.options)

    def render(self, shader_or_source: Shader | PathLike | str, element: str | None = None, *,
               size: int | None = None, environment=None, samples: int | None = None):
        """render(...) with this session's GL context: a Shader as it is, or a document's element generated first."""
        from mtlxgen import pipeline
        if isinstance(shader_or_source, Shader):
            shader = shader_or_source
        else:
            # a picture of the wrong element, or of one missing a texture, is no answer: unreadable textures raise
            shader = _generate_all(shader_or_source, element, self.target, self.interface, self.options,
                                   unreadable_textures="error")[0]
        renderer = self._renderer_for(size or self.size, environment if environment is not None else self.environment)
        renderer.env_samples = int(samples or self.samples)
        try:
            return renderer.render(shader)
        except MtlxError as e:
            raise DocumentError.of(pipeline.at_inputs(shader, e)) from None

    def _renderer_for(self, size, environment):
        from mtlxgen.draw import renderer as _render
        key = environment if isinstance(environment, (str, os.PathLike, type(None))) else id(environment)
        if self._renderer is not None and self._renderer.size != size:
            self._renderer.close()
            self._renderer = None
        if self._renderer is None:
            self._renderer = _render.Renderer(size=size, environment=_environment_map(environment),
                                              env_samples=self.samples)
            self._renderer_env = key
        elif self._renderer_env != key:
            self._renderer.set_environment(_environment_map(environment))
            self._renderer_env = key
        return self._renderer

    def close(self):
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None

    def __enter__(self) -> "Session":
        return self

    def __exit__(self, *exc):
        self.close()


def _environment_map(environment):
    """The radiance map a Renderer lights with: None (its sky), a file read as render reads --env, or an array."""
    if environment is None:
        return None
    if isinstance(environment, (str, os.PathLike)):
        from mtlxgen.draw.environment import load_environment
        try:
            return load_environment(os.fspath(environment))
        except MtlxError as e:
            raise DocumentError.of(e) from None
    from mtlxgen.draw.environment import Environment
    if isinstance(environment, Environment):
        return environment.radiance[0]
    return environment
