"""Nodegraph implementations as GLSL functions: built once, emitted once per shader, called per instance.

A node whose nodedef the libraries implement by a nodegraph (standard_surface, open_pbr_surface, gltf_pbr, ramp4,
...) is, in the complete interface, one *call node* in its graph (GNode.function, graph/build.py). Its implementation is a
graph of its own, the *body*: the nodegraph's nodes reading the nodedef's inputs as the function's parameters. The
emitter writes the body once as `void NAME(inputs..., out outputs...)` and each call node as a call
(emit.FunctionEmitter); MaterialX's CompoundNode::emitFunctionDefinition does the same.

One plain cache, per Library (Library.functions; a document's own definitions overlay the libraries in a Library of
its own, so they never mix): a Family per (nodedef, build rules, working colour space, the values of its string
inputs: they choose code). A Family holds the inputs its body reads at compile time (a `{{=name}}` field, a handler
reading a value: found by emitting, Family.compile_time) and, per their values, the body's emitted code per emission
settings (Family.code).

Inlined instead: graph/build.py expands the nodegraph in place, as the reduced interface always does (reduce.py and
fold.py turn inputs into constants and fold them through the implementation's nodes):
- an output that is a closure (BSDF, EDF, VDF: evaluated per lighting context by the shader reading it, not a value
  a function returns), a material, a displacement (the vertex stage) or a light, or a volume shader;
- an input of a closure or shader type, an array, or a filename (a sampler is the material's own uniform, whose
  manifest entry the image node writes), or a string input fed by a node (its value chooses code);
- a body that declares uniforms of its own (a texture inside), reads the document's own nodegraphs, outputs or
  geompropdefs, or runs a document's own GLSL (<implementation>: checked and reported per document);
and a call whose compile-time input is connected (no value to specialise on: the element is built again with its
implementations expanded, pipeline.py).
"""
from mtlxgen.graph.graphtypes import Graph, Source, glsl_identifier, sha256

# types a function can neither take nor return as a value
_NO_PARAMETER = frozenset(("filename", "BSDF", "EDF", "VDF", "surfaceshader", "volumeshader", "displacementshader",
                           "lightshader", "material", "floatarray", "integerarray", "color3array", "color4array",
                           "vector2array", "vector3array", "vector4array", "stringarray"))
_RETURNS = frozenset(("surfaceshader",))        # the shader types a function returns (a value: colour, transparency)
_NO_RETURN = _NO_PARAMETER - _RETURNS
STATIC_TYPES = ("string", "geomname")           # inputs whose values choose code: part of a Family's key

FAMILIES_MAX = 512                              # per library; a full table is cleared (documents' libraries are new)
VARIANTS_MAX = 64                               # compile-time specialisations per family


class CompileTime(Exception):
    """A body read the value of input `name` of `family` at compile time (Param below): the family is specialised on
    that input's value (emit/emitter.py)."""

    def __init__(self, family, name):
        super().__init__(name)
        self.family, self.name = family, name


class Inline(Exception):
    """A call whose compile-time input is connected: no value to specialise on. The element is built again with its
    nodegraph implementations expanded in place (pipeline.py), where the node reads the connection as it always did."""

    def __init__(self, node, name):
        super().__init__("%s.%s" % (node.id, name))


class Param:
    """The value of a function parameter while its body is emitted: not known. Anything that reads it as a value (a
    number, a truth value, text) raises CompileTime, so the function is specialised on that input instead."""
    __slots__ = ("family", "name")

    def __init__(self, family, name):
        self.family, self.name = family, name

    def _read(self, *args):
        raise CompileTime(self.family, self.name)

    def __repr__(self):
        return "Param(%r)" % self.name

    __bool__ = __float__ = __int__ = __index__ = __str__ = __format__ = __len__ = __iter__ = __getitem__ = _read
    __lt__ = __le__ = __gt__ = __ge__ = __neg__ = __add__ = __radd__ = __sub__ = __rsub__ = __mul__ = __rmul__ = _read


def signature_ok(nd):
    """Whether nodedef `nd` can be a function at all (module docstring: what is inlined)."""
    if any(o.type in _NO_RETURN for o in nd.outputs.values()):
        return False
    return not any(i.type in _NO_PARAMETER for i in nd.inputs.values())


