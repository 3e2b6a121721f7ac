"""Node implementations as data.

Each library module here (stdlib_math, stdlib_channel, ...) declares a table `NODES` keyed by node
category: one entry serves every type of that category. An entry is either a GLSL expression
template (str), or a dict with:
    "expr":    template of the single output           (or)
    "outputs": {output name: template} for multi-output nodes
    "files":   GLSL files under glsl_lib/ the templates call into (each emitted once)
    "handler": a function (or the name of one in handlers.py), for the few nodes that need code
    "closure": {context: template} for BSDF / EDF / VDF nodes, evaluated by the shader node that uses
               them once per context ("reflection" per light, "indirect" for the environment,
               "transmission", "emission"); a context without a template gives the empty closure
    "evaluate": the node's value computed in Python, term for term as the template computes it (nodevalue.py),
               where the reduced interface folds a node of literal inputs (fold.py): one place for a node's
               GLSL and its value
An optional `NODEDEFS` table keyed by nodedef name overrides the category entry for one signature.

Template fields (MaterialX's inline syntax, extended):
    {{in1}}        the GLSL expression of input in1
    {{=index}}     the compile-time value of a uniform input (error if it is connected)
    {{@name}}      a geometric stream from the vertex stage (see streams.py)
    {{$type}}      the GLSL type of the (single) output; {{$type:in1}} that of an input
Nodedefs implemented by nodegraphs in the data libraries need no entry: the graph is expanded.
"""
import importlib
import os
from mtlxgen.base.records import dataclass, field

from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.graph.build import BuildRules
from mtlxgen.base.identifiers import glsl_identifier

# every table module in this package (all but handlers), in name order (a listing of the folder: pkgutil would
# import typing, 2 ms of every start)
_MODULES = [importlib.import_module("%s.%s" % (__name__, name)) for name in sorted(
    {f[:-3] for d in __path__ for f in os.listdir(d) if f.endswith(".py") and f != "__init__.py"} - {"handlers"})]


@dataclass(frozen=True)
class Impl:
    outputs: dict = field(default_factory=dict)   # output name ("*" = the single output) -> template
    files: tuple = ()
    handler: object = None
    closure: dict = None                          # context -> template (closure nodes)
    opaque: bool = False                          # a BSDF that lets nothing through at any weight (see emit.closure)
    external: tuple = None                        # (GLSL file path, function) from a document's <implementation>
    origin: str = "mtlxgen"
    source: tuple = None                          # (name, Loc) of a document's <implementation>
    evaluate: object = None                       # the value in Python (nodevalue.evaluate), where it folds


def _normalize(entry, origin):
    if isinstance(entry, str):
        return Impl(outputs={"*": entry}, origin=origin)
    outputs = dict(entry.get("outputs", {}))
    if "expr" in entry:
        outputs["*"] = entry["expr"]
    return Impl(outputs=outputs, files=tuple(entry.get("files", ())), handler=entry.get("handler"),
                closure=entry.get("closure"), opaque=bool(entry.get("opaque")), evaluate=entry.get("evaluate"),
                origin=origin)


BY_CATEGORY, BY_NODEDEF = {}, {}
for _m in _MODULES:
    for _k, _v in getattr(_m, "NODES", {}).items():
        if _k in BY_CATEGORY:
            raise RuntimeError("node category %s is declared twice (%s)" % (_k, _m.__name__))
        BY_CATEGORY[_k] = _normalize(_v, _m.__name__)
    for _k, _v in getattr(_m, "NODEDEFS", {}).items():
        BY_NODEDEF[_k] = _normalize(_v, _m.__name__)


def lookup(nodedef, library):
    """The GLSL implementation of a nodedef, or None where it has none (but maybe a nodegraph)."""
    if nodedef.name in BY_NODEDEF:
        return BY_NODEDEF[nodedef.name]
    doc_impl = library.implementations.get(nodedef.name)
    if doc_impl is not None and nodedef.source in ("document", "user"):
        if doc_impl.sourcecode is not None:
            from mtlxgen.nodes.sourcecode import problem as sourcecode_problem
            problem = sourcecode_problem(doc_impl.sourcecode, nodedef, library.structs)
            if problem:
                raise MtlxError((doc_impl.loc, "implementation '%s': %s" % (doc_impl.name, problem)))
            return Impl(outputs={"*": doc_impl.sourcecode}, origin="document", source=(doc_impl.name, doc_impl.loc))
        if doc_impl.file and doc_impl.function:
            if glsl_identifier(doc_impl.function) != doc_impl.function:     # also refuses GLSL's reserved words
                raise MtlxError((doc_impl.loc, "implementation '%s': function %r is not a GLSL identifier free "
                                               "for a document's use" % (doc_impl.name, doc_impl.function)))
            return Impl(external=(doc_impl.file, doc_impl.function, doc_impl.loc), origin="document",
                        source=(doc_impl.name, doc_impl.loc))
    if nodedef.name in library.graph_impls:
        return None
    return BY_CATEGORY.get(nodedef.category)


def has_leaf_implementation(nodedef, library):
    if nodedef.name in BY_NODEDEF:
        return True
    doc_impl = library.implementations.get(nodedef.name)
    return doc_impl is not None and nodedef.source in ("document", "user") and bool(
        doc_impl.sourcecode is not None or (doc_impl.file and doc_impl.function))


class GlslRules(BuildRules):
    """What the GLSL target tells graph building (graph.BuildRules): the nodedefs it implements itself,
    which are kept as one node where the libraries also implement them by a nodegraph."""

    def implements(self, nodedef, library):
        return has_leaf_implementation(nodedef, library)


RULES = GlslRules()
