"""Kept emissions of kept expansions (issue 14): a library nodegraph implementation replayed by graph.py
(GraphBuilder.expansion) is emitted once per (expansion, emitter settings) and its text reused for later
materials with the same expansion.

What a run of an expansion's nodes emits differs between two materials of one expansion key only by
  - the names it takes (unique_identifier of stems made from the nodes' ids: the ids differ, and so may the names
    already taken in the shader),
  - the nodes' ids where a handler writes them,
  - the expressions of the outer node's inputs that are public uniforms or other nodes' outputs (a literal input's
    value is part of the expansion key).
The first time, the run is emitted as usual and then once more by a _Recorder: an emitter over copies of the
run's nodes whose ids, taken names and outer expressions are sentinels (plain GLSL identifiers, as the real ones
are, so every test on them goes the same way), logging what emission does besides writing text (the files
required, in order; the streams read; the stems names are taken from). Every recorded text becomes a
fieldtext.FieldText whose fields are exactly where the sentinels were written. A later material's run is instantiated: its
names taken by unique_identifier from the recorded stems with its own ids, in the recorded order, against its
own shader's names (so a collision is resolved as a fresh emission resolves it), the files required and streams
read replayed through the emitter, the variables, closure nodes, conditions and closure variables set.

A run is reused only where what its emission reads is what the key and the settings hold: the complete interface
(no reduce/fold: the nodes must be the builder's own objects), no displacement (no vertex emitter), every node of
the run emitted in the fragment stage and the run contiguous in the graph's order, no input or output of the
expansion of a closure type, every outer expression a plain name, the outer nodes not closure nodes and already
emitted, nodes whose implementations are templates or handlers known to read nothing else (_HANDLERS), no {{=x}}
of a public uniform, nothing that adds or drops a uniform, reads a texture, pastes a document's GLSL. The
recording must match the first real emission exactly (the whole emitter state compared), and the next
CHECKS - 1 uses are emitted in full and compared too; any difference, or any of the conditions failing while
recording, keeps the key from being reused (False), and a condition failing at a later use emits that run in full.
REUSE (module flag; MTLXGEN_EMIT_REUSE=0 in the environment) turns the reuse off.

What the argument rests on: emission's choices do not depend on the spelling of a name or of an outer expression
(templates paste them; the handlers allowed read ids only to make stems; the one test of a text, emit's
is_plain_name, answers the same for a sentinel and a real name as long as no template glues an identifier onto
an input's expression, which none does) and a run's emission reads no state from before it but the names taken,
the files required and the streams read (replayed through the emitter) and the outer inputs' variables.
"""
import copy
import os
import re

from .fieldtext import SEP, FieldText
from .graphtypes import is_plain_name, unique_identifier
from .stagewriter import StageWriter
from .template import CLOSURE_TYPES

REUSE = os.environ.get("MTLXGEN_EMIT_REUSE", "1") != "0"
CHECKS = 2              # uses of a recording emitted in full and compared (the first is the recording's own)

# runs, per process (tests read them): recorded and checked, checked again, instantiated, not recordable, refused
# by a check (the recording did not give what the full emission gave)
STATS = {"recorded": 0, "checked": 0, "reused": 0, "unkept": 0, "refused": 0}

_SENTINEL = re.compile(r"QZ([nieo])(\d+)\1ZQ")


def _handlers():
    from .nodes import handlers, pbrlib_shading
    # handlers that read only their node's inputs through the emitter's services, its static strings and id
    return {pbrlib_shading.surface, handlers.geometric, handlers.transform_space}


_HANDLERS = None


def _settings(em):
    return (em.environment, em.target.name, em.max_lights, em.compact)


def _outer_exprs(em, run, names):
    """The GLSL expressions of the outer inputs `names` in `em`, or None where one cannot be reused."""
    out = []
    for name in names:
        s = run.inputs[name]
        if s.node is not None:
            if s.node in em.closure_nodes:
                return None
            e = em.vars.get((s.node, s.output))
        else:
            e = s.uniform
        if e is None or not is_plain_name(e):
            return None
        out.append(e)
    return out


def emit_run(em, run, fragment_ids):
    """Emit the run's nodes into `em`: from the kept recording where it can be, else in full. Returns False where
    the caller must emit them itself (nothing done)."""
    if not REUSE or getattr(em.graph, "static_guards", False) or em.writer.depth != 1 or em.context is not None:
        return False
    nodes = em.graph.nodes
    for k, node in enumerate(run.nodes):
        if nodes[run.start + k] is not node or node.id not in fragment_ids:
            return False
    key = _settings(em)
    rec = run.template.emitted.get(key)
    if rec is False:
        return False
    if rec is None:
        if len(run.template.emitted) >= 16:
            run.template.emitted.clear()
        run.template.emitted[key] = False          # (until recorded and checked)
        snap = _snapshot(em)
        for node in run.nodes:
            em.emit_node(node)
        rec = _record(em, run)
        if rec is None:
            STATS["unkept"] += 1
        elif _check(em, snap, rec, run):
            run.template.emitted[key] = rec
            STATS["recorded"] += 1
        else:
            STATS["refused"] += 1
        return True
    exprs = _outer_exprs(em, run, rec.outer)
    if exprs is None or not _streams_agree(em, rec):
        return False
    if rec.checks < CHECKS:
        snap = _snapshot(em)
        for node in run.nodes:
            em.emit_node(node)
        rec.checks += 1
        STATS["checked"] += 1
        if not _check(em, snap, rec, run):
            run.template.emitted[key] = False
            STATS["refused"] += 1
        return True
    _instantiate(em, rec, run, exprs)
    STATS["reused"] += 1
    return True


