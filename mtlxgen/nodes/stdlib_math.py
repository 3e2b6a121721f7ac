"""stdlib math nodes (MaterialX Specification 1.39, "Math Nodes").

Matrices: MaterialX matrices are row-major with row vectors (v' = v M); we upload them as written,
so GLSL sees the transpose, and M1 M2 becomes {{in2}} * {{in1}}.
"""

from mtlxgen.nodes.nodevalue import domain, need, np


# evaluators (nodevalue.py): the templates' values in Python, term for term

def _divide(i, t, o):
    need(i["in2"] != 0.0, "division by zero")
    if o == "integer":
        return np.trunc(i["in1"] / i["in2"])
    return i["in1"] / i["in2"]


def _modulo(i, t, o):
    need(i["in2"] != 0.0, "modulo by zero")
    return i["in1"] - i["in2"] * np.floor(i["in1"] / i["in2"])        # GLSL mod()


def _power(i, t, o):
    x, y = np.broadcast_arrays(i["in1"], i["in2"])
    need((x > 0.0) | ((x == 0.0) & (y > 0.0)), "pow of a negative base (undefined in GLSL)")
    return np.power(x, y)


def _round(i, t, o):
    x = i["in"]
    need(np.abs(x - np.floor(x)) != 0.5, "round of a half (GLSL leaves the direction to the driver)")
    return np.round(x)


def _atan2(i, t, o):
    need((i["iny"] != 0.0) | (i["inx"] != 0.0), "atan(0, 0) is undefined")
    return np.arctan2(i["iny"], i["inx"])


def _normalize(i, t, o):
    n = np.sqrt(np.sum(i["in"] * i["in"]))
    need(n > 0.0, "normalize of a zero vector")
    return i["in"] / n


def _floor(i, t, o):
    return np.floor(i["in"])


def _ceil(i, t, o):
    return np.ceil(i["in"])