def function_for(builder, nd, impl_graph, inputs):
    """The Family a call to `nd` (implemented by `impl_graph`, its inputs' Sources `inputs`) runs, in `builder`'s
    library; None where the node is expanded in place instead. The body's warnings are the builder's too."""
    if not signature_ok(nd):
        return None
    statics = []
    for name, decl in nd.inputs.items():
        if decl.type in STATIC_TYPES:
            s = inputs[name]
            if s.node is not None or not isinstance(s.value, (str, type(None))):
                return None
            statics.append((name, s.value))
    table = builder.lib.functions
    key = (nd.name, builder.rules, builder.doc.colorspace, tuple(statics))
    family = table.get(key)
    if family is None or family.impl is not impl_graph or family.nodedef is not nd:
        if len(table) >= FAMILIES_MAX:
            table.clear()
        family = table[key] = Family(builder, nd, impl_graph, dict(statics), key)
    if family.inline:
        return None
    for loc, message in family.warnings:
        builder.warn(loc, message)
    return family


class Family:
    """One nodedef's implementation as functions (module docstring)."""

    def __init__(self, builder, nd, impl_graph, statics, key):
        from mtlxgen.read.document import Document
        self.nodedef, self.impl, self.statics = nd, impl_graph, statics
        self.rules, self.lib, self.builder_class = builder.rules, builder.lib, type(builder)
        # the document the body is built in: none of the caller's (a body reading the document is inlined), only its
        # working colour space; the library is the caller's (overlay(doc) of a document without definitions is it)
        self.doc = Document(path="", colorspace=builder.doc.colorspace)
        self.expanding = list(builder.expanding)   # a nodedef met inside its own implementation: refused as inline
        self.base = glsl_identifier("mg_" + nd.name)
        if statics:
            self.base += "_" + sha256(repr(sorted(statics)).encode("utf-8", "surrogatepass")).hexdigest()[:8]
        # (emission settings, ((input, value) fixed so far, ...)) -> ("input", the next input the body reads at
        # compile time) or ("code", emit.FunctionCode): each call walks it from nothing fixed (emit.Emitter.call),
        # so what a call gets depends on its own values and settings only, never on what was emitted before
        self.variants = {}
        self.warnings = []
        body, warnings, builder_ = self.body({})
        self.warnings = warnings
        self.generic = body             # the body with no input fixed: what most calls emit (not built twice)
        # the inputs the body reads: a call passes only those (an input no node of the implementation reads is no
        # uniform of the material, as where the implementation is expanded and pruned)
        self.reads = set(body.parameters) | set(statics)
        self.inline = bool(builder_.uniforms) or builder_.foreign or any(
            n.nodedef.source in ("document", "user") and n.nodedef.name in self.lib.implementations
            for n in body.nodes)

    def name(self, fixed):
        """The GLSL name of the variant with compile-time inputs `fixed` (((input, value), ...))."""
        if not fixed:
            return self.base
        return "%s_v%s" % (self.base, sha256(repr(fixed).encode("utf-8", "surrogatepass")).hexdigest()[:8])

    def body(self, fixed):
        """(Graph, warnings, builder) of the implementation with the parameters as inputs (Source.uniform names the
        parameter, Source.value is a Param), `fixed` {input: value} the compile-time ones given as constants (the
        string inputs are always the family's values)."""
        b = self.builder_class(self.doc, self.lib, self.rules, functions=True)
        b.expanding = self.expanding + [self.nodedef.name]
        params = {}
        for name, decl in self.nodedef.inputs.items():
            if name in fixed:
                params[name] = Source(decl.type, value=fixed[name], loc=decl.loc)
            elif decl.type in STATIC_TYPES:
                params[name] = Source(decl.type, value=self.statics.get(name), loc=decl.loc)
            else:
                params[name] = Source(decl.type, value=Param(self, name), uniform=b.new_id(name), loc=decl.loc)
        outs = b.expand_implementation(self.nodedef, self.impl, params, "", self.impl.loc)
        nodes = b.upstream([s for s in outs.values()])
        read = {s.uniform for n in nodes for s in n.inputs.values()} | {s.uniform for s in outs.values()}
        g = Graph(element=self.nodedef.name, kind="function", result=next(iter(outs.values())), nodes=nodes,
                  uniforms=dict(b.uniforms), structs=self.lib.structs, doc_path="", library=self.lib,
                  colorspace=self.doc.colorspace, outputs=outs,
                  parameters={name: s.uniform for name, s in params.items()
                              if isinstance(s.value, Param) and s.uniform in read})
        return g, list(b.warnings.items), b


def value_key(value):
    """A compile-time value as a key (lists as tuples); the value of an enclosing function's parameter is read,
    so that function is specialised on it first (CompileTime)."""
    if isinstance(value, Param):
        value._read()
    if isinstance(value, (list, tuple)):
        return tuple(value_key(v) for v in value)
    return value
