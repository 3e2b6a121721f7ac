"""An element's public inputs as a property panel shows them, and writing edited values back into the document.

public_inputs() lists the uniforms of an element's shader that a document input sets (or would set): each with
the node and input it belongs to (the uniform's Origin: the element's name path, the input, whether the document
writes it; never read from the uniform's GLSL name), the nodedef's ui metadata (uiname, uifolder, uimin, uimax,
uisoftmin, uisoftmax, uistep, enum, enumvalues) and where it is written: the uniform's FILE:LINE (an included
file's own), and the input's name path in its file (nodegraph/node/input, as MaterialX's getNamePath) with the
sha256 of the file's bytes, both confirmed against those bytes and the origin when the inputs are listed
(record_sources).

save_values() writes edited values back as the smallest edit of the file's bytes: the value attribute of the
<input> is replaced (or added); an input the document does not author is added as one <input> line in its node
(a self-closed node element is opened and closed). A file whose bytes are not the ones the inputs were listed
from is refused whole. Each input is found by its name path in a scan of the text that steps over comments,
CDATA sections, processing instructions and quoted attribute values, and the element found must be the one the
XML reader reads there (tag and line, lines counted as the reader counts them: CR LF, lone CR, LF). The file
keeps its encoding and byte-order mark (UTF-8, UTF-16 LE or BE with or without a mark, single-byte code pages),
its line endings and every byte outside the edited values; a character the encoding lacks is written as a
character reference (&#8364;). Every file is patched and read back (the values checked) before any is written,
and each is written through files.write_atomic (a temporary file renamed over it; mode and owner kept; a
symlink's target written), so a failed write leaves the old file whole. Problems are MtlxError lines,
FILE:LINE: ...: not saved.
"""
import bisect
import codecs
import hashlib
import os
import re
from mtlxgen.base.records import dataclass, field

from mtlxgen.base.diagnostics import Loc, MtlxError

EDITABLE_TYPES = ("float", "integer", "boolean", "color3", "color4", "vector2", "vector3", "vector4", "filename")


@dataclass
class PanelInput:
    uniform: str                # the shader's uniform (a texture's sampler for filename inputs)
    node: str                   # the name path of the node (or nodegraph, for its interface inputs) the input
                                # belongs to ("NG/N" for a node in a nodegraph; "doc": the document's own inputs)
    input: str
    mtlx_type: str
    value: object               # the value the document gives (or the nodedef's default)
    label: str = ""             # uiname, else the input's name
    folder: str = ""            # uifolder (MaterialX's '/' separated path), else ""
    ui: dict = field(default_factory=dict)        # uimin, uimax, uisoftmin, uisoftmax, uistep: parsed values
    enum: list = None           # enum names (integer inputs show them; the value is the index or enumvalues')
    enumvalues: list = None
    where: Loc = None           # the document's <input> element setting it; None: not authored
    node_loc: Loc = None        # the node's element: where an <input> is added when it is not authored
    tag: str = ""               # the node element's tag (its category), for closing a self-closed element
    element_path: tuple = None  # the input's name path in its file (MaterialX's getNamePath split at '/': nodegraph,
                                # node, input), confirmed against the file's bytes; None: not confirmed (not saved)
    source: "SourceFile" = None     # the file and the sha256 of its bytes when the path was confirmed
    origin: object = None       # graphtypes.Origin: the document element (name path) and input the uniform comes
                                # from; where it is written is confirmed against it (record_sources)

    @property
    def group(self):
        return "%s / %s" % (self.node, self.folder) if self.folder else self.node


# ------------------------------------------------------------------ reading

_ATTR_CACHE = {}        # path -> (mtime, attrs): one entry a file, its latest reading


