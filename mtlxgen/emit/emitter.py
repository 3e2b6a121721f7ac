"""GLSL emitter: a typed Graph -> vertex and fragment GLSL plus the interface manifest.

The fragment stage is: version, closure types (when used), the glsl_lib files the nodes need (each
once, dependencies first), public uniforms with initializers, varyings, then `main` with one
statement per node output in dependency order. Variable names come from the graph's node ids, so the
same document always gives byte-identical shaders. The vertex stage passes exactly the streams the
fragment stage reads.

The Emitter emits nodes and offers the services templates and handlers use (expressions of inputs,
streams, library files, uniforms, closures in a context); the parts it consumes are modules of their own:
stagewriter.py writes main's lines at their depth, template.py expands an implementation's inline
template, closureplan.py says when each closure node is needed. Handlers (nodes/) take the graph and
return code: nothing they do changes the graph (the emitter's uniform table is its own).
"""
import functools
import json
import os
import re
from mtlxgen.base.records import dataclass, field

from mtlxgen.passes import closureplan
from mtlxgen.graph import functions, graphwalk
from mtlxgen.emit import glsldeps
from mtlxgen.base import interface, mxtypes, streams, targets
from mtlxgen import nodes
from mtlxgen.emit import template as template_expander
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.base.identifiers import is_plain_name, sha256, unique_identifier
from mtlxgen.graph.graphtypes import Uniform
from mtlxgen.read.library import glsl_lib_root
from mtlxgen.emit.stagewriter import StageWriter, comment_text  # noqa: F401 (emit.comment_text for callers)
from mtlxgen.emit.template import CLOSURE_TYPES

GLSL_VERSION = targets.TARGETS["glsl"].version


@dataclass
class Shader:
    element: str                      # the element's name path, as the document spells it
    vertex: str
    fragment: str
    manifest: dict = field(default_factory=dict)
    stem: str = None                  # file name stem (file_stem(element) unless unique_stems changed it)
    document_code: list = field(default_factory=list)   # Emitter.document_code: a document's own GLSL in it
    # {texture file: Loc of the input naming it}, for what draws the shader (pipeline.Session.drawable)
    texture_inputs: dict = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self):
        if self.stem is None:
            self.stem = file_stem(self.element)

    @property
    def name(self):
        """The element's name path (mtlxgen.Shader.name: the public API's spelling of `element`)."""
        return self.element

    def write(self, out_dir, absolute_paths=False):
        """Write STEM.vert, STEM.frag and STEM.json into out_dir (made where missing), each through a temporary
        file and a rename (files.write_atomic: a symlink at an output is replaced, never followed). Texture files
        in STEM.json are relative to out_dir (interface.relative_textures), absolute with absolute_paths. Returns
        the paths; MtlxError (one line naming the file) where the file system refuses."""
        from mtlxgen.base.files import write_atomic
        from mtlxgen.base.interface import relative_textures
        manifest = dict(self.manifest, vertex=self.stem + ".vert", fragment=self.stem + ".frag")
        if not absolute_paths:
            manifest = relative_textures(manifest, out_dir)
        paths = []
        p = out_dir
        try:
            os.makedirs(out_dir, exist_ok=True)
            for ext, text in ((".vert", self.vertex), (".frag", self.fragment),
                              (".json", json.dumps(manifest, indent=1) + "\n")):
                p = os.path.join(out_dir, self.stem + ext)
                write_atomic(p, text, durable=False)    # made again by running generate again: no fsyncs
                paths.append(p)
        except OSError as e:
            raise MtlxError((Loc(p, 0), "cannot write: %s" % (e.strerror or e))) from None
        return paths


# ---------------------------------------------------------------- file names and comments from names

STEM_BYTES = 200          # under the usual 255-byte file name limit, with room for an extension
_WINDOWS_DEVICES = {"CON", "PRN", "AUX", "NUL"} | {"%s%d" % (d, i) for d in ("COM", "LPT") for i in range(1, 10)}


def file_stem(element):
    """A file name stem for an element name path that is safe on any file system: '/' becomes '_' (the
    established NODEGRAPH_OUTPUT stems), every other character but ASCII letters, digits, '_', '-', '.' and
    '+' becomes '_', as does a leading '.' or '-'. Where anything else was changed, or the stem is longer
    than STEM_BYTES, it ends in '-' and a hash of the real name, so different names keep different stems."""
    plain = element.replace("/", "_")
    safe = "".join(c if c.isascii() and (c.isalnum() or c in "_-.+") else "_" for c in plain)
    if safe[:1] in (".", "-"):
        safe = "_" + safe[1:]
    if safe != plain or not safe or len(safe) > STEM_BYTES or safe.split(".")[0].upper() in _WINDOWS_DEVICES:
        safe = _hashed(safe, element)
    return safe


def _hashed(stem, element, salt=""):
    digest = sha256((element + salt).encode("utf-8", "surrogatepass")).hexdigest()[:10]
    return "%s-%s" % (stem[:STEM_BYTES - len(digest) - 1], digest)


def unique_stems(shaders):
    """Shaders written to one folder get distinct stems: where two clash (compared case-insensitively, for
    case-insensitive file systems), the later one gets a hash of its element name appended."""
    seen = set()
    for s in shaders:
        n = 0
        while s.stem.casefold() in seen:
            n += 1
            s.stem = _hashed(file_stem(s.element), s.element, "#%d" % n if n > 1 else "")
        seen.add(s.stem.casefold())
    return shaders


# ---------------------------------------------------------------- glsl_lib files

_FILE_CACHE = {}
_FILE_UNIFORMS = {}


def read_lib_file(rel):
    """(text, [required files]) of a glsl_lib file; `// requires: a.glsl b.glsl` header lines name deps,
    `// uniforms: u_a u_b` lines the application uniforms it reads (lib_file_uniforms; interface.py)."""
    if rel not in _FILE_CACHE:
        path = os.path.join(glsl_lib_root(), rel)
        with open(path) as f:
            text = f.read()
        # our macros span lines with a trailing backslash for reading; GLSL 4.00 (unlike 4.20 and ES 3.00)
        # has no line continuation, so each macro is joined into one line here
        text = re.sub(r"\\[ \t]*\n", " ", text)
        deps, uniforms = [], []
        for line in text.splitlines():
            s = line.strip()
            if s.startswith("// requires:"):
                deps += s[len("// requires:"):].split()
            elif s.startswith("// uniforms:"):
                uniforms += s[len("// uniforms:"):].split()
            elif s and not s.startswith("//"):
                break
        unknown = [u for u in uniforms if u not in interface.TABLE]
        if unknown:
            raise RuntimeError("glsl_lib/%s names uniforms not in interface.TABLE: %s" % (rel, " ".join(unknown)))
        _FILE_CACHE[rel] = (text, deps)
        _FILE_UNIFORMS[rel] = tuple(uniforms)
    return _FILE_CACHE[rel]


# required_closure's results, per process: rel -> (files, application uniforms); one entry per glsl_lib file
_CLOSURES = {}


def required_closure(rel):
    """(the glsl_lib files `rel` requires, directly or not, then `rel`: each after what it requires, a tuple; the
    application uniforms they read, a frozenset). A file's closure is its requirements' closures then itself, so a
    stage that required a file before holds that file's whole closure, and pasting a closure's files not yet
    required in order is the depth-first walk from what the stage holds."""
    entry = _CLOSURES.get(rel)
    if entry is None:
        files, seen, uniforms = [], set(), set()

        def walk(r):
            if r in seen:
                return
            seen.add(r)
            try:
                _, deps = read_lib_file(r)
            except OSError:
                raise RuntimeError("glsl_lib file missing: %s" % r) from None
            for d in deps:
                walk(d)
            uniforms.update(lib_file_uniforms(r))
            files.append(r)
        walk(rel)
        entry = _CLOSURES[rel] = (tuple(files), frozenset(uniforms))
    return entry


