"""MaterialX data types: their GLSL spelling, value parsing and GLSL literals.

Plain tables: one row per type. Struct types declared with <typedef> are added per document.
"""
import re
from mtlxgen.base.records import dataclass, field


@dataclass(frozen=True)
class TypeInfo:
    name: str
    glsl: str            # GLSL type spelling ("" where the type has no run-time value, e.g. string)
    size: int = 1        # number of scalar components (0 for non-numeric)
    scalar: str = ""     # "float", "int", "bool", "string" or "" for closures / structs
    closure: bool = False


_ROWS = [
    # name, glsl, size, scalar
    ("float", "float", 1, "float"),
    ("integer", "int", 1, "int"),
    ("boolean", "bool", 1, "bool"),
    ("color3", "vec3", 3, "float"),
    ("color4", "vec4", 4, "float"),
    ("vector2", "vec2", 2, "float"),
    ("vector3", "vec3", 3, "float"),
    ("vector4", "vec4", 4, "float"),
    ("matrix33", "mat3", 9, "float"),
    ("matrix44", "mat4", 16, "float"),
    ("string", "int", 1, "string"),       # enum strings become int constants where they reach GLSL
    ("filename", "sampler2D", 1, "string"),
    ("geomname", "", 1, "string"),
    ("integerarray", "int[]", 0, "int"),
    ("floatarray", "float[]", 0, "float"),
    ("color3array", "vec3[]", 0, "float"),
    ("color4array", "vec4[]", 0, "float"),
    ("vector2array", "vec2[]", 0, "float"),
    ("vector3array", "vec3[]", 0, "float"),
    ("vector4array", "vec4[]", 0, "float"),
    ("stringarray", "", 0, "string"),
    ("geomnamearray", "", 0, "string"),
]
_CLOSURES = ["BSDF", "EDF", "VDF", "surfaceshader", "volumeshader", "displacementshader", "lightshader", "material"]

BUILTIN = {n: TypeInfo(n, g, s, sc) for n, g, s, sc in _ROWS}
BUILTIN.update({n: TypeInfo(n, n if n != "material" else "surfaceshader", 0, "", True) for n in _CLOSURES})
BUILTIN["none"] = TypeInfo("none", "", 0, "")
BUILTIN["multioutput"] = TypeInfo("multioutput", "", 0, "")

ARRAY_ELEMENT = {"integerarray": "integer", "floatarray": "float", "color3array": "color3", "color4array": "color4",
                 "vector2array": "vector2", "vector3array": "vector3", "vector4array": "vector4",
                 "stringarray": "string", "geomnamearray": "geomname"}


@dataclass
class StructType:
    """A <typedef> with <member>s: a GLSL struct of the same name."""
    name: str
    members: list = field(default_factory=list)   # [(name, type, default value string or None)]
    loc: object = None                            # the <typedef>'s diagnostics.Loc


CLOSURE_NAMES = frozenset(n for n, info in BUILTIN.items() if info.closure)
CLOSURE_TYPES = frozenset(("BSDF", "EDF", "VDF"))     # the closures a shader node evaluates per lighting context


def is_closure(type_name):
    return type_name in CLOSURE_NAMES


# Types MaterialX passes through where one is connected to the other (its validator calls it a mismatch, its
# generator writes the same GLSL type for both): measured with the materialx wheel, 1.39.5
INTERCHANGEABLE = ({"color3", "vector3"}, {"color4", "vector4"})


def interchangeable(a, b):
    return a != b and any(a in pair and b in pair for pair in INTERCHANGEABLE)


def glsl_type(type_name, structs=None):
    if type_name in BUILTIN:
        return BUILTIN[type_name].glsl
    if structs and type_name in structs:
        return type_name
    raise KeyError(type_name)


def components(type_name):
    info = BUILTIN.get(type_name)
    return info.size if info else 0


class ValueError_(ValueError):
    pass


