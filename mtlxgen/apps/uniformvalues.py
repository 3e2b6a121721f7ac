"""Uniform initial values in generated GLSL text, and setting uniforms on a linked program.

The viewer (view.py) and its property panel (viewpanel.py) share these: an edit that changes only
initial values keeps the linked program (equal skeletons) and sets the values that changed.
"""
import re

_UNIFORM_INIT = re.compile(r"^([ \t]*uniform[ \t]+(\w+)[ \t]+(\w+)[ \t]*)=([^;]*);", re.M)
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?)")
_SETTABLE = {"float": 1, "int": 1, "bool": 1, "vec2": 2, "vec3": 3, "vec4": 4, "ivec2": 2, "ivec3": 3, "ivec4": 4,
             "mat3": 9, "mat4": 16}


def skeleton(text):
    """GLSL with its uniforms' initial values taken out: equal skeletons link to the same program."""
    return _UNIFORM_INIT.sub(lambda m: m.group(1) + ";", text)


def initializers(text):
    """{uniform: initial value as written} of the uniforms declared with one."""
    return {m.group(3): m.group(4).strip() for m in _UNIFORM_INIT.finditer(text)}


def initial_values(text, names=None):
    """{uniform: value} of the uniforms declared with an initial value of a type a program can be set to
    (numbers, vectors, matrices); a value that is not plain numbers is left out. names: only these."""
    out = {}
    for m in _UNIFORM_INIT.finditer(text):
        glsl, name, expr = m.group(2), m.group(3), m.group(4).strip()
        if names is not None and name not in names:
            continue
        n = _SETTABLE.get(glsl)
        if n is None:
            continue
        if glsl == "bool":
            if expr in ("true", "false"):
                out[name] = expr == "true"
            continue
        nums = _NUMBER.findall(re.sub(r"^\w+\s*\(|\)$", "", expr) if "(" in expr else expr)
        if len(nums) == 1 and n > 1:            # vec3(0.5): every component
            nums = nums * (n if glsl.startswith(("vec", "ivec")) else 0)
        if len(nums) != n:
            continue
        values = [int(float(x)) for x in nums] if glsl.startswith(("int", "ivec")) else [float(x) for x in nums]
        out[name] = values[0] if n == 1 else tuple(values)
    return out


def set_uniform(prog, name, value):
    """Set a uniform on a linked program if the program kept it; False where it did not."""
    if name not in prog:
        return False
    u = prog[name]
    if isinstance(value, bool):
        value = int(value)
    u.value = value
    return True
