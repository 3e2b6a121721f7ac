"""Typed graph: a renderable element of a document, resolved against the libraries and flattened.

Every node is matched to its nodedef (MaterialX rules: category, output type, input names and types,
`nodedef=` overrides, versions), every connection is type-checked, nodegraph implementations are
expanded in place (library and document-defined, to any depth), interfacename bindings followed,
defaultgeomprops turned into geometric nodes, defaults filled in. What remains is a list of leaf
nodes in dependency order, each with a GLSL implementation in the node table, plus the public
uniforms of the material. Cycles, unknown nodes and type mismatches are reported with file:line.
"""
from mtlxgen.base.records import replace

from mtlxgen.base import colorspaces, mxtypes
from mtlxgen.graph import graphwalk
from mtlxgen.base.diagnostics import Loc, MtlxError, Problems, Warnings, did_you_mean
# what a document renders (reading's): graph.renderable_elements etc. for the callers
from mtlxgen.read.document import (MAX_LISTED, SHADER_TYPES, UNRENDERABLE_NODE_TYPES,  # noqa: F401
                                   no_element_message, renderable_elements)
# the graph's data types and naming rules live in a leaf module; named here too, as graph.X, for the callers
from mtlxgen.graph.graphtypes import (IDENTIFIER_CHARS, GNode, Graph, Origin, Source, Uniform,  # noqa: F401
                                      glsl_identifier, unique_identifier)
from mtlxgen.read.renamed_inputs import renamed_input_message

# a float port connected to one of these reads its first component (Builder.first_component)
# _default_uniform's records, per process: id(nodedef input) -> (the input, kept so its id stays its own; type,
# value, marked uniform, unit, unittype), or False where public_value must read it (bounded: libraries reloaded)
_DEFAULT_UNIFORMS = {}
_DEFAULT_UNIFORMS_MAX = 1 << 15
# the types such a record is made for: a value of one built-in type (no struct, array, file or string)
_PLAIN_UNIFORM_TYPES = frozenset(("float", "integer", "boolean", "color3", "color4", "vector2", "vector3", "vector4",
                                  "matrix33", "matrix44"))


def _default_uniform(decl):
    """The public uniform an input the document leaves out makes from nodedef input `decl` (GraphBuilder.public_value
    with the nodedef's own port), where nothing else is read: no geometric default, no slip to warn of."""
    if len(_DEFAULT_UNIFORMS) >= _DEFAULT_UNIFORMS_MAX:
        _DEFAULT_UNIFORMS.clear()
    record = False
    if decl.type in _PLAIN_UNIFORM_TYPES and not (decl.defaultgeomprop or decl.error or decl.warning):
        value = decl.value if decl.value is not None else mxtypes.zero(decl.type)
        record = (decl, decl.type, value, bool(decl.uniform), decl.unit, decl.unittype)
    _DEFAULT_UNIFORMS[id(decl)] = record
    return record


# types a public input of which is no uniform (compile-time values)
_NO_UNIFORM = frozenset(("string", "geomname", "stringarray"))
_FIRST_COMPONENT = {"color3": "r", "color4": "r", "vector2": "x", "vector3": "x", "vector4": "x"}


# Nodes of one scope are instantiated without recursion (GraphBuilder.instantiate); what still recurses
# is one scope inside another (a nodegraph output read by another nodegraph, an implementation inside an
# implementation), bounded here so that a document can never exhaust Python's stack.
MAX_SCOPE_DEPTH = 64


class _Scope:
    """A container of nodes being instantiated: the document, a document nodegraph, or an implementation."""
    _serial = 0

    def __init__(self, nodes, prefix, interface, public, graph=None, parent=None, loc=None):
        _Scope._serial += 1
        self.key = _Scope._serial     # memo key: unlike id(), never reused by another scope
        self.nodes = nodes            # name -> document.Node
        self.prefix = prefix          # id prefix for nodes instantiated from here
        self.interface = interface    # interface input name -> Source (implementations / doc nodegraphs)
        self.public = public          # unconnected inputs become public uniforms
        self.graph = graph            # document.NodeGraph for nodegraph scopes
        self.parent = parent
        self.loc = loc


class BuildRules:
    """What the target tells graph building, handed in by the caller (pipeline.py), as MaterialX hands its
    generator to the graph through a context. These are MaterialX's rules alone: a target with no
    implementations of its own. The GLSL target's are nodes.RULES; nodes/usd.SeedRules puts USD's seed rules on top."""

    def nodedef_for(self, node, library):
        """The nodedef a document node resolves to before MaterialX's matching, or None: match as MaterialX."""
        return None

    def output_name(self, category, name, outputs):
        """The output a connection naming output `name` of a node of `category` (outputs: its output names)
        reads; `name` itself where the rules rename nothing."""
        return name

    def implements(self, nodedef, library):
        """Whether the target implements `nodedef` itself: a nodedef the libraries implement by a nodegraph
        is then kept as one node, not expanded."""
        return False


