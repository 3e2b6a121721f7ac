"""graphwalk.py: reachability, pruning and dependency order over a graph's nodes, each written once."""
import pytest

from mtlxgen.graph import graphwalk
from mtlxgen.graph.graphtypes import GNode, Source


def _node(ident, *reads):
    """A node reading the nodes `reads` (in input order) and one literal."""
    inputs = {"in%d" % k: Source("float", node=r, output="out") for k, r in enumerate(reads)}
    inputs["lit"] = Source("float", value=0.5)
    return GNode(ident, "add", None, inputs, {"out": "float"}, None)


@pytest.fixture
def diamond():
    #   r -> a -> c
    #   r -> b -> c, d          (x reads c but nothing reads x)
    nodes = [_node("c"), _node("d"), _node("a", "c"), _node("b", "c", "d"), _node("r", "a", "b"), _node("x", "c")]
    return nodes, {n.id: n for n in nodes}


def test_upstream_follows_every_input_and_takes_sources_or_ids(diamond):
    nodes, by_id = diamond
    assert graphwalk.upstream(by_id, [Source("float", node="r", output="out")]) == {"r", "a", "b", "c", "d"}
    assert graphwalk.upstream(by_id, ["b"]) == {"b", "c", "d"}
    assert graphwalk.upstream(by_id, [Source("float", value=1.0), None]) == set()
    assert graphwalk.upstream(by_id, ["a", "x"]) == {"a", "c", "x"}


def test_upstream_skips_one_edge_and_ids_outside_the_table(diamond):
    nodes, by_id = diamond
    assert graphwalk.upstream(by_id, ["r"], skip=("r", "in1")) == {"r", "a", "c"}
    part = {k: v for k, v in by_id.items() if k != "c"}          # a walk kept to a part of the graph
    assert graphwalk.upstream(part, ["r"]) == {"r", "a", "b", "d"}


def test_prune_keeps_the_list_order(diamond):
    nodes, _ = diamond
    assert [n.id for n in graphwalk.prune(nodes, [Source("float", node="b", output="out")])] == ["c", "d", "b"]
    assert [n.id for n in graphwalk.prune(nodes, ["r"], skip=("b", "in0"))] == ["c", "d", "a", "b", "r"]
    assert graphwalk.prune(nodes, []) == []


def test_postorder_lists_each_node_after_what_it_reads(diamond):
    _, by_id = diamond
    order = graphwalk.postorder(by_id, ["r"])
    assert order == ["c", "a", "d", "b", "r"]        # depth first, inputs in their order
    for ident in order:
        for s in by_id[ident].inputs.values():
            if s.node is not None:
                assert order.index(s.node) < order.index(ident)
    assert graphwalk.postorder(by_id, ["a", "r"]) == ["c", "a", "d", "b", "r"]     # a node once
    assert graphwalk.postorder(by_id, ["r"], skip=("r", "in0")) == ["c", "d", "b", "r"]


def test_a_long_chain_takes_no_python_stack():
    n = 50000
    nodes = [_node("n0")] + [_node("n%d" % k, "n%d" % (k - 1)) for k in range(1, n)]
    by_id = {x.id: x for x in nodes}
    assert len(graphwalk.upstream(by_id, ["n%d" % (n - 1)])) == n
    assert graphwalk.postorder(by_id, ["n%d" % (n - 1)])[:3] == ["n0", "n1", "n2"]
    assert len(graphwalk.prune(nodes, ["n10"])) == 11
