"""stdlib channel nodes (MaterialX Specification 1.39, "Channel Nodes").

separateN and most convert variants are nodegraphs in the data library (built from extract,
combine and constant), so only the leaves live here.
"""
from mtlxgen.nodes.nodevalue import NotFoldable, need, np, size


# evaluators (nodevalue.py): the templates' values in Python, term for term

def _extract(i, t, o):
    k = int(i["index"])
    need(0 <= k < np.size(i["in"]), "extract index out of range")
    return np.asarray(i["in"]).reshape(-1)[k]


def _combine(*names):
    def fn(i, t, o):
        return np.concatenate([np.asarray(i[n]).reshape(-1) for n in names])
    return fn


_COMBINE2 = _combine("in1", "in2")


def _convert(i, t, o):
    x = np.asarray(i["in"], dtype=np.float64).reshape(-1)
    n = size(o)
    if o in ("integer", "boolean", "float"):
        if x.size != 1:
            raise NotFoldable("convert of a vector to a scalar")
        return np.trunc(x[0]) if o == "integer" else (x[0] != 0.0) if o == "boolean" else x[0]
    if x.size == 1:
        return np.repeat(x, n)
    need(x.size >= n, "a vector widened needs more components than it has")
    return x[:n]


NODES = {
    "extract": {"expr": "{{in}}[{{=index}}]", "evaluate": _extract},
    "combine2": {"expr": "{{$type}}({{in1}}, {{in2}})", "evaluate": _COMBINE2},
    "combine3": {"expr": "{{$type}}({{in1}}, {{in2}}, {{in3}})", "evaluate": _combine("in1", "in2", "in3")},
    "combine4": {"expr": "{{$type}}({{in1}}, {{in2}}, {{in3}}, {{in4}})",
                 "evaluate": _combine("in1", "in2", "in3", "in4")},
    # the leaf converts: scalar casts
    "convert": {"expr": "{{$type}}({{in}})", "evaluate": _convert},
}

NODEDEFS = {
    "ND_combine2_color4CF": {"expr": "vec4({{in1}}, {{in2}})", "evaluate": _COMBINE2},
    "ND_combine2_vector4VF": {"expr": "vec4({{in1}}, {{in2}})", "evaluate": _COMBINE2},
    "ND_combine2_vector4VV": {"expr": "vec4({{in1}}, {{in2}})", "evaluate": _COMBINE2},
}
