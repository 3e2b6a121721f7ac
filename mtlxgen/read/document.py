"""The document model: typed dataclasses for the MaterialX elements, built from the XML tree.

Values are parsed into Python values of their type; fileprefix / geomprefix / colorspace are
inherited down the tree and applied here, so later stages never look at ancestors.
"""
from mtlxgen.base.records import dataclass, field

from mtlxgen.base import mxtypes
from mtlxgen.base.diagnostics import did_you_mean, Loc, MtlxError, Problems
from mtlxgen.read.xmlreader import gc_paused, read_file

# Element tags that are not nodes.
NON_NODE_TAGS = {
    "nodedef", "nodegraph", "implementation", "typedef", "geompropdef", "look", "lookgroup", "collection",
    "geominfo", "propertyset", "propertysetassign", "variantset", "variantassign", "backdrop", "unitdef",
    "unittypedef", "attributedef", "targetdef", "member", "input", "output", "token", "parameter", "comment",
    "materialassign", "visibility", "variant", "geomprop", "property", "unit", "materialx",
}


@dataclass
class Port:
    """An <input>, <output> or <token> of a node, nodedef or nodegraph."""
    name: str
    type: str
    loc: Loc
    kind: str = "input"
    value: object = None            # parsed value (None where the port carries none)
    text: str = None                # the value string as written (after prefixes)
    nodename: str = None
    nodegraph: str = None
    output: str = None
    interfacename: str = None
    defaultgeomprop: str = None
    defaultinput: str = None
    colorspace: str = None
    unit: str = None
    unittype: str = None
    uniform: bool = False
    enum: str = None
    enumvalues: str = None
    channels: str = None            # 1.38 swizzle on inputs (upgraded away)
    error: str = None               # a value that does not parse: reported where the port is used
    warning: str = None             # a value MaterialX reads past a slip in ('0.5.0'): warned where the port is used

    @property
    def connected(self):
        return bool(self.nodename or self.nodegraph or self.interfacename)


@dataclass
class Node:
    category: str
    name: str
    type: str
    loc: Loc
    inputs: dict = field(default_factory=dict)      # name -> Port
    outputs: dict = field(default_factory=dict)     # name -> Port (declared outputs of multi-output nodes)
    tokens: dict = field(default_factory=dict)
    nodedef: str = None
    version: str = None
    attrs: dict = field(default_factory=dict)


@dataclass
class NodeDef:
    name: str
    category: str
    loc: Loc
    inputs: dict = field(default_factory=dict)
    outputs: dict = field(default_factory=dict)
    tokens: dict = field(default_factory=dict)
    inherit: str = None
    version: str = None
    isdefaultversion: bool = False
    nodegroup: str = None
    target: str = None
    source: str = ""                # which library it came from ("stdlib", ..., or "document")

    @property
    def type(self):
        return next(iter(self.outputs.values())).type if len(self.outputs) == 1 else "multioutput"


@dataclass
class NodeGraph:
    name: str
    loc: Loc
    nodedef: str = None
    inputs: dict = field(default_factory=dict)
    outputs: dict = field(default_factory=dict)
    tokens: dict = field(default_factory=dict)
    nodes: dict = field(default_factory=dict)
    version: str = None


@dataclass
class Implementation:
    name: str
    loc: Loc
    nodedef: str = None
    file: str = None
    function: str = None
    sourcecode: str = None
    target: str = None
    nodegraph: str = None


@dataclass
class GeomPropDef:
    name: str
    type: str
    geomprop: str
    loc: Loc
    space: str = None
    index: int = 0
    attrs: dict = field(default_factory=dict)


@dataclass
class Document:
    path: str
    version: str = "1.39"
    colorspace: str = None
    nodedefs: dict = field(default_factory=dict)
    nodegraphs: dict = field(default_factory=dict)
    nodes: dict = field(default_factory=dict)           # top-level nodes
    outputs: dict = field(default_factory=dict)         # top-level outputs
    inputs: dict = field(default_factory=dict)          # top-level inputs (rare)
    implementations: dict = field(default_factory=dict)
    structs: dict = field(default_factory=dict)         # name -> mxtypes.StructType
    geompropdefs: dict = field(default_factory=dict)
    unitdefs: dict = field(default_factory=dict)        # unittype -> {unit name: scale}
    looks: dict = field(default_factory=dict)
    order: list = field(default_factory=list)           # top-level element names in document order
    warnings: list = field(default_factory=list)        # (Loc, message): slips MaterialX reads on, document-wide