def _input_attrs(path):
    """{(line, input name): attrs} of every <input> element in a .mtlx file (read once per file and mtime; a
    file edited again and again in a long viewer session keeps one entry, its latest)."""
    from mtlxgen.read import xmlreader
    try:
        mtime = os.path.getmtime(path)
    except OSError:
        return {}
    cached = _ATTR_CACHE.get(path)
    if cached is None or cached[0] != mtime:
        out = {}
        try:
            stack = [xmlreader.read_file(path)]
        except MtlxError:
            stack = []
        while stack:
            el = stack.pop()
            if el.tag == "input" and el.get("name"):
                out[(el.loc.file, el.loc.line, el.get("name"))] = el.attrs
            stack.extend(el.children)
        _ATTR_CACHE[path] = cached = (mtime, out)
    return cached[1]


def _attrs(port):
    if port is None or port.loc is None or not port.loc.file or not os.path.isfile(port.loc.file):
        return {}
    return _input_attrs(port.loc.file).get((port.loc.file, port.loc.line, port.name), {})


def _number_list(text, mtlx_type):
    from mtlxgen.base import mxtypes
    try:
        return mxtypes.parse_value(mtlx_type, text)
    except Exception:
        return None


def _ui(decl_attrs, own_attrs, mtlx_type):
    ui = {}
    for key in ("uimin", "uimax", "uisoftmin", "uisoftmax", "uistep"):
        text = own_attrs.get(key, decl_attrs.get(key))
        if text is not None:
            v = _number_list(text, mtlx_type)
            if v is not None:
                ui[key] = v
    return ui


def _split(text):
    return [t.strip() for t in text.split(",")] if text else None


def public_inputs(session, element):
    """[PanelInput] of one element of a pipeline.Session, in the order its shader declares the uniforms. Each
    uniform's document input comes from its Origin (graphtypes.Origin: the element's name path, the input,
    whether the document writes it) and its loc (FILE:LINE of the input, or of the nodedef's input when not
    authored): never from the uniform's identifier."""
    from mtlxgen.graph.build import GraphBuilder
    g = session.graph(element)
    doc = session.doc
    builder = GraphBuilder(doc, session.library, session.rules)
    owners = {}             # origin element -> [(display name, tag, element loc, {input: port}, {input: declared})]
    out = []
    for u in g.uniforms.values():
        if u.type not in EDITABLE_TYPES or u.origin is None:
            continue
        o = u.origin
        if o.element not in owners:
            owners[o.element] = _owners(doc, session.library, builder, o.element)
        for name, tag, loc, ports, declared in owners[o.element]:
            port, decl = ports.get(o.input), declared.get(o.input)
            if decl is None:
                continue
            # the element whose input it is: the uniform's own FILE:LINE (an element MaterialX reads twice over,
            # a node and a nodegraph of one name: the one the graph was built from)
            if (port is None or port.loc != u.loc) if o.authored else (port is not None or decl.loc != u.loc):
                continue
            decl_attrs, own_attrs = _attrs(decl), _attrs(port) if o.authored else {}
            enum = port.enum if o.authored and port.enum else decl.enum
            enumvalues = port.enumvalues if o.authored and port.enumvalues else decl.enumvalues
            out.append(PanelInput(
                uniform=u.name, node=name, input=o.input, mtlx_type=u.type, value=u.value,
                label=own_attrs.get("uiname") or decl_attrs.get("uiname") or o.input,
                folder=own_attrs.get("uifolder") or decl_attrs.get("uifolder") or "",
                ui=_ui(decl_attrs, own_attrs, u.type), enum=_split(enum), enumvalues=_split(enumvalues),
                where=u.loc if o.authored else None, node_loc=loc if tag != "materialx" else None, tag=tag,
                origin=o))
            break
    return record_sources(out)


