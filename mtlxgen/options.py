"""How shaders are generated, beyond the document: one GenerateOptions, made and checked once where the settings
come in (the command line, the viewer, the Python API, a test) and handed down whole to pipeline.Session and
pipeline.generate, batch and golden runs (pickled to their workers as it is) and the viewer's Generator.

    opts = GenerateOptions(target="essl", interface="reduced", keep=("base_color",))
    shaders = pipeline.generate(path, opts)
    lit = opts.replace(max_lights=2)            # a variant: checked again, the original unchanged

Each bad value is a ValueError (a TypeError for a value of the wrong kind) of one sentence naming the option, raised
where the options are made, before any document is read. Light to import: nothing here reads a document or imports
the emitter (the command line builds one for --help-free argument checking)."""
import os
from mtlxgen.base.records import dataclass, fields, replace as _replace

from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.interface import LIGHTS_LIMIT
from mtlxgen.base.targets import NAMES as TARGETS

# emit.ENVIRONMENT_METHODS (tests/read/test_library_index.py holds them equal): here so that checking options does not
# import the emitter
ENVIRONMENT_METHODS = ("fis", "prefiltered")
INTERFACES = ("complete", "reduced")                    # reduce.INTERFACES
UNREADABLE_TEXTURES = ("warning", "error")
RENDER_CONTEXTS = ("mtlx", "universal")                 # usdstage: the surface output a material draws


