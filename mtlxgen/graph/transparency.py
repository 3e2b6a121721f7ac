"""The manifest's transparency flag: whether a surface may be see-through, as MaterialX's isTransparentSurface
tells it (a host sorts and blends it)."""


# The inputs of a surface shader that make it see-through, with the value at which they are opaque: those MaterialX's
# isTransparentSurface reads (standard_surface, open_pbr_surface and UsdPreviewSurface reach them through the nodes
# their nodegraphs are made of).
TRANSPARENCY_INPUTS = (("opacity", 1.0), ("existence", 1.0), ("alpha", 1.0), ("transmission", 0.0),
                      # the inputs MaterialX's nodedefs mark hint="opacity" / hint="transparency" (open_pbr_surface)
                      ("geometry_opacity", 1.0), ("transmission_weight", 0.0))
PASS_THROUGH_GROUPS = ("adjustment", "channel")     # an input fed through these alone does not count as connected
_OPAQUE_EPSILON = 1e-5


def transparent_surface(doc, lib, element):
    """Whether element `element` of `doc` is a surface that may be see-through, as MaterialX's isTransparentSurface
    tells it (a host sorts and blends it): the material's shader (or the element's) has an opacity-like input
    (TRANSPARENCY_INPUTS) fed by a node other than an adjustment or channel one, or set away from opaque; a mix of shaders, either
    of its shaders; a shader made of a nodegraph, any surface shader in it, read against the outer node's inputs.
    Values are the document's (a host that changes such a uniform at run time decides again)."""
    top = _Scope(doc.nodes, doc.nodegraphs, None, None, lib)
    graph_name, _, output = element.partition("/")
    if output and graph_name in doc.nodegraphs:
        g = doc.nodegraphs[graph_name]
        port, scope = g.outputs.get(output), _Scope(g.nodes, {}, g, top, lib)
    else:
        port, scope = doc.outputs.get(element), top
    if port is not None:
        node, scope = scope.upstream(port)
    else:
        node = doc.nodes.get(element)
    if node is not None and node.category == "surfacematerial":
        shader = node.inputs.get("surfaceshader")
        node, scope = scope.upstream(shader) if shader is not None else (None, scope)
    if node is None or node.type != "surfaceshader":
        return False
    if _shader_transparent(node, scope, None):
        return True
    impl = scope.implementation(node)
    if impl is None or not impl.outputs:
        return False
    out = next(iter(impl.outputs.values()))
    if out.type != "surfaceshader":
        return False
    # the walk through the implementation reads the outer node only through the inputs its shaders name: walked once
    # per implementation (and library), recording those; then only they are read, for each node
    entry = _WALKS.get(id(impl))
    if entry is None or entry[0] is not impl or entry[1] is not lib:
        if len(_WALKS) >= _WALKS_MAX:
            _WALKS.clear()
        reads = _Reads()
        entry = _WALKS[id(impl)] = (impl, lib, _graph_transparent(out, _Scope(impl.nodes, {}, impl, scope, lib), reads),
                                    tuple(reads.names))
    outer = _Outer(node)
    return entry[2] or any(outer.see_through(name, opaque) for name, opaque in entry[3])


_WALKS = {}             # id(implementation) -> (implementation, library, see-through whatever the node, [(input, opaque)])
_WALKS_MAX = 256


class _Outer:
    """The node whose implementation is walked: whether its input `name` makes it see-through (connected, or a value
    away from `opaque`)."""
    __slots__ = ("node",)

    def __init__(self, node):
        self.node = node

    def see_through(self, name, opaque):
        port = self.node.inputs.get(name)
        return port is not None and (port.connected or _away_from(port.value, opaque))


class _Reads:
    """An outer node not known yet: records what the walk would read of it, and reads nothing."""
    __slots__ = ("names",)

    def __init__(self):
        self.names = []

    def see_through(self, name, opaque):
        if (name, opaque) not in self.names:
            self.names.append((name, opaque))
        return False


