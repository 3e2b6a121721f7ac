"""Generation-time folding (issue 14): what the reduced interface made constant is computed here, not per pixel.

fold() is a graph pass: a Graph in, a new Graph out (the input is never changed). In dependency order, each node
  - whose inputs are all literals and whose category has an evaluator below (the stdlib math, colour, channel,
    conditional and compositing nodes, and cmlib's colour-space conversions) becomes a literal: its value computed
    with numpy by evaluate(), term for term what its GLSL template computes. A value GLSL leaves undefined (the
    power of a negative base, the square root or log of a negative, asin beyond 1, normalize of zero, a division by
    zero) or that no literal can carry (inf, nan) is not folded: the node stays and the GPU computes it as before;
  - that only selects one of its inputs by literals (ifgreater/ifgreatereq/ifequal on literal values, a mix whose
    factor is exactly 0 or 1) is replaced by the input it selects;
  - is a closure that the literals make empty or transparent is removed: a BSDF whose weight is below 1e-6 (the
    emitter's own rule: the empty closure), a uniform_edf of colour 0, a mix of closures by a factor at (or, for
    BSDFs and VDFs, which hold it to [0, 1], beyond) 0 or 1, a layer, add or multiply with an empty side. Every
    rewrite gives what the emitted GLSL would give: mg_layer(empty, b) = b, mg_mix_BSDF(f, b, 0) = b, ...
Nodes that are not foldable stay nodes; nodes no longer needed are dropped. The emitter then decides the closure
guards whose conditions are now literal (static_condition, reached through Graph.static_guards).

evaluate() is the one implementation of these nodes' values in Python: the tests compare it with the GLSL's pixels
(tests/test_fold.py) and reference.node_value is it.
"""
import math
import re
from dataclasses import replace

import numpy as np

from . import mxtypes
from .graph import Source

FLOAT_TYPES = ("float", "color3", "color4", "vector2", "vector3", "vector4")
VALUE_TYPES = FLOAT_TYPES + ("integer", "boolean")
BSDF_EPSILON = 1.0e-6           # emit.Emitter.closure: a BSDF of weight below this is the empty closure


class NotFoldable(Exception):
    """The node's value is left to the GPU (undefined in GLSL, not finite, or no evaluator)."""


# ---------------------------------------------------------------- values

def _size(t):
    return mxtypes.BUILTIN[t].size if t in mxtypes.BUILTIN else 0


def _arr(value):
    return np.asarray(value, dtype=np.float64)


def to_value(out_type, a):
    """A numpy result as the Python value a Source of `out_type` holds (float, int, bool or a tuple)."""
    a = np.asarray(a)
    if out_type == "boolean":
        return bool(a)
    if out_type == "integer":
        v = int(a)
        if not mxtypes.INT_MIN <= v <= mxtypes.INT_MAX:
            raise NotFoldable("integer out of range")
        return v
    flat = np.asarray(a, dtype=np.float64).reshape(-1)
    n = _size(out_type)
    if flat.size == 1 and n > 1:
        flat = np.repeat(flat, n)                 # GLSL's vecN(x): the scalar in every component
    if flat.size != n or not np.all(np.abs(flat) <= mxtypes.FLOAT_MAX):      # also nan
        raise NotFoldable("not a finite %s" % out_type)
    return float(flat[0]) if n == 1 else tuple(float(v) for v in flat)


def _need(cond, why):
    if not np.all(cond):
        raise NotFoldable(why)


# ---------------------------------------------------------------- evaluators
# Each takes ({input name: numpy value}, {input name: type}, output type) and returns a numpy value. They follow
# the templates of mtlxgen/nodes (and the glsl_lib functions those call) term for term.

def _divide(i, t, o):
    _need(i["in2"] != 0.0, "division by zero")
    if o == "integer":
        return np.trunc(i["in1"] / i["in2"])
    return i["in1"] / i["in2"]


