"""The emitter's parts on their own: the stage writer, the template tokenizer, closure planning."""
import pytest

from util import write_doc

from mtlxgen.passes import closureplan
from mtlxgen.emit import emitter as emit
from mtlxgen import pipeline
from mtlxgen.emit.stagewriter import StageWriter
from mtlxgen.emit.template import Unterminated, tokens


def test_the_writer_indents_scopes_and_single_statements():
    w = StageWriter()
    w.line("int a = 0;")
    w.open_scope("a */ comment\nwith a break")
    w.line("if (a > 0)")
    with w.indented():
        w.line("a = 1;")
    w.close_scope()
    assert w.lines == ["    int a = 0;", "    // a *? comment?with a break", "    {", "        if (a > 0)",
                       "            a = 1;", "    }"]
    assert w.depth == 1


def test_template_tokens_left_to_right_and_unterminated():
    assert list(tokens("f({{ in1 }}, {{=n}})")) == [(False, "f("), (True, "in1"), (False, ", "), (True, "=n"),
                                                    (False, ")")]
    seen = []
    with pytest.raises(Unterminated):
        for t in tokens("{{a}} + {{b"):
            seen.append(t)
    assert seen == [(False, ""), (True, "a")]


def test_an_unterminated_template_is_a_located_error(tmp_path):
    body = ('<nodedef name="ND_t" node="t"><input name="x" type="float" value="1" /><output name="out" type="float" />'
            '</nodedef><implementation name="IM_t" nodedef="ND_t" target="genglsl" sourcecode="{{x} * 2.0" />'
            '<t name="n" type="float" /><output name="o" type="float" nodename="n" />')
    shaders, error = pipeline.generate(write_doc(tmp_path, body), partial=True)
    assert not shaders and error is not None
    assert any("unterminated" in line or "{{" in line for line in error.lines()), error.lines()


MIX = ('<oren_nayar_diffuse_bsdf name="a" type="BSDF" /><oren_nayar_diffuse_bsdf name="b" type="BSDF" />'
       '<mix name="m" type="BSDF"><input name="fg" type="BSDF" nodename="a" /><input name="bg" type="BSDF" nodename="b" />'
       '<input name="mix" type="float" value="0.25" /></mix>'
       '<surface name="s" type="surfaceshader"><input name="bsdf" type="BSDF" nodename="m" /></surface>'
       '<output name="o" type="surfaceshader" nodename="s" />')


def test_closure_planning_is_plain_data_over_the_graph(tmp_path):
    g = pipeline.Session(write_doc(tmp_path, MIX)).graph("o")
    plan = closureplan.ClosurePlan(g)
    mix = next(n.id for n in g.nodes if n.category == "mix")
    a, b = (next(n.id for n in g.nodes if n.id.startswith(x) and n.category != "mix") for x in "ab")
    conds = plan.conditions(mix)
    assert conds == {mix: None, a: ("cmp", mix, "mix", "!=", 0.0), b: ("cmp", mix, "mix", "!=", 1.0)}
    assert closureplan.glsl(conds[a], lambda node_id: {"mix": "k"}) == "k != 0.0"
    assert closureplan.glsl(closureplan.disjoin(conds[a], closureplan.conjoin(conds[b], "w")),
                            lambda node_id: {"mix": "k"}) == "(k != 0.0) || (k != 1.0 && w)"
    factor = next(n for n in g.nodes if n.id == mix).inputs["mix"].uniform     # a public uniform at document level
    frag = emit.emit(g).fragment
    # a lobe that does not sample the environment (a diffuse one) is computed unguarded (the emitter's guard
    # policy), then made the empty closure where its weight is below closureplan.ZERO_WEIGHT
    assert "%s != 0.0" % factor not in frag and "%s != 1.0" % factor not in frag
    assert "if (!(a_weight >= 1.0e-6))" in frag and "if (!(b_weight >= 1.0e-6))" in frag
    # one that samples it keeps its planned condition, and its weight, as the `if` that computes it
    sampled = MIX.replace("oren_nayar_diffuse_bsdf", "dielectric_bsdf")
    g = pipeline.Session(write_doc(tmp_path, sampled, name="sampled.mtlx")).graph("o")
    factor = next(n for n in g.nodes if n.category == "mix").inputs["mix"].uniform
    frag = emit.emit(g).fragment
    assert "if (%s != 0.0 && a_weight >= 1.0e-6)" % factor in frag
    assert "if (%s != 1.0 && b_weight >= 1.0e-6)" % factor in frag
    # a disjunction of uses, conjoined with a weight, keeps its brackets (&& binds tighter than ||)
    assert closureplan.glsl(closureplan.conjoin(closureplan.disjoin(conds[a], conds[b]), "w"),
                            lambda node_id: {"mix": "k"}) == "((k != 0.0) || (k != 1.0)) && w"


def test_closure_condition_memo_is_by_identity_and_per_input_values():
    # take_plan writes a plan's conditions with one memo: shared parents written once, the same text as without it
    edge_a, edge_b = closureplan.compare("m", "mix", "!=", 0.0), closureplan.compare("n", "mix", "!=", 1.0)
    parent = closureplan.conjoin(edge_a, "w")
    conds = [parent, closureplan.conjoin(parent, edge_b), closureplan.disjoin(closureplan.conjoin(parent, edge_b), edge_a)]
    values = {"m": {"mix": "k"}, "n": {"mix": "j"}}
    memo = {}
    with_memo = [closureplan.glsl(c, values.get, memo) for c in conds]
    assert with_memo == [closureplan.glsl(c, values.get) for c in conds]
    assert with_memo[1] == "k != 0.0 && w && j != 1.0"
    # an equal condition that is another tuple is written afresh; another emission's values take another memo
    other = tuple(list(edge_a))             # (a literal tuple equal to edge_a could be the same constant)
    assert other == edge_a and other is not edge_a
    assert closureplan.glsl(other, {"m": {"mix": "q"}}.get, memo) == "q != 0.0"
    assert closureplan.glsl(parent, {"m": {"mix": "q"}}.get, {}) == "q != 0.0 && w"


def test_interface_declarations_kept_per_names_target_and_lights():
    # emit keeps each set's declarations: every part of the key changes them, and a kept answer is a fresh one's
    base = {"u_envMatrix", "u_viewPosition"}
    cases = [(base, "glsl", 0), (base, "essl", 0), (base | {"u_lightData"}, "glsl", 0),
             (base | {"u_lightData"}, "glsl", 3), (frozenset(base | {"u_lightData"}), "glsl", 3)]
    seen = []
    for names, target, lights in cases * 2:
        lines = emit.interface_declarations(names, target, lights)
        assert lines == emit._interface_declarations(set(names), target, lights)
        lines.append("changed")                 # a caller's list is its own: the kept lines stay as they were
        seen.append(emit.interface_declarations(names, target, lights))
    assert len({tuple(s) for s in seen}) == 4   # glsl/essl, with and without the light record, 0 and 3 lights
    assert seen[2] != seen[3] and seen[0] != seen[1]
    # a list with a name twice is declared as it always was (not kept under its set)
    assert emit.interface_declarations(["u_envMatrix", "u_envMatrix"]) == emit._interface_declarations(
        ["u_envMatrix", "u_envMatrix"], "glsl", emit.interface.MAX_LIGHTS)
