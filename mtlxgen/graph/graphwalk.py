"""Walks over a graph's nodes, written once: what a set of roots depends on, the nodes kept for them, and an order
with every node after the nodes it reads.

Plain functions over the graph's data (graphtypes.GNode: `id` and `inputs`, {input name: Source}; a Source reads
node `node` where it is linked). `nodes_by_id` is {id: GNode}; an input linked to an id that is not in it is not
followed, so a walk can be kept to a part of a graph (closureplan.py: the closure nodes). Roots are Sources or node
ids (a Source not linked, or None, roots nothing). `skip` is one (node id, input name) edge not followed (the
fragment stage does not read a material's displacement).

Every walk uses an explicit stack: a chain of any length takes no Python stack.
"""


def _root_ids(roots):
    for r in roots:
        node = r if r is None or isinstance(r, str) else r.node
        if node is not None:
            yield node


def _linked(node, nodes_by_id, skip):
    """The ids `node` reads, in input order (an id once per input that reads it)."""
    for name, s in node.inputs.items():
        if s.node is not None and s.node in nodes_by_id and (skip is None or (node.id, name) != skip):
            yield s.node


def upstream(nodes_by_id, roots, skip=None):
    """The set of ids of the nodes the roots depend on, the roots' own nodes included."""
    seen = set()
    stack = [r for r in _root_ids(roots) if r in nodes_by_id]
    while stack:
        node_id = stack.pop()
        if node_id not in seen:
            seen.add(node_id)
            stack.extend(c for c in _linked(nodes_by_id[node_id], nodes_by_id, skip) if c not in seen)
    return seen


def prune(nodes, roots, skip=None):
    """The nodes (a list, in its order) that the roots depend on; the others dropped."""
    by_id = {n.id: n for n in nodes}
    needed = upstream(by_id, roots, skip)
    return [n for n in nodes if n.id in needed]


def postorder(nodes_by_id, roots, skip=None):
    """The ids of the nodes the roots depend on, each after every node it reads (dependencies first): a depth-first
    walk from each root in turn, a node's inputs taken in their order, a node listed when all it reads is."""
    order, seen = [], set()
    for root in _root_ids(roots):
        if root in seen or root not in nodes_by_id:
            continue
        seen.add(root)
        stack = [(root, _linked(nodes_by_id[root], nodes_by_id, skip))]
        while stack:
            node_id, children = stack[-1]
            child = next((c for c in children if c not in seen), None)
            if child is None:
                stack.pop()
                order.append(node_id)
            else:
                seen.add(child)
                stack.append((child, _linked(nodes_by_id[child], nodes_by_id, skip)))
    return order
