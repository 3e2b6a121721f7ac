"""Kept elements (issue 14): a document's materials of one structure generated once, the others instantiated.

A material library holds hundreds of materials built alike: a standard_surface with values of its own, the same
small nodegraph under another name. Two top-level nodes of one document whose elements (the node, the nodes it
reads, the nodegraphs they read, whole) are the same up to the elements' names and the values of float, colour
and vector inputs make shaders that differ only in those names and values, in the complete interface: there such
a value is a public uniform's initial value, written as it is read, and nothing is chosen from it.

Per Session (one document, one library, one set of settings) and structure key (`structure`):
  first met:   generated in full (the key noted);
  second:      generated in full, then once more over a sentinel copy of its elements (`_record`): every name
               replaced by QX<k>XQ (a plain GLSL identifier, as the real names are, so every test on a name goes
               the same way), every such value by an mxtypes.Hole (written by glsl_literal as a placeholder,
               refusing any other use). The copy holds only these elements: what building reads besides them
               is not there, and fails. Its shader, each name and placeholder made a field, is the Template;
               instantiated with this element's names and values it must give this element's shader exactly;
  third:       generated in full, compared with the instance again (CHECKS uses in all);
  then:        instantiated (`Template.make`), the placeholders written by glsl_literal from the element's own
               values, the manifest's from emit.manifest_value.
A key is refused (generated in full from then on) where the sentinel run fails, warns, reads a Hole (Hole.refused:
counted even where the reader caught the error), or leaves a placeholder where it cannot be replaced, or where a
comparison differs. Nothing is recorded for a structure fewer than CHECKS + 2 of the session's elements have (no
material of it would be instantiated). An element is not kept where its name is not a file stem as it is, nor
where any of its names is not a plain identifier (what glsl_identifier keeps as it is whatever follows it: no
leading or trailing '_', not gl, u or i). An instance is generated in full where the names substituted would make
two names taken while building or emitting one, meet a name the template's run took that holds no name of the
structure, or make an identifier longer than glsl_identifier keeps whole: what unique_identifier would have
resolved otherwise than in the sentinel run.
Not kept: the reduced interface (values become code), a USD stage, a document with definitions of its own (the
library overlaid), top-level <input>s, elements other than top-level nodes. REUSE (MTLXGEN_ELEMENT_REUSE=0 in the
environment) turns it off.
"""
import json
import operator
import os
import re
from dataclasses import fields, replace

from . import document, emit, graph, mxtypes
from .fieldtext import SEP, FieldText
from .graphtypes import IDENTIFIER_CHARS, glsl_identifier

REUSE = os.environ.get("MTLXGEN_ELEMENT_REUSE", "1") != "0"
CHECKS = 2              # uses of a template compared with a full generation (the recording's own is the first)
KEYS_MAX = 4096         # structures kept per session

# per process (tests read them): templates recorded, compared, instantiated; keys refused; instances generated
# in full for their names
STATS = {"recorded": 0, "checked": 0, "reused": 0, "refused": 0, "names": 0}

# a node's XML attributes generation never reads: its name (numbered) and where an editor drew it
UNREAD_ATTRS = frozenset(("name", "xpos", "ypos"))
HOLE_TYPES = frozenset(("float", "color3", "color4", "vector2", "vector3", "vector4"))

# the fields of the document's classes the key holds as they are; names and references are numbered, a hole's
# value and text are left out (test_element_cache checks every field is one or the other)
PORT_FIELDS = tuple(f.name for f in fields(document.Port) if f.name not in ("loc", "value", "text", "nodename",
                                                                           "nodegraph"))
NODE_FIELDS = ("category", "type", "nodedef", "version")            # + name, loc, inputs, outputs, tokens, attrs
GRAPH_FIELDS = ("nodedef", "version")                   # + name, loc, inputs, outputs, tokens, nodes
_PORT_FIELDS, _NODE_FIELDS = operator.attrgetter(*PORT_FIELDS), operator.attrgetter(*NODE_FIELDS)

_SENTINEL = "QX%dXQ"
_FIELD = re.compile(r'QX(\d+)XQ|\x1e(\d+):(\w+)\x1e|"\\u001d(\d+)\\u001d"')
_SENTINELS = re.compile(r"QX(\d+)XQ")
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_REFUSED = object()