def _owners(doc, library, builder, path):
    """The document elements at name path `path` (an Origin's element) that may own a public input: [(display
    name, tag, loc, {input: authored port}, {input: declared port})]. "": the document's own inputs; "NG": a
    nodegraph's interface or a node at the document's level; "NG/N": a node in nodegraph NG."""
    if path == "":
        return [("doc", "materialx", None, doc.inputs, doc.inputs)] if doc.inputs else []
    parent, _, name = path.rpartition("/")
    found = []
    if not parent and name in doc.nodegraphs:
        ng = doc.nodegraphs[name]
        nd = library.nodedefs.get(ng.nodedef) if ng.nodedef else None
        declared = dict(nd.inputs) if nd is not None else {}
        declared.update({k: v for k, v in ng.inputs.items() if k not in declared})
        found.append((path, "nodegraph", ng.loc, ng.inputs, declared))
    nodes = doc.nodes if not parent else (doc.nodegraphs[parent].nodes if parent in doc.nodegraphs else {})
    node = nodes.get(name)
    if node is not None:
        try:
            nd = builder.nodedef_for(node)
        except MtlxError:
            nd = None
        if nd is not None:
            found.append((path, node.category, node.loc, node.inputs, nd.inputs))
    return found


# ------------------------------------------------------------------ where each input is written

@dataclass(eq=False)
class SourceFile:
    """A document file as the panel read it: its path and the sha256 of its bytes then (after a save of the
    panel's own: of the bytes it wrote). Save refuses the file once its bytes are different."""
    path: str
    sha256: str


class _ReaderIndex:
    """The XML reader's view of one file's bytes: every element with its name path (None for one MaterialX
    drops: a later sibling repeating a name, an element without a name, and what they hold), and the element
    each name path names (the first child of that name at every level, as MaterialX reads them)."""

    def __init__(self, root):
        self.by_path = {(): root}   # name path -> XElement
        self.by_line = {}           # line -> [(XElement, name path or None, parent XElement)]
        self.count = 0              # elements
        work = [(root, (), None)]
        while work:
            el, names, parent = work.pop()
            self.count += 1
            self.by_line.setdefault(el.loc.line, []).append((el, names, parent))
            for c in el.children:
                name = c.get("name")
                sub = None
                if names is not None and name is not None and names + (name,) not in self.by_path:
                    sub = names + (name,)
                    self.by_path[sub] = c
                work.append((c, sub, el))


_INDEX = {}             # (path, sha256) -> _ReaderIndex of those bytes, the last few
_INDEX_KEEP = 4


def _sha256(data):
    return hashlib.sha256(data).hexdigest()


def _reader_index(path, data, sha):
    """_ReaderIndex of a file's bytes (parsed once per content). Raises MtlxError where they do not parse."""
    key = (path, sha)
    index = _INDEX.get(key)
    if index is None:
        from mtlxgen.read import xmlreader
        index = _ReaderIndex(xmlreader.parse_text(data, path))
        while len(_INDEX) >= _INDEX_KEEP:
            _INDEX.pop(next(iter(_INDEX)))
        _INDEX[key] = index
    return index


def record_sources(items):
    """Confirm where each PanelInput is written against its file's bytes as they are now, and remember them:
    the element the reader found at the input's line is that input of that node (for an input the document
    does not author: the node's element is at its line and holds no such input), and it is the element its name
    path names. Sets item.source (the file and the sha256 of those bytes, one SourceFile per file) and
    item.element_path; an item that does not match gets neither (its file changed after the document was
    read): Save refuses it."""
    from mtlxgen.read.usdstage import is_usd
    sources = {}
    for item in items:
        item.source, item.element_path = None, None
        loc = item.where or item.node_loc
        if loc is None or not loc.file or loc.where is not None or is_usd(loc.file):
            continue
        if loc.file not in sources:
            sources[loc.file] = _read_source(loc.file)
        if sources[loc.file] is None:
            continue
        source, index = sources[loc.file]
        names = _confirmed_path(item, index)
        if names is not None:
            item.source, item.element_path = source, names
    return items