@dataclass(frozen=True)
class GenerateOptions:
    """Every setting generation reads (pipeline.Session, pipeline.generate).

    target: "glsl" (desktop GLSL 4.00), "essl" (WebGL2's GLSL ES 3.00) or "vulkan" (GLSL 4.50 for SPIR-V): targets.py.
    interface: "complete" (every public input a uniform) or "reduced" (reduce.py); a reduce.Interface is taken
    apart into its kind and keep list. keep: inputs the reduced interface keeps uniforms, each a name or a
    (name, Loc or None) pair (Loc: the --keep-file line naming it); stored as pairs.
    environment: "fis" (filtered importance sampling) or "prefiltered" (ENVIRONMENT_METHODS).
    max_lights: direct lights (u_lightData[]) lit surfaces loop over, 0 to interface.LIGHTS_LIMIT (0: none).
    strict: a warning is an error. usd_seed_rules: USD's preview nodes by the UsdPreviewSurface seed's rules
    (nodes/usd.py); None: on for documents from USD.
    library_dirs: extra folders of .mtlx definitions.
    variants: USD stages, ((variant set, variant), ...) selected before reading; render_context: USD stages,
    "mtlx" or "universal" (None: "mtlx"). Either given for a .mtlx document is a problem at the file
    (stage_options).
    unreadable_textures: a texture file that cannot be read is a "warning" (the shader is valid) or an "error"
    (for whatever draws the shader, which would show a wrong image)."""
    target: str = "glsl"
    interface: str = "complete"
    keep: tuple = ()
    environment: str = "fis"
    max_lights: int = 0
    strict: bool = False
    usd_seed_rules: object = None                   # bool or None
    library_dirs: tuple = ()
    variants: tuple = ()
    render_context: object = None                   # str or None
    unreadable_textures: str = "warning"

    def __post_init__(self):
        iface = self.interface
        if not isinstance(iface, str):                  # a reduce.Interface: its kind and keep list
            from mtlxgen.passes.reduce import Interface
            if not isinstance(iface, Interface):
                raise TypeError("interface must be 'complete', 'reduced' or a reduce.Interface, not %s"
                                % type(iface).__name__)
            if self.keep:
                raise ValueError("keep is given twice: by the reduce.Interface and by keep")
            self._set("interface", iface.kind)
            self._set("keep", iface.keep)
        self._choice("interface", INTERFACES)
        self._set("keep", tuple(_keep_item(k) for k in _sequence("keep", self.keep)))
        if self.keep and self.interface != "reduced":
            raise ValueError("keep names inputs kept uniforms in the reduced interface (every input is a uniform in "
                             "the complete one): use interface='reduced'")
        self._choice("target", TARGETS)
        self._choice("environment", ENVIRONMENT_METHODS)
        self._choice("unreadable_textures", UNREADABLE_TEXTURES)
        if isinstance(self.max_lights, bool) or not isinstance(self.max_lights, int) \
                or not 0 <= self.max_lights <= LIGHTS_LIMIT:
            raise ValueError("max_lights must be a whole number from 0 to %d, not %r" % (LIGHTS_LIMIT, self.max_lights))
        if not isinstance(self.strict, bool):
            raise TypeError("strict must be True or False, not %r" % (self.strict,))
        if self.usd_seed_rules is not None and not isinstance(self.usd_seed_rules, bool):
            raise TypeError("usd_seed_rules must be True, False or None, not %r" % (self.usd_seed_rules,))
        dirs = _sequence("library_dirs", self.library_dirs)
        if not all(isinstance(d, (str, os.PathLike)) for d in dirs):
            raise TypeError("library_dirs must be folder paths, not %r" % (self.library_dirs,))
        self._set("library_dirs", tuple(os.fspath(d) for d in dirs))
        self._set("variants", tuple(_variant(v) for v in _sequence("variants", self.variants)))
        if self.render_context is not None:
            self._choice("render_context", RENDER_CONTEXTS)

    def _set(self, name, value):
        object.__setattr__(self, name, value)

    def _choice(self, name, allowed):
        value = getattr(self, name)
        if not isinstance(value, str) or value not in allowed:
            raise ValueError("%s must be one of %s, not %r" % (name, ", ".join(allowed), value))

    @classmethod
    def of(cls, options=None, **settings):
        """GenerateOptions from None (the defaults) or a GenerateOptions, with `settings` (field=value) on top:
        how pipeline.generate and Session take keywords as well as an options object. An unknown name is a
        TypeError naming the fields."""
        if options is not None and not isinstance(options, cls):
            raise TypeError("options must be a GenerateOptions, not %s" % type(options).__name__)
        if not settings:
            return options if options is not None else cls()
        return (options or cls()).replace(**settings)

    def replace(self, **changes):
        """These options with `changes` (field=value): checked as new ones are (an unknown name: TypeError)."""
        unknown = set(changes) - set(FIELDS)
        if unknown:
            raise TypeError("unknown generation option(s) %s; the options are %s"
                            % (", ".join(sorted(unknown)), ", ".join(FIELDS)))
        if "interface" in changes and not isinstance(changes["interface"], str) and "keep" not in changes:
            changes["keep"] = ()            # a reduce.Interface brings its own keep list
        return _replace(self, **changes)

    def make_interface(self):
        """A fresh reduce.Interface of the interface and keep list (it records which kept names matched an input
        of the elements generated: one per generation)."""
        from mtlxgen.passes.reduce import Interface
        return Interface(self.interface, list(self.keep))

    def stage_options(self, path):
        """usdstage.StageOptions for a USD stage at `path`; None for a .mtlx document, where variants or a render
        context are a problem (MtlxError, one line at the file)."""
        from mtlxgen import is_usd
        if not is_usd(path):
            if self.variants or self.render_context:
                raise MtlxError((Loc(path, 0), "%s applies to USD stages (.usd, .usda, .usdc, .usdz) only"
                                 % ("--variant" if self.variants else "--render-context")))
            return None
        from mtlxgen.read.usdstage import StageOptions
        return StageOptions(variants=self.variants, render_context=self.render_context or "mtlx")


FIELDS = tuple(f.name for f in fields(GenerateOptions))


def _sequence(name, value):
    if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
        raise TypeError("%s must be a list or tuple, not %r" % (name, value))
    return tuple(value)


def _keep_item(item):
    """(name, Loc or None) of a keep entry: a name alone, or a pair."""
    if isinstance(item, str):
        name, loc = item, None
    elif isinstance(item, (tuple, list)) and len(item) == 2 and isinstance(item[0], str) \
            and (item[1] is None or isinstance(item[1], Loc)):
        name, loc = item
    else:
        raise TypeError("keep must name inputs (strings), not %r" % (item,))
    if not name.strip():
        raise ValueError("keep: an input name must not be empty")
    return name, loc


def _variant(item):
    if not (isinstance(item, (tuple, list)) and len(item) == 2 and all(isinstance(s, str) and s.strip()
                                                                       for s in item)):
        raise ValueError("variants must be (variant set, variant) pairs of names, not %r" % (item,))
    return tuple(item)