def lib_file_uniforms(rel):
    """The application uniforms glsl_lib file `rel` reads (its `// uniforms:` header)."""
    read_lib_file(rel)
    return _FILE_UNIFORMS[rel]


# interface_declarations of a set of names, per process: (frozenset(names), target, max_lights) -> the lines (what
# they depend on besides interface.TABLE's frozen records); a few hundred sets at most, bounded all the same
_DECLARATIONS = {}
_DECLARATIONS_MAX = 1024


def interface_declarations(names, target="glsl", max_lights=interface.MAX_LIGHTS):
    """GLSL declarations of the named application uniforms for a target without a uniform block (what a
    stage or a test assembling glsl_lib files by hand puts before the files): the light record, then the
    uniforms in name order."""
    if isinstance(names, (set, frozenset)) and type(target) is str and type(max_lights) is int:
        key = (frozenset(names), target, max_lights)
        lines = _DECLARATIONS.get(key)
        if lines is None:
            if len(_DECLARATIONS) >= _DECLARATIONS_MAX:
                _DECLARATIONS.clear()
            lines = _DECLARATIONS[key] = tuple(_interface_declarations(names, target, max_lights))
        return list(lines)
    return _interface_declarations(names, target, max_lights)


def _interface_declarations(names, target, max_lights):
    t = targets.get(target)
    lines = interface.types_needed(names, max_lights)
    for name in sorted(names):
        u = interface.TABLE[name]
        init = interface.glsl_value(u) if t.initializers else None
        lines.append("uniform %s %s%s%s;" % (u.type, name, u.array_suffix, " = " + init if init else ""))
    return lines


def app_constant_lines(names):
    """`const` declarations of application uniforms `names` at their defaults (Graph.app_constants), in name order."""
    return ["const %s %s = %s;" % (interface.TABLE[n].type, n, interface.glsl_value(interface.TABLE[n]))
            for n in sorted(names)]


def lib_source(rels, target="glsl"):
    """glsl_lib files `rels` (in this order, dependencies not added) after the declarations of the application
    uniforms they read: what a test compiling library code by hand puts after its #version line."""
    names = {u for r in rels for u in lib_file_uniforms(r)}
    return "\n".join(interface_declarations(names, target) + [read_lib_file(r)[0] for r in rels])


# library_code's pasted sections, per process: (rel, the code used_code kept, compact) -> the text pasted
_SECTIONS = {}
_SECTIONS_MAX = 4096
# library_code's files with their switches resolved, per process: (files, their texts, switches set, the switch
# names) -> ((rel, text), ...)
_SWITCHED_FILES = {}


# How environment light is integrated (CLI --environment): "fis" samples each lobe (Krivanek & Colbert 2008),
# "prefiltered" reads one roughness-chosen mip level per lobe (split sum, Karis 2013): the glsldeps paste switches
# each method sets (resolved where glsl_lib code is pasted: a shader holds its own method's code only).
ENVIRONMENT_METHODS = ("fis", "prefiltered")
ENVIRONMENT_SWITCHES = {"fis": frozenset(), "prefiltered": frozenset({"MG_ENV_PREFILTERED", "MG_REFRACTION_PREFILTERED"})}


# an opaque BSDF (nodes' "opaque") of zero weight where it reflects: nothing reflected, nothing let through
_OPAQUE_BSDF = "BSDF(vec3(0.0), vec3(0.0))"
_OPAQUE_CONTEXTS = ("reflection", "indirect")

# Guard policy (Emitter.closure): a lobe is skipped behind an `if` only where it samples the environment (these
# files' loops, in the contexts that run them). Elsewhere the lobe costs a few instructions, and an `if` around it
# costs GPU compilers more than it saves (a branch each, and no common subexpressions shared with the other
# lobes: benchmarks/bench_gpu_compilers.py, docs/measuring.md): such a lobe is computed and then set to the empty
# closure where its weight is below closureplan.ZERO_WEIGHT (a select, whatever its other inputs hold: 0/0 too);
# a mix side its factor weighs 0 is computed to no effect, as MaterialX computes both sides.
_SAMPLING_FILES = frozenset(("lighting/environment_specular.glsl", "lighting/environment_refraction.glsl"))
_SAMPLING_CONTEXTS = ("indirect", "transmission")


@functools.lru_cache(maxsize=None)
def _requires_sampling(files):
    """Whether glsl_lib files `files` (a tuple) pull in an environment sample loop (_SAMPLING_FILES)."""
    seen, todo = set(), list(files)
    while todo:
        rel = todo.pop()
        if rel in _SAMPLING_FILES:
            return True
        if rel not in seen:
            seen.add(rel)
            todo += read_lib_file(rel)[1]
    return False


# the GLSL spelling of each built-in type that has one, closures aside (Emitter.glsl_type notes those): what
# mxtypes.glsl_type gives whatever the document's structs (a built-in name is never a struct's)
_SPELLING = {name: info.glsl for name, info in mxtypes.BUILTIN.items() if info.glsl and not info.closure}


# uniform_parts' literals of built-in types, per process: (type, value) -> GLSL literal (what it depends on: the two)
_LITERALS = {}
_LITERALS_MAX = 1 << 16
_LITERAL_SPELLING = {t: _SPELLING[t] for t in ("float", "integer", "boolean", "color3", "color4", "vector2", "vector3",
                                               "vector4", "matrix33", "matrix44")}


def _at_most_zero(value):
    try:
        return float(value) <= 0.0
    except (TypeError, ValueError):
        return False


