"""What a node table's evaluators are written with: a node's value computed in Python, term for term as its GLSL
template computes it, for the constant folding of the reduced interface (fold.py) and reference.node_value.

An entry of a node table (mtlxgen/nodes) may carry, beside its template, "evaluate": a function
({input name: numpy value}, {input name: type}, output type) -> numpy value. It raises NotFoldable where the value is
left to the GPU: undefined in GLSL (the power of a negative base, the square root or log of a negative, asin beyond 1,
normalize of zero, a division by zero) or not something a literal carries. to_value() turns its result into the value
a graph Source of the output type holds.

`np` here is numpy, imported on first use: the node tables are read by every start of the program, most of which
fold nothing (numpy costs tens of milliseconds to import).
"""
import importlib

from mtlxgen.base import mxtypes

FLOAT_TYPES = ("float", "color3", "color4", "vector2", "vector3", "vector4")
VALUE_TYPES = FLOAT_TYPES + ("integer", "boolean")


class NotFoldable(Exception):
    """The node's value is left to the GPU (undefined in GLSL, not finite, or no evaluator)."""


class _Numpy:
    """numpy, imported where an evaluator first reads one of its names."""

    def __getattr__(self, name):
        return getattr(importlib.import_module("numpy"), name)


np = _Numpy()


def size(t):
    """The number of floats of a value type (0 for a type that is not one)."""
    return mxtypes.BUILTIN[t].size if t in mxtypes.BUILTIN else 0


def need(cond, why):
    """NotFoldable(why) unless every element of `cond` holds."""
    if not np.all(cond):
        raise NotFoldable(why)


def domain(name, ok, why):
    """An evaluator of numpy's function `name` of input in, refused (why) where ok(in) does not hold: the GLSL
    function is undefined there."""
    def fn(i, t, o):
        need(ok(i["in"]), why)
        return getattr(np, name)(i["in"])
    return fn


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
    n = size(out_type)
    if flat.size == 1 and n > 1:
        flat = np.repeat(flat, n)                 # GLSL's vecN(x): the scalar in every component
    if flat.size != n or not np.all(np.abs(flat) <= mxtypes.FLOAT_MAX):      # also nan
        raise NotFoldable("not a finite %s" % out_type)
    return float(flat[0]) if n == 1 else tuple(float(v) for v in flat)


def evaluate(fn, inputs, types, out_type):
    """The value of a node whose table entry's evaluator is `fn` (None: none), for literal inputs ({name: Python
    value}, their {name: type}), as a Python value of `out_type`. Raises NotFoldable where it is left to the GPU."""
    if out_type not in VALUE_TYPES or any(t not in VALUE_TYPES for n, t in types.items() if n in inputs):
        raise NotFoldable("a type without a folded value")
    if fn is None:
        raise NotFoldable("no evaluator")
    numpy = importlib.import_module("numpy")
    values = {n: numpy.asarray(v, dtype=numpy.float64) for n, v in inputs.items()}
    with numpy.errstate(all="ignore"):
        result = fn(values, types, out_type)
    return to_value(out_type, result)
