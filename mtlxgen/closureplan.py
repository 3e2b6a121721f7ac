"""Closure planning: when each closure node of a graph is needed, a pass over the graph the emitter consumes.

A closure node (all of its outputs BSDF, EDF or VDF) is evaluated per lighting context by the shader node
that uses it, and only where it can matter: a lobe behind a mix whose factor selects the other side costs
nothing, its value being the empty closure. ClosurePlan.conditions(root) gives, for the closure nodes
upstream of a root, None (always needed) or a condition: the disjunction over the node's uses of (its
parent's condition and the edge's). Conditions are plain data (below); glsl() writes one as GLSL from the
values of the nodes' inputs, which only emission knows.

A condition is None (always), GLSL text, ("edge", node id, template) (the template formatted with the
node's input expressions), ("and", a, b) or ("or", a, b).
"""
from .template import CLOSURE_TYPES

# edges that carry a condition: (category, input) -> template of when the input's closure matters
# (exactly, for every factor: an EDF mix extrapolates outside [0, 1]; a BSDF/VDF mix holds its factor there,
# where a side it weighs 0 is computed to no effect)
EDGE_CONDITIONS = {("mix", "fg"): "{mix} != 0.0", ("mix", "bg"): "{mix} != 1.0"}


def is_closure_node(node):
    return bool(node.outputs) and CLOSURE_TYPES.issuperset(node.outputs.values())


def conjoin(a, b):
    if a is None or b is None:
        return a if b is None else b
    return ("and", a, b)


def disjoin(a, b):
    if a is None or b is None:
        return None
    return ("or", a, b)


def glsl(cond, input_values, memo=None):
    """GLSL text of a condition (None stays None); input_values(node id) -> {input name: GLSL expression}.

    memo: a dict for the text of each condition tuple written, by identity (a plan's conditions share their
    parents' tuples): for one input_values, while the conditions it holds are alive (ClosurePlan keeps them)."""
    if cond is None or isinstance(cond, str):
        return cond
    if memo is not None:
        text = memo.get(id(cond))
        if text is not None:
            return text
    if cond[0] == "edge":
        text = cond[2].format(**input_values(cond[1]))
    else:
        a, b = glsl(cond[1], input_values, memo), glsl(cond[2], input_values, memo)
        if cond[0] == "and":        # && binds tighter than ||: a disjunction inside a conjunction is bracketed
            text = "%s && %s" % tuple("(%s)" % s if "||" in s else s for s in (a, b))
        else:
            text = "(%s) || (%s)" % (a, b)
    if memo is not None:
        memo[id(cond)] = text
    return text


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

    def _plan(self, root):
        order, seen, stack = [], {root}, [(root, iter(self._closure_inputs(root)))]
        while stack:                    # post-order, iterative: a chain of any length takes no Python stack
            node_id, children = stack[-1]
            child = next((c for c in children if c not in seen), None)
            if child is None:
                stack.pop()
                order.append(node_id)
            else:
                seen.add(child)
                stack.append((child, iter(self._closure_inputs(child))))
        conds = {root: None}
        for node_id in reversed(order):            # parents before children
            node = self.nodes[node_id]
            for name, s in node.inputs.items():
                if s.node not in self.nodes:
                    continue
                edge = EDGE_CONDITIONS.get((node.category, name))
                use = conjoin(conds.get(node_id), ("edge", node_id, edge) if edge is not None else None)
                conds[s.node] = use if s.node not in conds else disjoin(conds[s.node], use)
        return conds

    def _closure_inputs(self, node_id):
        return [s.node for s in self.nodes[node_id].inputs.values() if s.node in self.nodes]
