"""GLSL identifiers from MaterialX names: what nodes, uniforms and variables of a shader are called.

glsl_identifier turns any name into a valid identifier that is not a GLSL keyword, a built-in's, or one of the
prefixes mtlxgen's own names use (u_, i_, gl_), cut to IDENTIFIER_CHARS with a hash where longer; unique_identifier
makes it unique among the names taken.
"""
import re


_GLSL_RESERVED = set("""attribute const uniform varying layout centroid flat smooth noperspective patch sample
break continue do for while switch case default if else subroutine in out inout float double int void bool true
false invariant discard return mat2 mat3 mat4 dmat2 dmat3 dmat4 mat2x2 mat2x3 mat2x4 mat3x2 mat3x3 mat3x4 mat4x2
mat4x3 mat4x4 vec2 vec3 vec4 ivec2 ivec3 ivec4 bvec2 bvec3 bvec4 dvec2 dvec3 dvec4 uint uvec2 uvec3 uvec4 lowp
mediump highp precision sampler1D sampler2D sampler3D samplerCube struct common partition active asm class union
enum typedef template this packed goto inline noinline volatile public static extern external interface long
short half fixed unsigned superp input output filter sizeof cast namespace using main texture sample resource
BSDF EDF VDF surfaceshader volumeshader displacementshader lightshader material""".split())


IDENTIFIER_CHARS = 64     # longer names are cut and end in a hash: not every driver takes 1,000-character names


_NOT_IDENTIFIER = re.compile(r"[^A-Za-z0-9_]")
_UNDERSCORES = re.compile(r"__+")
_IDENTIFIERS = {}                   # name -> glsl_identifier(name): nodes of one kind share their stems
_IDENTIFIERS_MAX = 200000


def glsl_identifier(name):
    s = _IDENTIFIERS.get(name)
    if s is None:
        if len(_IDENTIFIERS) >= _IDENTIFIERS_MAX:
            _IDENTIFIERS.clear()
        s = _IDENTIFIERS[name] = _glsl_identifier(name)
    return s


def _glsl_identifier(name):
    if name.isascii() and name.isidentifier() and "__" not in name:
        s = name                    # [A-Za-z_][A-Za-z0-9_]* without a double underscore: nothing to replace
    else:
        s = _UNDERSCORES.sub("_", _NOT_IDENTIFIER.sub("_", name))
    if not s or s[0].isdigit():
        s = "n" + s
    if s in _GLSL_RESERVED or s.startswith("gl_") or s.startswith("u_") or s.startswith("i_"):
        s = "n_" + s
    if len(s) > IDENTIFIER_CHARS:
        digest = sha256(name.encode("utf-8", "surrogatepass")).hexdigest()[:8]
        s = s[:IDENTIFIER_CHARS - 10].rstrip("_") + "_h" + digest
    return s


def sha256(data):
    """hashlib.sha256(data), from CPython's own SHA-256 module where it has one: hashlib loads OpenSSL (2 to 6 ms of
    the start of a generate that hashes a long name, a clashing stem or a primvar's name)."""
    try:
        from _sha256 import sha256          # CPython 3.11
    except ImportError:
        try:
            from _sha2 import sha256        # CPython 3.12 and later
        except ImportError:
            from hashlib import sha256
    return sha256(data)


def is_plain_name(e):
    """Whether GLSL text `e` is one identifier (a variable or uniform, not a literal such as `true`): what needs no
    copy into a variable of its own."""
    return e.replace("_", "a").isalnum() and not e[0].isdigit() and e not in ("true", "false")


def unique_identifier(stem, taken):
    """A GLSL identifier from `stem` not yet in `taken` (a counter appended where needed); adds it."""
    base = _IDENTIFIERS.get(stem) or glsl_identifier(stem)       # (glsl_identifier's look-up, inline)
    name, k = base, 1
    while name in taken:
        k += 1
        name = "%s%d" % (base, k)
    taken.add(name)
    return name