def _read_source(path):
    from mtlxgen.base import files
    try:
        data = files.read_bounded(path, Loc(path, 0), "the document")
        sha = _sha256(data)
        return SourceFile(path, sha), _reader_index(path, data, sha)
    except MtlxError:
        return None


def _confirmed_path(item, index):
    """The name path in its file of the input item sets, where that file's elements confirm it (see
    record_sources): the element the reader finds at the item's line is the input (or, for an input not
    authored, the node) its Origin names. The path in an included file is the tail of the path in the document
    (the file's elements sit where the xi:include element was)."""
    o = item.origin
    if o is None:
        return None
    wanted = tuple(o.element.split("/")) if o.element else ()

    def names_of(names, whole, least):
        # a name path in the file naming the document's element `whole`: all of it (the document's own file, an
        # include at the top level), or its tail of `least` names or more (an include inside a nodegraph)
        return names is not None and (names == whole or least <= len(names) < len(whole)
                                      and whole[len(whole) - len(names):] == names)

    if o.authored:
        if item.where is None:
            return None
        found = [names for el, names, parent in index.by_line.get(item.where.line, ())
                 if el.tag == "input" and el.get("name") == o.input and names_of(names, wanted + (o.input,), 2)]
        return found[0] if len(found) == 1 else None
    if item.node_loc is None or not wanted:
        return None
    found = [names for el, names, parent in index.by_line.get(item.node_loc.line, ())
             if el.tag == item.tag and names_of(names, wanted, 1)]
    if len(found) != 1 or found[0] + (o.input,) in index.by_path:
        return None
    return found[0] + (o.input,)


# ------------------------------------------------------------------ writing

def format_value(mtlx_type, value):
    """A value as a MaterialX value string: shortest round numbers, components joined by ', '."""
    if mtlx_type == "boolean":
        return "true" if value else "false"
    if mtlx_type == "filename":
        return str(value)

    def one(x):
        if mtlx_type == "integer":
            return str(int(round(float(x))))
        text = "%.6g" % float(x)
        return "0" if text == "-0" else text
    if isinstance(value, (list, tuple)):
        return ", ".join(one(x) for x in value)
    return one(value)


def _escape(text, quote='"'):
    """Text as an attribute value between `quote`s: markup and that quote escaped, tabs and line breaks as
    character references (an XML reader turns them into spaces otherwise)."""
    text = text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;").replace(">", "&gt;")
    if quote == "'":
        text = text.replace("'", "&apos;")
    return text.replace("\t", "&#9;").replace("\n", "&#10;").replace("\r", "&#13;")


_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")     # not even as a reference
_BREAK = re.compile(r"\r\n|\r|\n")           # a line break as XML (and the reader's line numbers) count them
_SPACE = re.compile(r"[ \t\r\n]*")
_INDENT = re.compile(r"[ \t]*")
_NAME = re.compile(r"[^ \t\r\n/>=<\"'!?]+")
_REF = re.compile(r"&(#x[0-9a-fA-F]+|#[0-9]+|lt|gt|amp|quot|apos);|\r\n|[\r\n\t]")
_ENTITY = {"lt": "<", "gt": ">", "amp": "&", "quot": '"', "apos": "'"}


class _ScanError(Exception):
    def __init__(self, offset, message):
        super().__init__(message)
        self.offset = offset


class _Tag:
    """An element of the text: its tag, where its start tag begins and ends, its attributes' value spans."""
    __slots__ = ("tag", "start", "end", "attrs", "attrs_end", "closed", "children", "_named")

    def __init__(self, tag, start):
        self.tag, self.start, self.end = tag, start, start
        self.attrs = {}             # name -> (start, end, quote): the value between its quotes
        self.attrs_end = start      # just after the last attribute (where one is added)
        self.closed = False         # <tag ... />
        self.children = []
        self._named = None

    def child(self, name, text):
        """The first child element named `name` (the one MaterialX reads), else None."""
        if self._named is None:
            self._named = {}
            for c in self.children:
                span = c.attrs.get("name")
                if span is not None:
                    self._named.setdefault(_unescape(text[span[0]:span[1]]), c)
        return self._named.get(name)