class Emitter:
    stage = "fragment"                # the stage its code goes to (VertexEmitter: "vertex")

    def __init__(self, graph, environment="fis", target="glsl", max_lights=0, compact=False):
        if environment not in ENVIRONMENT_METHODS:
            raise ValueError("environment must be one of %s, not %r" % (ENVIRONMENT_METHODS, environment))
        # the emitter's own view of the graph: the public uniforms are its own table, which emission may
        # extend (UDIM tiles, primvar flags) or thin (a sampler nothing reads); the graph itself never changes
        view = self.graph = object.__new__(type(graph))     # (copy.copy's shallow copy, without its protocol)
        view.__dict__.update(graph.__dict__)
        view.uniforms = dict(graph.uniforms)
        self.environment = environment
        self.target = targets.get(target)
        self.max_lights = int(max_lights)   # u_lightData's length; 0: lit surfaces have no light loop
        self.compact = compact        # library code pasted without comments and blank lines (reduced shaders)
        self.files = []               # glsl_lib files in emission order
        self._required = set()        # the same files, for require's test
        self.external = []            # (path, text) of document-supplied GLSL
        self.streams = {}             # name -> Stream, in first-use order
        self.app_uniforms = set()
        self.vars = {}                # (node id, output) -> GLSL expression
        self.writer = StageWriter()   # main's statements
        self.body = self.writer.lines
        # main's lines that hold no name a glsl_lib file defines (calls of the stage's functions: their arguments
        # are variables, uniforms and literals), left out of the scan for the library code the stage needs
        self.unscanned = set()
        self.names = set(graph.uniforms) | set(graph.structs)   # a variable must not hide a struct type
        self.textures = {}            # sampler uniform -> extra manifest fields
        self.primvars = []            # manifest "primvars": readers of named geometry primvars (nodes/usd.py)
        self.uses_closures = False
        self.closure_nodes = {}       # id -> GNode of closure nodes, evaluated per context by shader nodes
        self._closure_impls = {}      # id -> the nodes.Impl emit_node looked up for each of them
        self.context = None           # closure context being emitted ("reflection", "indirect", ...)
        self.block = 0                # serial of the current closure block (closure variables live in it)
        self.closure_vars = {}        # (block, node id, output) -> variable
        self.closure_plan = graph.closure_plan or closureplan.ClosurePlan(graph)   # when each closure node is needed
        self.conditions = {}          # closure node id -> GLSL condition under which it is needed (None: always;
                                      # False: never, decided on literals in the reduced interface)
        self._contexts = []           # contexts of the enclosing blocks
        self.current = None           # the node being emitted (errors of the streams it asks for name it)
        self.document_code = []       # [((name, Loc) of a document's <implementation>, {GLSL lines it made})]
        self.functions = {}           # GLSL name -> FunctionCode of the functions the stage calls, callees first
        self.function_types = set()   # the types their bodies use (struct declarations)
        self.function_switches = None  # the paste switches every function's body allows (None: no function)
        for n in graph.nodes:         # a variable must not hide a function the stage calls
            if n.function is not None:
                self.names.add(n.function.base)

    # ---------- services for templates and handlers ----------
    def fail(self, node, message):
        raise MtlxError((node.loc, "node '%s' (%s): %s" % (node.id, node.nodedef.name, message)))

    def require(self, rel):
        """The stage pastes glsl_lib file `rel`: it and the files it requires (before it), those not yet required,
        and the application uniforms they read."""
        if rel in self._required:
            return
        files, uniforms = required_closure(rel)
        self.paste_files(files)
        self.app_uniforms.update(uniforms)

    def paste_files(self, files):
        """The stage pastes glsl_lib `files` (each after what it requires): those not yet pasted, in order. A file
        pasted before brought what it requires (required_closure is post-order)."""
        required = self._required
        for f in files:
            if f not in required:
                required.add(f)
                self.files.append(f)

    def app_uniform(self, name):
        """An application uniform (interface.md) the fragment stage reads."""
        self.app_uniforms.add(name)
        return name

    def stream(self, name, mx_type=None, node=None):
        s = self.streams.get(name)
        if s is None:
            s = self.lookup_stream(name, mx_type, node)
            self.streams[name] = s
        return s.fragment.format("v_" + name)

    def lookup_stream(self, name, mx_type, node):
        try:
            return streams.lookup(name, mx_type)
        except KeyError:
            node = node or self.current
            if node is None:
                raise
            self.fail(node, "no geometric stream '%s' (%s)" % (name, streams.NAMES))

    def expr(self, src):
        if src.node is not None:
            return self.vars[(src.node, src.output)]
        if src.uniform:
            return src.uniform
        if src.type in mxtypes.CLOSURE_NAMES:
            self.uses_closures = True
            return mxtypes.closure_zero(src.type)
        try:
            return mxtypes.glsl_literal(src.type, src.value, self.graph.structs)
        except mxtypes.ValueError_ as e:
            raise MtlxError((src.loc, str(e))) from None

    def input_expr(self, node, name):
        return self.expr(node.inputs[name])

    def static(self, node, name):
        src = node.inputs.get(name)
        if src is None:
            self.fail(node, "has no input '%s'" % name)
        if src.linked:
            self.fail(node, "input '%s' must be a constant, it is connected" % name)
        return src.value

    def glsl_type(self, mx_type, loc=None):
        """GLSL spelling of a type; an error at `loc` (else the node being emitted) for a type without one."""
        t = _SPELLING.get(mx_type)
        if t is not None:
            return t
        if mx_type in mxtypes.CLOSURE_NAMES:
            self.uses_closures = True
        try:
            t = mxtypes.glsl_type(mx_type, self.graph.structs)
        except KeyError:
            t = ""
        if not t:       # unknown, or a type without run-time value (geomname, stringarray, ...)
            why = "a value of type %r has no GLSL type" % mx_type
            if loc is None and self.current is not None:
                self.fail(self.current, why)
            raise MtlxError((loc or self.graph.result.loc, why))
        return t

    def fresh(self, stem):
        """A variable's name from `stem`, unique in the stage (each name the emission takes goes through here)."""
        return unique_identifier(stem, self.names)

    def uniform(self, name):
        """The public uniform `name` of the shader being emitted, or None."""
        return self.graph.uniforms.get(name)

    def add_uniform(self, stem, mx_type, value, loc, colorspace=None):
        """A public uniform the emission itself adds (a UDIM tile's sampler, a primvar reader's flag), named
        from `stem`; returns its name."""
        name = self.fresh(stem)
        self.graph.uniforms[name] = Uniform(name, mx_type, value, loc, colorspace)
        return name

    def drop_unread_uniform(self, name, reader):
        """Leave public uniform `name` undeclared where no node but `reader` reads it (a <UDIM> pattern, which
        is no file; a texture the node's choices do not read)."""
        if not any(s.uniform == name for n in self.graph.nodes if n is not reader for s in n.inputs.values()):
            self.graph.uniforms.pop(name, None)

    # ---------- the stage writer, closure scopes ----------
    def line(self, text):
        """Append a statement to main at the current depth."""
        self.writer.line(text)

    def indented(self):
        """Lines written inside are one level deeper (the statement of an `if` without braces)."""
        return self.writer.indented()

    def open_block(self, context, comment=None):
        """A braced scope in which closures are evaluated in `context` (None: the enclosing context's)."""
        self.writer.open_scope(comment)
        self.block += 1
        self._contexts.append(self.context)
        self.context = context

    def close_block(self):
        self.writer.close_scope()
        self.context = self._contexts.pop()

    # ---------- templates (template.py) ----------
    def render(self, template, node, out_type):
        return template_expander.render(self, template, node, out_type)

    # ---------- closures ----------
    def closure(self, src, context):
        """A closure Source evaluated in `context` inside the current block: its upstream closure nodes
        are emitted first (each once per block); returns the GLSL expression of its value.

        Each closure node is evaluated only where it can matter (closureplan.py): a lobe whose mix
        factor or weight is zero costs nothing, its value being the empty closure."""
        self.uses_closures = True
        if src.node is None or src.node not in self.closure_nodes:
            return self.expr(src)
        key = (self.block, src.node, src.output)
        var = self.closure_vars.get(key)
        if var is not None:
            return var
        if src.node not in self.conditions:
            self.take_plan(src.node)
        node = self.closure_nodes[src.node]
        impl = self._closure_impls[src.node]           # (looked up by emit_node, which made it a closure node)
        saved, self.context = self.context, context
        zero = mxtypes.closure_zero(src.type)          # what the lobe is where it is not computed
        unweighed = None        # a cheap lobe's weight condition: computed, then the empty closure where it fails
        try:
            cond = self.conditions.get(node.id)        # GLSL text; None: always; False: never (take_plan)
            if impl.closure is not None:
                template = impl.closure.get(context)
                expr = self.render(template, node, src.type) if template else zero
                sampled = self._sampled(impl, context)
                if not sampled and cond is not False:
                    cond = None                         # (the guard policy above)
                weight = node.inputs.get("weight")
                if template and src.type == "BSDF" and weight is not None and weight.type == "float":
                    # a BSDF of (near) zero weight is the empty closure whatever its other inputs are
                    # (as in MaterialX: e.g. gltf_pbr's sheen colour is 0/0 when sheen is off): closureplan.weighed
                    weighed = closureplan.weighed(node.id)
                    if self.graph.static_guards:        # the reduced interface (fold.py)
                        weighed = closureplan.decide(weighed, self.closure_plan.literal_value)
                    weighed = closureplan.glsl(weighed, lambda node_id: {"weight": self.input_expr(node, "weight")})
                    if sampled or weighed is False:
                        cond = closureplan.glsl(closureplan.conjoin(cond, weighed), None)       # "cond && weighed"
                    elif cond is not False:
                        unweighed = weighed
                    if impl.opaque and context in _OPAQUE_CONTEXTS:
                        # but a lobe that lets nothing through (a diffuse one) stays opaque at zero weight, black
                        # over what is under it, as MaterialX's: its throughput is 0 at every weight, so the
                        # picture does not jump between a weight of 1e-6 and 0
                        zero = _OPAQUE_BSDF
                if not template:
                    cond = None
            elif impl.outputs:
                template = impl.outputs.get(src.output) or impl.outputs.get("*")
                expr = self.render(template, node, src.type)
                if not self._sampled(impl, context) and cond is not False:
                    cond = None                         # a combinator (mix, layer, add...): the guard policy above
            else:
                self.fail(node, "closure node without a closure implementation")
        finally:
            self.context = saved
        if cond is False:           # decided on literals (the reduced interface): never needed, never computed
            expr, cond = zero, None
        var = self.fresh("%s_%s" % (node.id, src.output))
        first = len(self.body)
        w = self.writer
        if cond is None:
            w.line("%s %s = %s;" % (self.glsl_type(src.type), var, expr))
            if unweighed is not None:
                w.line("if (!(%s))" % unweighed)
                w.depth += 1
                w.line("%s = %s;" % (var, zero))
                w.depth -= 1
        else:
            # the empty closure, replaced where the condition holds: a disabled lobe is never computed (an `if`,
            # not `?:`, whose struct operands WebGL's validator refuses though GLSL ES 3.00 allows them)
            w.line("%s %s = %s;" % (self.glsl_type(src.type), var, zero))
            w.line("if (%s)" % cond)
            w.depth += 1                # (self.indented(), without a context manager's cost)
            w.line("%s = %s;" % (var, expr))
            w.depth -= 1
        if impl.source is not None:
            self.note_document_code(impl, self.body[first:])
        self.closure_vars[key] = var
        return var

    @staticmethod
    def _sampled(impl, context):
        """Whether a closure node's evaluation in `context` is guarded (the guard policy, _SAMPLING_FILES): where
        it samples the environment, or is a document's own code, whose cost is not known."""
        return impl.source is not None or (context in _SAMPLING_CONTEXTS and _requires_sampling(tuple(impl.files)))

    def take_plan(self, root):
        """The closure plan's conditions for the closure nodes upstream of `root`, written as GLSL (None: always);
        a node planned before keeps its first condition. Where the graph's guards are decided at generation time
        (static_guards: the reduced interface, fold.py), each condition is first decided on the literal inputs it
        compares (closureplan.decide): one always true is None, one never true False."""
        plan = self.closure_plan.conditions(root)
        values, memo = {}, {}
        decided = {} if self.graph.static_guards else None
        literal_value = self.closure_plan.literal_value

        def input_values(node_id):                      # condition_values, once per node in this plan
            v = values.get(node_id)
            if v is None:
                v = values[node_id] = self.condition_values(node_id)
            return v

        conditions = self.conditions
        for node_id, cond in plan.items():
            if node_id not in conditions:
                if decided is not None:
                    cond = closureplan.decide(cond, literal_value, decided)
                conditions[node_id] = closureplan.glsl(cond, input_values, memo)

    def condition_values(self, node_id):
        """{input: GLSL expression} of the values a closure node's edge conditions read."""
        return {k: self.expr(v) for k, v in self.closure_plan.nodes[node_id].inputs.items()
                if not mxtypes.is_closure(v.type) and v.type != "string"}

    # ---------- nodes ----------
    def note_document_code(self, impl, lines):
        """Remember the lines a document's own GLSL went into: a compile error in one of them is reported
        at that <implementation> (glslcheck.py)."""
        if impl.source is None:
            return
        entry = next((e for e in self.document_code if e[0] == impl.source), None)
        if entry is None:
            entry = (impl.source, set())
            self.document_code.append(entry)
        entry[1].update(line.strip() for line in lines if line.strip())

    def emit_node(self, node):
        self.current = node
        if node.function is not None:
            self.call(node)
            return
        impl = nodes.lookup(node.nodedef, self.graph.library)
        if impl is None:
            self.fail(node, "no GLSL implementation for nodedef %s" % node.nodedef.name)
        first_line, first_file = len(self.body), len(self.external)
        required = self._required
        for f in impl.files:
            if f not in required:       # (require's own first test)
                self.require(f)
        if node.id in self.closure_plan.nodes:        # closureplan.is_closure_node, found once per graph
            self.closure_nodes[node.id] = node     # evaluated per context by the shader node using it
            self._closure_impls[node.id] = impl
            return
        if impl.external is not None:
            exprs = self.external_call(node, impl.external)
        elif impl.handler:
            from mtlxgen.nodes import handlers
            handler = impl.handler if callable(impl.handler) else getattr(handlers, impl.handler)
            exprs = handler(node, self)
        else:
            exprs = {}
            for oname, otype in node.outputs.items():
                template = impl.outputs.get(oname) or (impl.outputs.get("*") if len(node.outputs) == 1 else None)
                if template is None:
                    self.fail(node, "implementation has no template for output '%s'" % oname)
                exprs[oname] = self.render(template, node, otype)
        for oname, otype in node.outputs.items():
            e = exprs[oname]
            if is_plain_name(e) or otype in ("filename", "string"):
                self.vars[(node.id, oname)] = e     # pass-through: no copy
                continue
            var = self.fresh("%s_%s" % (node.id, oname))
            self.writer.line("%s %s = %s;" % (self.glsl_type(otype), var, e))
            self.vars[(node.id, oname)] = var
        if impl.source is not None:
            self.note_document_code(impl, self.body[first_line:] + [
                line for _, text in self.external[first_file:] for line in text.splitlines()])

    # ---------- nodegraph implementations as functions (functions.py) ----------
    def call(self, node):
        """A call node: its function (the variant its compile-time inputs choose, emitted once per settings) called
        with its inputs, one variable per output."""
        code = self.function_code(node)
        self.use_function(code)
        args = [self.expr(node.inputs[name]) for name in code.parameters]
        for oname, otype in node.outputs.items():
            var = self.fresh("%s_%s" % (node.id, oname))
            self.line("%s %s;" % (self.glsl_type(otype), var))
            args.append(var)
            self.vars[(node.id, oname)] = var
        self.line("%s(%s);" % (code.name, ", ".join(args)))
        self.unscanned.add(self.body[-1])   # the call: names and literals, nothing a glsl_lib file defines

    def settings(self):
        """What a function's emitted text depends on besides its body."""
        return (self.stage, self.target.name, self.environment, self.max_lights, self.compact)

    def function_code(self, node):
        """The FunctionCode call node `node` calls: Family.variants walked from nothing fixed, each compile-time
        input the body reads fixed to the node's value, until the body emits."""
        family, settings, fixed = node.function, self.settings(), ()
        while True:
            key = (settings, fixed)
            entry = family.variants.get(key)
            if entry is None:
                if len(family.variants) >= functions.VARIANTS_MAX:
                    family.variants.clear()
                body = family.body(dict(fixed))[0] if fixed else family.generic
                try:
                    entry = ("code", FunctionEmitter(body, family, family.name(fixed), self).emit_function())
                except functions.CompileTime as e:
                    if e.family is not family:
                        raise
                    entry = ("input", e.name)
                family.variants[key] = entry
            if entry[0] == "code":
                return entry[1]
            src = node.inputs[entry[1]]
            if src.node is not None:
                raise functions.Inline(node, entry[1])
            fixed += ((entry[1], functions.value_key(src.value)),)

    def use_function(self, code):
        """The stage calls `code`: its callees and it are declared before main, what its body reads is the stage's."""
        if code.name in self.functions:
            return
        for callee in code.callees:
            self.use_function(callee)
        self.functions[code.name] = code
        self.paste_files(code.files)        # (the body's required files with what they require, in order)
        self.app_uniforms.update(code.app_uniforms)     # (those of its files too: FunctionEmitter.require)
        for name, stream in code.streams.items():
            self.streams.setdefault(name, stream)
        for name, t in code.attributes.items():
            self.attributes.setdefault(name, t)     # (a vertex stage's body: its emitter has attributes)
        self.uses_closures = self.uses_closures or code.uses_closures
        self.function_types |= code.types
        self.function_switches = set(code.switches) if self.function_switches is None else \
            self.function_switches & code.switches

    def external_call(self, node, external):
        path, function, loc = external
        full = path if os.path.isabs(path) else os.path.join(os.path.dirname(loc.file), path)
        if not any(p == full for p, _ in self.external):
            from mtlxgen.base.files import read_implementation     # only GLSL inside the allowed roots is pasted in
            self.external.append((full, read_implementation(full, path, loc, self.graph.doc_path)))
        args = [self.expr(s) for n, s in node.inputs.items() if s.type not in ("string", "geomname")]
        exprs = {}
        for oname, otype in node.outputs.items():
            var = self.fresh("%s_%s" % (node.id, oname))
            self.line("%s %s;" % (self.glsl_type(otype), var))
            args.append(var)
            exprs[oname] = var
        self.line("%s(%s);" % (function, ", ".join(args)))
        return exprs

    # ---------- stages ----------
    def output_statement(self, result):
        t = result.type
        if t in CLOSURE_TYPES and result.node in self.closure_nodes:
            from mtlxgen.nodes.pbrlib_shading import shade
            if t == "EDF":
                e = shade(self, edf=result, stem="edf")
            elif t == "BSDF":
                e = shade(self, bsdf=result, stem="bsdf")
            else:
                return "vec4(%s.response, 1.0)" % self.closure(result, "indirect")
            return "vec4(%s.color, 1.0)" % e
        e = self.expr(result)
        if t in ("surfaceshader", "material"):
            self.uses_closures = True
            return "vec4(%s.color, clamp(1.0 - dot(%s.transparency, vec3(1.0 / 3.0)), 0.0, 1.0))" % (e, e)
        if t in ("BSDF", "VDF"):
            self.uses_closures = True
            return "vec4(%s.response, 1.0)" % e
        if t == "EDF":
            return "vec4(%s, 1.0)" % e
        if t == "volumeshader":
            return "vec4(%s.color, 1.0)" % e
        if t == "float":
            return "vec4(vec3(%s), 1.0)" % e
        if t in ("integer", "boolean"):
            return "vec4(vec3(float(%s)), 1.0)" % e
        if t == "vector2":
            return "vec4(%s, 0.0, 1.0)" % e
        if t in ("color3", "vector3"):
            return "vec4(%s, 1.0)" % e
        if t in ("color4", "vector4"):
            return e
        if t in ("matrix33", "matrix44", "displacementshader"):
            # no colour meaning (MaterialX draws these black too); a displacement still moves the vertices
            return "vec4(0.0, 0.0, 0.0, 1.0)"
        if t == "lightshader":
            self.uses_closures = True
            return "vec4(%s.intensity, 1.0)" % e
        raise MtlxError((result.loc, "an output of type %s cannot be rendered" % t))

    def uniform_parts(self, u):
        """(GLSL type, array length or 0, GLSL initializer or None) of one of the material's uniforms."""
        t = u.type
        spelling = _LITERAL_SPELLING.get(t)
        if spelling is not None:        # a built-in type of one value: the literal kept per value
            key = (t, u.value)
            try:
                literal = _LITERALS.get(key)
            except TypeError:           # a value not hashable (a list): spelt each time
                key = literal = None
            if literal is None:
                try:
                    literal = mxtypes.glsl_literal(t, u.value)
                except mxtypes.ValueError_ as e:
                    raise MtlxError((u.loc, "input '%s': %s" % (u.name, e))) from None
                if key is not None:
                    if len(_LITERALS) >= _LITERALS_MAX:
                        _LITERALS.clear()
                    _LITERALS[key] = literal
            return spelling, 0, literal
        try:
            if t == "filename":
                return "sampler2D", 0, None
            if t in mxtypes.ARRAY_ELEMENT:
                return (mxtypes.glsl_type(mxtypes.ARRAY_ELEMENT[t]), max(1, len(u.value or ())),
                        mxtypes.glsl_literal(t, u.value, self.graph.structs))
            return self.glsl_type(t, u.loc), 0, mxtypes.glsl_literal(t, u.value, self.graph.structs)
        except mxtypes.ValueError_ as e:
            raise MtlxError((u.loc, "input '%s': %s" % (u.name, e))) from None

    def displacement(self):
        """The displacementshader the element applies (a material's, or the element itself), or None."""
        r = self.graph.result
        if r.type == "displacementshader" and r.linked:
            return r
        node = next((n for n in self.graph.nodes if n.id == r.node), None)
        if node is not None and node.category == "surfacematerial":
            d = node.inputs.get("displacementshader")
            if d is not None and d.linked:
                return d
        return None

    def library_code(self, files, roots, known=frozenset()):
        """The sections ("// ---- glsl_lib/REL", code) of the glsl_lib files `files` that the texts `roots` (and the
        identifiers `known`) reach, the paste switches resolved for this shader (glsldeps.SWITCHES: paste_switches()
        and its environment method's, MG_ENV_ONE_FRAME where progressive refinement's pair is constant), compacted in a
        reduced shader."""
        switches = self.paste_switches() | ENVIRONMENT_SWITCHES[self.environment]
        if "u_envSampleFrames" in self.graph.app_constants:
            switches.add("MG_ENV_ONE_FRAME")
        switches = frozenset(switches)
        cache = _FILE_CACHE
        raw = tuple(cache[r][0] if r in cache else read_lib_file(r)[0] for r in files)
        # (a str keeps its hash: the texts are hashed once; glsldeps.SWITCHES: which names resolve_switches resolves)
        key = (tuple(files), raw, switches, glsldeps.SWITCHES)
        texts = _SWITCHED_FILES.get(key)
        if texts is None:
            if len(_SWITCHED_FILES) >= _SECTIONS_MAX:
                _SWITCHED_FILES.clear()
            texts = _SWITCHED_FILES[key] = tuple((r, glsldeps.resolve_switches(t, switches))
                                                 for r, t in zip(files, raw))
        out = []
        for rel, text in glsldeps.used_code(texts, roots, known):
            key = (rel, text, self.compact)
            section = _SECTIONS.get(key)
            if section is None:
                if len(_SECTIONS) >= _SECTIONS_MAX:
                    _SECTIONS.clear()
                section = _SECTIONS[key] = (glsldeps.compact(text, rel) if self.compact else text.rstrip()) + "\n"
            out.append("// ---- glsl_lib/%s" % rel)
            out.append(section)
        return out

    def paste_switches(self):
        """The glsldeps.SWITCHES this shader sets: MG_NO_THIN_FILM where every closure node's thinfilm_thickness is a
        literal <= 0 and no document GLSL is pasted (it could reach the film code)."""
        for node in self.closure_nodes.values():
            film = node.inputs.get("thinfilm_thickness")
            if film is not None and not (film.literal and _at_most_zero(film.value)):
                return set()
        if self.external:
            return set()
        return {"MG_NO_THIN_FILM"} if self.function_switches is None else {"MG_NO_THIN_FILM"} & self.function_switches

    def reachable(self, src, skip=None):
        """Ids of the nodes `src` depends on, not following the (node id, input) edge `skip`."""
        return graphwalk.upstream({n.id: n for n in self.graph.nodes}, [src], skip)

    def emit(self):
        g = self.graph
        disp = self.displacement()
        vertex_emitter = None
        if disp is not None and disp is not g.result:
            material = g.result.node
            fragment_ids = self.reachable(g.result, skip=(material, "displacementshader"))
        else:
            fragment_ids = self.reachable(g.result)
        if disp is not None:
            vertex_emitter = VertexEmitter(g, self.target.name)
            vertex_ids = self.reachable(disp)
            for node in g.nodes:
                if node.id in vertex_ids:
                    vertex_emitter.emit_node(node)
            vertex_emitter.result = vertex_emitter.expr(disp)
        for node in g.nodes:
            if node.id in fragment_ids:
                self.emit_node(node)
        self.current = None
        out_expr = self.output_statement(g.result)
        if any(not mxtypes.CLOSURE_NAMES.isdisjoint(n.outputs.values()) for n in g.nodes if n.id in fragment_ids):
            self.uses_closures = True          # shader-typed values need the closure structs
        if self.uses_closures:              # the closure types first, once (a library file may require them too)
            self.files = ["closures.glsl"] + [f for f in self.files if f != "closures.glsl"]
        lit = "lighting/environment.glsl" in self.files
        fixed = self.app_uniforms & g.app_constants      # read as constants at their defaults (the reduced interface)
        self.app_uniforms -= fixed
        vertex = VertexStage(self, vertex_emitter)
        decl = Declarations(self, vertex)
        frag = decl.preamble("// %s: generated by mtlxgen from %s" % (
            comment_text(g.element), comment_text(os.path.basename(g.doc_path))))
        used = node_types(g.nodes) | {g.result.type} | {u.type for u in g.uniforms.values()} | self.function_types
        own = app_constant_lines(fixed) + \
            decl.uniforms("fragment", self.app_uniforms, list(g.uniforms.values()), used)
        tail = decl.varyings("in", list(self.streams.values())) + ["layout(location = 0) out vec4 out_color;", ""]
        # What glsl_lib code the stage needs is read from its text: the declarations (the same for materials alike:
        # their identifiers kept per text), main, a document's GLSL. Left out: the comment naming the element, the
        # material's own uniform declarations (a built-in type, the uniform's name, a literal: nothing a glsl_lib
        # file defines) and the calls of functions (self.unscanned).
        head = [line for line in frag if not line.startswith("// ")] + own[:len(own) - decl.material_lines] + tail
        known = declaration_identifiers("\n".join(head)) | function_identifiers(self.functions)
        unscanned = self.unscanned
        roots = [line for line in self.body if line not in unscanned] + [out_expr] if unscanned else \
            self.body + [out_expr]
        joined = "\n".join(roots)          # one text to scan, not one per line (a `/*` may span lines: then each)
        roots = ([joined] if "/*" not in joined else roots) + [text for _, text in self.external]
        frag += own + tail
        frag += self.library_code(self.files, roots, known)
        for path, text in self.external:
            frag.append("// ---- %s" % comment_text(os.path.basename(path)))
            frag.append(text.rstrip() + "\n")
        frag += function_texts(self.functions)
        frag.append("void main()")
        frag.append("{")
        frag.extend(self.body)
        frag.append("    out_color = %s;" % out_expr)
        frag.append("}")
        frag.append("")
        fragment = "\n".join(frag)
        stem = file_stem(g.element)
        manifest = {
            "element": g.element,
            "target": self.target.name,
            "glsl_version": self.target.version,
            "vertex": stem + ".vert",
            "fragment": stem + ".frag",
            "attributes": dict(vertex.attributes),
            "uniforms": [self.manifest_uniform(u, decl) for u in g.uniforms.values() if u.type != "filename"],
            "textures": [self.manifest_texture(u, decl) for u in g.uniforms.values() if u.type == "filename"],
            "application": application_entries(decl.app_names, self.max_lights, self.environment if lit else None),
        }
        manifest.update(decl.manifest())
        if lit:
            manifest["environment"] = self.environment
            manifest["max_lights"] = self.max_lights
        if self.primvars:
            manifest["primvars"] = self.primvars
        code = self.document_code + (vertex_emitter.document_code if vertex_emitter is not None else [])
        return Shader(g.element, vertex.text(decl), fragment, manifest, document_code=code)

    def manifest_uniform(self, u, decl=None):
        t = u.type
        spelling = _LITERAL_SPELLING.get(t)
        if spelling is not None:            # a built-in type of one value (most): no struct, no array
            v = u.value
            entry = {"name": u.name, "type": spelling, "mtlx_type": t,
                     "value": manifest_value(v) if type(v) is tuple else v}
            if decl is not None and decl.offsets:
                entry.update(decl.member_fields(u.name))
            return entry
        entry = {"name": u.name, "type": self.uniform_type(u), "mtlx_type": u.type, "value": manifest_value(u.value)}
        if u.type in self.graph.structs:
            entry["members"] = [{"name": mn, "type": mxtypes.glsl_type(mt, self.graph.structs)}
                                for mn, mt, _ in self.graph.structs[u.type].members]
        if decl is not None:
            entry.update(decl.member_fields(u.name))
        return entry

    def uniform_type(self, u):
        if u.type in mxtypes.ARRAY_ELEMENT:
            return "%s[%d]" % (mxtypes.glsl_type(mxtypes.ARRAY_ELEMENT[u.type]), max(1, len(u.value or ())))
        return self.glsl_type(u.type)

    def manifest_texture(self, u, decl=None):
        from mtlxgen.base.resolve import resolve_file
        entry = {"uniform": u.name, "file": resolve_file(u.value, self.graph.doc_path) or u.value,
                 "colorspace": u.colorspace or ""}
        entry.update(self.textures.get(u.name, {}))
        if decl is not None and u.name in decl.bindings:
            entry.update(set=targets.BLOCK_SET, binding=decl.bindings[u.name])
        return entry