class Structure:
    """An element's document elements, numbered: key (hashable; None where the element is not kept), the real
    names by number, the hole ports by number (their values are the element's)."""
    __slots__ = ("key", "names", "holes", "elements")

    def __init__(self):
        self.key, self.names, self.holes, self.elements = None, [], [], []


def _plain(name):
    return glsl_identifier(name) == name and name[0] != "_" and name[-1] != "_" and name not in ("gl", "u", "i")


def _hole(port):
    return (port.type in HOLE_TYPES and port.value is not None and not port.connected and port.error is None
            and port.warning is None)


def structure(doc, element):
    """The Structure of a top-level node `element` of `doc` (its key None where it is not kept)."""
    st = Structure()
    node = doc.nodes.get(element)
    if node is None or doc.inputs or emit.file_stem(element) != element:     # (the files' names: the element's)
        return st
    number = {}                         # (scope, name) -> k; scope "node", "graph" or ("in", graph name)
    queue = []

    def ref(scope, name):
        k = number.get((scope, name))
        if k is None:
            if scope == "node":
                found = doc.nodes.get(name)
            elif scope == "graph":
                found = doc.nodegraphs.get(name)
            else:
                found = doc.nodegraphs[scope[1]].nodes.get(name)
            if found is None or not _plain(name):
                raise LookupError(name)
            k = number[(scope, name)] = len(st.names)
            st.names.append(name)
            st.elements.append((scope, found))
            if scope != "node" and scope != "graph":
                return k
            queue.append(k)
            if scope == "graph":        # a nodegraph whole: its nodes numbered in order
                for inner in found.nodes:
                    ref(("in", name), inner)
        return k

    def port(p, scope):
        """(key part of port p, in scope "node" (top level) or ("in", a nodegraph's name))."""
        if p.nodegraph and scope != "node":
            raise LookupError(p.nodegraph)
        n = ref(scope, p.nodename) if p.nodename else None
        g = ref("graph", p.nodegraph) if p.nodegraph else None
        if _hole(p):
            st.holes.append(p)
            value = ("hole",)
        else:
            value = (p.value, p.text)
        return (n, g, value) + _PORT_FIELDS(p)

    def ports(table, scope):
        return tuple(port(p, scope) for p in table.values())

    def node_part(n, scope):
        return (_NODE_FIELDS(n), ports(n.inputs, scope), ports(n.outputs, scope),
                ports(n.tokens, scope), tuple(item for item in n.attrs.items() if item[0] not in UNREAD_ATTRS))

    try:
        ref("node", element)
        parts = []
        i = 0
        while i < len(queue):
            k = queue[i]
            i += 1
            scope, el = st.elements[k]
            if scope == "node":
                parts.append((k, node_part(el, "node")))
                continue
            gname = ("in", st.names[k])
            inner = tuple((number[(gname, name)], node_part(n, gname)) for name, n in el.nodes.items())
            parts.append((k, tuple(getattr(el, f) for f in GRAPH_FIELDS), ports(el.inputs, "node"),
                          ports(el.outputs, gname), ports(el.tokens, gname), inner))
        key = tuple(parts)
        hash(key)
    except (LookupError, TypeError):    # a name not kept, an element not there, a value that is a list
        return st
    st.key = key
    return st