def _unescape(raw):
    """An attribute value's text as an XML reader gives it: references expanded, line breaks and tabs spaces."""
    def one(m):
        ref = m.group(1)
        if ref is None:
            return " "
        if ref[0] == "#":
            try:
                return chr(int(ref[2:], 16) if ref[1] == "x" else int(ref[1:]))
            except (ValueError, OverflowError):
                return m.group(0)
        return _ENTITY[ref]
    return _REF.sub(one, raw) if ("&" in raw or "\r" in raw or "\n" in raw or "\t" in raw) else raw


def _scan(text):
    """(root _Tag, [(start, end)] of the comments, CDATA sections, processing instructions and declarations) of
    a document's text: those skipped whole, attribute values read between their quotes. Raises _ScanError."""
    root, stack, pos, skipped = None, [], 0, []
    while True:
        i = text.find("<", pos)
        if i < 0:
            break
        if text.startswith("<!--", i):
            pos = _past(text, "-->", i + 4, i, "comment")
            skipped.append((i, pos))
        elif text.startswith("<![CDATA[", i):
            pos = _past(text, "]]>", i + 9, i, "CDATA section")
            skipped.append((i, pos))
        elif text.startswith("<?", i):
            pos = _past(text, "?>", i + 2, i, "processing instruction")
            skipped.append((i, pos))
        elif text.startswith("<!", i):
            pos = _past_declaration(text, i)
            skipped.append((i, pos))
        elif text.startswith("</", i):
            m = _NAME.match(text, i + 2)
            if not stack or m is None or m.group() != stack[-1].tag:
                raise _ScanError(i, "an end tag that closes no open element")
            stack.pop()
            pos = _past(text, ">", m.end(), i, "end tag")
        elif text.startswith(("<UDIM>", "<UVTILE>"), i):
            pos = i + 1                 # filename tokens the reader takes as text
        else:
            el, pos = _start_tag(text, i)
            if stack:
                stack[-1].children.append(el)
            elif root is None:
                root = el
            else:
                raise _ScanError(i, "a second root element")
            if not el.closed:
                stack.append(el)
    if root is None:
        raise _ScanError(0, "no element")
    if stack:
        raise _ScanError(stack[-1].start, "<%s> is not closed" % stack[-1].tag)
    return root, skipped


def _past(text, end, at, start, what):
    j = text.find(end, at)
    if j < 0:
        raise _ScanError(start, "unterminated " + what)
    return j + len(end)


def _past_declaration(text, i):
    """Just past a <!DOCTYPE ...> declaration: quoted strings, an internal subset in brackets and its comments."""
    depth, pos, n = 0, i + 2, len(text)
    while pos < n:
        c = text[pos]
        if c in "\"'":
            pos = _past(text, c, pos + 1, i, "declaration")
            continue
        if depth and text.startswith("<!--", pos):
            pos = _past(text, "-->", pos + 4, i, "comment")
            continue
        if c == "[":
            depth += 1
        elif c == "]":
            depth -= 1
        elif c == ">" and depth <= 0:
            return pos + 1
        pos += 1
    raise _ScanError(i, "unterminated declaration")


