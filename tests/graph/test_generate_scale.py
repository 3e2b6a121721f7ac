"""Large graphs generate, whole and in order (issue 14): a chain, a fan-in (an add tree over many leaves) and a
fan-out (one node read by many, their results summed by an add tree), of 10,000 nodes always and of 100,000
where MTLXGEN_SCALE=1 (about a minute on one core). Correctness only: no time is asserted here; time against
size, ours and MaterialX's, is benchmarks/bench_scale.py's."""
import os
import re

import pytest

from mtlxgen import pipeline
from util import write_doc

SIZES = [10_000] + ([100_000] if os.environ.get("MTLXGEN_SCALE") == "1" else [])


def add(name, a, b):
    """An add node: a and b are node names (connected) or numbers (values)."""
    def port(p, v):
        src = 'nodename="%s"' % v if isinstance(v, str) else 'value="%g"' % v
        return '<input name="%s" type="float" %s />' % (p, src)
    return '<add name="%s" type="float">%s%s</add>' % (name, port("in1", a), port("in2", b))


def tree(leaves, lines, prefix="t"):
    """Add nodes summing `leaves` (node names) pairwise, level by level; returns the root's name."""
    level, k = list(leaves), 0
    while len(level) > 1:
        nxt = []
        for i in range(0, len(level) - 1, 2):
            name = "%s%d" % (prefix, k)
            k += 1
            lines.append(add(name, level[i], level[i + 1]))
            nxt.append(name)
        if len(level) % 2:
            nxt.append(level[-1])
        level = nxt
    return level[0]


def chain(n):
    lines = [add("n0", 0.5, 0.25)] + [add("n%d" % i, "n%d" % (i - 1), 0.001) for i in range(1, n)]
    return lines, "n%d" % (n - 1)


def fan_in(n):
    leaves = n // 2
    lines = [add("l%d" % i, i % 7, 1) for i in range(leaves)]
    return lines, tree(["l%d" % i for i in range(leaves)], lines)


def fan_out(n):
    readers = n // 2
    lines = [add("src", 0.5, 0.25)]
    lines += ['<multiply name="r%d" type="float"><input name="in1" type="float" nodename="src" />'
              '<input name="in2" type="float" value="%d" /></multiply>' % (i, i % 5) for i in range(readers)]
    return lines, tree(["r%d" % i for i in range(readers)], lines)


def generate(tmp_path, shape, n):
    lines, root = shape(n)
    path = write_doc(tmp_path, "\n".join(lines + ['<output name="out" type="float" nodename="%s" />' % root]))
    shader, = pipeline.generate(path)
    assigned = dict(re.findall(r"^\s*float (\w+)_out = (.+);$", shader.fragment, flags=re.M))
    return lines, root, shader, assigned


def operands(expr):
    return re.findall(r"\b(\w+)_out\b", expr)


@pytest.mark.parametrize("n", SIZES)
def test_chain_generates_every_link_in_order(tmp_path, n):
    _, root, shader, assigned = generate(tmp_path, chain, n)
    assert len(assigned) == n
    assert list(assigned)[0] == "n0" and list(assigned)[-1] == root
    for i in range(1, n):
        assert operands(assigned["n%d" % i]) == ["n%d" % (i - 1)]
    assert "n%d_out" % (n - 1) in shader.fragment.split("out_color", 1)[1]


@pytest.mark.parametrize("n", SIZES)
def test_fan_in_tree_generates_every_node_once_after_its_inputs(tmp_path, n):
    lines, root, shader, assigned = generate(tmp_path, fan_in, n)
    assert len(assigned) == len(lines)
    order = {name: k for k, name in enumerate(assigned)}
    for name, expr in assigned.items():
        ops = operands(expr)
        assert len(ops) == (2 if name.startswith("t") else 0)
        assert all(order[o] < order[name] for o in ops)
    assert list(assigned)[-1] == root


@pytest.mark.parametrize("n", SIZES)
def test_fan_out_reads_one_node_from_many(tmp_path, n):
    lines, root, shader, assigned = generate(tmp_path, fan_out, n)
    assert len(assigned) == len(lines)
    readers = [name for name in assigned if name.startswith("r")]
    assert len(readers) == n // 2 and all(operands(assigned[r]) == ["src"] for r in readers)
    assert list(assigned)[0] == "src" and list(assigned)[-1] == root
