"""Shader targets: what differs between desktop GLSL 4.00, WebGL2's GLSL ES 3.00 and Vulkan GLSL 4.50.

The graph and the node code are target-free; a target decides only how a stage's sections are spelled:
the version line and what follows it, how uniforms are declared (initializers, or one std140 block with a
binding), and whether ins and outs carry explicit locations. emit/emitter.py assembles the sections and asks the
target for each declaration; the differences between targets live here and nowhere else (glsl_lib reads
`GL_ES` where ES lacks a built-in).

- glsl: `#version 400`, every uniform with its default as initializer (the shader draws without a manifest).
- essl: `#version 300 es` with precision qualifiers; ES has no uniform initializers, so the manifest's
  values (material) and "application" defaults are what a page binds; at most 16 samplers (WebGL2's
  guaranteed MAX_TEXTURE_IMAGE_UNITS).
- vulkan: `#version 450`; every non-sampler uniform of both stages in one std140 block (set 0, binding 0, the
  same declaration in both stages, so one buffer serves the material), samplers combined image samplers at
  bindings 1..n, every in and out at an explicit location. The manifest gives the block's size, each
  member's offset, each sampler's binding and each attribute's location.
"""
import re
from mtlxgen.base.records import dataclass

BLOCK_NAME = "MaterialUniforms"
BLOCK_SET = 0
BLOCK_BINDING = 0


@dataclass(frozen=True)
class Target:
    name: str
    version: str                  # after `#version `
    header: tuple = ()            # lines after the version line
    initializers: bool = True     # uniforms carry their defaults
    uniform_block: bool = False   # non-opaque uniforms in one std140 block
    locations: bool = False       # explicit `layout(location = N)` on ins and outs
    max_samplers: int = 0         # samplers one fragment stage may use; 0: no limit checked
    api: str = "OpenGL 4.0"       # what the shaders are for (messages, manifest)


TARGETS = {t.name: t for t in [
    Target("glsl", "400"),
    Target("essl", "300 es", ("precision highp float;", "precision highp int;", "precision highp sampler2D;"),
           initializers=False, max_samplers=16, api="WebGL2 / OpenGL ES 3.0"),
    Target("vulkan", "450", initializers=False, uniform_block=True, locations=True, api="Vulkan (SPIR-V)"),
]}
NAMES = tuple(TARGETS)
DEFAULT = "glsl"


def get(name):
    if name not in TARGETS:
        raise ValueError("target must be one of %s, not %r" % (", ".join(NAMES), name))
    return TARGETS[name]


# ---------------------------------------------------------------- std140 (OpenGL 4.5 spec, sec. 7.6.2.2)

_SCALARS = {"float": 4, "int": 4, "uint": 4, "bool": 4}
_VECTORS = {"vec2": ("float", 2), "vec3": ("float", 3), "vec4": ("float", 4), "ivec2": ("int", 2),
            "ivec3": ("int", 3), "ivec4": ("int", 4), "bvec2": ("bool", 2), "bvec3": ("bool", 3),
            "bvec4": ("bool", 4)}
_MATRICES = {"mat2": 2, "mat3": 3, "mat4": 4}


def _round_up(n, a):
    return (n + a - 1) // a * a


def std140(glsl_type, structs):
    """(base alignment, size) of a GLSL type in a std140 block. structs: {name: [(member, type, length)]}."""
    if glsl_type in _SCALARS:
        return 4, 4
    if glsl_type in _VECTORS:
        n = _VECTORS[glsl_type][1]
        return (8 if n == 2 else 16), 4 * n
    if glsl_type in _MATRICES:              # column-major: an array of n column vectors, stride 16
        n = _MATRICES[glsl_type]
        return 16, 16 * n
    if glsl_type in structs:
        offset, align = 0, 16
        for _, t, length in structs[glsl_type]:
            a, size = member_layout(t, length, structs)
            align = max(align, a)
            offset = _round_up(offset, a) + size
        return align, _round_up(offset, align)
    raise KeyError(glsl_type)


def member_layout(glsl_type, length, structs):
    """(alignment, size) of a member, an array of `length` elements when length > 0 (stride a multiple of 16)."""
    a, size = std140(glsl_type, structs)
    if not length:
        return a, size
    stride = _round_up(size, 16)
    return max(a, 16), stride * length


def block_layout(members, structs):
    """[(name, offset, stride or 0)] and the block's size for [(name, glsl type, length)] in order."""
    out, offset = [], 0
    for name, t, length in members:
        a, size = member_layout(t, length, structs)
        offset = _round_up(offset, a)
        stride = _round_up(std140(t, structs)[1], 16) if length else 0
        out.append((name, offset, stride))
        offset += size
    return out, _round_up(offset, 16)


def for_opengl(text):
    """A stage's text as an OpenGL context compiles it: Vulkan GLSL's `set = N` layout qualifier (OpenGL has
    no descriptor sets; the bindings stay) dropped. Every other target's text is returned unchanged. The
    renderer draws vulkan shaders this way, through the same block offsets and bindings a Vulkan renderer
    uses; the line numbers stay those of the written file."""
    if not text.startswith("#version 450"):
        return text
    return re.sub(r"\bset = \d+, ", "", text)