# Numbers are read as MaterialX 1.39 reads them (C++ stream extraction, measured with the materialx wheel): leading
# whitespace is skipped, then the longest number the text starts with is taken and whatever follows is ignored
# ('0.5.0' reads 0.5, '1.842,1.044,0.35' reads 1.842, integer '2.7' reads 2). Ignoring the rest is a slip, reported
# through `slips` (a warning) or, without it, refused. Text that starts with no number (Python's float() would take
# 'nan', 'Infinity', '1_000', non-ASCII digits; MaterialX takes none), an exponent without digits ('1e', '1e+'),
# and numbers beyond a 32-bit float or int are refused: MaterialX reads no value there, and no GLSL literal can
# carry them.
_FLOAT_PREFIX = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d*)?", re.ASCII)
_INT_PREFIX = re.compile(r"[+-]?\d+", re.ASCII)
_LEADING_SPACE = " \t\n\v\f\r"
FLOAT_MAX = 3.4028234663852886e38                        # largest finite 32-bit float (GLSL's float)
INT_MIN, INT_MAX = -2 ** 31, 2 ** 31 - 1                 # GLSL's int


def _rest_is_slip(text, rest, whole, slips, shown):
    """Text after a number: nothing (fine), or a slip MaterialX reads past (warned, or refused without `slips`)."""
    if not rest.strip(_LEADING_SPACE):
        return
    where = " in %r" % whole if whole is not None else ""
    if slips is None:
        raise ValueError_("not a number: %r%s" % (text, where))
    slips.append("%r%s has more after its number: read as %s, as MaterialX reads it" % (text, where, shown))


def _float(text, whole=None, slips=None):
    """A float value (or a component of the list value `whole`, which messages then name)."""
    t, where = text.lstrip(_LEADING_SPACE), " in %r" % whole if whole is not None else ""
    m = _FLOAT_PREFIX.match(t)
    if not m or m.group()[-1] in "eE+-":          # no number, or an exponent without digits ('1e', '1e+')
        if t.strip().lstrip("+-").lower() in ("inf", "infinity", "nan"):
            raise ValueError_("non-finite value %r%s (no GLSL literal can carry it)" % (text, where))
        raise ValueError_("not a number: %r%s" % (text, where))
    x = float(m.group())
    if abs(x) > FLOAT_MAX:
        raise ValueError_("non-finite value %r%s (beyond the range of a 32-bit float)" % (text, where))
    _rest_is_slip(text, t[m.end():], whole, slips, repr(x))
    return x


def _list_items(text, separators, slips):
    """Items of a list value: split at any of `separators`; empty items between commas (',,', a leading or
    trailing comma) are dropped, as MaterialX drops them, and reported as a slip."""
    parts = re.split("[%s]" % re.escape(separators), text)
    items = [p for p in parts if p.strip(_LEADING_SPACE)]
    commas = text.split(",")
    if len(commas) > 1 and any(not p.strip(_LEADING_SPACE) for p in commas):
        if slips is None:
            raise ValueError_("empty item between commas in %r" % text)
        slips.append("%r has an empty item between commas: skipped, as MaterialX skips it" % text)
    return items


def _floats(text, count, slips=None):
    # MaterialX splits vector, colour and matrix values at commas and spaces alike ('0.1 0.2 0.3' is seen in the
    # wild and reads as '0.1, 0.2, 0.3'); the count must be exact
    parts = _list_items(text, ", ", slips)
    if len(parts) != count:
        raise ValueError_("expected %d comma-separated numbers, got %d in %r" % (count, len(parts), text))
    return tuple(_float(p, text, slips) for p in parts)


def _int(text, whole=None, slips=None):
    t, where = text.lstrip(_LEADING_SPACE), " in %r" % whole if whole is not None else ""
    m = _INT_PREFIX.match(t)
    if not m:
        raise ValueError_("not an integer: %r%s" % (text, where))
    n = int(m.group())
    if not INT_MIN <= n <= INT_MAX:
        raise ValueError_("integer %r%s is outside the 32-bit range of GLSL's int" % (text, where))
    rest = t[m.end():]
    if re.fullmatch(r"\.0*[ \t\n\v\f\r]*", rest):        # '2.0' reads as 2: a whole number, no slip
        return n
    if slips is None and rest.strip(_LEADING_SPACE):
        raise ValueError_("not an integer: %r%s" % (text, where))
    _rest_is_slip(text, rest, whole, slips, str(n))
    return n


