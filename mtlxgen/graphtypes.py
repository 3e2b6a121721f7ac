"""The typed graph's data and naming rules: what graph building produces and emission reads.

Plain dataclasses (Source, GNode, Uniform, Graph) and the GLSL identifier rules that give nodes and
uniforms their names (glsl_identifier, unique_identifier). A leaf: it knows no document reader, no node
table and no target, so both sides of the pipeline can share it without importing each other.
"""
import re
from dataclasses import dataclass, field

from .diagnostics import Loc


@dataclass(slots=True)
class Source:
    """Where an input's value comes from: a constant, a public uniform, or another node's output."""
    type: str
    value: object = None              # constant value (also the uniform's initial value)
    uniform: str = None               # public uniform name, when the value is exposed
    node: str = None                  # producing node id, when linked
    output: str = None                # producing node's output name
    colorspace: str = None            # filename inputs: the file's colour space
    unit: str = None
    unittype: str = None
    loc: Loc = None

    @property
    def linked(self):
        return self.node is not None

    @property
    def literal(self):
        """A constant in the code: neither connected nor a uniform."""
        return self.node is None and self.uniform is None


@dataclass(slots=True)
class GNode:
    id: str                           # unique within the graph; also the stem of its GLSL variables
    category: str
    nodedef: object                   # document.NodeDef
    inputs: dict                      # input name -> Source, in nodedef order
    outputs: dict                     # output name -> type
    loc: Loc
    static: dict = field(default_factory=dict)   # string/enum inputs: name -> value (compile time)
    function: object = None           # functions.Function: the node calls its nodegraph implementation's function


@dataclass(frozen=True, slots=True)
class Origin:
    """Where a public uniform comes from in the document: the input `input` of the element at name path `element`
    (a node at the document's level "N", a node in a nodegraph "NG/N", a nodegraph's own input "NG", the document's
    top-level inputs ""). authored: the document writes the input (else its value is the nodedef's default). The
    viewer's value edits and the write-back (docedit.py) find the input from here."""
    element: str
    input: str
    authored: bool = True


@dataclass(slots=True)
class Uniform:
    name: str
    type: str
    value: object
    loc: Loc = None
    colorspace: str = None            # filename uniforms only
    default: object = None            # image nodes: the colour outside the image
    marked: bool = False              # the document marks it uniform="true" (the input or its nodedef's): kept
                                      # a uniform in the reduced interface (reduce.py)
    origin: Origin = None             # the document input it comes from (None: one emission or a library made)


@dataclass
class Graph:
    element: str                      # name path of the renderable element
    kind: str                         # "material", "shader" or "output"
    result: Source                    # the value rendered
    nodes: list                       # GNode in dependency order, only those the result needs
    uniforms: dict                    # name -> Uniform (public inputs)
    structs: dict
    doc_path: str
    library: object = None
    colorspace: str = None            # the document's working colour space (None: files are not converted)
    warnings: list = field(default_factory=list)   # (Loc, message): slips MaterialX reads on, read as it reads them
    # a function's body (functions.py): {output name: Source} it returns, {input name: parameter name} it takes
    outputs: dict = None
    parameters: dict = None
    # closure guards are decided on literal inputs at generation time (the fold pass: the reduced interface)
    static_guards: bool = False
    closure_plan: object = None       # closureplan.ClosurePlan (the closures pass; the emitter makes one where none)


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
