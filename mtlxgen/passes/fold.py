"""Generation-time folding: what the reduced interface made constant is computed here, not per pixel.

fold() is a graph pass: a Graph in, a new Graph out (the input is never changed). In dependency order, each node
  - whose inputs are all literals and whose node table entry carries an evaluator (mtlxgen/nodes: the stdlib math,
    colour, channel, conditional and compositing nodes, and cmlib's colour-space conversions) becomes a literal: its
    value computed with numpy by that evaluator, term for term what its GLSL template computes. A value GLSL leaves
    undefined (the power of a negative base, the square root or log of a negative, asin beyond 1, normalize of zero,
    a division by zero) or that no literal can carry (inf, nan) is not folded: the node stays and the GPU computes
    it as before;
  - that only selects one of its inputs by literals (ifgreater/ifgreatereq/ifequal on literal values, a mix whose
    factor is exactly 0 or 1) is replaced by the input it selects;
  - is a closure that the literals make empty or transparent is removed: a BSDF whose weight is below
    closureplan.ZERO_WEIGHT (the emitter's own rule: the empty closure), a uniform_edf of colour 0, a mix of
    closures by a factor at (or, for BSDFs and VDFs, which hold it to [0, 1], beyond) 0 or 1, a layer, add or
    multiply with an empty side. Every rewrite gives what the emitted GLSL would give: mg_layer(empty, b) = b,
    mg_mix_BSDF(f, b, 0) = b, ...
Nodes that are not foldable stay nodes; nodes no longer needed are dropped (graphwalk.prune). The graph is marked
static_guards: the emitter decides the closure guards whose conditions are now literal (closureplan.decide).

evaluate() is the node tables' values in Python by category and nodedef: the tests compare it with the GLSL's pixels
(tests/passes/test_fold.py) and reference.node_value is it.
"""
from mtlxgen.base.records import replace

import numpy as np

from mtlxgen.graph import graphwalk
from mtlxgen.base import mxtypes
from mtlxgen import nodes
from mtlxgen.nodes import nodevalue
from mtlxgen.passes.closureplan import ZERO_WEIGHT
from mtlxgen.graph.build import Source
from mtlxgen.nodes.stdlib_conditional import COMPARISONS
from mtlxgen.nodes.nodevalue import (FLOAT_TYPES, VALUE_TYPES,  # noqa: F401 (fold.NotFoldable, fold.VALUE_TYPES)
                                     NotFoldable)


def _arr(value):
    return np.asarray(value, dtype=np.float64)


def evaluate(category, nodedef_name, inputs, types, out_type):
    """The value of one node of `category` (nodedef `nodedef_name`) with literal inputs ({name: Python value},
    their {name: type}) as a Python value of `out_type`, by the evaluator its node table entry carries (the nodedef's
    entry where it has one, else its category's). Raises NotFoldable where it is left to the GPU."""
    impl = nodes.BY_NODEDEF.get(nodedef_name) or nodes.BY_CATEGORY.get(category)
    return nodevalue.evaluate(impl.evaluate if impl is not None else None, inputs, types, out_type)


# ---------------------------------------------------------------- the pass

def is_empty_closure(s):
    """An unconnected closure value: the empty closure (emit: mxtypes.closure_zero)."""
    return s.literal and mxtypes.is_closure(s.type)


def _numbers(s):
    return np.asarray(s.value, dtype=np.float64).reshape(-1)


def _own_impl(node, library):
    """The node's implementation where it is our own table's (not a document's <implementation>), else None."""
    impl = nodes.lookup(node.nodedef, library)
    return impl if impl is not None and impl.origin != "document" else None


def _passthrough(node, ins, impl):
    """The Source a node's only output reduces to given its literal inputs, or None."""
    cat = node.category
    (otype,) = node.outputs.values() if len(node.outputs) == 1 else (None,)
    if otype is None:
        return None
    if cat == "dot" and otype != "filename":
        return ins["in"]
    if cat in COMPARISONS and "in1" in ins and "in2" in ins and ins["value1"].literal and ins["value2"].literal \
            and ins["value1"].type in VALUE_TYPES and ins["value2"].type in VALUE_TYPES:
        return ins["in1"] if COMPARISONS[cat](_arr(ins["value1"].value), _arr(ins["value2"].value)) else ins["in2"]
    if mxtypes.is_closure(otype):
        return _closure_passthrough(node, ins, otype, impl)
    if cat == "mix" and ins["mix"].literal and ins["mix"].type in FLOAT_TYPES:
        m = _numbers(ins["mix"])
        if np.all(m == 0.0):
            return ins["bg"]
        if np.all(m == 1.0):
            return ins["fg"]
    return None