def _sentinel_doc(doc, st):
    """A copy of `doc` holding only the Structure's elements, renamed QX<k>XQ, its hole values mxtypes.Holes."""
    holes = {id(p): i for i, p in enumerate(st.holes)}
    number = {}
    for k, (scope, el) in enumerate(st.elements):
        number[(scope, st.names[k])] = _SENTINEL % k

    def port(p, scope):
        changes = {}
        if p.nodename:
            changes["nodename"] = number[(scope, p.nodename)]
        if p.nodegraph:
            changes["nodegraph"] = number[("graph", p.nodegraph)]
        i = holes.get(id(p))
        if i is not None:
            changes["value"] = changes["text"] = mxtypes.Hole(i)
        return replace(p, **changes) if changes else p

    def node(n, scope, name):
        return replace(n, name=name, attrs=dict(n.attrs, name=name), inputs={k: port(p, scope) for k, p in n.inputs.items()},
                       outputs={k: port(p, scope) for k, p in n.outputs.items()},
                       tokens={k: port(p, scope) for k, p in n.tokens.items()})

    nodes, graphs = {}, {}
    for k, (scope, el) in enumerate(st.elements):
        name = _SENTINEL % k
        if scope == "node":
            nodes[name] = node(el, "node", name)
        elif scope == "graph":
            g = ("in", st.names[k])
            graphs[name] = replace(
                el, name=name, nodes={number[(g, n)]: node(inner, g, number[(g, n)]) for n, inner in el.nodes.items()},
                inputs={k2: port(p, "node") for k2, p in el.inputs.items()},
                outputs={k2: port(p, g) for k2, p in el.outputs.items()},
                tokens={k2: port(p, g) for k2, p in el.tokens.items()})
    return replace(doc, nodes=nodes, nodegraphs=graphs, outputs={}, inputs={}, order=list(nodes) + list(graphs))


class Template:
    """A sentinel run's shader as one text with fields (vertex, fragment and the manifest's JSON, SEP between them):
    fields 0..n-1 the names, then one per (hole, GLSL type) the hole's GLSL literal (`literals`), then one per hole
    the manifest's JSON of its value (`values`). `named`: the names taken while building and emitting that hold a
    name, `fixed` the others: what the names substituted must not meet; `lengths`: (the length of an identifier
    holding names without them, the names it holds), the longest per set of names."""

    def __init__(self, shader, names, taken):
        if shader.document_code:
            raise ValueError("document code")
        manifest = json.dumps(_json_holes(shader.manifest))
        texts = (shader.vertex, shader.fragment, manifest)
        if any(SEP in t for t in texts):
            raise ValueError("separator in text")
        joined = SEP.join(texts)
        # fill's args: the names, then each (hole, GLSL type)'s literal, then each hole's JSON, in order of meeting
        literals, values = {}, {}
        for m in _FIELD.finditer(joined):
            if m.group(2) is not None:
                literals.setdefault((int(m.group(2)), m.group(3)), names + len(literals))
            elif m.group(4) is not None:
                values.setdefault(int(m.group(4)), len(values))
        first_value = names + len(literals)

        def field(m):
            if m.group(1) is not None:
                if int(m.group(1)) >= names:
                    raise ValueError("a name not numbered")
                return int(m.group(1))
            if m.group(2) is not None:
                return literals[(int(m.group(2)), m.group(3))]
            return first_value + values[int(m.group(4))]

        self.text = FieldText(joined, _FIELD, field)
        if any("\x1e" in p or "\\u001d" in p or "\\u001e" in p for p in self.text.literals):
            raise ValueError("placeholder")         # a placeholder cut or glued: not kept
        self.literals, self.values = list(literals), list(values)
        named = sorted(i for i in taken if "QX" in i and _SENTINELS.search(i))
        self.fixed = frozenset(i for i in taken if not ("QX" in i and _SENTINELS.search(i)))
        self.named = FieldText(SEP.join(named), _SENTINELS, lambda m: int(m.group(1)))
        self.count = len(named)
        idents = set(_IDENT.findall(shader.vertex)) | set(_IDENT.findall(shader.fragment)) | set(named)
        lengths = {}
        for i in idents:
            ks = tuple(sorted(set(int(k) for k in _SENTINELS.findall(i))))
            if ks:
                if len(i) > IDENTIFIER_CHARS - 2:
                    raise ValueError("long identifier")     # (a stem glsl_identifier might have cut: not kept)
                rest = len(_SENTINELS.sub("", i))
                lengths[ks] = max(lengths.get(ks, 0), rest)
        self.lengths = [(rest, ks) for ks, rest in lengths.items()]
        self.checks = 0

    def make(self, element, st):
        """The Shader of `element` (Structure st, this template's key), or None where its names would not be
        taken as the sentinel run took them, or a value has no GLSL literal."""
        names = st.names
        if self.count:
            named = self.named.fill(names).split(SEP)
            if len(set(named)) != self.count or not self.fixed.isdisjoint(named):
                return None
        sizes = [len(n) for n in names]
        if any(rest + sum(sizes[k] for k in ks) > IDENTIFIER_CHARS for rest, ks in self.lengths):
            return None
        values = [p.value for p in st.holes]
        try:
            args = (names + [mxtypes.glsl_literal(t, values[k]) for k, t in self.literals]
                    + [json.dumps(emit.manifest_value(values[k])) for k in self.values])
        except (mxtypes.ValueError_, ValueError, TypeError):    # (a full generation says which input)
            return None
        vertex, fragment, manifest = self.text.fill(args).split(SEP)
        return emit.Shader(element, vertex, fragment, json.loads(manifest))