class _Recording:
    __slots__ = ("outer", "n_names", "stems", "texts", "requires", "streams", "app_uniforms", "n_lines", "vars",
                 "closure_nodes", "conditions", "closure_vars", "blocks", "uses_closures", "checks")


def _streams_agree(em, rec):
    for name, s in rec.streams:
        e = em.streams.get(name)
        if e is not None and e is not s and e != s:
            return False
    return True


def _record(em, run):
    """The _Recording of the run's emission (emitted again by a _Recorder), or None where it cannot be kept."""
    global _HANDLERS
    if _HANDLERS is None:
        _HANDLERS = _handlers()
    from . import nodes as nodes_
    template = run.template
    for name, ref in template.outputs:
        if ref[0] == "node" and ref[2].type in CLOSURE_TYPES:
            return None
    for s in run.inputs.values():
        if s.type in CLOSURE_TYPES:
            return None
    lib = em.graph.library
    for node in run.nodes:
        impl = nodes_.lookup(node.nodedef, lib)
        if impl is None or impl.external is not None or impl.source is not None:
            return None
        if impl.handler:
            from .nodes import handlers
            h = impl.handler if callable(impl.handler) else getattr(handlers, impl.handler, None)
            if h not in _HANDLERS:
                return None
    # the outer inputs the run reads that are not literals, each as a sentinel
    outer, sandbox_inputs, fake_vars = [], {}, {}
    from dataclasses import replace
    for name, s in run.inputs.items():
        if s.node is None and s.uniform is None:
            sandbox_inputs[name] = s
            continue
        m = len(outer)
        outer.append(name)
        sentinel = "QZe%deZQ" % m
        if s.node is not None:
            fake = "QZo%doZQ" % m
            sandbox_inputs[name] = replace(s, node=fake)
            fake_vars[(fake, s.output)] = sentinel
        else:
            sandbox_inputs[name] = replace(s, uniform=sentinel)
    sids = ["QZi%diZQ" % k for k in range(len(run.nodes))]
    sandbox, _ = template.make(sids, sandbox_inputs)
    g = copy.copy(em.graph)
    g.nodes, g.uniforms = sandbox, {}
    g.expansion_runs = {}
    r = _Recorder(type(em), g, em.environment, em.target.name, em.max_lights, em.compact)
    r.vars.update(fake_vars)
    try:
        for node in sandbox:
            r.emit_node(node)
    except Exception:
        return None
    if r.invalid or r.writer.depth != 1 or r.context is not None or r.external or r.document_code or r.textures \
            or r.primvars or r.graph.uniforms:
        return None
    index = {sid: k for k, sid in enumerate(sids)}
    n_names = len(r.stems)
    base = {"n": 0, "i": n_names, "e": n_names + len(sids)}
    limits = {"n": n_names, "i": len(sids), "e": len(outer)}
    bad = []

    def field(names_allowed):
        def at(m):
            """The index into _instantiate's values of sentinel match m (a bad sentinel noted, its field 0)."""
            kind, i = m.group(1), int(m.group(2))
            if kind == "o" or i >= limits[kind] or (kind == "n" and not names_allowed):
                bad.append(m.group(0))
            return base.get(kind, 0) + i
        return at

    def fields(texts, names_allowed=True):
        """`texts` as one FieldText (SEP between them): each sentinel a field of the values _instantiate fills."""
        if any(SEP in t for t in texts):
            bad.append(SEP)
        ft = FieldText(SEP.join(texts), _SENTINEL, field(names_allowed))
        if any("QZ" in p for p in ft.literals):     # a sentinel's part that is not one
            bad.append("QZ")
        return ft

    rec = _Recording()
    rec.outer, rec.n_names, rec.checks = outer, n_names, 1
    rec.stems = fields(r.stems, False)
    lines = r.body
    vars_ = [((index[nid], out), text) for (nid, out), text in r.vars.items() if nid in index]
    if len(vars_) + len(fake_vars) != len(r.vars):
        return None
    conds = [(index[nid], text) for nid, text in r.conditions.items()]
    cvars = [((block, index[nid], out), text) for (block, nid, out), text in r.closure_vars.items()]
    texts = list(lines) + [t for _, t in vars_] + [t for _, t in conds if t is not None] + [t for _, t in cvars]
    rec.texts = fields(texts)
    if bad:
        return None
    rec.n_lines = len(lines)
    rec.vars = [k for k, _ in vars_]
    rec.conditions = [(k, t is not None) for k, t in conds]
    rec.closure_vars = [k for k, _ in cvars]
    rec.requires = list(dict.fromkeys(r.required_calls))     # (a file required again is a no-op: once each)
    rec.streams = [(name, r.streams[name]) for name in r.streams]
    rec.app_uniforms = frozenset(r.app_uniforms)
    rec.closure_nodes = [(index[nid], r._closure_impls[nid]) for nid in r.closure_nodes]
    rec.blocks = r.block
    rec.uses_closures = r.uses_closures
    return rec