def _start_tag(text, i):
    m = _NAME.match(text, i + 1)
    if m is None:
        raise _ScanError(i, "a '<' that starts no element")
    el = _Tag(m.group(), i)
    pos = el.attrs_end = m.end()
    while True:
        pos = _SPACE.match(text, pos).end()
        if text.startswith("/>", pos):
            el.closed, el.end = True, pos + 2
            return el, el.end
        if text.startswith(">", pos):
            el.end = pos + 1
            return el, el.end
        a = _NAME.match(text, pos)
        if a is None:
            raise _ScanError(i, "<%s>: an attribute without a name" % el.tag)
        pos = _SPACE.match(text, a.end()).end()
        if not text.startswith("=", pos):
            raise _ScanError(i, "<%s>: attribute %s without a value" % (el.tag, a.group()))
        pos = _SPACE.match(text, pos + 1).end()
        quote = text[pos:pos + 1]
        if quote not in ("'", '"'):
            raise _ScanError(i, "<%s>: attribute %s not quoted" % (el.tag, a.group()))
        end = _past(text, quote, pos + 1, i, "attribute value") - 1
        el.attrs.setdefault(a.group(), (pos + 1, end, quote))
        pos = el.attrs_end = end + 1


class _Lines:
    """Line numbers of text offsets, counted as the XML reader counts them: CR LF, a lone CR and LF each end
    a line."""

    def __init__(self, text):
        self.ends = [m.end() for m in _BREAK.finditer(text)]

    def line(self, offset):
        return bisect.bisect_right(self.ends, offset) + 1


def _encoding(data, loc):
    """(byte-order mark, codec) of a document's bytes: the XML reader's decision (xmlreader._encoding_of: a
    byte-order mark, UTF-16 without one from its first character '<', the XML declaration's encoding, else
    UTF-8), with the mark split off so that the edited text is encoded without it and the mark kept as it was."""
    from mtlxgen.read.xmlreader import _encoding_of
    try:
        codec = _encoding_of(data, loc.file)
    except MtlxError as e:
        raise MtlxError((loc, "cannot save: %s: not saved" % e.problems[0][1])) from None
    if codec == "utf-8-sig":
        return (codecs.BOM_UTF8 if data.startswith(codecs.BOM_UTF8) else b""), "utf-8"
    if codec == "utf-16":
        for bom, name in ((codecs.BOM_UTF16_LE, "utf-16-le"), (codecs.BOM_UTF16_BE, "utf-16-be")):
            if data.startswith(bom):
                return bom, name
        raise MtlxError((loc, "cannot save into UTF-16 text without a byte-order mark declared as 'utf-16': "
                              "not saved"))
    return b"", codec


def _break_after(text, pos, skipped):
    """The first line break at or after `pos` outside comments, CDATA sections and processing instructions (a
    break inside one of those may be an odd one out), else None."""
    starts = [s for s, _ in skipped]
    for m in _BREAK.finditer(text, pos):
        k = bisect.bisect_right(starts, m.start()) - 1
        if k < 0 or m.start() >= skipped[k][1]:
            return m
    return None


def _newline_after(text, pos, skipped):
    """The line break ending the line at `pos`, else the document's first, else LF."""
    m = _break_after(text, pos, skipped) or _break_after(text, 0, skipped)
    return m.group(0) if m else "\n"


def _child_indent(text, el, indent, skipped):
    """The indentation of the element's first child line, else the element's own plus two spaces."""
    if not el.closed:
        m = _break_after(text, el.end, skipped)
        if m is not None:
            child = _INDENT.match(text, m.end()).group(0)
            if len(child) > len(indent) and text.startswith("<", m.end() + len(child)):
                return child
    return indent + "  "


def _hint(item):
    """Where an edit's problems are reported: its input's line, else its node's (as the document was read)."""
    return item.where or item.node_loc


