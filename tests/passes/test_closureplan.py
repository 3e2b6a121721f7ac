"""closureplan.py: closure guards are data, decided on the literal inputs they compare (decide), never by reading
GLSL text back; the zero-weight rule is one condition (weighed) with one threshold (ZERO_WEIGHT)."""
import itertools
import random

import pytest

from util import write_doc

from mtlxgen.passes import closureplan, reduce
from mtlxgen import pipeline
from mtlxgen.passes.closureplan import UNKNOWN, compare, conjoin, decide, disjoin, glsl, weighed


def _values(table):
    """literal_value over {(node, input): value}; UNKNOWN for what the table does not hold."""
    return lambda node_id, name: table.get((node_id, name), UNKNOWN)


def test_a_comparison_of_a_literal_is_decided_and_of_anything_else_kept():
    lit = _values({("m", "mix"): 0.0, ("b", "weight"): 0.5, ("z", "weight"): 0.0, ("i", "n"): 3})
    assert decide(compare("m", "mix", "!=", 0.0), lit) is False
    assert decide(compare("m", "mix", "!=", 1.0), lit) is True
    assert decide(weighed("b"), lit) is True
    assert decide(weighed("z"), lit) is False
    assert decide(compare("i", "n", ">", 2.0), lit) is True and decide(compare("i", "n", "<=", 2.0), lit) is False
    kept = compare("k", "mix", "!=", 0.0)
    assert decide(kept, lit) is kept                   # a uniform or a connection: the same condition
    assert decide(None, lit) is True                   # None is always
    assert decide("x > 0.0", lit) == "x > 0.0"         # text is never read back


def test_a_weight_just_under_the_threshold_is_decided_as_the_gpu_would():
    w = closureplan.ZERO_WEIGHT
    below = w * (1.0 - 2 ** -52)
    assert decide(weighed("b"), _values({("b", "weight"): w})) is True
    assert decide(weighed("b"), _values({("b", "weight"): below})) is False
    assert glsl(weighed("b"), lambda node_id: {"weight": "b_weight"}) == "b_weight >= 1.0e-6"   # the emitter's text


def test_decided_terms_drop_out_of_conjunctions_and_disjunctions():
    lit = _values({("m", "mix"): 0.5, ("n", "mix"): 1.0, ("b", "weight"): 1.0})
    x, y = compare("k", "mix", "!=", 0.0), compare("j", "mix", "!=", 1.0)
    assert decide(conjoin(x, weighed("b")), lit) is x                               # x && true
    assert decide(conjoin(x, compare("n", "mix", "!=", 1.0)), lit) is False         # x && false
    assert decide(disjoin(compare("n", "mix", "!=", 1.0), y), lit) is y              # false || y
    assert decide(disjoin(x, compare("m", "mix", "!=", 0.0)), lit) is True           # x || true
    both = disjoin(conjoin(x, weighed("b")), conjoin(y, weighed("c")))
    assert decide(both, lit) == ("or", x, conjoin(y, weighed("c")))
    assert glsl(decide(both, lit), lambda node_id: {"mix": node_id + "_mix", "weight": node_id + "_weight"}) \
        == "(k_mix != 0.0) || (j_mix != 1.0 && c_weight >= 1.0e-6)"
    undecided = conjoin(x, y)
    assert decide(undecided, lit) is undecided                  # nothing decided: the same tuple


def test_conjoin_and_disjoin_take_decisions():
    x = compare("k", "mix", "!=", 0.0)
    assert conjoin(True, x) is x and conjoin(x, None) is x and conjoin(False, x) is False
    assert disjoin(False, x) is x and disjoin(x, True) is None and disjoin(None, x) is None
    assert glsl(False, None) is False and glsl(True, None) is None and glsl(None, None) is None
    with pytest.raises(ValueError):
        compare("k", "mix", "=>", 0.0)


def _evaluate(cond, values):
    """A condition's truth under {(node, input): value} holding every input it compares."""
    if cond is None or cond is True or cond is False:
        return cond is not False
    if cond[0] == "cmp":
        _, node_id, name, op, c = cond
        return {"!=": lambda a: a != c, ">=": lambda a: a >= c, "==": lambda a: a == c, "<": lambda a: a < c}[op](
            values[(node_id, name)])
    a, b = _evaluate(cond[1], values), _evaluate(cond[2], values)
    return (a and b) if cond[0] == "and" else (a or b)