def _modulo(i, t, o):
    _need(i["in2"] != 0.0, "modulo by zero")
    return i["in1"] - i["in2"] * np.floor(i["in1"] / i["in2"])        # GLSL mod()


def _power(i, t, o):
    x, y = np.broadcast_arrays(i["in1"], i["in2"])
    _need((x > 0.0) | ((x == 0.0) & (y > 0.0)), "pow of a negative base (undefined in GLSL)")
    return np.power(x, y)


def _round(i, t, o):
    x = i["in"]
    _need(np.abs(x - np.floor(x)) != 0.5, "round of a half (GLSL leaves the direction to the driver)")
    return np.round(x)


def _domain(f, ok, why):
    def fn(i, t, o):
        _need(ok(i["in"]), why)
        return f(i["in"])
    return fn


def _atan2(i, t, o):
    _need((i["iny"] != 0.0) | (i["inx"] != 0.0), "atan(0, 0) is undefined")
    return np.arctan2(i["iny"], i["inx"])


def _normalize(i, t, o):
    n = np.sqrt(np.sum(i["in"] * i["in"]))
    _need(n > 0.0, "normalize of a zero vector")
    return i["in"] / n


def _mix(i, t, o):
    return i["bg"] * (1.0 - i["mix"]) + i["fg"] * i["mix"]


def _remap(i, t, o):
    d = i["inhigh"] - i["inlow"]
    _need(d != 0.0, "remap of an empty range")
    return i["outlow"] + (i["in"] - i["inlow"]) * (i["outhigh"] - i["outlow"]) / d


def _smoothstep(i, t, o):
    x, lo, hi = i["in"], i["low"], i["high"]
    if x >= hi:
        return np.float64(1.0)
    if x <= lo:
        return np.float64(0.0)
    s = (x - lo) / (hi - lo)
    return s * s * (3.0 - 2.0 * s)


def _luminance(i, t, o):
    c = i["in"]
    y = np.dot(c[:3], i["lumacoeffs"])
    return np.array([y, y, y] + list(c[3:]))


def rgb_to_hsv(c):
    """glsl_lib/stdlib/adjustment/rgbtohsv.glsl, for a colour (alpha kept)."""
    r, g, b = (float(v) for v in c[:3])
    hi, lo = max(r, g, b), min(r, g, b)
    delta = hi - lo
    s = delta / hi if hi > 0.0 else 0.0
    h = 0.0
    if s > 0.0:
        if r >= hi:
            h = (g - b) / delta
        elif g >= hi:
            h = 2.0 + (b - r) / delta
        else:
            h = 4.0 + (r - g) / delta
        h /= 6.0
        if h < 0.0:
            h += 1.0
    return np.array([h, s, hi] + [float(v) for v in c[3:]])


def hsv_to_rgb(c):
    """glsl_lib/stdlib/adjustment/hsvtorgb.glsl, for a colour (alpha kept)."""
    x, s, v = (float(a) for a in c[:3])
    h = (x - math.floor(x)) * 6.0
    rest = [float(a) for a in c[3:]]
    if s <= 0.0:
        return np.array([v, v, v] + rest)
    sector = math.floor(h)
    f = h - sector
    p, q, t = v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f))
    rgb = ([v, t, p] if sector < 1 else [q, v, p] if sector < 2 else [p, v, t] if sector < 3 else
           [p, q, v] if sector < 4 else [t, p, v] if sector < 5 else [v, p, q])
    return np.array(rgb + rest)


def _extract(i, t, o):
    k = int(i["index"])
    _need(0 <= k < np.size(i["in"]), "extract index out of range")
    return np.asarray(i["in"]).reshape(-1)[k]


def _combine(*names):
    def fn(i, t, o):
        return np.concatenate([np.asarray(i[n]).reshape(-1) for n in names])
    return fn


