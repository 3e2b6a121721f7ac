"""Build a one-node document for any nodedef and generate + compile it (used by the coverage test)."""
import os

from mtlxgen.emit import emitter as emit
from mtlxgen.graph import build as graph
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.read.document import Document, Node

VALUE_TYPES = {"float", "integer", "boolean", "color3", "color4", "vector2", "vector3", "vector4",
               "matrix33", "matrix44", "surfaceshader", "material", "BSDF", "EDF", "VDF", "volumeshader",
               "displacementshader", "lightshader"}


def probe_nodedef(nd, library, compile_fn):
    """None when the nodedef generates and compiles; otherwise a one-line reason."""
    from mtlxgen.base.diagnostics import Loc
    loc = Loc("<probe %s>" % nd.name, 1)
    node_type = nd.type if len(nd.outputs) == 1 else "multioutput"
    doc = Document(path=os.path.join(os.getcwd(), "probe.mtlx"))
    doc.nodes["probe"] = Node(category=nd.category, name="probe", type=node_type, loc=loc, nodedef=nd.name)
    builder = graph.GraphBuilder(doc, library, pipeline.graph_rules())
    try:
        outs = builder.instantiate(doc.nodes["probe"], builder.doc_scope)
    except MtlxError as e:
        return "graph: " + e.lines()[0]
    for oname, src in outs.items():
        if src.type not in VALUE_TYPES:
            continue        # strings and filenames are consumed by other nodes, never drawn
        g = builder.build_result(src, "probe/" + oname)
        try:
            shader = emit.emit(g)
        except MtlxError as e:
            return "emit: " + e.lines()[0]
        err = compile_fn(shader)
        if err:
            return "compile: " + err
    return None