# declaration_identifiers' sets, per process: the text of a stage's declarations -> its identifiers
_DECLARATION_IDENTIFIERS = {}


def declaration_identifiers(text):
    """glsldeps.identifiers of a stage's declarations, kept per text (materials alike declare alike)."""
    found = _DECLARATION_IDENTIFIERS.get(text)
    if found is None:
        if len(_DECLARATION_IDENTIFIERS) >= _DECLARATIONS_MAX:
            _DECLARATION_IDENTIFIERS.clear()
        found = _DECLARATION_IDENTIFIERS[text] = frozenset(glsldeps.identifiers(text))
    return found


# application_entries' records, per process: (names, max_lights, environment) -> the entries (a few dozen sets)
_APPLICATION = {}


def application_entries(names, max_lights, environment):
    """The manifest's records of the application uniforms `names` (interface.manifest_entry), in name order; each
    call has its own dicts (the records are kept per process, the caller may change its copies)."""
    key = (frozenset(names), max_lights, environment)
    entries = _APPLICATION.get(key)
    if entries is None:
        if len(_APPLICATION) >= _DECLARATIONS_MAX:
            _APPLICATION.clear()
        entries = _APPLICATION[key] = tuple(interface.manifest_entry(interface.TABLE[n], max_lights, environment)
                                            for n in sorted(names))
    return [_data_copy(e) for e in entries]