def _bool(text):
    if text in ("true", "false"):   # MaterialX reads no other spelling ("1", "TRUE", "yes", " true")
        return text == "true"
    raise ValueError_("not a boolean: %r (MaterialX reads only 'true' or 'false')" % text)


def parse_value(type_name, text, structs=None, slips=None):
    """Value string of a MaterialX type -> Python value.

    float -> float; integer -> int; boolean -> bool; colorN/vectorN/matrixNN -> tuple of floats
    (matrices row by row, as written); string/filename -> str; arrays -> tuple; structs -> tuple of
    member values. Raises ValueError_ with a message for text that does not fit the type.

    slips: a list to collect the slips MaterialX reads on (text after a number, empty items between commas):
    with it such a value is read as MaterialX reads it and a message appended; without it, it is refused.
    """
    if text is None:
        return None
    key = (type_name, text)
    value = _PARSED.get(key)
    if value is not None:
        return value
    if type_name in _PARSED_TYPES:                  # a number or a few: kept once read with no slip
        found = len(slips) if slips is not None else 0
        value = _parse_value(type_name, text, structs, slips)
        if value is not None and (slips is None or len(slips) == found):
            if len(_PARSED) >= _PARSED_MAX:
                _PARSED.clear()
            _PARSED[key] = value
        return value
    return _parse_value(type_name, text, structs, slips)


# parse_value's values of built-in numeric types read with no slip, per process: (type, text) -> the value (floats,
# ints, bools, tuples of floats: immutable). A library of materials writes the same few values again and again.
_PARSED = {}
_PARSED_MAX = 1 << 16
_PARSED_TYPES = frozenset(("float", "integer", "boolean", "color3", "color4", "vector2", "vector3", "vector4",
                           "matrix33", "matrix44"))


def _parse_value(type_name, text, structs=None, slips=None):
    if not text.strip() and type_name in ("float", "integer", "boolean", "color3", "color4", "vector2", "vector3",
                                          "vector4", "matrix33", "matrix44"):
        # value="" (seen in exported files): MaterialX reads no value there, so its nodedef's default
        if slips is None:
            raise ValueError_("empty value")
        slips.append("the value is empty: read as no value (its default), as MaterialX reads it")
        return None
    if type_name == "float":
        return _float(text, None, slips)
    if type_name == "integer":
        return _int(text, None, slips)
    if type_name == "boolean":
        return _bool(text)
    if type_name in ("string", "filename", "geomname"):
        return text
    info = BUILTIN.get(type_name)
    if info and info.size > 1:
        return _floats(text, info.size, slips)
    if type_name in ARRAY_ELEMENT:
        if not text.strip():
            return ()
        element = ARRAY_ELEMENT[type_name]
        if element in ("string", "geomname"):
            return tuple(p.strip() for p in text.split(","))
        size = components(element)
        parts = [p.strip() for p in _list_items(text, ",", slips)]    # arrays split at commas only
        if len(parts) % size:
            raise ValueError_("%s needs a multiple of %d numbers, got %d" % (type_name, size, len(parts)))
        conv = _int if element == "integer" else _float
        vals = [conv(p, text, slips) for p in parts]
        if size == 1:
            return tuple(vals)
        return tuple(tuple(vals[i:i + size]) for i in range(0, len(vals), size))
    if structs and type_name in structs:
        if not text.strip():
            # a nodedef's (or a struct member's) value="": MaterialX's generator reads no value there, so the
            # struct's default (an instance's empty struct value MaterialX cannot read: document.py refuses it)
            if slips is None:
                raise ValueError_("empty value")
            slips.append("the value is empty: read as no value (its default), as MaterialX reads it")
            return None
        # struct values are written as a ';'-separated list of member values
        members = structs[type_name].members
        parts = _struct_parts(text)
        if len(parts) != len(members):
            raise ValueError_("struct %s has %d members, value %r has %d" % (type_name, len(members), text, len(parts)))
        for (mn, _, _), p in zip(members, parts):
            if not p.strip():           # (MaterialX cannot read it: it stops, or crashes)
                raise ValueError_("member '%s' of struct %s is empty in %r" % (mn, type_name, text))
        return tuple(parse_value(mt, p.strip(), structs, slips) for (_, mt, _), p in zip(members, parts))
    if info is not None:   # closures and "none" carry no value
        return None
    raise ValueError_("unknown type %r" % type_name)