def version_tuple(v):
    try:
        return tuple(int(x) for x in (v or "0").split("."))
    except ValueError:
        return (0,)


# port attributes kept as the document writes them (Port fields of the same names)
_PORT_TEXT_ATTRS = frozenset(("nodename", "nodegraph", "output", "interfacename", "defaultgeomprop", "defaultinput",
                              "colorspace", "unit", "unittype", "enum", "enumvalues", "channels"))


class _Builder:
    def __init__(self, doc, problems):
        self.doc = doc
        self.problems = problems

    def port(self, el, ctx, kind, declared=False):
        """A Port of <input>, <output> or <token> `el`; declared: it is a nodedef's (its value a default)."""
        a = el.attrs
        name = a.get("name")
        if not name:
            self.problems.add(el.loc, "<%s> without a name" % el.tag)
            name = "?"
        type_name = a.get("type", "")
        if not type_name and kind != "token":
            self.problems.add(el.loc, "%s '%s' has no type" % (kind, name))
        p = Port(name, type_name or "string", el.loc, kind)
        for key in a:                       # the attributes a port keeps as written (most ports have none)
            if key in _PORT_TEXT_ATTRS:
                setattr(p, key, a[key])
        if "uniform" in a:
            p.uniform = a["uniform"] == "true"
        text = a.get("value")
        if text is not None:
            if p.type == "filename" and ctx.get("fileprefix") and text:
                text = ctx["fileprefix"] + text
            if p.type in ("geomname", "geomnamearray") and ctx.get("geomprefix") and text:
                text = ctx["geomprefix"] + text
            p.text = text
            slips = []
            try:
                if not text.strip() and p.type in self.doc.structs and not declared:
                    # a nodedef's empty struct default MaterialX reads as none; an instance's, it cannot read
                    raise mxtypes.ValueError_("the value is empty, which MaterialX cannot read for a struct here "
                                              "(only a nodedef's empty value reads as no value)")
                p.value = mxtypes.parse_value(p.type, text, self.doc.structs, slips)
            except mxtypes.ValueError_ as e:
                p.error = "%s '%s' of type %s: %s" % (kind, name, p.type, e)
            else:
                if slips:
                    p.warning = "%s '%s' of type %s: %s" % (kind, name, p.type, "; ".join(slips))
        if p.type in ("filename", "color3", "color4") and p.colorspace is None:
            p.colorspace = ctx.get("colorspace")      # its active colour space: node's, nodegraph's, document's
        return p

    def repeated(self, el, what):
        """Children of `el` named like an earlier sibling (of any kind: an element's children share one namespace).
        MaterialX's reader keeps the first of each name and drops the others: so do we, with a warning each."""
        seen, dropped = set(), set()
        for c in el.children:
            name = c.get("name")
            if name is None or c.tag == "typedef":          # typedefs: refused when repeated (_struct_types)
                continue
            if name in seen:
                dropped.add(id(c))
                self.doc.warnings.append((c.loc, "<%s> '%s' repeats the name of an earlier element in %s; MaterialX "
                                                 "reads the first and drops this one" % (c.tag, name, what)))
            seen.add(name)
        return dropped

    def ports_of(self, el, ctx, target, dropped=None):
        if dropped is None:
            dropped = self.repeated(el, "%s '%s'" % (el.tag, el.get("name", "")))
        for c in el.children:
            if id(c) in dropped:
                continue
            if c.tag == "parameter" and version_tuple(self.doc.version) >= (1, 38):
                # MaterialX upgrades <parameter> to <input> only in documents older than 1.38 (which removed
                # the element); in a newer document it keeps it as an unknown child, which sets nothing
                self.doc.warnings.append((c.loc, "<parameter> '%s' in a %s document: MaterialX 1.38 replaced "
                                                 "<parameter> with <input>, so MaterialX ignores it (as we do)"
                                          % (c.get("name", ""), self.doc.version)))
                continue
            if c.tag in ("input", "parameter"):
                p = self.port(c, ctx, "input", isinstance(target, NodeDef))
                target.inputs[p.name] = p
            elif c.tag == "output":
                p = self.port(c, ctx, "output")
                target.outputs[p.name] = p
            elif c.tag == "token":
                p = self.port(c, ctx, "token")
                target.tokens[p.name] = p

    def node(self, el, ctx):
        a = el.attrs
        n = Node(category=el.tag, name=a.get("name", ""), type=a.get("type", ""), loc=el.loc,
                 nodedef=a.get("nodedef"), version=a.get("version"), attrs=dict(a))
        if not n.name:
            self.problems.add(el.loc, "<%s> node without a name" % el.tag)
        if not n.type:
            self.problems.add(el.loc, "node '%s' has no type" % n.name)
        self.ports_of(el, ctx, n)
        return n

    def nodedef(self, el, ctx, source):
        a = el.attrs
        ns = ctx.get("namespace")
        nd = NodeDef(name=_qualify(ns, a.get("name", "")), category=_qualify(ns, a.get("node", "")), loc=el.loc,
                     inherit=_qualify(ns, a.get("inherit")),
                     version=a.get("version"), isdefaultversion=a.get("isdefaultversion") == "true",
                     nodegroup=a.get("nodegroup"), target=a.get("target"), source=source)
        self.ports_of(el, ctx, nd)
        if not nd.outputs and a.get("type"):
            nd.outputs["out"] = Port(name="out", type=a["type"], loc=el.loc, kind="output")
        return nd

    def nodegraph(self, el, ctx):
        a = el.attrs
        ns = ctx.get("namespace")
        g = NodeGraph(name=_qualify(ns, a.get("name", "")), loc=el.loc, nodedef=_qualify(ns, a.get("nodedef")),
                      version=a.get("version"))
        dropped = self.repeated(el, "nodegraph '%s'" % g.name)
        for c in el.children:
            cctx = _child_ctx(ctx, c)
            if c.tag in ("input", "parameter", "output", "token") or id(c) in dropped:
                continue
            if c.tag in NON_NODE_TAGS:
                continue
            n = self.node(c, cctx)
            g.nodes[n.name] = n
        self.ports_of(el, ctx, g, dropped)
        return g