def _convert(i, t, o):
    x = np.asarray(i["in"], dtype=np.float64).reshape(-1)
    n = _size(o)
    if o in ("integer", "boolean", "float"):
        if x.size != 1:
            raise NotFoldable("convert of a vector to a scalar")
        return np.trunc(x[0]) if o == "integer" else (x[0] != 0.0) if o == "boolean" else x[0]
    if x.size == 1:
        return np.repeat(x, n)
    _need(x.size >= n, "a vector widened needs more components than it has")
    return x[:n]


def _select(op):
    def fn(i, t, o):
        return i["in1"] if op(i["value1"], i["value2"]) else i["in2"]
    return fn


_CMP = {"ifgreater": lambda a, b: bool(a > b), "ifgreatereq": lambda a, b: bool(a >= b),
        "ifequal": lambda a, b: bool(a == b)}


def _blend(f):
    def fn(i, t, o):
        return i["bg"] * (1.0 - i["mix"]) + f(i["fg"], i["bg"]) * i["mix"]
    return fn


def _unpremult(i, t, o):
    c = i["in"]
    _need(c[3] != 0.0, "unpremult of zero alpha")
    return np.concatenate([c[:3] / c[3], c[3:]])


EVALUATORS = {
    "add": lambda i, t, o: i["in1"] + i["in2"],
    "subtract": lambda i, t, o: i["in1"] - i["in2"],
    "multiply": lambda i, t, o: i["in1"] * i["in2"],
    "divide": _divide,
    "modulo": _modulo,
    "fract": lambda i, t, o: i["in"] - np.floor(i["in"]),
    "invert": lambda i, t, o: i["amount"] - i["in"],
    "absval": lambda i, t, o: np.abs(i["in"]),
    "sign": lambda i, t, o: np.sign(i["in"]),
    "floor": lambda i, t, o: np.floor(i["in"]),
    "ceil": lambda i, t, o: np.ceil(i["in"]),
    "round": _round,
    "power": _power,
    "sin": lambda i, t, o: np.sin(i["in"]),
    "cos": lambda i, t, o: np.cos(i["in"]),
    "tan": lambda i, t, o: np.tan(i["in"]),
    "asin": _domain(np.arcsin, lambda x: np.abs(x) <= 1.0, "asin beyond [-1, 1]"),
    "acos": _domain(np.arccos, lambda x: np.abs(x) <= 1.0, "acos beyond [-1, 1]"),
    "atan2": _atan2,
    "sqrt": _domain(np.sqrt, lambda x: x >= 0.0, "sqrt of a negative"),
    "ln": _domain(np.log, lambda x: x > 0.0, "log of zero or a negative"),
    "exp": lambda i, t, o: np.exp(i["in"]),
    "clamp": lambda i, t, o: np.minimum(np.maximum(i["in"], i["low"]), i["high"]),
    "min": lambda i, t, o: np.minimum(i["in1"], i["in2"]),
    "max": lambda i, t, o: np.maximum(i["in1"], i["in2"]),
    "normalize": _normalize,
    "magnitude": lambda i, t, o: np.sqrt(np.sum(i["in"] * i["in"])),
    "dotproduct": lambda i, t, o: np.sum(i["in1"] * i["in2"]),
    "crossproduct": lambda i, t, o: np.cross(i["in1"], i["in2"]),
    "mincomponent": lambda i, t, o: np.min(i["in"]),
    "maxcomponent": lambda i, t, o: np.max(i["in"]),
    "mix": _mix,
    "remap": _remap,
    "smoothstep": _smoothstep,
    "luminance": _luminance,
    "rgbtohsv": lambda i, t, o: rgb_to_hsv(i["in"]),
    "hsvtorgb": lambda i, t, o: hsv_to_rgb(i["in"]),
    "dot": lambda i, t, o: i["in"],
    "constant": lambda i, t, o: i["value"],
    "extract": _extract,
    "combine2": _combine("in1", "in2"),
    "combine3": _combine("in1", "in2", "in3"),
    "combine4": _combine("in1", "in2", "in3", "in4"),
    "convert": _convert,
    "ifgreater": _select(_CMP["ifgreater"]),
    "ifgreatereq": _select(_CMP["ifgreatereq"]),
    "ifequal": _select(_CMP["ifequal"]),
    "and": lambda i, t, o: bool(i["in1"]) and bool(i["in2"]),
    "or": lambda i, t, o: bool(i["in1"]) or bool(i["in2"]),
    "xor": lambda i, t, o: bool(i["in1"]) != bool(i["in2"]),
    "not": lambda i, t, o: not bool(i["in"]),
    "plus": _blend(lambda f, b: b + f),
    "minus": _blend(lambda f, b: b - f),
    "difference": _blend(lambda f, b: np.abs(b - f)),
    "screen": _blend(lambda f, b: f + b - f * b),
    "inside": lambda i, t, o: i["in"] * i["mask"],
    "outside": lambda i, t, o: i["in"] * (1.0 - i["mask"]),
    "premult": lambda i, t, o: np.concatenate([i["in"][:3] * i["in"][3], i["in"][3:]]),
    "unpremult": _unpremult,
}

