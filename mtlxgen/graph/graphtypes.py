"""The typed graph's data and naming rules: what graph building produces and emission reads.

Plain dataclasses (Source, GNode, Uniform, Graph) and the GLSL identifier rules that give nodes and
uniforms their names (glsl_identifier, unique_identifier). A leaf: it knows no document reader, no node
table and no target, so both sides of the pipeline can share it without importing each other.
"""
from collections import namedtuple
from mtlxgen.base.records import dataclass, field

from mtlxgen.base.diagnostics import Loc
# the GLSL identifier rules nodes and uniforms are named by (base: reading names stems too); graphtypes.X
from mtlxgen.base.identifiers import (IDENTIFIER_CHARS, glsl_identifier, is_plain_name,  # noqa: F401
                                      sha256, unique_identifier)


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


Origin = namedtuple("Origin", "element input authored", defaults=(True,))
Origin.__doc__ = (
    "Where a public uniform comes from in the document: the input `input` of the element at name path `element` (a "
    "node at the document's level \"N\", a node in a nodegraph \"NG/N\", a nodegraph's own input \"NG\", the "
    "document's top-level inputs \"\"). authored: the document writes the input (else its value is the nodedef's "
    "default). The viewer's value edits and the write-back (docedit.py) find the input from here. A named tuple: one "
    "is made for each public uniform of every element.")


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
    # application uniforms read as constants at their defaults (the reduced interface: interface.PROGRESSIVE)
    app_constants: frozenset = frozenset()