def _qualify(namespace, name):
    """A name declared inside a `namespace` (MaterialX 1.38): `ns:name`, unless already qualified."""
    if not namespace or not name or ":" in name:
        return name
    return namespace + ":" + name


_CTX_KEYS = ("fileprefix", "geomprefix", "colorspace", "namespace")


def _child_ctx(ctx, el):
    if el.attrs.keys().isdisjoint(_CTX_KEYS):
        return ctx
    new = dict(ctx)
    for k in _CTX_KEYS:
        if k in el.attrs:
            new[k] = el.attrs[k]
    return new


def build(root, path, source="document"):
    """XElement tree of one file (includes spliced) -> Document. Raises MtlxError listing all problems."""
    version = root.get("version", "1.39")
    from mtlxgen.read.upgrade import upgrade_tree       # an older document is read as the 1.39 one it stands for
    assumed = []        # what the upgrade assumes an older document meant: the document's first warnings
    root = upgrade_tree(root, assumed)
    doc = Document(path=path, version=version, colorspace=root.get("colorspace"), warnings=assumed)
    problems = Problems()
    b = _Builder(doc, problems)
    ctx = _child_ctx({}, root)
    _check_names(root, problems)
    # typedefs first: struct values elsewhere depend on them
    doc.structs = _struct_types(root, problems, doc.warnings)
    dropped = b.repeated(root, "the document")
    for el in root.children:
        cctx = _child_ctx(ctx, el)
        tag, name = el.tag, el.get("name", "")
        if tag == "typedef" or id(el) in dropped:
            continue
        if tag in ("nodedef",):
            nd = b.nodedef(el, cctx, source)
            doc.nodedefs[nd.name] = nd
        elif tag == "nodegraph":
            g = b.nodegraph(el, cctx)
            doc.nodegraphs[g.name] = g
        elif tag == "implementation":
            a = el.attrs
            ns = cctx.get("namespace")
            doc.implementations[name] = Implementation(name=name, loc=el.loc, nodedef=_qualify(ns, a.get("nodedef")),
                                                       file=a.get("file"), function=a.get("function"),
                                                       sourcecode=a.get("sourcecode"), target=a.get("target"),
                                                       nodegraph=_qualify(ns, a.get("nodegraph")))
        elif tag == "geompropdef":
            a = el.attrs
            slips = []
            try:
                index = mxtypes.parse_value("integer", a.get("index", "0"), slips=slips)
            except mxtypes.ValueError_ as e:
                problems.add(el.loc, "geompropdef '%s': index: %s" % (name, e))
                index = 0
            doc.warnings.extend((el.loc, "geompropdef '%s': index: %s" % (name, w)) for w in slips)
            doc.geompropdefs[name] = GeomPropDef(name=name, type=a.get("type", ""), geomprop=a.get("geomprop", ""),
                                                 loc=el.loc, space=a.get("space"), index=index, attrs=dict(a))
        elif tag == "unitdef":
            units = doc.unitdefs.setdefault(el.get("unittype", ""), {})
            for u in el.children:
                if u.tag == "unit":
                    slips = []
                    try:
                        units[u.get("name")] = mxtypes.parse_value("float", u.get("scale", "1"), slips=slips)
                    except mxtypes.ValueError_ as e:
                        problems.add(u.loc, "unit '%s': scale: %s" % (u.get("name"), e))
                    doc.warnings.extend((u.loc, "unit '%s': scale: %s" % (u.get("name"), w)) for w in slips)
        elif tag == "output":
            p = b.port(el, cctx, "output")
            doc.outputs[p.name] = p
        elif tag == "input":
            p = b.port(el, cctx, "input")
            doc.inputs[p.name] = p
        elif tag == "look":
            doc.looks[name] = el
        elif tag in NON_NODE_TAGS:
            continue
        else:
            n = b.node(el, cctx)
            doc.nodes[n.name] = n
        if name:
            doc.order.append(name)
    if problems:
        raise MtlxError(problems.items, doc.warnings)
    _substitute_tokens(doc)
    return doc


