"""Geometric streams: what the vertex stage computes and passes to the fragment stage.

A stream is requested by name from a template ({{@normal_world}}) or a handler. Each row gives the
GLSL type, the vertex attributes it reads, the vertex-stage expression and how the fragment stage
reads the interpolated value. Names with an index or a property name are built by `lookup`.
"""
import re
from mtlxgen.base.records import dataclass

_N_WORLD = "(u_worldInverseTransposeMatrix * vec4(i_normal, 0.0)).xyz"
_T_WORLD = "(u_worldMatrix * vec4(i_tangent, 0.0)).xyz"


@dataclass(frozen=True)
class Stream:
    name: str
    type: str                 # GLSL type of the varying
    attributes: tuple         # ((name, glsl type), ...)
    vertex: str               # vertex-stage expression ("world_position" is in scope)
    fragment: str = "{}"      # fragment-stage read of the varying "{}"
    uniforms: tuple = ()      # application uniforms the vertex expression needs
    flat: bool = False


_POS = (("i_position", "vec3"),)
_NRM = (("i_normal", "vec3"),)
_TAN = (("i_tangent", "vec3"),)

FIXED = {s.name: s for s in [
    Stream("position_object", "vec3", _POS, "i_position"),
    Stream("position_world", "vec3", _POS, "world_position.xyz"),
    Stream("normal_object", "vec3", _NRM, "i_normal", "normalize({})"),
    Stream("normal_world", "vec3", _NRM, _N_WORLD, "normalize({})", ("u_worldInverseTransposeMatrix",)),
    Stream("tangent_object", "vec3", _TAN, "i_tangent", "normalize({})"),
    Stream("tangent_world", "vec3", _TAN, _T_WORLD, "normalize({})", ("u_worldMatrix",)),
    # bitangent = N x T, as MaterialX derives it (meshes need not carry i_bitangent)
    Stream("bitangent_object", "vec3", _NRM + _TAN, "cross(i_normal, i_tangent)", "normalize({})"),
    Stream("bitangent_world", "vec3", _NRM + _TAN, "cross(%s, %s)" % (_N_WORLD, _T_WORLD), "normalize({})",
           ("u_worldInverseTransposeMatrix", "u_worldMatrix")),
]}

_GLSL_OF = {"float": "float", "integer": "int", "boolean": "int", "color3": "vec3", "color4": "vec4",
            "vector2": "vec2", "vector3": "vec3", "vector4": "vec4"}


NAMES = ("streams are position/normal/tangent/bitangent_object or _world, texcoord_N, color_N and geomprop_NAME, "
         "N a number, NAME of ASCII letters, digits and single '_'")
# N and NAME become part of a GLSL attribute name ("__" is reserved in GLSL)
_INDEX = re.compile(r"\d{1,9}", re.ASCII)
_PRIMVAR = re.compile(r"[A-Za-z0-9]+(_[A-Za-z0-9]+)*_?", re.ASCII)


def lookup(name, mx_type=None):
    """Stream by name: fixed ones, texcoord_N, color_N, or geomprop_NAME (typed by mx_type).
    KeyError for any other name."""
    if name in FIXED:
        return FIXED[name]
    kind, _, rest = name.partition("_")
    if kind == "texcoord" and _INDEX.fullmatch(rest):
        return Stream(name, "vec2", (("i_texcoord_" + rest, "vec2"),), "i_texcoord_" + rest)
    if kind == "color" and _INDEX.fullmatch(rest):
        return Stream(name, "vec4", (("i_color_" + rest, "vec4"),), "i_color_" + rest)
    if kind == "geomprop" and _PRIMVAR.fullmatch(rest):
        t = _GLSL_OF.get(mx_type or "float", "float")
        read = "({} != 0)" if mx_type == "boolean" else "{}"
        return Stream(name, t, (("i_geomprop_" + rest, t),), "i_geomprop_" + rest, read, flat=t == "int")
    raise KeyError(name)