def _plan(path, items):
    """(real path, the file's sha256, its new bytes) with [(PanelInput, value)] written into one file.
    Raises MtlxError (one line each, FILE:LINE) where the file cannot take them; nothing is written here."""
    from mtlxgen.base import files
    from mtlxgen.read import xmlreader
    first = _hint(items[0][0])
    unconfirmed = [(_hint(item), "input '%s' of '%s': the file changed while the document was read: not saved; "
                                 "reload first" % (item.input, item.node))
                   for item, _ in items if item.source is None or item.element_path is None]
    if unconfirmed:
        raise MtlxError(unconfirmed)
    real = os.path.realpath(path)
    data = files.read_bounded(real, first, "the document")
    sha = _sha256(data)
    if any(item.source.sha256 != sha for item, _ in items):
        raise MtlxError((first, "changed on disk since it was read: not saved; reload first"))
    bom, codec = _encoding(data, first)
    try:
        text = data[len(bom):].decode(codec)
    except UnicodeDecodeError:
        raise MtlxError((first, "not valid %s text: not saved" % codec)) from None
    index = _reader_index(path, data, sha)
    lines = _Lines(text)
    try:
        root, skipped = _scan(text)
    except _ScanError as e:
        raise MtlxError((Loc(path, lines.line(e.offset)), "cannot find the elements in the text (%s): not saved"
                         % e)) from None
    problems, values, edited, inserts = [], {}, {}, {}
    for item, value in items:
        loc, names = _hint(item), item.element_path
        value_text = format_value(item.mtlx_type, value)
        bad = _NOT_XML.search(value_text)
        if bad:
            problems.append((loc, "input '%s' of '%s': the value holds U+%04X, which XML cannot hold: not saved"
                             % (item.input, item.node, ord(bad.group(0)))))
            continue
        owner = _resolve(root, names[:-1], text)
        el = owner.child(names[-1], text) if owner is not None else None
        expected = [(names[:-1], owner)] + ([(names, el)] if el is not None else [])
        if any(got is None or index.by_path.get(n) is None or index.by_path[n].tag != got.tag
               or index.by_path[n].loc.line != lines.line(got.start) for n, got in expected):
            problems.append((loc, "input '%s' of '%s': its element in the text is not the one the XML reader "
                                  "reads: not saved" % (item.input, item.node)))
            continue
        if el is not None and el.tag != "input":
            problems.append((loc, "'%s' of '%s' is a <%s> element, not an input: not saved"
                             % (item.input, item.node, el.tag)))
        elif el is None and item.where is not None:
            problems.append((loc, "input '%s' of '%s' is no longer at this line: not saved" % (item.input, item.node)))
        elif el is None and names[:-1] and owner.tag != item.tag:
            problems.append((loc, "node '%s' is a <%s> element, not a <%s>: input '%s' not saved"
                             % (item.node, owner.tag, item.tag, item.input)))
        elif el is not None:
            edited[el.start] = (el, value_text)
            values[names] = value_text
        else:
            inserts.setdefault(owner.start, (owner, {}))[1][names[-1]] = (item, value_text)
            values[names] = value_text
    if problems:
        raise MtlxError(problems)
    replacements = []                   # (start, end, new text)
    for el, value_text in edited.values():
        span = el.attrs.get("value")
        if span is not None:
            replacements.append((span[0], span[1], _escape(value_text, span[2])))
        else:
            replacements.append((el.attrs_end, el.attrs_end, ' value="%s"' % _escape(value_text)))
    added = 0
    for owner, by_name in inserts.values():
        line_begin = max(text.rfind("\n", 0, owner.start), text.rfind("\r", 0, owner.start)) + 1
        indent = _INDENT.match(text, line_begin).group(0)
        newline = _newline_after(text, owner.end, skipped)
        child = _child_indent(text, owner, indent, skipped)
        body = "".join('%s%s<input name="%s" type="%s" value="%s" />' % (
            newline, child, _escape(name), _escape(item.mtlx_type), _escape(value_text))
            for name, (item, value_text) in by_name.items())
        added += len(by_name)
        if owner.closed:                # <node ... /> becomes <node ...> + inputs + </node>
            close = owner.end - 2
            while close > owner.attrs_end and text[close - 1] in " \t\r\n":
                close -= 1
            replacements.append((close, owner.end, ">" + body + newline + indent + "</%s>" % owner.tag))
        else:
            replacements.append((owner.end, owner.end, body))
    new = _splice(data, bom, codec, text, replacements, first)
    try:
        new_index = _ReaderIndex(xmlreader.parse_text(new, path))
    except MtlxError as e:
        raise MtlxError((first, "the edited file would not read back (%s): not saved"
                         % "; ".join(msg for _, msg in e.problems))) from None
    wrong = [n for n, v in values.items() if new_index.by_path.get(n) is None
             or new_index.by_path[n].tag != "input" or new_index.by_path[n].get("value") != v]
    if wrong or new_index.count != index.count + added:
        raise MtlxError((first, "the edited file would not read back with the values set (%s): not saved"
                         % ("/".join(wrong[0]) if wrong else "elements added")))
    new_sha = _sha256(new)
    while len(_INDEX) >= _INDEX_KEEP:
        _INDEX.pop(next(iter(_INDEX)))
    _INDEX[(path, new_sha)] = new_index
    return real, sha, new