def _check_names(root, problems):
    """Element names may hold what MaterialX's generator takes (it reads names its validator calls invalid,
    e.g. with spaces), but not '/', which separates name paths, nor line breaks or other control characters,
    which no GLSL comment, file name or one-line message could carry."""
    stack = [root]
    while stack:                # iterative: documents may nest deeply
        el = stack.pop()
        stack.extend(el.children)
        name = el.get("name")
        if name is None:
            continue
        if "/" in name:
            problems.add(el.loc, "<%s> name %r holds '/', which separates MaterialX name paths" % (el.tag, name))
        elif not name.isprintable():
            problems.add(el.loc, "<%s> name %r holds a control character" % (el.tag, name))


# member types a GLSL struct can hold besides other structs: values with a GLSL type and a literal
_MEMBER_TYPES = ("float", "integer", "boolean", "color3", "color4", "vector2", "vector3", "vector4",
                 "matrix33", "matrix44")
STRUCT_DEPTH = 32           # structs nested deeper are refused (values of them are read recursively)


def _struct_types(root, problems, warnings):
    """{name: StructType} of the document's <typedef>s with <member>s (those without members declare
    built-in types, as stdlib's do). Each must be a GLSL struct: named by a GLSL identifier, members of
    value types or other structs of the document, uniquely named, none containing itself."""
    from mtlxgen.base.identifiers import glsl_identifier
    structs, locs = {}, {}
    for el in root.children:
        members = [m for m in el.children if m.tag == "member"] if el.tag == "typedef" else []
        if not members:
            continue
        name = el.get("name") or ""
        if name in mxtypes.BUILTIN:
            problems.add(el.loc, "typedef '%s' gives members to a built-in type" % name)
        elif glsl_identifier(name) != name:
            problems.add(el.loc, "typedef %r: a struct name must be a GLSL identifier not reserved by GLSL or "
                                 "mtlxgen (ASCII letters, digits, single '_')" % name)
        elif name in structs:
            problems.add(el.loc, "duplicate typedef '%s'" % name)
        else:
            rows, seen = [], set()
            for m in members:
                mn, mt = m.get("name") or "", m.get("type") or ""
                if glsl_identifier(mn) != mn:
                    problems.add(m.loc, "member %r of struct '%s': a member name must be a GLSL identifier not "
                                        "reserved by GLSL or mtlxgen" % (mn, name))
                elif mn in seen:
                    problems.add(m.loc, "struct '%s' has two members named '%s'" % (name, mn))
                seen.add(mn)
                rows.append((mn, mt, m.get("value")))
                locs[(name, mn)] = m.loc
            structs[name] = mxtypes.StructType(name, rows, el.loc)
            locs[name] = el.loc
    for name, st in structs.items():
        for mn, mt, value in st.members:
            loc = locs[(name, mn)]
            if mt in structs:
                continue
            if mt not in _MEMBER_TYPES:
                why = "which a struct cannot hold" if mt in mxtypes.BUILTIN else "an unknown type"
                problems.add(loc, "member '%s' of struct '%s' has type %r, %s" % (mn, name, mt, why))
            elif value is not None:
                slips = []
                try:
                    mxtypes.parse_value(mt, value, slips=slips)
                except mxtypes.ValueError_ as e:
                    problems.add(loc, "member '%s' of struct '%s': %s" % (mn, name, e))
                warnings.extend((loc, "member '%s' of struct '%s': %s" % (mn, name, w)) for w in slips)
    for name, problem in _struct_nesting(structs).items():
        problems.add(locs[name], problem)
    if problems:
        return {}
    for name, st in structs.items():        # struct-typed member defaults, now that every struct is sound
        for mn, mt, value in st.members:
            if mt in structs and value is not None:
                slips = []
                try:
                    mxtypes.parse_value(mt, value, structs, slips)
                    warnings.extend((locs[(name, mn)], "member '%s' of struct '%s': %s" % (mn, name, w)) for w in slips)
                except mxtypes.ValueError_ as e:
                    problems.add(locs[(name, mn)], "member '%s' of struct '%s': %s" % (mn, name, e))
    return structs