def _data_copy(value):
    """A copy of JSON-like data (dicts and lists copied all the way down, other values shared): copy.deepcopy's
    result for the manifest's records at a fraction of its cost (no memo, no dispatch per value)."""
    if type(value) is dict:
        return {k: _data_copy(v) if type(v) in (dict, list) else v for k, v in value.items()}
    if type(value) is list:
        return [_data_copy(v) if type(v) in (dict, list) else v for v in value]
    return value


def manifest_value(value):
    """A uniform's value as the manifest (JSON) holds it: tuples as lists."""
    if isinstance(value, tuple):
        return [list(v) if isinstance(v, tuple) else v for v in value]
    return value


# A vertex stage has no screen-space derivatives: there they read as zero, so a texture read through textureGrad
# (UsdUVTexture, UDIM tiles, hex tiling) takes the full-resolution level, as texture() does in a vertex stage.
VERTEX_DERIVATIVES = ["#define dFdx(x) ((x) * 0.0)", "#define dFdy(x) ((x) * 0.0)", "#define fwidth(x) ((x) * 0.0)"]


class VertexStage:
    """The vertex stage: position, the streams the fragment stage reads, and displacement when the material
    has one (its nodes evaluated here, the position moved by offset * scale). Built from the fragment
    emitter's streams; text() spells it once the declarations are planned (they span both stages)."""

    def __init__(self, em, displacer=None):
        self.em, self.displacer = em, displacer
        self.attributes = {"i_position": "vec3"}
        self.app_uniforms = {"u_worldMatrix", "u_viewProjectionMatrix"}
        for s in em.streams.values():
            for a, t in s.attributes:
                self.attributes.setdefault(a, t)
            self.app_uniforms.update(s.uniforms)
        self.material = []          # the material's uniforms the displacement reads
        if displacer is not None:
            for a, t in displacer.attributes.items():
                self.attributes.setdefault(a, t)
            self.app_uniforms.update(displacer.app_uniforms)
            used = {src.uniform for n in em.graph.nodes if n.id in displacer.vars_owner
                    for src in n.inputs.values() if src.uniform}
            self.material = [u for u in em.graph.uniforms.values() if u.name in used]

    def text(self, decl):
        em, displacer = self.em, self.displacer
        lines = decl.preamble("// %s: generated by mtlxgen" % comment_text(em.graph.element))
        if displacer is not None:
            lines += VERTEX_DERIVATIVES
        lines += decl.attributes(self.attributes)
        used = {u.type for u in self.material}
        if displacer is not None:
            g = em.graph
            used |= node_types(n for n in g.nodes if n.id in displacer.vars_owner) | displacer.function_types
        lines += decl.uniforms("vertex", self.app_uniforms, self.material, used)
        lines += decl.varyings("out", list(em.streams.values()))
        body = ["    vec4 world_position = u_worldMatrix * vec4(i_position, 1.0);"]
        if displacer is not None:
            files = ["closures.glsl"] + [f for f in displacer.files if f != "closures.glsl"]
            body += displacer.body
            body += ["    displacementshader mg_displacement = %s;" % displacer.result,
                     "    world_position = u_worldMatrix * vec4(i_position + mg_displacement.offset * "
                     "mg_displacement.scale, 1.0);"]
            calls = function_texts(displacer.functions)
            lines += em.library_code(files, lines + body, function_identifiers(displacer.functions))
            lines += calls
        lines += ["", "void main()", "{"] + body
        lines += ["    gl_Position = u_viewProjectionMatrix * world_position;"]
        lines += ["    v_%s = %s;" % (s.name, s.vertex) for s in em.streams.values()]
        lines.append("}")
        return "\n".join(lines) + "\n"