def _resolve(root, names, text):
    el = root
    for name in names:
        el = el.child(name, text)
        if el is None:
            return None
    return el


def _splice(data, bom, codec, text, replacements, loc):
    """The file's new bytes: its own bytes outside the replaced spans, each replacement encoded (a character the
    encoding lacks as a character reference). Refuses text whose unedited parts do not encode back to the bytes
    they were read from."""
    old, new, last = [bom], [bom], 0
    for start, end, piece in sorted(replacements):
        keep = text[last:start].encode(codec)
        old += [keep, text[start:end].encode(codec)]
        new += [keep, piece.encode(codec, "xmlcharrefreplace")]
        last = end
    keep = text[last:].encode(codec)
    old.append(keep)
    new.append(keep)
    if b"".join(old) != data:
        raise MtlxError((loc, "the file's %s text does not encode back to its own bytes: not saved" % codec))
    return b"".join(new)


def save_values(edits):
    """Write [(PanelInput, value)] into their files (as record_sources confirmed them). Returns the files
    written. Every file is patched and read back before any is written; a file whose bytes changed since the
    panel read them, or where an input is not where it was, is refused (MtlxError, one FILE:LINE line each) and
    then nothing is written."""
    by_file = {}
    for item, value in edits:
        loc = _hint(item)
        if loc is None or not loc.file:
            raise MtlxError((Loc("<document>", 0), "input '%s' of '%s' is not written in a file: not saved"
                             % (item.input, item.node)))
        from mtlxgen.read.usdstage import is_usd
        if loc.where is not None or is_usd(loc.file):
            raise MtlxError((loc, "input '%s' of '%s': values are saved into .mtlx documents only, not into "
                                  "a USD stage" % (item.input, item.node)))
        by_file.setdefault(loc.file, []).append((item, value))
    planned, problems = [], []
    for path, items in by_file.items():
        try:
            planned.append((path, items) + _plan(path, items))
        except MtlxError as e:
            problems.extend(e.problems)
        except Exception as e:          # a bug of ours: one line, nothing written
            problems.append((_hint(items[0][0]), "internal error preparing the edit (%s: %s): not saved"
                             % (type(e).__name__, e)))
    if problems:
        raise MtlxError(problems)
    from mtlxgen.base import files
    for path, items, real, sha, _ in planned:      # changed while being patched: refused before any is written
        try:
            same = _sha256(files.read_bounded(real, _hint(items[0][0]), "the document")) == sha
        except MtlxError:
            same = False
        if not same:
            problems.append((_hint(items[0][0]), "changed on disk since it was read: not saved; reload first"))
    if problems:
        raise MtlxError(problems)
    written = []
    for path, items, real, sha, new in planned:
        try:
            files.write_atomic(real, new)
        except OSError as e:
            raise MtlxError((_hint(items[0][0]), "cannot write the file (%s): not saved%s" % (
                e.strerror or e, "; saved before it: " + ", ".join(written) if written else ""))) from None
        new_sha = _sha256(new)
        for item, _ in items:
            item.source.sha256 = new_sha
        written.append(path)
    return written