# nodedefs whose implementation differs from their category's (mtlxgen/nodes NODEDEFS)
_BOOLEAN_COMPARISONS = {nd: _CMP[cat] for cat, names in (
    ("ifgreater", ("ND_ifgreater_boolean", "ND_ifgreater_booleanI")),
    ("ifgreatereq", ("ND_ifgreatereq_boolean", "ND_ifgreatereq_booleanI")),
    ("ifequal", ("ND_ifequal_boolean", "ND_ifequal_booleanI", "ND_ifequal_booleanB"))) for nd in names}


def _cm_space(nodedef_name):
    """The colour space a cmlib nodedef converts from (ND_srgb_texture_to_lin_rec709_color3 -> srgb_texture)."""
    m = re.match(r"ND_(.+)_to_lin_rec709_color[34]$", nodedef_name)
    return m.group(1) if m else None


def evaluate(category, nodedef_name, inputs, types, out_type):
    """The value of one node of `category` (nodedef `nodedef_name`) with literal inputs ({name: Python value},
    their {name: type}) as a Python value of `out_type`. Raises NotFoldable where it is left to the GPU."""
    if out_type not in VALUE_TYPES or any(t not in VALUE_TYPES for n, t in types.items() if n in inputs):
        raise NotFoldable("a type without a folded value")
    if nodedef_name in _BOOLEAN_COMPARISONS:
        return bool(_BOOLEAN_COMPARISONS[nodedef_name](_arr(inputs["value1"]), _arr(inputs["value2"])))
    space = _cm_space(nodedef_name)
    if space is not None:
        from .nodes import cmlib
        return to_value(out_type, np.asarray(cmlib.convert_value(space, tuple(inputs["in"]))))
    fn = EVALUATORS.get(category)
    if fn is None:
        raise NotFoldable("no evaluator for %s" % category)
    values = {n: _arr(v) for n, v in inputs.items()}
    with np.errstate(all="ignore"):
        result = fn(values, types, out_type)
    return to_value(out_type, result)


# ---------------------------------------------------------------- the pass

def is_empty_closure(s):
    """An unconnected closure value: the empty closure (emit: mxtypes.closure_zero)."""
    return s.literal and mxtypes.is_closure(s.type)


def _numbers(s):
    return np.asarray(s.value, dtype=np.float64).reshape(-1)


def _own_impl(node, library):
    """The node's implementation where it is our own table's (not a document's <implementation>), else None."""
    from . import nodes
    impl = nodes.lookup(node.nodedef, library)
    return impl if impl is not None and impl.origin != "document" else None