class Declarations:
    """How the two stages declare their interface for the emitter's target (targets.py): uniforms with or
    without initializers, or one std140 block shared by both stages with samplers at bindings; ins and outs
    with or without locations. Planned once for both stages, so the block and the bindings agree."""

    def __init__(self, em, vertex):
        self.em, self.target, self.graph = em, em.target, em.graph
        g = self.graph
        self.app_names = set(em.app_uniforms) | set(vertex.app_uniforms)
        self._attribute_order = list(vertex.attributes)
        material = list(g.uniforms.values())
        self.structs = {name: [(mn, mxtypes.glsl_type(mt, g.structs), 0) for mn, mt, _ in s.members]
                        for name, s in g.structs.items()}
        self.structs["LightData"] = [(n, t, 0) for n, t in interface.LIGHT_DATA]
        app_samplers = sorted(n for n in self.app_names if interface.TABLE[n].type in interface.SAMPLER_TYPES)
        samplers = app_samplers + [u.name for u in material if u.type == "filename"]
        self.bindings, self.block, self.offsets, self.block_size = {}, [], {}, 0
        self.material_lines = 0     # uniforms(): how many of its last lines declare the material's uniforms
        if self.target.uniform_block:
            self.bindings = {name: i + 1 for i, name in enumerate(samplers)}
            for name in sorted(self.app_names):
                u = interface.TABLE[name]
                if u.type not in interface.SAMPLER_TYPES:
                    self.block.append((name, u.type, em.max_lights if name == "u_lightData" else u.length))
            for u in material:
                if u.type != "filename":
                    t, length, _ = em.uniform_parts(u)
                    self.block.append((u.name, t, length))
            layout, self.block_size = targets.block_layout(self.block, self.structs)
            self.offsets = {name: (offset, stride) for name, offset, stride in layout}
        fragment_samplers = len([n for n in app_samplers if n in em.app_uniforms]) + \
            len([u for u in material if u.type == "filename"])
        if self.target.max_samplers and fragment_samplers > self.target.max_samplers:
            raise MtlxError((g.result.loc, "element '%s' needs %d texture samplers in its fragment stage; %s "
                             "guarantees %d" % (comment_text(g.element), fragment_samplers, self.target.api,
                                                self.target.max_samplers)))

    def preamble(self, comment):
        return ["#version " + self.target.version] + list(self.target.header) + [comment, ""]

    def struct_lines(self, types):
        """Declarations of the document's struct types among `types` (and the types they hold)."""
        g = self.graph
        return ["struct %s { %s };" % (name, " ".join(
            "%s %s;" % (mxtypes.glsl_type(mt, g.structs), mn) for mn, mt, _ in g.structs[name].members))
            for name in struct_order([t for t in g.structs if t in types], g.structs)]

    def uniforms(self, stage, app_names, material, used_types):
        """The struct types and uniforms of one stage: application uniforms `app_names`, the material's
        `material` (graph Uniforms). With a block, every stage declares the whole block."""
        if not self.target.uniform_block:
            lines = self.struct_lines(used_types)
            lines += interface_declarations(app_names, self.target.name, self.em.max_lights)
            self.material_lines = len(material)     # the last lines: the material's uniforms
            initializers = self.target.initializers
            for u in material:
                t, length, init = self.em.uniform_parts(u)
                suffix = "[%d]" % length if length else ""
                if init is not None and initializers:
                    lines.append("uniform " + t + " " + u.name + suffix + " = " + init + ";")
                else:
                    lines.append("uniform " + t + " " + u.name + suffix + ";")
            return lines
        block_types = {u.type for u in self.graph.uniforms.values()}
        lines = self.struct_lines(set(used_types) | block_types)
        lines += interface.types_needed(self.app_names, self.em.max_lights)
        lines.append("layout(std140, set = %d, binding = %d) uniform %s" % (targets.BLOCK_SET, targets.BLOCK_BINDING,
                                                                          targets.BLOCK_NAME))
        lines.append("{")
        for name, t, length in self.block:
            suffix = interface.TABLE[name].array_suffix if name in interface.TABLE else \
                ("[%d]" % length if length else "")
            lines.append("    %s %s%s;" % (t, name, suffix))
        lines.append("};")
        stage_samplers = [n for n in sorted(app_names) if interface.TABLE[n].type in interface.SAMPLER_TYPES]
        stage_samplers += [u.name for u in material if u.type == "filename"]
        for name in stage_samplers:
            lines.append("layout(set = %d, binding = %d) uniform sampler2D %s;" % (
                targets.BLOCK_SET, self.bindings[name], name))
        return lines

    def attributes(self, attrs):
        if not self.target.locations:
            return ["in %s %s;" % (t, a) for a, t in attrs.items()]
        return ["layout(location = %d) in %s %s;" % (i, t, a) for i, (a, t) in enumerate(attrs.items())]

    def varyings(self, direction, streams_):
        lines = []
        for i, s in enumerate(streams_):
            decl = "%s%s %s v_%s;" % ("flat " if s.flat else "", direction, s.type, s.name)
            lines.append("layout(location = %d) %s" % (i, decl) if self.target.locations else decl)
        return lines

    def member_fields(self, name):
        """Manifest fields of a block member: its byte offset (and array stride) in the block."""
        if name not in self.offsets:
            return {}
        offset, stride = self.offsets[name]
        return {"offset": offset, "stride": stride} if stride else {"offset": offset}

    def manifest(self):
        """The target's own manifest fields: the block's layout, the samplers' bindings, the attributes'
        locations (vulkan); nothing for the others."""
        if not self.target.uniform_block:
            return {}
        members = []
        for name, t, length in self.block:
            entry = {"name": name, "type": t + ("[%d]" % length if length else "")}
            entry.update(self.member_fields(name))
            if t in self.structs:
                layout, size = targets.block_layout(self.structs[t], self.structs)
                entry["members"] = [{"name": n, "type": mt, "offset": off} for (n, off, _), (_, mt, _) in
                                    zip(layout, self.structs[t])]
            members.append(entry)
        return {
            "uniform_block": {"name": targets.BLOCK_NAME, "set": targets.BLOCK_SET, "binding": targets.BLOCK_BINDING,
                              "layout": "std140", "size": self.block_size, "members": members},
            "samplers": [{"name": n, "set": targets.BLOCK_SET, "binding": b} for n, b in self.bindings.items()],
            "attribute_locations": {a: i for i, a in enumerate(self._attribute_order)},
        }