def _struct_nesting(structs):
    """{name: problem} for structs that cannot be declared: those that contain themselves (through their
    members' types) and those nesting structs more than STRUCT_DEPTH deep."""
    inner = {n: [mt for _, mt, _ in st.members if mt in structs] for n, st in structs.items()}
    holders = {n: [] for n in structs}
    for n, members in inner.items():
        for mt in members:
            holders[mt].append(n)
    # depth by peeling structs whose inner structs all have one (Kahn's order: linear, no recursion)
    waiting = {n: len(members) for n, members in inner.items()}
    depth = {}
    ready = [n for n, k in waiting.items() if k == 0]
    while ready:
        n = ready.pop()
        depth[n] = 1 + max((depth[mt] for mt in inner[n]), default=0)
        for h in holders[n]:
            waiting[h] -= 1
            if waiting[h] == 0:
                ready.append(h)
    problems = {}
    for n in structs:                   # in document order
        if n not in depth:              # on a cycle, or holding a struct on one
            path = _path_back(n, inner)
            if path:
                problems[n] = "struct '%s' contains itself (%s)" % (n, " -> ".join(path))
        elif depth[n] > STRUCT_DEPTH:
            problems[n] = "struct '%s' nests structs more than %d deep" % (n, STRUCT_DEPTH)
    return problems


def _path_back(name, inner):
    """[name, ..., name]: member types leading from struct `name` back to it, or None."""
    parent, queue = {}, [name]
    for n in queue:                     # breadth first: the shortest cycle
        for mt in inner[n]:
            if mt == name:
                path = [n]
                while path[-1] != name:
                    path.append(parent[path[-1]])
                return path[::-1] + [name]
            if mt not in parent:
                parent[mt] = n
                queue.append(mt)
    return None