def _passthrough(node, ins, impl):
    """The Source a node's only output reduces to given its literal inputs, or None."""
    cat, nd = node.category, node.nodedef.name
    (otype,) = node.outputs.values() if len(node.outputs) == 1 else (None,)
    if otype is None:
        return None
    if cat == "dot" and otype != "filename":
        return ins["in"]
    if cat in _CMP and nd not in _BOOLEAN_COMPARISONS and ins["value1"].literal and ins["value2"].literal \
            and ins["value1"].type in VALUE_TYPES and ins["value2"].type in VALUE_TYPES:
        return ins["in1"] if _CMP[cat](_arr(ins["value1"].value), _arr(ins["value2"].value)) else ins["in2"]
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
            and impl.closure is not None and weight.value < BSDF_EPSILON and not impl.opaque:
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
    # only what the result still reads
    by_id = {n.id: n for n in kept}
    needed, stack = set(), [result]
    while stack:
        s = stack.pop()
        if s.node is not None and s.node not in needed and s.node in by_id:
            needed.add(s.node)
            stack.extend(by_id[s.node].inputs.values())
    nodes = [n for n in kept if n.id in needed]
    out = replace(graph, nodes=nodes, result=result, uniforms={k: replace(u) for k, u in graph.uniforms.items()},
                  warnings=list(graph.warnings))
    out.static_guards = True        # emit.Emitter.closure: guards on literals decided here (static_condition)
    return out


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
        v = evaluate(node.category, node.nodedef.name, {k: s.value for k, s in values.items()},
                     {k: s.type for k, s in values.items()}, otype)
    except (NotFoldable, KeyError, TypeError, ValueError, IndexError):
        return None
    return {oname: Source(otype, value=v, loc=node.loc)}


# ---------------------------------------------------------------- guards decided at generation time

_ATOM = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(==|!=|>=|<=|>|<)\s*"
                   r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*$")
_OPS = {"==": lambda a, b: a == b, "!=": lambda a, b: a != b, ">=": lambda a, b: a >= b, "<=": lambda a, b: a <= b,
        ">": lambda a, b: a > b, "<": lambda a, b: a < b}


def _tokens(text):
    return [t for t in re.split(r"(&&|\|\||\(|\))", text) if t.strip()]


def static_condition(text):
    """A closure guard (emit.Emitter.closure: comparisons joined by && and ||, parenthesized) with its comparisons
    of two literals decided: True, False, or the text of what remains (the constant terms dropped). Text it does not
    read is returned as it is."""
    toks = _tokens(text)
    pos = [0]

    def peek():
        return toks[pos[0]] if pos[0] < len(toks) else None

    def take():
        pos[0] += 1
        return toks[pos[0] - 1]

    def parse_chain(op, parse_term, absorbing):
        """Terms joined by `op`, decided where a term is `absorbing` (True for ||, False for &&), the others'
        identity dropped."""
        terms = [parse_term()]
        while peek() == op:
            take()
            terms.append(parse_term())
        if any(t is absorbing for t in terms):
            return absorbing
        terms = [t for t in terms if t is not (not absorbing)]
        if not terms:
            return not absorbing
        return terms[0] if len(terms) == 1 else (" %s " % op).join(_wrap(t) for t in terms)

    def parse_or():
        return parse_chain("||", parse_and, True)

    def parse_and():
        return parse_chain("&&", parse_primary, False)

    def parse_primary():
        t = peek()
        if t == "(":
            take()
            inner = parse_or()
            if take() != ")":
                raise ValueError("unbalanced")
            return inner
        if t in (None, ")", "&&", "||"):
            raise ValueError("expected a comparison")
        atom = take().strip()
        m = _ATOM.match(atom)
        if m:
            return bool(_OPS[m.group(2)](float(m.group(1)), float(m.group(3))))
        if atom in ("true", "false"):
            return atom == "true"
        return atom

    try:
        out = parse_or()
        if pos[0] != len(toks):
            return text
        return out
    except (ValueError, IndexError):
        return text


def _wrap(t):
    return "(%s)" % t if ("&&" in t or "||" in t) else t