class VertexEmitter(Emitter):
    """Emits nodes into the vertex stage (for displacement): streams read the attributes directly."""
    stage = "vertex"

    def __init__(self, graph, target="glsl"):
        super().__init__(graph, target=target)
        self.graph = graph            # the fragment emitter's own view (emit() hands it): one uniform table
        self.attributes = {}
        self.result = None

    @property
    def vars_owner(self):
        return {node_id for node_id, _ in self.vars}

    def stream(self, name, mx_type=None, node=None):
        s = self.lookup_stream(name, mx_type, node)
        for a, t in s.attributes:
            self.attributes.setdefault(a, t)
        self.app_uniforms.update(s.uniforms)
        return "(%s)" % s.fragment.format("(%s)" % s.vertex)


@dataclass(frozen=True, eq=False)
class FunctionCode:
    """A nodegraph implementation's function as one stage emits it (functions.Family.variants keeps it)."""
    name: str                         # GLSL name
    text: str                         # the definition: `void NAME(params, out outputs) { ... }`
    parameters: tuple                 # the inputs the call passes, in order (then one variable per output)
    callees: tuple                    # FunctionCode of the functions its body calls, callees first
    files: tuple                      # glsl_lib files its body needs, each after those it requires
    app_uniforms: frozenset           # application uniforms its body reads
    streams: dict                     # geometric streams its body reads: name -> streams.Stream
    attributes: dict                  # vertex attributes its body reads (a vertex stage's): name -> GLSL type
    uses_closures: bool
    types: frozenset                  # types its body uses (struct declarations)
    switches: frozenset               # the glsldeps paste switches its body allows

    @functools.cached_property
    def identifiers(self):
        """The identifiers its text uses (glsldeps.identifiers), read once."""
        return frozenset(glsldeps.identifiers(self.text))