NODES = {
    "add": {"expr": "{{in1}} + {{in2}}", "evaluate": lambda i, t, o: i["in1"] + i["in2"]},
    "subtract": {"expr": "{{in1}} - {{in2}}", "evaluate": lambda i, t, o: i["in1"] - i["in2"]},
    "multiply": {"expr": "{{in1}} * {{in2}}", "evaluate": lambda i, t, o: i["in1"] * i["in2"]},
    "divide": {"expr": "{{in1}} / {{in2}}", "evaluate": _divide},
    "modulo": {"expr": "mod({{in1}}, {{in2}})", "evaluate": _modulo},
    "fract": {"expr": "fract({{in}})", "evaluate": lambda i, t, o: i["in"] - np.floor(i["in"])},
    "invert": {"expr": "{{amount}} - {{in}}", "evaluate": lambda i, t, o: i["amount"] - i["in"]},
    "absval": {"expr": "abs({{in}})", "evaluate": lambda i, t, o: np.abs(i["in"])},
    "sign": {"expr": "sign({{in}})", "evaluate": lambda i, t, o: np.sign(i["in"])},
    "floor": {"expr": "floor({{in}})", "evaluate": _floor},
    "ceil": {"expr": "ceil({{in}})", "evaluate": _ceil},
    "round": {"expr": "round({{in}})", "evaluate": _round},
    # FA variants: the float exponent widened
    "power": {"expr": "pow({{in1}}, {{$type}}({{in2}}))", "evaluate": _power},
    "sin": {"expr": "sin({{in}})", "evaluate": lambda i, t, o: np.sin(i["in"])},
    "cos": {"expr": "cos({{in}})", "evaluate": lambda i, t, o: np.cos(i["in"])},
    "tan": {"expr": "tan({{in}})", "evaluate": lambda i, t, o: np.tan(i["in"])},
    "asin": {"expr": "asin({{in}})",
             "evaluate": domain("arcsin", lambda x: np.abs(x) <= 1.0, "asin beyond [-1, 1]")},
    "acos": {"expr": "acos({{in}})",
             "evaluate": domain("arccos", lambda x: np.abs(x) <= 1.0, "acos beyond [-1, 1]")},
    "atan2": {"expr": "atan({{iny}}, {{inx}})", "evaluate": _atan2},
    "sqrt": {"expr": "sqrt({{in}})", "evaluate": domain("sqrt", lambda x: x >= 0.0, "sqrt of a negative")},
    "ln": {"expr": "log({{in}})", "evaluate": domain("log", lambda x: x > 0.0, "log of zero or a negative")},
    "exp": {"expr": "exp({{in}})", "evaluate": lambda i, t, o: np.exp(i["in"])},
    "clamp": {"expr": "clamp({{in}}, {{low}}, {{high}})",
              "evaluate": lambda i, t, o: np.minimum(np.maximum(i["in"], i["low"]), i["high"])},
    "min": {"expr": "min({{in1}}, {{in2}})", "evaluate": lambda i, t, o: np.minimum(i["in1"], i["in2"])},
    "max": {"expr": "max({{in1}}, {{in2}})", "evaluate": lambda i, t, o: np.maximum(i["in1"], i["in2"])},
    "normalize": {"expr": "normalize({{in}})", "evaluate": _normalize},
    "magnitude": {"expr": "length({{in}})", "evaluate": lambda i, t, o: np.sqrt(np.sum(i["in"] * i["in"]))},
    "dotproduct": {"expr": "dot({{in1}}, {{in2}})", "evaluate": lambda i, t, o: np.sum(i["in1"] * i["in2"])},
    "crossproduct": {"expr": "cross({{in1}}, {{in2}})", "evaluate": lambda i, t, o: np.cross(i["in1"], i["in2"])},
    "transpose": "transpose({{in}})",
    "determinant": "determinant({{in}})",
    "invertmatrix": "inverse({{in}})",
    "transformmatrix": "{{mat}} * {{in}}",
    "rotate2d": {"expr": "mg_rotate2d({{in}}, {{amount}})", "files": ["stdlib/math/rotate.glsl"]},
    "rotate3d": {"expr": "mg_rotate3d({{in}}, {{amount}}, {{axis}})", "files": ["stdlib/math/rotate.glsl"]},
    "mincomponent": {"expr": "mg_mincomponent({{in}})", "files": ["stdlib/math/component.glsl"],
                     "evaluate": lambda i, t, o: np.min(i["in"])},
    "maxcomponent": {"expr": "mg_maxcomponent({{in}})", "files": ["stdlib/math/component.glsl"],
                     "evaluate": lambda i, t, o: np.max(i["in"])},
    "transformpoint": {"handler": "transform_space"},
    "transformvector": {"handler": "transform_space"},
    "transformnormal": {"handler": "transform_space"},
    "creatematrix": "{{$type}}({{in1}}, {{in2}}, {{in3}})",
}

NODEDEFS = {
    # integer results of rounding nodes
    "ND_floor_integer": {"expr": "int(floor({{in}}))", "evaluate": _floor},
    "ND_ceil_integer": {"expr": "int(ceil({{in}}))", "evaluate": _ceil},
    "ND_round_integer": {"expr": "int(round({{in}}))", "evaluate": _round},
    # matrix products in GLSL's (transposed) view of MaterialX's row-major matrices
    "ND_multiply_matrix33": "{{in2}} * {{in1}}",
    "ND_multiply_matrix44": "{{in2}} * {{in1}}",
    "ND_divide_matrix33": "inverse({{in2}}) * {{in1}}",
    "ND_divide_matrix44": "inverse({{in2}}) * {{in1}}",
    # affine transforms of lower-dimensional vectors (homogeneous coordinate 1)
    "ND_transformmatrix_vector2M3": "({{mat}} * vec3({{in}}, 1.0)).xy",
    "ND_transformmatrix_vector3M4": "({{mat}} * vec4({{in}}, 1.0)).xyz",
    "ND_creatematrix_vector3_matrix44": "mat4(vec4({{in1}}, 0.0), vec4({{in2}}, 0.0), vec4({{in3}}, 0.0), vec4({{in4}}, 1.0))",
    "ND_creatematrix_vector4_matrix44": "mat4({{in1}}, {{in2}}, {{in3}}, {{in4}})",
}
