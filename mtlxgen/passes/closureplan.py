"""Closure planning: when each closure node of a graph is needed, a pass over the graph the emitter consumes.

A closure node (all of its outputs BSDF, EDF or VDF) is evaluated per lighting context by the shader node
that uses it, and only where it can matter: a lobe behind a mix whose factor selects the other side costs
nothing, its value being the empty closure, and so does a BSDF of (near) zero weight. ClosurePlan.conditions(root)
gives, for the closure nodes upstream of a root, None (always needed) or a condition: the disjunction over the
node's uses of (its parent's condition and the edge's). weighed(node id) is a BSDF's own condition on its weight.

Conditions are plain data: None (always), ("cmp", node id, input, operator, constant) (the node's input compared
with a number), ("and", a, b), ("or", a, b); GLSL text stands for a condition given as text (it is written as it
is and never decided). decide() decides a condition on the literal values of the inputs it compares (the reduced
interface's constants): True, False, or what remains of it. glsl() writes one as GLSL from the expressions of the
nodes' inputs, which only emission knows.
"""
import operator
from mtlxgen.base.records import replace

from mtlxgen.graph import graphwalk
from mtlxgen.base.mxtypes import format_float
from mtlxgen.base.mxtypes import CLOSURE_TYPES

# a BSDF weighing less is the empty closure whatever its other inputs are (as in MaterialX: e.g. gltf_pbr's sheen
# colour is 0/0 when sheen is off); fold.py removes such a lobe where its weight is a literal
ZERO_WEIGHT = 1.0e-6

# edges that carry a condition: (category, input) -> (input of the node, operator, constant): when the input's
# closure matters (exactly, for every factor: an EDF mix extrapolates outside [0, 1]; a BSDF/VDF mix holds its
# factor there, where a side it weighs 0 is computed to no effect)
EDGE_CONDITIONS = {("mix", "fg"): ("mix", "!=", 0.0), ("mix", "bg"): ("mix", "!=", 1.0)}

_OPERATORS = {"==": operator.eq, "!=": operator.ne, ">=": operator.ge, "<=": operator.le, ">": operator.gt,
              "<": operator.lt}

UNKNOWN = object()          # decide's literal_value for an input that is not a literal


def is_closure_node(node):
    return bool(node.outputs) and CLOSURE_TYPES.issuperset(node.outputs.values())


def compare(node_id, name, op, constant):
    """The condition `input name of node_id` op `constant` (a number)."""
    if op not in _OPERATORS:
        raise ValueError("not a comparison operator: %r" % op)
    return ("cmp", node_id, name, op, constant)


def weighed(node_id):
    """A BSDF's condition on its own weight: weight >= ZERO_WEIGHT."""
    return ("cmp", node_id, "weight", ">=", ZERO_WEIGHT)


def conjoin(a, b):
    """a and b; None (or True) is always, False never."""
    if a is False or b is False:
        return False
    if a is None or a is True or b is None or b is True:
        return b if a is None or a is True else a
    return ("and", a, b)


def disjoin(a, b):
    """a or b; None (or True) is always, False never."""
    if a is None or a is True or b is None or b is True:
        return None
    if a is False or b is False:
        return b if a is False else a
    return ("or", a, b)


def decide(cond, literal_value, memo=None):
    """`cond` decided where the inputs it compares are literals: True (always; also for None), False (never), or the
    condition that remains (its comparisons of literals decided, the terms that decide nothing dropped; the same
    tuple where nothing was decided). literal_value(node id, input) -> the input's literal value, or UNKNOWN.

    memo: a dict for the decision of each condition tuple, by identity (a plan's conditions share their parents'
    tuples), for one literal_value; it keeps the tuples it holds alive."""
    if cond is None or cond is True:
        return True
    if cond is False or isinstance(cond, str):
        return cond
    if memo is not None:
        hit = memo.get(id(cond))
        if hit is not None:
            return hit[1]
    kind = cond[0]
    if kind == "cmp":
        _, node_id, name, op, constant = cond
        v = literal_value(node_id, name)
        out = cond if v is UNKNOWN else bool(_OPERATORS[op](v, constant))
    elif kind in ("and", "or"):
        a, b = decide(cond[1], literal_value, memo), decide(cond[2], literal_value, memo)
        if a is cond[1] and b is cond[2]:
            out = cond
        else:
            out = conjoin(a, b) if kind == "and" else disjoin(a, b)
            out = True if out is None else out
    else:
        raise ValueError("not a condition: %r" % (cond,))
    if memo is not None:
        memo[id(cond)] = (cond, out)
    return out


def glsl(cond, input_values, memo=None):
    """GLSL text of a condition: None (always, as is True) stays None, False stays False; input_values(node id) ->
    {input name: GLSL expression}.

    memo: a dict for the text of each condition tuple written, by identity (a plan's conditions share their
    parents' tuples), for one input_values; it keeps the tuples it holds alive."""
    if cond is None or cond is True:
        return None
    if cond is False or isinstance(cond, str):
        return cond
    if memo is not None:
        hit = memo.get(id(cond))
        if hit is not None:
            return hit[1]
    kind = cond[0]
    if kind == "cmp":
        _, node_id, name, op, constant = cond
        text = "%s %s %s" % (input_values(node_id)[name], op, format_float(constant))
    elif kind in ("and", "or"):
        a, b = glsl(cond[1], input_values, memo), glsl(cond[2], input_values, memo)
        if a is None or b is None or a is False or b is False:        # (a tuple built around True or False)
            text = glsl(conjoin(a, b) if kind == "and" else disjoin(a, b), input_values)
        elif kind == "and":         # && binds tighter than ||: a disjunction inside a conjunction is bracketed
            text = "%s && %s" % tuple("(%s)" % s if "||" in s else s for s in (a, b))
        else:
            text = "(%s) || (%s)" % (a, b)
    else:
        raise ValueError("not a condition: %r" % (cond,))
    if memo is not None:
        memo[id(cond)] = (cond, text)
    return text


def plan(graph):
    """The closures pass (passes/order.py): `graph` with its ClosurePlan (Graph.closure_plan), which the emitter reads."""
    return replace(graph, closure_plan=ClosurePlan(graph))


class ClosurePlan:
    def __init__(self, graph):
        self.nodes = {n.id: n for n in graph.nodes if is_closure_node(n)}
        self._plans = {}

    def conditions(self, root):
        """{closure node id: condition} for `root` (a closure node id) and the closure nodes upstream of it,
        in the order they were reached (parents before children)."""
        if root not in self._plans:
            self._plans[root] = self._plan(root)
        return self._plans[root]

    def literal_value(self, node_id, name):
        """The value of a closure node's input where it is a literal number (decide's literal_value), else
        UNKNOWN: a uniform, a connection, a value of another type."""
        s = self.nodes[node_id].inputs.get(name)
        if s is None or not s.literal or s.type not in ("float", "integer"):
            return UNKNOWN
        v = s.value
        return v if isinstance(v, (int, float)) and not isinstance(v, bool) else UNKNOWN

    def _plan(self, root):
        conds = {root: None}
        for node_id in reversed(graphwalk.postorder(self.nodes, [root])):      # parents before children
            node = self.nodes[node_id]
            for name, s in node.inputs.items():
                if s.node not in self.nodes:
                    continue
                edge = EDGE_CONDITIONS.get((node.category, name))
                use = conjoin(conds.get(node_id), compare(node_id, *edge) if edge is not None else None)
                conds[s.node] = use if s.node not in conds else disjoin(conds[s.node], use)
        return conds