def _substitute_tokens(doc):
    """Expand [TOKEN] in filename values from <token>s: the node's own, then its nodegraph's, then
    the nodedef the nodegraph implements (top-level tokens are not used, as in MaterialX)."""
    def substitute(port, *scopes):
        if port.type != "filename" or not port.text or "[" not in port.text:
            return
        text = port.text
        for scope in scopes:
            for name, token in scope.items():
                text = text.replace("[%s]" % name, token.text or "")
        port.text = port.value = text

    for g in doc.nodegraphs.values():
        nd = doc.nodedefs.get(g.nodedef) if g.nodedef else None
        nd_tokens = nd.tokens if nd is not None else {}
        for port in g.inputs.values():
            substitute(port, g.tokens, nd_tokens)
        for node in g.nodes.values():
            for port in node.inputs.values():
                substitute(port, node.tokens, g.tokens, nd_tokens)
    for node in doc.nodes.values():
        for port in node.inputs.values():
            substitute(port, node.tokens)


@gc_paused()
def load(path, search_paths=(), source="document"):
    """Read and build a document from a .mtlx file."""
    from mtlxgen.read.upgrade import upgrade_tree       # each included document from its own version, as MaterialX reads it
    read_slips = []     # slips of the XML itself and included documents' upgrade warnings (read_file's)
    root = read_file(path, search_paths, warnings=read_slips, upgrade=upgrade_tree)
    try:
        doc = build(root, path, source)
    except MtlxError as e:
        e.warnings[:0] = read_slips
        raise
    doc.warnings[:0] = read_slips
    return doc


def load_upgraded(path, library_dirs=()):
    """A .mtlx file as the 1.39 document it stands for: read (includes found in the search paths and
    library_dirs) and upgraded (upgrade.py)."""
    from mtlxgen.base.resolve import search_paths
    from mtlxgen.read.upgrade import upgrade
    return upgrade(load(path, search_paths(library_dirs)))


SHADER_TYPES = ("surfaceshader", "volumeshader")


# Outputs connected to nodes of these types are not drawn on their own (MaterialX's findRenderableElements skips
# them; measured with the materialx wheel, 1.39.5)
UNRENDERABLE_NODE_TYPES = ("BSDF", "EDF", "VDF", "lightshader")


def renderable_elements(doc):
    """Name paths of what MaterialX's findRenderableElements returns for this document: its material
    nodes; where there are none, the outputs of its nodegraphs and its top-level outputs that are connected
    (by nodename) to a node of their own scope, other than a BSDF, EDF, VDF or light (an output holding a value
    alone, bound to an interface input, reading another nodegraph, or naming a node that is not there is not
    drawn). Where MaterialX finds nothing, we still draw what there is: every output (a light's, a BSDF's),
    else the shader nodes."""
    materials = [n.name for n in doc.nodes.values() if n.type == "material"]
    if materials:
        return materials
    outputs = [("%s/%s" % (g.name, o.name), o, g.nodes) for g in doc.nodegraphs.values() for o in g.outputs.values()]
    outputs += [(o.name, o, doc.nodes) for o in doc.outputs.values()]
    drawn = [name for name, o, nodes in outputs if _drawn_output(o, nodes)]
    if drawn:
        return drawn
    if outputs:
        return [name for name, _, _ in outputs]
    return [n.name for n in doc.nodes.values() if n.type in SHADER_TYPES]


def _drawn_output(port, nodes):
    node = nodes.get(port.nodename) if port.nodename else None
    return node is not None and node.type not in UNRENDERABLE_NODE_TYPES


MAX_LISTED = 20


def no_element_message(doc, element):
    """Why --element ELEMENT names nothing: the closest names, then the elements the document renders (the first
    MAX_LISTED of them, then how many more)."""
    names = renderable_elements(doc)
    every = list(names) + [n for n in doc.nodes] + ["%s/%s" % (g.name, o) for g in doc.nodegraphs.values()
                                                   for o in g.outputs] + list(doc.outputs)
    listed = ", ".join(names[:MAX_LISTED]) + (" and %d more" % (len(names) - MAX_LISTED) if len(names) > MAX_LISTED
                                              else "")
    return "no element '%s' in the document%s (renderable elements: %s)" % (
        element, did_you_mean(element, every), listed or "none")