def _json_holes(value):
    """The manifest with each Hole as a string the JSON text holds as "\\u001d<index>\\u001d"."""
    if isinstance(value, dict):
        return {k: _json_holes(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_json_holes(v) for v in value]
    if value.__class__ is mxtypes.Hole:
        return "\x1d%d\x1d" % value.index
    if isinstance(value, str) and "\x1d" in value:
        raise ValueError("placeholder")
    if isinstance(value, (float, int, str, bool)) or value is None:
        return value
    raise ValueError("a manifest value JSON would not give back: %s" % type(value).__name__)


def _record(session, element, st):
    """The Template of element `element`'s structure, from a sentinel run; None where it cannot be kept."""
    sdoc = _sentinel_doc(session.doc, st)
    refused = mxtypes.Hole.refused
    try:
        builder = graph.GraphBuilder(sdoc, session.library, session.rules)
        g = builder.build(_SENTINEL % 0)
        if builder.warnings.items:
            return None
        em = emit.Emitter(g, session.environment, session.target, session.max_lights, False)
        shader = em.emit()
        if mxtypes.Hole.refused != refused:
            return None
        return Template(shader, len(st.names), builder.used_ids | em.names)
    except Exception:                   # anything the sentinel run cannot do: the key is generated in full
        return None


class KeptElements:
    """A Session's kept structures: shader(name, full) is full(name) or an instance of a checked template. Only a
    structure the session's elements hold at least CHECKS + 2 times is recorded (one fewer: no material would be
    instantiated, and the recording's sentinel run would be paid for nothing)."""

    def __init__(self, session):
        lib = session.library
        self.on = (REUSE and session.stage is None and getattr(lib, "overlaid", None) is None
                   and not session.interface.reduced and len(session.elements) >= CHECKS + 2)
        self.session = session
        self.structures = None          # element name -> Structure, made on the first shader()
        self.count = {}                 # key -> how many of the session's elements have it
        self.kept = {}                  # key -> times met (1), a Template (with .checks), or _REFUSED

    def structure_of(self, name):
        if self.structures is None:
            doc = self.session.doc
            self.structures = {e: structure(doc, e) for e in self.session.elements}
            for st in self.structures.values():
                if st.key is not None:
                    self.count[st.key] = self.count.get(st.key, 0) + 1
        st = self.structures.get(name)
        return st if st is not None else structure(self.session.doc, name)

    def shader(self, name, full):
        if not self.on:
            return full(name)
        st = self.structure_of(name)
        key = st.key
        if key is None or self.count.get(key, 0) < CHECKS + 2:
            return full(name)
        entry = self.kept.get(key)
        if entry is None:
            if len(self.kept) >= KEYS_MAX:
                self.kept.clear()
            self.kept[key] = 1
            return full(name)
        if entry is _REFUSED:
            return full(name)
        if entry.__class__ is int:
            shader = full(name)
            template = _record(self.session, name, st)
            if template is None:
                self.kept[key] = _REFUSED
                STATS["refused"] += 1
                return shader
            STATS["recorded"] += 1
            self.kept[key] = entry = template
            return self._check(entry, key, name, st, shader)
        if entry.checks < CHECKS:
            return self._check(entry, key, name, st, full(name))
        made = entry.make(name, st)
        if made is None:
            STATS["names"] += 1
            return full(name)
        STATS["reused"] += 1
        return self.session.finish(name, made)

    def _check(self, template, key, name, st, shader):
        made = template.make(name, st)
        if made is not None:
            made = self.session.finish(name, made)
            if made != shader:
                self.kept[key] = _REFUSED
                STATS["refused"] += 1
                return shader
            template.checks += 1
            STATS["checked"] += 1
        return shader