class FunctionEmitter(Emitter):
    """Emits a function's body (functions.Family.body) under the settings of the emitter `caller` (its stage,
    target, environment method, lights): the body's nodes are main's were it inlined, the parameters read as
    variables. What a material declares (uniforms, textures, primvars, a document's GLSL) never comes from a body:
    functions.py inlines those."""

    def __init__(self, body, family, name, caller):
        super().__init__(body, caller.environment, caller.target.name, caller.max_lights, caller.compact)
        self.stage, self.name, self.family = caller.stage, name, family
        self.vertex = caller.stage == "vertex"
        self.attributes = {}
        self.names.update(body.parameters.values())
        self.outputs = {oname: self.fresh("out_" + oname) for oname in body.outputs}

    def stream(self, name, mx_type=None, node=None):
        if self.vertex:
            return VertexEmitter.stream(self, name, mx_type, node)
        return super().stream(name, mx_type, node)

    def emit_function(self):
        g = self.graph
        ids = set()
        for src in g.outputs.values():
            ids |= self.reachable(src)
        for node in g.nodes:
            if node.id in ids:
                self.emit_node(node)
        self.current = None
        for oname, src in g.outputs.items():
            self.line("%s = %s;" % (self.outputs[oname], self.expr(src)))
        if self.graph.uniforms or self.textures or self.primvars or self.external or self.document_code:
            raise RuntimeError("the body of %s declares what its material should (uniforms, textures, a document's "
                               "GLSL): functions.py should have inlined it" % g.element)
        nd = self.family.nodedef
        decls = ["%s %s" % (self.glsl_type(nd.inputs[name].type), param) for name, param in g.parameters.items()]
        decls += ["out %s %s" % (self.glsl_type(nd.outputs[oname].type), var) for oname, var in self.outputs.items()]
        if any(not mxtypes.CLOSURE_NAMES.isdisjoint(n.outputs.values()) for n in g.nodes if n.id in ids) or \
                not mxtypes.CLOSURE_NAMES.isdisjoint(nd.outputs[o].type for o in self.outputs):
            self.uses_closures = True
        text = "\n".join(["// %s" % comment_text("%s, from nodegraph %s" % (nd.name, self.family.impl.name)),
                          "void %s(%s)" % (self.name, ", ".join(decls)), "{"] + self.body + ["}"]) + "\n"
        types = node_types(g.nodes) | {nd.inputs[name].type for name in g.parameters} | {
            nd.outputs[o].type for o in self.outputs} | self.function_types
        return FunctionCode(self.name, text, tuple(g.parameters), tuple(self.functions.values()), tuple(self.files),
                            frozenset(self.app_uniforms), dict(self.streams), dict(self.attributes), self.uses_closures,
                            frozenset(types), frozenset(self.paste_switches()))


def node_types(nodes):
    """The types the inputs and outputs of `nodes` carry (the struct declarations a stage needs)."""
    used = set()
    for n in nodes:
        used.update(s.type for s in n.inputs.values())
        used.update(n.outputs.values())
    return used


def function_texts(codes):
    """The definitions of the functions a stage calls, in order (callees first)."""
    return [code.text for code in codes.values()]


def function_identifiers(codes):
    """The identifiers the bodies of the functions a stage calls use (glsl_lib code they reach)."""
    names = set()
    for code in codes.values():
        names |= code.identifiers
    return names


def struct_order(names, structs):
    """`names` and the struct types their members hold, each after the structs it holds (GLSL declares a
    type before its use). Structs are acyclic (document.py refuses a struct that contains itself)."""
    order, done = [], set()
    for root in names:
        stack, on_stack = [(root, iter(structs[root].members))], {root}
        while stack:
            name, members = stack[-1]
            inner = next((mt for _, mt, _ in members if mt in structs and mt not in done | on_stack), None)
            if inner is not None:
                stack.append((inner, iter(structs[inner].members)))
                on_stack.add(inner)
            else:
                stack.pop()
                on_stack.discard(name)
                if name not in done:
                    done.add(name)
                    order.append(name)
    return order


def emit(graph, environment="fis", target="glsl", max_lights=0, compact=False):
    """The Shader of a graph. max_lights: how many direct lights (u_lightData) lit surfaces loop over; 0 (the
    default) writes no light loop: environment light only. compact: glsl_lib code without comments and blank lines
    (the reduced interface's shaders: made for one use, not for reading; the complete ones keep their citations)."""
    return Emitter(graph, environment, target, max_lights, compact).emit()