class GraphBuilder:
    def __init__(self, doc, library, rules, functions=False):
        self.doc = doc
        self.functions = functions    # nodegraph implementations called as functions where they can be (functions.py)
        self.rules = rules            # the target's BuildRules (nodedefs it implements, USD's seed rules)
        self.lib = library.overlay(doc)
        self.problems = Problems()
        self.nodes = {}               # id -> GNode
        self.order = []               # ids in completion order (dependencies first)
        self.memo = {}                # (scope key, node name) -> {output: Source}
        self.active = set()
        self.uniforms = {}
        self.used_ids = set(self.lib.structs)     # struct type names are GLSL identifiers too
        self.geom_memo = {}
        self.expanding = []           # nodedefs whose implementation graphs are being expanded
        self.graph_path = []          # "graph.output" of document nodegraph outputs being resolved
        self.direct_graph = None      # the nodegraph whose output is the element drawn (its inputs: sockets)
        self.warnings = Warnings()    # slips MaterialX reads on, met while building (each read as MaterialX reads it)
        self.foreign = False          # it read the document's own nodegraphs, outputs or geompropdefs (functions.py)

    def warn(self, loc, message):
        self.warnings.add(loc, message)

    def note_value(self, port):
        """A port whose own value is read: warn of the slips MaterialX read it past (document.Port.warning)."""
        if port is not None and port.warning:
            self.warn(port.loc, port.warning)

    # ---------- names ----------
    def new_id(self, stem):
        return unique_identifier(stem, self.used_ids)

    def add_node(self, stem, nd, inputs, loc, static=None):
        """A node of nodedef `nd` added to the graph (in order) under a fresh id from `stem`; returns the id."""
        ident = self.new_id(stem)
        self.nodes[ident] = GNode(id=ident, category=nd.category, nodedef=nd, inputs=inputs,
                                  outputs={o.name: o.type for o in nd.outputs.values()}, loc=loc,
                                  static={} if static is None else static)
        self.order.append(ident)
        return ident

    def add_uniform(self, stem, type_name, value, loc, colorspace=None):
        name = self.new_id(stem)
        self.uniforms[name] = Uniform(name, type_name, value, loc, colorspace)
        return name

    # ---------- nodedef resolution ----------
    def nodedef_for(self, node):
        lib = self.lib
        nd = self.rules.nodedef_for(node, lib)
        if nd is not None:
            return nd
        if node.nodedef:
            nd = lib.nodedefs.get(node.nodedef)
            if nd is None:
                raise MtlxError((node.loc, "node '%s' names nodedef '%s', which is not defined" % (node.name, node.nodedef)))
            return nd
        nd = lib.find_nodedef(node.category, node.version, node.type, node.inputs)     # indexed, memoized
        if nd is not None:
            return nd
        # none matches: the scan below finds none either, and says why
        candidates = lib.by_category.get(node.category)
        if not candidates:
            raise MtlxError((node.loc, "unknown node category '%s' (node '%s')%s"
                             % (node.category, node.name, did_you_mean(node.category, lib.by_category))))
        matches = []
        for nd in candidates:
            if node.version:
                if nd.version != node.version:
                    continue
            elif nd.version and not nd.isdefaultversion and any(
                    o.version is None or o.isdefaultversion for o in candidates if o is not nd):
                continue
            if not self._type_matches(node, nd):
                continue
            if all(i.name in nd.inputs and nd.inputs[i.name].type == i.type for i in node.inputs.values()):
                matches.append(nd)
        if matches:
            return matches[0]
        renamed = [(i.loc, renamed_input_message(node.category, i.name)) for i in node.inputs.values()
                   if not any(i.name in nd.inputs for nd in candidates)]
        if any(m for _, m in renamed):
            raise MtlxError([(loc, m) for loc, m in renamed if m])
        typed = [nd for nd in candidates if self._type_matches(node, nd)]
        if not typed:
            raise MtlxError((node.loc, "node '%s': no '%s' nodedef outputs type %s (types: %s)"
                             % (node.name, node.category, node.type, ", ".join(sorted({nd.type for nd in candidates})))))
        at_inputs = self._input_problems(node, typed)
        if at_inputs:
            raise MtlxError(at_inputs)
        sig = ", ".join("%s: %s" % (i.name, i.type) for i in node.inputs.values())
        raise MtlxError((node.loc, "node '%s': no '%s' nodedef of type %s takes inputs (%s)"
                         % (node.name, node.category, node.type, sig)))

    @staticmethod
    def _input_problems(node, nodedefs):
        """Where no nodedef of a node's category and type takes its inputs: each input that none of them takes
        by that name (with the closest names they have), else each input whose type the nodedef that matches
        the most inputs expects otherwise, at the input's own line, naming it, its type and the types expected."""
        problems = []
        names = {n for nd in nodedefs for n in nd.inputs}
        for i in node.inputs.values():
            if i.name not in names:
                problems.append((i.loc, "node '%s' (%s, type %s) has no input '%s'%s"
                                 % (node.name, node.category, node.type, i.name, did_you_mean(i.name, names))))
        if problems:
            return problems
        best = max(nodedefs, key=lambda nd: sum(i.name in nd.inputs and nd.inputs[i.name].type == i.type
                                                for i in node.inputs.values()))
        for i in node.inputs.values():
            want = best.inputs[i.name].type if i.name in best.inputs else None
            if want is not None and want != i.type:
                others = sorted({nd.inputs[i.name].type for nd in nodedefs if i.name in nd.inputs} - {want})
                problems.append((i.loc, "input '%s' of node '%s' has type %s; %s expects %s%s"
                                 % (i.name, node.name, i.type, best.name, want,
                                    " (other %s nodedefs of type %s: %s)" % (node.category, node.type, ", ".join(others))
                                    if others else "")))
        return problems

    @staticmethod
    def _type_matches(node, nd):
        if len(nd.outputs) > 1:
            return node.type in ("multioutput", "")
        return nd.type == node.type

    # ---------- sources ----------
    def source_of_port(self, port, scope, want_type, owner):
        """The Source feeding `port` (an input of a node, or an output) in `scope`; None where nothing is
        connected, or where the connection leads nowhere (warned: MaterialX then reads the port's own value)."""
        if port.error and not port.connected:
            raise MtlxError((port.loc, port.error))
        if port.interfacename:
            src = scope.interface.get(port.interfacename)
            if src is None:
                return self.dangling(port, "input '%s' names interface input '%s', which '%s' does not declare"
                                     % (port.name, port.interfacename,
                                        scope.graph.name if scope.graph else "the document"))
            return src
        if port.nodegraph and not port.nodename:
            self.foreign = True
            g = self.doc.nodegraphs.get(port.nodegraph) or self.lib.nodegraphs.get(port.nodegraph)
            if g is None:
                return self.dangling(port, "input '%s' connects to nodegraph '%s', which does not exist%s"
                                     % (port.name, port.nodegraph, did_you_mean(port.nodegraph, self.doc.nodegraphs)))
            if port.output and port.output not in g.outputs:
                return self.dangling(port, "nodegraph '%s' has no output '%s'%s"
                                     % (g.name, port.output, did_you_mean(port.output, g.outputs)))
            if not g.outputs:
                return self.dangling(port, "nodegraph '%s' has no outputs" % g.name)
            out_name = port.output or next(iter(g.outputs))
            if not port.output and len(g.outputs) > 1:
                self.warn(port.loc, "input '%s' connects to nodegraph '%s', which has %d outputs, without naming one: "
                                    "reads its first, '%s', as MaterialX does" % (port.name, g.name, len(g.outputs), out_name))
            src = self.graph_output(g, g.outputs[out_name])
            if src is None:             # the output holds no connection: MaterialX reads the input's own value
                return self.dangling(port, "output '%s' of nodegraph '%s' is not connected" % (out_name, g.name))
            return src
        if port.nodename:
            node = scope.nodes.get(port.nodename)
            if node is None:
                return self.dangling(port, "'%s' connects to node '%s', which does not exist%s%s"
                                     % (port.name, port.nodename,
                                        " in nodegraph '%s'" % scope.graph.name if scope.graph else "",
                                        did_you_mean(port.nodename, scope.nodes)))
            outs = self.instantiate(node, scope)
            if port.output:
                name = port.output
                if name not in outs:
                    name = self.rules.output_name(node.category, name, outs)
                if name not in outs:
                    first = next(iter(outs))
                    self.warn(port.loc, "node '%s' has no output '%s': '%s' reads its first output, '%s', as MaterialX "
                                        "does" % (node.name, port.output, port.name, first))
                    return outs[first]
                return outs[name]
            if len(outs) == 1:
                return next(iter(outs.values()))
            if "out" in outs:
                return outs["out"]
            first = next(iter(outs))
            self.warn(port.loc, "'%s' connects to multi-output node '%s' without naming an output: reads its first "
                                "output, '%s', as MaterialX does" % (port.name, node.name, first))
            return outs[first]
        if port.output and scope is self.doc_scope:
            self.foreign = True
            return self.document_output(port)
        return None

    def document_output(self, port):
        """An `output` named alone, at the document's level, connects to the document's top-level output of that
        name (as MaterialX's Input::getConnectedOutput reads it: 1.37's bindinput output=, upgraded)."""
        out = self.doc.outputs.get(port.output)
        if out is None or out is port:
            return self.dangling(port, "'%s' connects to output '%s', which the document does not have"
                                 % (port.name, port.output))
        key = "/" + out.name
        if key in self.graph_path:
            cycle = self.graph_path[self.graph_path.index(key):] + [key]
            raise MtlxError((out.loc, "cycle: outputs %s" % " -> ".join("'%s'" % c[1:] for c in cycle)))
        self.graph_path.append(key)
        try:
            src = self.source_of_port(out, self.doc_scope, out.type, out.name)
        finally:
            self.graph_path.pop()
        if src is None:
            return self.dangling(port, "output '%s' is not connected" % out.name)
        return src

    def dangling(self, port, problem):
        """A connection that leads nowhere: MaterialX's generator drops it and reads the port's own value (its
        validator calls the connection invalid). Warned; returns None, the Source of an unconnected port."""
        if port.error:
            raise MtlxError((port.loc, "%s, so its own value is read, and that is malformed: %s" % (problem, port.error)))
        if port.kind == "output":
            self.warn(port.loc, "%s: the connection is ignored, as MaterialX ignores it" % problem)
        else:
            self.warn(port.loc, "%s: the connection is ignored and the input's own value read, as MaterialX does"
                      % problem)
        return None

    def graph_output(self, g, out_port):
        """Source of a document nodegraph's output (its nodes instantiated in the graph's own scope)."""
        key = "%s.%s" % (g.name, out_port.name)
        if key in self.graph_path:        # nodegraphs reading each other's outputs (or their own)
            cycle = self.graph_path[self.graph_path.index(key):] + [key]
            raise MtlxError((out_port.loc, "cycle: nodegraph outputs %s" % " -> ".join("'%s'" % c for c in cycle)))
        if len(self.graph_path) >= MAX_SCOPE_DEPTH:
            raise MtlxError((out_port.loc, "nodegraph outputs read each other more than %d deep (from '%s')"
                             % (MAX_SCOPE_DEPTH, self.graph_path[0])))
        self.graph_path.append(key)
        try:
            return self._graph_output(g, out_port)
        finally:
            self.graph_path.pop()

    def _graph_output(self, g, out_port):
        """The output's Source; None where it holds no connection (a value alone, which MaterialX's generator
        does not read through a connection to the output), or one that leads nowhere."""
        scope = self.doc_graph_scope(g)
        src = self.source_of_port(out_port, scope, out_port.type, g.name)
        if src is None:
            return None
        src = self.check_type(out_port, src, "output '%s' of '%s'" % (out_port.name, g.name))
        return src

    def doc_graph_scope(self, g):
        key = ("graph", g.name)
        if key not in self.memo:
            if key in self.active:
                raise MtlxError((g.loc, "cycle: an input of nodegraph '%s' reads the nodegraph's own output" % g.name))
            self.active.add(key)
            try:
                self.memo[key] = self._doc_graph_scope(g)
            finally:
                self.active.discard(key)
        return self.memo[key]

    def _doc_graph_scope(self, g):
        interface = {}
        nd = self.lib.nodedefs.get(g.nodedef) if g.nodedef else None
        for inp in (nd.inputs.values() if nd else ()):      # an implementation drawn on its own
            if inp.name not in g.inputs:
                if inp.defaultgeomprop and inp.value is None:
                    interface[inp.name] = self.geom_source(inp.defaultgeomprop, inp.loc, None)
                else:
                    interface[inp.name] = self.public_value(g.name, inp, inp, g.name)
        for inp in g.inputs.values():
            src = None
            if inp.nodename or inp.nodegraph or inp.interfacename:     # interfacename: a document input
                src = self.source_of_port(inp, self.doc_scope, inp.type, g.name)
            if src is not None:
                interface[inp.name] = self.check_type(inp, src, "input '%s' of nodegraph '%s'" % (inp.name, g.name))
            elif inp.defaultgeomprop and inp.value is None:
                interface[inp.name] = self.geom_source(inp.defaultgeomprop, inp.loc, None)
            else:
                interface[inp.name] = self.public_value(g.name, inp, inp, g.name, True)
        return _Scope(g.nodes, g.name + "/", interface, True, g, self.doc_scope, g.loc)

    def public_value(self, owner, port, declared, element=None, authored=None):
        """An unconnected input at document level: a public uniform initialised with its value (one that does not
        parse is the input's problem, as for a node's input). element: the name path of the document element whose
        input it is (the uniform's Origin); None inside an implementation (a library's input, not the document's).
        authored: the document writes the input (default: `port` is not `declared`, the nodedef's own)."""
        if port is declared:        # an input the document leaves out (most of a shader node's): read once
            default = _DEFAULT_UNIFORMS.get(id(declared))
            if default is None:
                default = _default_uniform(declared)
            if default:
                _, t, value, marked, unit, unittype = default
                name = unique_identifier(owner + "_" + declared.name, self.used_ids)
                self.uniforms[name] = Uniform(name, t, value, declared.loc, None, None, marked,
                                              None if element is None else
                                              Origin(element, declared.name, bool(authored)))
                return Source(t, value, name, None, None, None, unit, unittype, declared.loc)
        if port.error:
            raise MtlxError((port.loc, port.error))
        value = port.value
        if value is None or port.warning:
            self.note_value(port if value is not None or port.warning else declared)   # value="": its warning
        if value is None:
            value = declared.value
            if value is None:
                value = mxtypes.zero(declared.type, self.lib.structs)
        t = declared.type
        if t in _NO_UNIFORM or t in mxtypes.CLOSURE_NAMES:
            return Source(t, value=value, loc=port.loc)
        colorspace = (port.colorspace or declared.colorspace) if t == "filename" else None
        loc = port.loc
        name = unique_identifier("%s_%s" % (owner, declared.name), self.used_ids)
        self.uniforms[name] = Uniform(name, t, value, loc, colorspace, None, bool(port.uniform or declared.uniform),
                                      None if element is None else
                                      Origin(element, declared.name,
                                             port is not declared if authored is None else authored))
        return Source(t, value, name, None, None, colorspace, port.unit or declared.unit,
                      port.unittype or declared.unittype, loc)

    def color_managed(self, src, port, scope, stem):
        """A node's colour input converted from its active colour space (its own `colorspace`, else its
        node's, nodegraph's or document's) to the working space, as MaterialX's colour management does:
        only values, never connections; a value reaching the input by interfacename counts where MaterialX
        reads the nodegraph through a connection, not where the nodegraph's own output is the element drawn
        (there its inputs are the shader's, unconverted), nor inside a nodedef's implementation (a function
        parameter). A public uniform keeps its authored value and a cmlib node converts it in the shader;
        a constant is converted here."""
        if src.linked or not colorspaces.is_working_space(self.doc.colorspace) or colorspaces.canonical(port.colorspace) is None:
            return src
        if port.interfacename and not (scope.public and scope.graph is not None
                                       and scope.graph.name != self.direct_graph):
            return src
        if not src.uniform:
            return Source(src.type, value=colorspaces.convert_value(port.colorspace, src.value), loc=src.loc,
                          unit=src.unit, unittype=src.unittype)
        nd = self.lib.nodedefs.get(colorspaces.nodedef_name(port.colorspace, src.type))
        if nd is None:          # a library without cmlib: as MaterialX, which then has no transform
            return src
        ident = self.add_node(stem + "_cm", nd, {"in": src}, port.loc)
        return Source(src.type, node=ident, output="out", loc=port.loc)

    @staticmethod
    def check_enum(decl, src, port, node, nd):
        """A string input whose nodedef lists its values (`enum`) must hold one of them: the emitter turns
        the value into code, so anything else would be an undeclared identifier in the shader."""
        allowed = [v.strip() for v in (decl.enum or "").split(",") if v.strip()]
        if allowed and src.value not in allowed and src.value not in ("", None):
            raise MtlxError((port.loc, "node '%s' (%s): %s '%s' is not one of %s"
                             % (node.name, nd.name, decl.name, src.value, ", ".join(allowed))))

    def check_type(self, port, src, what, want=None):
        """`src` as the value of `port` (of type `want`, default the port's own): the same type, or one MaterialX
        passes through unchanged (color3 and vector3, color4 and vector4: one GLSL type), warned and retyped;
        anything else is refused."""
        want = want or port.type
        if src.type == want:
            return src
        if want == "float" and src.type in _FIRST_COMPONENT:
            return self.first_component(port, src, what)
        if not mxtypes.interchangeable(src.type, want):
            raise MtlxError((port.loc, "%s has type %s but is connected to a value of type %s" % (what, want, src.type)))
        self.warn(port.loc, "%s has type %s but is connected to a value of type %s: passed through as %s, as "
                            "MaterialX does (both are %s in GLSL)" % (what, want, src.type, want, mxtypes.glsl_type(want)))
        return replace(src, type=want)

    @staticmethod
    def broadcasts(port, dtype):
        """A float value (no connection) on an input whose named nodedef declares a colour or vector: MaterialX's
        generator writes the nodedef's type built from the one number (`vec3(0.7)`), every component that value."""
        return (port.type == "float" and dtype in _FIRST_COMPONENT and port.value is not None and not port.error
                and not (port.nodename or port.nodegraph or port.interfacename or port.output))

    def first_component(self, port, src, what):
        """A float port connected to a colour or vector: its first component (r or x), warned. MaterialX's GLSL
        assigns the vector to the float (`float x = v;`), which drivers that accept it (NVIDIA's) read as the
        first component and others (Mesa's) refuse to compile."""
        self.warn(port.loc, "%s has type float but is connected to a value of type %s: reads its first component "
                            "(%s), as MaterialX's GLSL does where its shader compiles" % (what, src.type,
                                                                                         _FIRST_COMPONENT[src.type]))
        if src.literal:
            value = src.value
            return Source("float", value=float(value[0]) if isinstance(value, (tuple, list)) else value, loc=port.loc)
        nd = self.lib.nodedefs.get("ND_extract_" + src.type)
        if nd is None:
            raise MtlxError((port.loc, "%s has type float but is connected to a value of type %s (no extract "
                                       "nodedef in the libraries to read its first component)" % (what, src.type)))
        ident = self.add_node("%s_first" % (src.node or src.uniform or "value"), nd,
                              {"in": src, "index": Source("integer", value=0, loc=port.loc)}, port.loc)
        return Source("float", node=ident, output="out", loc=port.loc)

    # ---------- nodes ----------
    def geom_source(self, geomprop_name, loc, scope):
        gp = self.lib.geompropdefs.get(geomprop_name)
        if gp is None:
            gp = self.doc.geompropdefs.get(geomprop_name)
            self.foreign = True
        if gp is None:
            raise MtlxError((loc, "unknown defaultgeomprop '%s'" % geomprop_name))
        if gp.name in self.geom_memo:
            return self.geom_memo[gp.name]
        recipe = self.lib.geom_nodes.get(gp.name)
        if recipe is not None and recipe[0] is gp:      # built before in this library: the same node again
            _, stem, nd, inputs, static, output, otype = recipe
            ident = self.add_node(stem, nd, {k: Source(t, value, None, None, None, None, unit, unittype,
                                                       loc if at is None else at)
                                             for k, t, value, unit, unittype, at in inputs}, loc, dict(static))
            src = self.geom_memo[gp.name] = Source(otype, node=ident, output=output, loc=loc)
            return src
        category = gp.geomprop
        inputs = {}
        if gp.space:
            inputs["space"] = gp.space
        if category in ("texcoord", "geomcolor"):
            inputs["index"] = gp.index
        from mtlxgen.read.document import Node, Port
        node = Node(category=category, name="geomprop_" + gp.name, type=gp.type, loc=loc)
        for k, v in inputs.items():
            t = "string" if k == "space" else "integer"
            node.inputs[k] = Port(name=k, type=t, loc=loc, value=v, text=str(v))
        if category not in self.lib.by_category:
            node = Node(category="geompropvalue", name="geomprop_" + gp.name, type=gp.type, loc=loc)
            node.inputs["geomprop"] = Port(name="geomprop", type="string", loc=loc, value=gp.geomprop, text=gp.geomprop)
        sub = _Scope({node.name: node}, "", {}, False, None, None, loc)
        order, warned = len(self.order), len(self.warnings.items)
        outs = self.instantiate(node, sub)
        src = next(iter(outs.values()))
        self.geom_memo[gp.name] = src
        # the node built, kept for the next graph of this library where it is one leaf node of literal inputs and
        # warned of nothing (else the next graph builds it as this one did: an implementation, a warning)
        made = self.nodes.get(src.node) if src.node is not None else None
        if (gp.name in self.lib.geompropdefs and self.lib.geompropdefs[gp.name] is gp and len(self.order) == order + 1
                and made is not None and self.order[-1] == made.id and made.function is None
                and len(self.warnings.items) == warned and all(v.literal for v in made.inputs.values())):
            self.lib.geom_nodes[gp.name] = (gp, node.name, made.nodedef,
                                            tuple((k, v.type, v.value, v.unit, v.unittype,
                                                   None if v.loc is loc else v.loc)     # (None: the reader's)
                                                  for k, v in made.inputs.items()),
                                            tuple(made.static.items()), src.output, src.type)
        return src

    def instantiate(self, node, scope):
        """Outputs of `node` in `scope` ({output: Source}).

        Without recursion per node: _instantiate is a generator that yields each node of its own scope
        it reads before that node is built; this loop builds it on an explicit stack and resumes the
        reader, so the order of everything created (ids, uniforms) is that of a depth-first recursion,
        while a chain of any length takes no Python stack. Recursion is left only across scopes (a
        nodegraph output read by another, an implementation inside an implementation), bounded by
        MAX_SCOPE_DEPTH."""
        key = (scope.key, node.name)
        if key in self.memo:
            return self.memo[key]
        if key in self.active:
            raise MtlxError((node.loc, "cycle: node '%s' depends on itself" % node.name))
        stack = [(node, self._instantiate(node, scope))]
        self.active.add(key)
        try:
            while stack:
                current, steps = stack[-1]
                try:
                    port, dep = next(steps)
                except StopIteration as done:
                    stack.pop()
                    self.active.discard((scope.key, current.name))
                    self.memo[(scope.key, current.name)] = done.value
                    continue
                dkey = (scope.key, dep.name)
                if dkey in self.memo:
                    continue
                if dkey in self.active:
                    path = [n.name for n, _ in stack]
                    cycle = path[path.index(dep.name):] if dep.name in path else path
                    raise MtlxError((port.loc, "cycle: %s" % " -> ".join("'%s'" % n for n in cycle + [dep.name])))
                self.active.add(dkey)
                stack.append((dep, self._instantiate(dep, scope)))
        finally:
            for n, _ in stack:
                self.active.discard((scope.key, n.name))
        return self.memo[key]

    @staticmethod
    def names_nodedef(node):
        """Whether the document names the node's nodedef (`nodedef=`, as written in a .mtlx file): MaterialX then
        takes that nodedef as it is, without matching the node's inputs to it."""
        return bool(node.nodedef) and "nodedef" in node.attrs

    def check_named_nodedef(self, node, nd):
        """A nodedef= naming a nodedef of another node or type: MaterialX draws the nodedef named (warned)."""
        if nd.category.split(":")[-1] != node.category.split(":")[-1]:
            self.warn(node.loc, "node '%s' is a %s but names nodedef %s, of node %s: drawn as %s, as MaterialX draws it"
                      % (node.name, node.category, nd.name, nd.category, nd.category))
        if len(nd.outputs) == 1 and node.type and node.type != nd.type:
            self.warn(node.loc, "node '%s' has type %s but its nodedef %s outputs %s: read as %s, as MaterialX reads it"
                      % (node.name, node.type, nd.name, nd.type, nd.type))

    def _instantiate(self, node, scope):
        """Generator: yields (port, node) for each same-scope node to build first; returns the outputs."""
        nd = self.nodedef_for(node)
        named = self.names_nodedef(node) and nd is self.lib.nodedefs.get(node.nodedef)
        if named:
            self.check_named_nodedef(node, nd)
        for name, port in node.inputs.items():
            if name not in nd.inputs:
                problem = (renamed_input_message(node.category, name) or
                           "node '%s' (%s) has no input '%s'%s" % (node.name, nd.name, name,
                                                                   did_you_mean(name, nd.inputs)))
                if not named:
                    raise MtlxError((port.loc, problem))
                self.warn(port.loc, "%s: ignored, as MaterialX ignores an input the nodedef a node names lacks" % problem)
        stem = scope.prefix + node.name if scope.prefix and not scope.public else node.name
        inputs, static = {}, {}
        node_port = node.inputs.get
        public, memo, scope_key = scope.public, self.memo, scope.key
        # the name path of the element whose public inputs these are (their uniforms' Origin)
        element = ((scope.graph.name + "/" if scope.graph is not None else "") + node.name) if public else None
        for name, decl in nd.inputs.items():
            port = node_port(name)
            dtype = decl.type
            src = None
            if port is not None:
                if port.type != dtype:
                    problem = "input '%s' of node '%s' has type %s; %s expects %s" % (name, node.name, port.type,
                                                                                     nd.name, dtype)
                    if named and self.broadcasts(port, dtype):
                        self.warn(port.loc, "%s: its value %s is read as %s, every component %s, as MaterialX reads "
                                            "it where a node names its nodedef" % (problem, port.value, dtype, port.value))
                        port = replace(port, type=dtype, value=(float(port.value),) * mxtypes.components(dtype))
                    elif not (named and mxtypes.interchangeable(port.type, dtype)):
                        raise MtlxError((port.loc, problem))
                    else:
                        self.warn(port.loc, "%s: read as %s, as MaterialX does where a node names its nodedef"
                                  % (problem, dtype))
                if port.nodename or port.nodegraph or port.interfacename or port.output:
                    if port.nodename and not port.interfacename and not (port.error and not port.connected):
                        dep = scope.nodes.get(port.nodename)        # a node of this scope not built yet:
                        if dep is not None and (scope_key, dep.name) not in memo:
                            yield port, dep                 # instantiate() builds it, then resumes here
                    src = self.source_of_port(port, scope, dtype, node.name)
                    if src is not None:
                        if src.type != port.type:
                            src = self.check_type(port, src, "input '%s' of node '%s'" % (name, node.name))
                        if src.type != dtype:       # declared as the interchangeable type (warned above)
                            src = replace(src, type=dtype)
                elif port.error:                    # no connection: its own value, which does not parse
                    raise MtlxError((port.loc, port.error))
            if src is None and decl.defaultgeomprop:
                # an unconnected input with a default geomprop reads the geometry even where the document
                # authors a value (as MaterialX's generator does: gltf_pbr_default's normal = (0, 0, 1))
                src = self.geom_source(decl.defaultgeomprop, (port or decl).loc if port else node.loc, scope)
            if src is None:
                p = port if port is not None else decl
                if p.error:
                    raise MtlxError((p.loc, p.error))
                if public or dtype == "filename":
                    src = self.public_value(stem, p, decl, element)
                else:
                    q = p if p.value is not None or p.warning else decl
                    if q.warning:
                        self.warn(q.loc, q.warning)
                    value = p.value if p.value is not None else decl.value
                    if value is None:
                        value = mxtypes.zero(dtype, self.lib.structs)
                    src = Source(dtype, value, None, None, None, None, p.unit or decl.unit,
                                 p.unittype or decl.unittype, p.loc)
            if port is not None and (dtype == "color3" or dtype == "color4") and port.colorspace:
                src = self.color_managed(src, port, scope, "%s_%s" % (stem, name))
            if (dtype == "string" or dtype == "geomname") and src.node is None:
                static[name] = src.value
                if decl.enum:
                    self.check_enum(decl, src, port or decl, node, nd)
            inputs[name] = src
        impl_graph = self.lib.graph_impls.get(nd.name)
        if impl_graph is not None and not self._has_leaf_impl(nd):
            if nd.name in self.expanding:
                raise MtlxError((impl_graph.loc, "nodegraph '%s' implements %s and uses it inside itself"
                                 % (impl_graph.name, nd.name)))
            if len(self.expanding) >= MAX_SCOPE_DEPTH:
                raise MtlxError((node.loc, "nodegraph implementations nest more than %d deep (from %s)"
                                 % (MAX_SCOPE_DEPTH, self.expanding[0])))
            if self.functions:
                from mtlxgen.graph.functions import function_for
                family = function_for(self, nd, impl_graph, inputs)
                if family is not None:          # one call node: the body is emitted once, as a function
                    ident = self.add_node(stem, nd, {k: s for k, s in inputs.items() if k in family.reads}, node.loc,
                                          static)
                    self.nodes[ident].function = family
                    return {oname: Source(t, node=ident, output=oname, loc=node.loc)
                            for oname, t in self.nodes[ident].outputs.items()}
            self.expanding.append(nd.name)
            try:
                return self._expand(node, nd, impl_graph, inputs, stem, scope)
            finally:
                self.expanding.pop()
        ident = self.add_node(stem, nd, inputs, node.loc, static)
        return {oname: Source(t, node=ident, output=oname, loc=node.loc)
                for oname, t in self.nodes[ident].outputs.items()}

    def _expand(self, node, nd, impl_graph, inputs, stem, scope):
        """Instantiate a nodegraph implementation in place of `node`; returns its output sources, in the
        nodedef's order. Outputs pair by name, as the spec says; a graph whose output names are not the
        nodedef's but as many pairs by position, as MaterialX pairs them (warned)."""
        inner = _Scope(impl_graph.nodes, self.child_prefix(stem), inputs, False, impl_graph, scope, node.loc)
        pairs = [(oname, impl_graph.outputs[oname]) for oname in nd.outputs if oname in impl_graph.outputs]
        if len(pairs) < len(nd.outputs):
            missing = next(o for o in nd.outputs if o not in impl_graph.outputs)
            if len(impl_graph.outputs) != len(nd.outputs):
                raise MtlxError((impl_graph.loc, "nodegraph '%s' implements %s but has no output '%s'"
                                 % (impl_graph.name, nd.name, missing)))
            pairs = list(zip(nd.outputs, impl_graph.outputs.values()))
            self.warn(impl_graph.loc, "nodegraph '%s' implements %s but names its outputs %s where %s declares %s: "
                                      "paired by position, as MaterialX pairs them"
                      % (impl_graph.name, nd.name, ", ".join("'%s'" % o for o in impl_graph.outputs), nd.name,
                         ", ".join("'%s'" % o for o in nd.outputs)))
        outs = {}
        for oname, oport in pairs:
            src = self.source_of_port(oport, inner, oport.type, impl_graph.name)
            if src is None:
                self.note_value(oport)
                value = oport.value if oport.value is not None else mxtypes.zero(oport.type, self.lib.structs)
                src = Source(oport.type, value=value, loc=oport.loc)
            outs[oname] = self.check_type(oport, src, "output '%s' of nodegraph '%s' (%s's output '%s')"
                                          % (oport.name, impl_graph.name, nd.name, oname),
                                          want=nd.outputs[oname].type)
        return outs

    def child_prefix(self, stem):
        return stem + "_" if stem else ""

    def expand_implementation(self, nd, impl_graph, inputs, stem, loc):
        """The output Sources of nodegraph implementation `impl_graph` of `nd` instantiated over `inputs` (a function's
        body: functions.py), its node ids from `stem`."""
        if len(self.expanding) > MAX_SCOPE_DEPTH:
            raise MtlxError((loc, "nodegraph implementations nest more than %d deep (from %s)"
                             % (MAX_SCOPE_DEPTH, self.expanding[0])))
        return self._expand(_At(loc), nd, impl_graph, inputs, stem, None)

    def upstream(self, sources):
        """The nodes `sources` depend on, in the order they were made (dependencies first)."""
        needed = graphwalk.upstream(self.nodes, sources)
        return [self.nodes[i] for i in self.order if i in needed]

    def _has_leaf_impl(self, nd):
        return self.rules.implements(nd, self.lib)

    # ---------- elements ----------
    @property
    def doc_scope(self):
        if "_doc_scope" not in self.__dict__:
            # top-level <input>s: the document's own interface, public uniforms like any other
            interface = {i.name: self.public_value("doc", i, i, "", True) for i in self.doc.inputs.values()}
            self._doc_scope = _Scope(self.doc.nodes, "", interface, True, None, None, None)
        return self._doc_scope

    def build(self, element):
        """Build the Graph of one renderable element name path."""
        kind, result = self._element_result(element)
        return self.build_result(result, element, kind)

    def build_result(self, result, element, kind="output"):
        """The pruned, ordered Graph of everything `result` depends on."""
        nodes = self.upstream([result])         # prune: only the nodes the result needs
        used_uniforms = {s.uniform for n in nodes for s in n.inputs.values() if s.uniform}
        if result.uniform:
            used_uniforms.add(result.uniform)
        uniforms = {k: u for k, u in self.uniforms.items() if k in used_uniforms}
        g = Graph(element=element, kind=kind, result=result, nodes=nodes, uniforms=uniforms,
                  structs=self.lib.structs, doc_path=self.doc.path, library=self.lib,
                  colorspace=self.doc.colorspace)
        return g

    def _element_result(self, element):
        doc = self.doc
        if "/" in element:
            gname, oname = element.split("/", 1)
            g = doc.nodegraphs.get(gname)
            if g is None or oname not in g.outputs:
                raise MtlxError((Loc(doc.path, 0), no_element_message(doc, element)))
            self.direct_graph = gname
            out_port = g.outputs[oname]
            src = self.graph_output(g, out_port)
            if src is None:             # drawn on its own: an output holding a value alone draws it
                if out_port.value is None:
                    raise MtlxError((out_port.loc, "output '%s' of nodegraph '%s' is not connected" % (oname, gname)))
                self.note_value(out_port)
                src = Source(out_port.type, value=out_port.value, loc=out_port.loc)
            return "output", src
        if element in doc.outputs:
            port = doc.outputs[element]
            src = self.source_of_port(port, self.doc_scope, port.type, element)
            if src is None:
                raise MtlxError((port.loc, "output '%s' is not connected" % element))
            src = self.check_type(port, src, "output '%s'" % element)
            return "output", src
        node = doc.nodes.get(element)
        if node is None:
            raise MtlxError((Loc(doc.path, 0), no_element_message(doc, element)))
        outs = self.instantiate(node, self.doc_scope)
        src = outs.get("out") or next(iter(outs.values()))
        if node.type == "material":
            # a material renders its surface shader
            shader = outs.get("out")
            return "material", shader
        return "shader", src


class _At:
    """What _expand reads of the node it expands (its place): a function's body has none but the nodegraph's."""
    __slots__ = ("loc",)

    def __init__(self, loc):
        self.loc = loc


def build_graph(doc, library, element, rules, warnings=None, functions=False):
    """The Graph of one element under the target's BuildRules `rules`. warnings: a list that receives the
    element's warnings (also where building stops with an MtlxError); they are the Graph's `warnings` too.
    functions: nodegraph implementations become call nodes where they can (functions.py; the complete interface)."""
    builder = GraphBuilder(doc, library, rules, functions)
    try:
        g = builder.build(element)
        g.warnings = list(builder.warnings.items)
        return g
    finally:
        if warnings is not None:
            warnings.extend(builder.warnings.items)