def _struct_parts(text):
    """'{a;{b;c}}' -> ['a', '{b;c}']: member values split at the ';' outside nested braces."""
    t = text.strip()
    if t.startswith("{") and t.endswith("}"):
        t = t[1:-1]
    parts, depth, start = [], 0, 0
    for i, ch in enumerate(t):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth < 0:
                break
        elif ch == ";" and depth == 0:
            parts.append(t[start:i])
            start = i + 1
    if depth != 0:
        raise ValueError_("unbalanced braces in struct value %r" % text)
    return parts + [t[start:]]


def format_float(x):
    """Shortest GLSL float literal that round-trips to the same double (always with a '.' or exponent)."""
    x = float(x)
    if not abs(x) <= FLOAT_MAX:       # also catches nan
        raise ValueError_("non-finite value %r (no GLSL literal can carry it)" % x)
    s = repr(x)
    if "e" in s or "E" in s:
        mant, exp = s.lower().split("e")
        if "." not in mant:
            mant += ".0"
        return "%se%d" % (mant, int(exp))
    return s


def glsl_literal(type_name, value, structs=None):
    """Python value -> GLSL constant expression of the type's GLSL spelling."""
    if type_name == "float":
        return format_float(value)
    if type_name == "integer":
        if not INT_MIN <= int(value) <= INT_MAX:
            raise ValueError_("integer %d is outside the 32-bit range of GLSL's int" % value)
        return str(int(value))
    if type_name == "boolean":
        return "true" if value else "false"
    info = BUILTIN.get(type_name)
    if info and info.size > 1:
        return "%s(%s)" % (info.glsl, ", ".join(format_float(v) for v in value))
    if type_name in ARRAY_ELEMENT and ARRAY_ELEMENT[type_name] not in ("string", "geomname"):
        element = ARRAY_ELEMENT[type_name]
        items = [glsl_literal(element, v) for v in value] or [glsl_literal(element, zero(element))]
        return "%s[%d](%s)" % (glsl_type(element), len(items), ", ".join(items))
    if structs and type_name in structs:
        members = structs[type_name].members
        return "%s(%s)" % (type_name, ", ".join(glsl_literal(mt, v, structs) for (_, mt, _), v in zip(members, value)))
    raise ValueError_("type %s has no GLSL literal" % type_name)


def zero(type_name, structs=None):
    """The default value a type takes when nothing sets it."""
    if type_name == "float":
        return 0.0
    if type_name == "integer":
        return 0
    if type_name == "boolean":
        return False
    info = BUILTIN.get(type_name)
    if info and type_name in ("matrix33", "matrix44"):
        n = 3 if type_name == "matrix33" else 4
        return tuple(1.0 if i == j else 0.0 for i in range(n) for j in range(n))
    if info and info.size > 1:
        return (0.0,) * info.size
    if type_name in ("string", "filename", "geomname"):
        return ""
    if type_name in ARRAY_ELEMENT:
        return ()
    if structs and type_name in structs:
        # slips in a member default were warned at its typedef; an empty one (value="") is no default
        values = [parse_value(mt, d, structs, []) if d is not None else None for _, mt, d in structs[type_name].members]
        return tuple(zero(mt, structs) if v is None else v for (_, mt, _), v in zip(structs[type_name].members, values))
    return None


_CLOSURE_ZERO = {
    "BSDF": "BSDF(vec3(0.0), vec3(1.0))",
    "EDF": "vec3(0.0)",
    "VDF": "VDF(vec3(0.0), vec3(1.0))",
    "surfaceshader": "surfaceshader(vec3(0.0), vec3(0.0))",
    "material": "surfaceshader(vec3(0.0), vec3(0.0))",
    "volumeshader": "volumeshader(vec3(0.0), vec3(0.0))",
    "displacementshader": "displacementshader(vec3(0.0), 1.0)",
    "lightshader": "lightshader(vec3(0.0), vec3(0.0))",
}


def closure_zero(type_name):
    """GLSL expression of an empty closure value."""
    return _CLOSURE_ZERO[type_name]