class _Scope:
    """Where names are looked up: a document's or a nodegraph's nodes, the document's nodegraphs, the nodegraph
    whose inputs `interfacename` names, the scope around it, and the library (nodedefs, implementations)."""
    __slots__ = ("nodes", "graphs", "graph", "outer", "lib")

    def __init__(self, nodes, graphs, graph, outer, lib):
        self.nodes, self.graphs, self.graph, self.outer, self.lib = nodes, graphs, graph, outer, lib

    def upstream(self, port):
        """(the node a port is connected to, its scope), or (None, self): through nodegraph outputs too."""
        if port.nodegraph and port.nodegraph in self.graphs:
            g = self.graphs[port.nodegraph]
            out = g.outputs.get(port.output) if port.output else next(iter(g.outputs.values()), None)
            return (None, self) if out is None else _Scope(g.nodes, {}, g, self, self.lib).upstream(out)
        if port.nodename:
            return self.nodes.get(port.nodename), self
        return None, self

    def interface_input(self, name):
        """The input an `interfacename` names: the nodegraph's nodedef's (its default), else the nodegraph's own."""
        if self.graph is None:
            return None
        nd = self.lib.nodedefs.get(self.graph.nodedef) if self.graph.nodedef and self.lib is not None else None
        return (nd.inputs if nd is not None else self.graph.inputs).get(name)

    def nodedef(self, node):
        if self.lib is None:
            return None
        if node.nodedef and node.nodedef in self.lib.nodedefs:
            return self.lib.nodedefs[node.nodedef]
        return self.lib.find_nodedef(node.category, node.version, node.type, node.inputs)

    def implementation(self, node):
        nd = self.nodedef(node)
        return self.lib.graph_impls.get(nd.name) if nd is not None else None


def _shader_transparent(node, scope, interface_node):
    """One surface shader node's own inputs (MaterialX's rule)."""
    if node.type != "surfaceshader":
        return False
    if node.category == "mix":
        for name in ("fg", "bg"):
            port = node.inputs.get(name)
            inner = scope.upstream(port)[0] if port is not None else None
            if inner is not None and _shader_transparent(inner, scope, None):
                return True
        return False
    if interface_node is not None:          # inside a shader's nodegraph: the outer node's inputs they name
        for name, opaque in TRANSPARENCY_INPUTS:
            port = node.inputs.get(name)
            if port is not None and port.interfacename and interface_node.see_through(port.interfacename, opaque):
                return True
    for name, opaque in TRANSPARENCY_INPUTS:
        port = node.inputs.get(name)
        if port is None:
            continue
        here = scope
        if port.interfacename:
            port = scope.interface_input(port.interfacename)
            if port is None:
                return False
            here = scope.outer or scope
        source = here.upstream(port)[0] if (port.nodename or port.nodegraph) else None
        if source is not None:
            nd = here.nodedef(source)
            if nd is None or nd.nodegroup not in PASS_THROUGH_GROUPS:
                return True
        elif _away_from(port.value, opaque):
            return True
    return False


def _graph_transparent(output, scope, interface_node):
    """Any shader upstream of a nodegraph's output (and inside the nodegraphs of BSDF nodes there) see-through."""
    seen, stack = set(), [scope.upstream(output)[0]]
    while stack:
        node = stack.pop()
        if node is None or id(node) in seen:
            continue
        seen.add(id(node))
        if _shader_transparent(node, scope, interface_node):
            return True
        if node.type == "BSDF":
            impl = scope.implementation(node)
            if impl is not None and impl.outputs and _graph_transparent(
                    next(iter(impl.outputs.values())), _Scope(impl.nodes, {}, impl, scope, scope.lib), _Outer(node)):
                return True
        stack.extend(scope.upstream(p)[0] for p in node.inputs.values() if p.nodename)
    return False


def _away_from(value, opaque):
    """A value MaterialX reads as not opaque: a float or colour3 off `opaque`, any other value."""
    if value is None:
        return False
    values = value if isinstance(value, (tuple, list)) else (value,)
    if len(values) not in (1, 3) or not all(isinstance(v, (int, float)) for v in values):
        return True
    return any(abs(float(v) - opaque) >= _OPAQUE_EPSILON for v in values)