def _closure_passthrough(node, ins, otype, impl):
    cat, nd = node.category, node.nodedef.name
    empty = Source(otype, loc=node.loc)
    weight = ins.get("weight")
    if otype == "BSDF" and weight is not None and weight.type == "float" and weight.literal \
            and impl.closure is not None and weight.value < ZERO_WEIGHT and not impl.opaque:
        return empty        # (an opaque lobe of zero weight is black, not empty: emit.Emitter.closure decides it)
    if cat == "mix" and ins["mix"].literal and ins["mix"].type == "float":
        m = float(ins["mix"].value)
        clamped = otype in ("BSDF", "VDF")           # mg_mix_BSDF / mg_mix_VDF hold the factor to [0, 1]
        if m == 0.0 or (clamped and m < 0.0):
            return ins["bg"]
        if m == 1.0 or (clamped and m > 1.0):
            return ins["fg"]
        if is_empty_closure(ins["fg"]) and is_empty_closure(ins["bg"]):
            return empty
    if nd == "ND_layer_bsdf":
        if is_empty_closure(ins["top"]):
            return ins["base"]
        if is_empty_closure(ins["base"]):
            return ins["top"]
    if cat == "add" and otype in ("BSDF", "EDF", "VDF"):
        if is_empty_closure(ins["in1"]):
            return ins["in2"]
        if is_empty_closure(ins["in2"]):
            return ins["in1"]
    if cat == "multiply" and otype in ("BSDF", "EDF", "VDF"):
        if is_empty_closure(ins["in1"]):
            return empty
        w = ins["in2"]
        if w.literal and w.type in FLOAT_TYPES:
            v = _numbers(w)
            if otype == "BSDF" and np.all(v >= 1.0):       # mg_scale(c, clamp(w, 0, 1)): c itself
                return ins["in1"]
            if otype != "BSDF" and np.all(v == 1.0):
                return ins["in1"]
            if otype == "EDF" and np.all(v == 0.0):        # an EDF is a colour: times 0 is none
                return empty
    if cat == "uniform_edf" and ins["color"].literal and np.all(_numbers(ins["color"]) == 0.0):
        return empty
    if cat == "generalized_schlick_edf" and is_empty_closure(ins["base"]):
        return empty                                      # base * tint
    return None


def fold(graph):
    """The Graph with every foldable node folded (see the module's docstring); static_guards set on it so that the
    emitter decides guards on literals at generation time."""
    lib = graph.library
    subst = {}                  # (node id, output) -> Source it is replaced by

    def follow(s):
        while s.node is not None and (s.node, s.output) in subst:
            s = subst[(s.node, s.output)]
        return s

    kept = []
    for node in graph.nodes:
        ins = {k: follow(s) for k, s in node.inputs.items()}
        new = replace(node, inputs=ins, outputs=dict(node.outputs), static=dict(node.static))
        impl = _own_impl(node, lib)
        if impl is not None:
            values = _fold_node(new, ins, impl)
            if values is not None:
                for oname, src in values.items():
                    subst[(node.id, oname)] = src
                continue
        kept.append(new)
    result = follow(graph.result)
    return replace(graph, nodes=graphwalk.prune(kept, [result]),      # only what the result still reads
                   result=result, uniforms={k: replace(u) for k, u in graph.uniforms.items()},
                   warnings=list(graph.warnings), static_guards=True)   # guards decided on literals (closureplan.decide)


def _fold_node(node, ins, impl):
    """{output: Source} replacing the node, or None where it stays."""
    if len(node.outputs) != 1:
        return None
    (oname, otype), = node.outputs.items()
    through = _passthrough(node, ins, impl)
    if through is not None:
        return {oname: through}
    values = {k: s for k, s in ins.items() if s.type not in ("string", "geomname")}
    if not values or not all(s.literal for s in values.values()) or mxtypes.is_closure(otype):
        return None
    try:
        v = nodevalue.evaluate(impl.evaluate, {k: s.value for k, s in values.items()},
                               {k: s.type for k, s in values.items()}, otype)
    except (NotFoldable, KeyError, TypeError, ValueError, IndexError):
        return None
    return {oname: Source(otype, value=v, loc=node.loc)}