def _instantiate(em, rec, run, exprs):
    ids = run.ids
    n = rec.n_names
    values = ("",) * n + tuple(ids) + tuple(exprs)
    names = em.names
    taken = [unique_identifier(stem, names) for stem in rec.stems.fill(values).split(SEP)] if n else []
    values = tuple(taken) + values[n:]
    texts = rec.texts.fill(values).split(SEP)
    for rel in rec.requires:
        em.require(rel)
    em.app_uniforms |= rec.app_uniforms
    streams = em.streams
    for name, s in rec.streams:
        if name not in streams:
            streams[name] = s
    nl = rec.n_lines
    em.body.extend(texts[:nl])
    i = nl
    vars_ = em.vars
    for k, out in rec.vars:
        vars_[(ids[k], out)] = texts[i]
        i += 1
    nodes = run.nodes
    for k, impl in rec.closure_nodes:
        em.closure_nodes[ids[k]] = nodes[k]
        em._closure_impls[ids[k]] = impl
    conditions = em.conditions
    for k, has in rec.conditions:
        if has:
            conditions[ids[k]] = texts[i]
            i += 1
        else:
            conditions[ids[k]] = None
    b0 = em.block
    closure_vars = em.closure_vars
    for block, k, out in rec.closure_vars:
        closure_vars[(b0 + block, ids[k], out)] = texts[i]
        i += 1
    em.block = b0 + rec.blocks
    if rec.uses_closures:
        em.uses_closures = True
    em.current = nodes[-1] if nodes else em.current


# ---------------------------------------------------------------- the recorder and the check

def _make_recorder(Emitter):
    """A recording emitter over the emitter class `Emitter` (handed in, not imported: emit imports this module)."""

    class Recorder(Emitter):
        def __init__(self, *args):
            super().__init__(*args)
            self.stems, self.required_calls, self.invalid, self._depth = [], [], False, 0

        def fresh(self, stem):
            self.stems.append(stem)
            return "QZn%dnZQ" % (len(self.stems) - 1)

        def require(self, rel):
            if self._depth == 0:
                self.required_calls.append(rel)
            self._depth += 1
            try:
                super().require(rel)
            finally:
                self._depth -= 1

        def static(self, node, name):
            src = node.inputs.get(name)
            if src is not None and src.uniform is not None:
                self.invalid = True
            return super().static(node, name)

        def uniform(self, name):
            self.invalid = True
            return super().uniform(name)

        def add_uniform(self, *args, **kw):
            self.invalid = True
            return super().add_uniform(*args, **kw)

        def drop_unread_uniform(self, *args):
            self.invalid = True

        def external_call(self, *args):
            self.invalid = True
            return super().external_call(*args)

        def note_document_code(self, *args):
            self.invalid = True

    return Recorder


_RECORDERS = {}         # emitter class -> its recording subclass


def _Recorder(base, *args):
    cls = _RECORDERS.get(base)
    if cls is None:
        cls = _RECORDERS[base] = _make_recorder(base)
    return cls(*args)


_STATE = ("names", "files", "_required", "app_uniforms", "streams", "vars", "closure_nodes", "_closure_impls",
          "conditions", "closure_vars", "block", "uses_closures", "textures", "primvars", "external", "document_code",
          "context")


def _snapshot(em):
    snap = {}
    for a in _STATE:
        v = getattr(em, a)
        snap[a] = copy.copy(v)
    snap["lines"] = list(em.body)
    snap["depth"] = em.writer.depth
    snap["uniforms"] = dict(em.graph.uniforms)
    return snap


def _check(em, snap, rec, run):
    """Whether the recording instantiated on the state before the run (`snap`) gives exactly the state the full
    emission left in `em`."""
    if dict(em.graph.uniforms) != snap["uniforms"] or em.textures != snap["textures"] or \
            em.primvars != snap["primvars"] or em.external != snap["external"] or \
            em.document_code != snap["document_code"]:
        return False
    t = copy.copy(em)
    for a in _STATE:
        setattr(t, a, copy.copy(snap[a]))
    t.writer = StageWriter(snap["depth"])
    t.writer.lines = list(snap["lines"])
    t.body = t.writer.lines
    exprs = _outer_exprs(t, run, rec.outer)
    if exprs is None or not _streams_agree(t, rec):
        return False
    _instantiate(t, rec, run, exprs)
    for a in _STATE:
        x, y = getattr(t, a), getattr(em, a)
        if isinstance(x, dict):
            if list(x.items()) != list(y.items()):
                return False
        elif x != y:
            return False
    return t.body == em.body and t.writer.depth == em.writer.depth and t.current is em.current
