"""The graph passes, in the order they run: from a document's element to the IR the emitter reads.

The IR is the typed graph (graphtypes.Graph: GNodes in dependency order, Sources between them, the public Uniforms
with their Origin). The first pass makes it from the document; each later one takes a Graph and returns a new one
(its input is never changed), and says what it guarantees. pipeline.Session runs them (run()), the emitter
(emit/emitter.py) reads the result; nothing else changes a graph.

    build     graph.build_graph            every node resolved to its nodedef (MaterialX's matching rules), every
                                           connection type-checked (or read as MaterialX reads it, warned),
                                           defaults and default geometric properties filled in, colour-managed
                                           values converted; nodegraph implementations called as functions
                                           (functions.py, complete interface) or expanded in place; only what the
                                           element needs, in dependency order. Cycles, unknown nodes and types:
                                           FILE:LINE errors.
    reduce    reduce.reduce                (reduced interface) the inputs not kept editable become literals.
    fold      fold.fold                    (reduced interface) nodes of literal inputs computed (their evaluators,
                                           nodes/), selections made, empty closures removed, the rest pruned;
                                           closure guards marked decidable on literals (static_guards).
    closures  closureplan.plan             which nodes are closures (evaluated per lighting context by the shader
                                           node that reads them) and the condition under which each is needed:
                                           a condition tree over inputs, decided on the literals where the graph's
                                           guards are static (closureplan.decide), never by reading emitted text.

Implementations emitted as functions get the same passes inside (functions.Family.body: build; the emitter plans
their closures).
"""
from mtlxgen.base.records import dataclass


@dataclass(frozen=True)
class Pass:
    name: str
    run: object                       # Graph (, interface) -> Graph
    reduced_only: bool = False        # runs for the reduced interface alone


def _reduce(graph, iface, kept):
    from mtlxgen.passes.reduce import reduce
    graph, names = reduce(graph, iface)
    kept.extend(names)
    return graph


def _fold(graph, iface, kept):
    from mtlxgen.passes.fold import fold
    return fold(graph)


def _closures(graph, iface, kept):
    from mtlxgen.passes.closureplan import plan
    return plan(graph)


# after build (graph.build_graph, which makes the graph from the document: pipeline.Session.graph), in order
PASSES = (
    Pass("reduce", _reduce, reduced_only=True),
    Pass("fold", _fold, reduced_only=True),
    Pass("closures", _closures),
)


def run(graph, iface):
    """(the Graph `graph` (the build pass's) through the later passes for interface `iface` (a reduce.Interface),
    [names of the uniforms the reduced interface kept] or None for the complete interface)."""
    kept = []
    for p in PASSES:
        if p.reduced_only and not iface.reduced:
            continue
        graph = p.run(graph, iface, kept)
    return graph, (kept if iface.reduced else None)
