"""The template expander: a node implementation's inline template (nodes/__init__.py) to a GLSL expression.

    {{in1}}        the GLSL expression of input in1 (a closure input: its value in the current context)
    {{=index}}     the compile-time value of an unconnected input (a string one as an identifier)
    {{@name}}      a geometric stream (streams.py)
    {{$type}}      the GLSL type of the output; {{$type:in1}} that of an input

Expansion reads values through the emitter's services (expr, static, stream, glsl_type, closure, require,
fail) and writes nothing itself.
"""
from mtlxgen.base import mxtypes
from mtlxgen.base.identifiers import glsl_identifier

from mtlxgen.base.mxtypes import CLOSURE_TYPES  # noqa: E402 (template.CLOSURE_TYPES for the emitter)

# closure contexts in which a BSDF shades with its normal turned towards the viewer
FACING_CONTEXTS = ("reflection", "indirect", "transmission")


class Unterminated(Exception):
    pass


def tokens(template):
    """(is_field, text) of a template, left to right; raises Unterminated where a `{{` is not closed (after
    the tokens before it)."""
    i = 0
    while True:
        j = template.find("{{", i)
        if j < 0:
            yield False, template[i:]
            return
        k = template.find("}}", j)
        if k < 0:
            raise Unterminated()
        yield False, template[i:j]
        yield True, template[j + 2:k].strip()
        i = k + 2


# parsed templates: template text -> ([(kind, text)], unterminated); kind None for literal text, else the field's
# kind (_kind). A node table has a few hundred templates, each parsed once per process, not once per node emitted.
_PARSED = {}
_PARSED_MAX = 20000         # templates of documents' own implementations too: bounded, cleared when full


def _kind(f):
    """The kind of field `f`, as field() tests them, in its order."""
    if f.startswith("="):
        return "="
    if f.startswith("@"):
        return "@"
    if f == "$type":
        return "$type"
    if f.startswith("$type:"):
        return "$type:"
    return "input"


def parse(template):
    """([(kind, text)], whether a `{{` is left unclosed after those tokens) of a template, cached."""
    parsed = _PARSED.get(template)
    if parsed is None:
        toks, unterminated = [], False
        try:
            for is_field, text in tokens(template):
                if is_field:
                    toks.append((_kind(text), text))
                elif text:                  # empty literal text adds nothing
                    toks.append((None, text))
        except Unterminated:
            unterminated = True
        if len(_PARSED) >= _PARSED_MAX:
            _PARSED.clear()
        parsed = _PARSED[template] = (toks, unterminated)
    return parsed


def render(em, template, node, out_type):
    """The template of `node` (whose output has type `out_type`) expanded through emitter `em`."""
    toks, unterminated = parse(template)
    inputs = node.inputs
    values, closure_nodes = em.vars, em.closure_nodes
    out = []
    for kind, text in toks:
        if kind is None:
            out.append(text)
        elif kind == "input" and text in inputs:
            src = inputs[text]
            # the common case first: another node's (not a closure node's) output, as em.expr reads it (a normal
            # may be turned towards the viewer: _input)
            if src.node is not None:
                if text != "normal" and src.node not in closure_nodes:
                    out.append(values[(src.node, src.output)])
                else:
                    out.append(_input(em, text, src, node))
            elif src.uniform and text != "normal" and src.type != "string" and src.type != "geomname":
                out.append(src.uniform)             # a public uniform, as em.expr reads it
            else:
                out.append(_input(em, text, src, node))
        else:
            out.append(field(em, text, node, out_type))
    if unterminated:
        em.fail(node, "unterminated '{{' in implementation template")
    return "".join(out)


def _input(em, f, src, node):
    """The GLSL text of field `f` naming input `f` of `node`, whose Source is `src`."""
    t = src.type
    if t in ("string", "geomname") and src.node is None:
        em.fail(node, "string input '%s' cannot be used as a GLSL value" % f)
    if t in CLOSURE_TYPES and src.node in em.closure_nodes:
        return em.closure(src, em.context or "indirect")
    if f == "normal" and t == "vector3" and em.context in FACING_CONTEXTS \
            and "BSDF" in node.outputs.values():
        # a BSDF shades with its normal turned towards the viewer: a normal-mapped or authored
        # normal facing away would light the surface from behind (as MaterialX's BSDFs do)
        em.require("pbrlib/forward_facing.glsl")
        return "mg_forward_facing(%s, mg_V)" % em.expr(src)
    return em.expr(src)


def field(em, f, node, out_type):
    """The GLSL text of one template field."""
    if f.startswith("="):
        value = em.static(node, f[1:])
        t = node.inputs[f[1:]].type
        if t in ("string", "filename", "geomname"):
            return glsl_identifier(str(value))
        try:
            return mxtypes.glsl_literal(t, value, em.graph.structs)
        except mxtypes.ValueError_ as e:
            em.fail(node, "input '%s': %s" % (f[1:], e))
    if f.startswith("@"):
        return em.stream(f[1:], node=node)
    if f == "$type":
        return em.glsl_type(out_type)
    if f.startswith("$type:"):
        if f[6:] not in node.inputs:
            em.fail(node, "implementation template names '%s', which is not an input" % f[6:])
        return em.glsl_type(node.inputs[f[6:]].type)
    if f in node.inputs:
        return _input(em, f, node.inputs[f], node)
    em.fail(node, "implementation template names '%s', which is not an input" % f)