def _random_condition(rng, leaves, depth):
    if depth == 0 or rng.random() < 0.3:
        return rng.choice(leaves)
    a, b = _random_condition(rng, leaves, depth - 1), _random_condition(rng, leaves, depth - 1)
    return conjoin(a, b) if rng.random() < 0.5 else disjoin(a, b)


def test_a_decision_agrees_with_the_condition_for_every_value_of_what_stays_unknown():
    rng = random.Random(7)
    inputs = [("a", "mix"), ("b", "mix"), ("c", "weight"), ("d", "weight")]
    leaves = [compare(n, i, op, c) for (n, i), op, c in itertools.product(
        inputs, ("!=", ">=", "==", "<"), (0.0, 1.0, closureplan.ZERO_WEIGHT))]
    samples = [0.0, 1.0, 0.5, closureplan.ZERO_WEIGHT, -0.25, 2.0]
    for _ in range(300):
        cond = _random_condition(rng, leaves, 4)
        known = {k: rng.choice(samples) for k in inputs if rng.random() < 0.5}
        memo = {}
        out = decide(cond, _values(known), memo)
        assert decide(cond, _values(known), memo) is out            # the memo answers the same
        for rest in itertools.product(samples, repeat=len(inputs) - len(known)):
            values = dict(known)
            values.update(zip([k for k in inputs if k not in known], rest))
            assert _evaluate(out, values) == _evaluate(cond, values), (cond, known, out)
        if out is not True and out is not False:
            leftover = {(c[1], c[2]) for c in _leaves(out)}
            assert not leftover & set(known), (cond, known, out)       # no literal left in what remains


def _leaves(cond):
    if cond[0] == "cmp":
        return [cond]
    return _leaves(cond[1]) + _leaves(cond[2])


MIX = ('<oren_nayar_diffuse_bsdf name="a" type="BSDF"><input name="weight" type="float" value="%s" />'
       '</oren_nayar_diffuse_bsdf><dielectric_bsdf name="b" type="BSDF" /><mix name="m" type="BSDF">'
       '<input name="fg" type="BSDF" nodename="a" /><input name="bg" type="BSDF" nodename="b" />'
       '<input name="mix" type="float" value="%s" /></mix>'
       '<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="m" /></surface>'
       '<output name="o" type="surfaceshader" nodename="s" />')


@pytest.mark.parametrize("weight, factor", [("0.5", "0.25"), ("0", "0.25"), ("1", "1")])
def test_the_plan_of_a_reduced_graph_reads_its_literals(tmp_path, weight, factor):
    session = pipeline.Session(write_doc(tmp_path, MIX % (weight, factor)))
    g = session.graph("o")
    complete = closureplan.ClosurePlan(g)
    mix = next(n.id for n in g.nodes if n.category == "mix")
    a = next(n.id for n in g.nodes if n.category == "oren_nayar_diffuse_bsdf")
    # the complete interface: every input a uniform, nothing decided
    assert complete.literal_value(mix, "mix") is UNKNOWN and complete.literal_value(a, "weight") is UNKNOWN
    cond = conjoin(complete.conditions(mix)[a], weighed(a))
    assert decide(cond, complete.literal_value) is cond
    # the reduced interface: the factor and the weight are literals, the lobe's guard is decided
    r = closureplan.ClosurePlan(reduce.reduce(g, reduce.Interface("reduced"))[0])
    assert r.literal_value(mix, "mix") == float(factor) and r.literal_value(a, "weight") == float(weight)
    assert r.literal_value(mix, "fg") is UNKNOWN                 # a closure input is no number
    assert decide(conjoin(r.conditions(mix)[a], weighed(a)), r.literal_value) is (
        float(factor) != 0.0 and float(weight) >= closureplan.ZERO_WEIGHT)
    # keeping the factor editable keeps its comparison
    kept = reduce.Interface("reduced", [(g.nodes[[n.id for n in g.nodes].index(mix)].inputs["mix"].uniform, None)])
    k = closureplan.ClosurePlan(reduce.reduce(g, kept)[0])
    assert decide(k.conditions(mix)[a], k.literal_value) == compare(mix, "mix", "!=", 0.0)
