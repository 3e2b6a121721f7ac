"""stdlib math nodes (MaterialX Specification 1.39, "Math Nodes").

Matrices: MaterialX matrices are row-major with row vectors (v' = v M); we upload them as written,
so GLSL sees the transpose, and M1 M2 becomes {{in2}} * {{in1}}.
"""

NODES = {
    "add": "{{in1}} + {{in2}}",
    "subtract": "{{in1}} - {{in2}}",
    "multiply": "{{in1}} * {{in2}}",
    "divide": "{{in1}} / {{in2}}",
    "modulo": "mod({{in1}}, {{in2}})",
    "fract": "fract({{in}})",
    "invert": "{{amount}} - {{in}}",
    "absval": "abs({{in}})",
    "sign": "sign({{in}})",
    "floor": "floor({{in}})",
    "ceil": "ceil({{in}})",
    "round": "round({{in}})",
    "power": "pow({{in1}}, {{$type}}({{in2}}))",     # FA variants: the float exponent widened
    "sin": "sin({{in}})",
    "cos": "cos({{in}})",
    "tan": "tan({{in}})",
    "asin": "asin({{in}})",
    "acos": "acos({{in}})",
    "atan2": "atan({{iny}}, {{inx}})",
    "sqrt": "sqrt({{in}})",
    "ln": "log({{in}})",
    "exp": "exp({{in}})",
    "clamp": "clamp({{in}}, {{low}}, {{high}})",
    "min": "min({{in1}}, {{in2}})",
    "max": "max({{in1}}, {{in2}})",
    "normalize": "normalize({{in}})",
    "magnitude": "length({{in}})",
    "dotproduct": "dot({{in1}}, {{in2}})",
    "crossproduct": "cross({{in1}}, {{in2}})",
    "transpose": "transpose({{in}})",
    "determinant": "determinant({{in}})",
    "invertmatrix": "inverse({{in}})",
    "transformmatrix": "{{mat}} * {{in}}",
    "rotate2d": {"expr": "mg_rotate2d({{in}}, {{amount}})", "files": ["stdlib/math/rotate.glsl"]},
    "rotate3d": {"expr": "mg_rotate3d({{in}}, {{amount}}, {{axis}})", "files": ["stdlib/math/rotate.glsl"]},
    "mincomponent": {"expr": "mg_mincomponent({{in}})", "files": ["stdlib/math/component.glsl"]},
    "maxcomponent": {"expr": "mg_maxcomponent({{in}})", "files": ["stdlib/math/component.glsl"]},
    "transformpoint": {"handler": "transform_space"},
    "transformvector": {"handler": "transform_space"},
    "transformnormal": {"handler": "transform_space"},
    "creatematrix": "{{$type}}({{in1}}, {{in2}}, {{in3}})",
}

NODEDEFS = {
    # integer results of rounding nodes
    "ND_floor_integer": "int(floor({{in}}))",
    "ND_ceil_integer": "int(ceil({{in}}))",
    "ND_round_integer": "int(round({{in}}))",
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
