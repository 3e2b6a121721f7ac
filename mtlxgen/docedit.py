"""An element's public inputs as a property panel shows them, and writing edited values back into the document.

public_inputs() lists the uniforms of an element's shader that a document input sets (or would set): each with
the node and input it belongs to, the nodedef's ui metadata (uiname, uifolder, uimin, uimax, uisoftmin,
uisoftmax, uistep, enum, enumvalues) and where it is written in the document. save_values() writes edited
values back as the smallest text edit: the value attribute of the <input> at its line is replaced (or added);
an input the document does not author is added as one <input> line in its node. Nothing else in the file
changes: comments, formatting, attribute order and line endings stay as they were.
"""
import os
import re
from dataclasses import dataclass, field

from .diagnostics import Loc, MtlxError

EDITABLE_TYPES = ("float", "integer", "boolean", "color3", "color4", "vector2", "vector3", "vector4", "filename")


@dataclass
class PanelInput:
    uniform: str                # the shader's uniform (a texture's sampler for filename inputs)
    node: str                   # the node (or nodegraph, for its interface inputs) the input belongs to
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

    @property
    def group(self):
        return "%s / %s" % (self.node, self.folder) if self.folder else self.node


# ------------------------------------------------------------------ reading

_ATTR_CACHE = {}


def _input_attrs(path):
    """{(line, input name): attrs} of every <input> element in a .mtlx file (read once per file and mtime)."""
    from . import xmlreader
    try:
        key = (path, os.path.getmtime(path))
    except OSError:
        return {}
    if key not in _ATTR_CACHE:
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
        _ATTR_CACHE[key] = out
    return _ATTR_CACHE[key]


def _attrs(port):
    if port is None or port.loc is None or not port.loc.file or not os.path.isfile(port.loc.file):
        return {}
    return _input_attrs(port.loc.file).get((port.loc.file, port.loc.line, port.name), {})


def _number_list(text, mtlx_type):
    from . import mxtypes
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
    """[PanelInput] of one element of a pipeline.Session, in the order its shader declares the uniforms."""
    from .graph import GraphBuilder, glsl_identifier
    g = session.graph(element)
    doc = session.doc
    builder = GraphBuilder(doc, session.library, session.rules)
    owners = []         # (stem, node name, tag, node loc, {input: authored port}, {input: declared port})
    for node in list(doc.nodes.values()) + [n for ng in doc.nodegraphs.values() for n in ng.nodes.values()]:
        try:
            nd = builder.nodedef_for(node)
        except MtlxError:
            continue
        owners.append((node.name, node.category, node.loc, node.inputs, nd.inputs))
    for ng in doc.nodegraphs.values():
        nd = session.library.nodedefs.get(ng.nodedef) if ng.nodedef else None
        declared = dict(nd.inputs) if nd is not None else {}
        declared.update({k: v for k, v in ng.inputs.items() if k not in declared})
        owners.append((ng.name, "nodegraph", ng.loc, ng.inputs, declared))
    if doc.inputs:
        owners.append(("doc", "materialx", None, doc.inputs, doc.inputs))
    by_stem = {}
    for name, tag, loc, authored, declared in owners:
        for input_name, decl in declared.items():
            by_stem.setdefault(glsl_identifier("%s_%s" % (name, input_name)), []).append(
                (name, tag, loc, authored.get(input_name), decl))
    out = []
    for u in g.uniforms.values():
        if u.type not in EDITABLE_TYPES:
            continue
        stem = re.sub(r"\d+$", "", u.name)
        for name, tag, loc, port, decl in by_stem.get(u.name, []) + (by_stem.get(stem, []) if stem != u.name else []):
            authored = port is not None and port.loc == u.loc
            if not authored and not (decl.loc == u.loc and port is None):
                continue
            decl_attrs, own_attrs = _attrs(decl), _attrs(port) if authored else {}
            enum = port.enum if authored and port.enum else decl.enum
            enumvalues = port.enumvalues if authored and port.enumvalues else decl.enumvalues
            out.append(PanelInput(
                uniform=u.name, node=name, input=decl.name, mtlx_type=u.type, value=u.value,
                label=own_attrs.get("uiname") or decl_attrs.get("uiname") or decl.name,
                folder=own_attrs.get("uifolder") or decl_attrs.get("uifolder") or "",
                ui=_ui(decl_attrs, own_attrs, u.type), enum=_split(enum), enumvalues=_split(enumvalues),
                where=port.loc if authored else None, node_loc=loc if tag != "materialx" else None, tag=tag))
            break
    return out


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


def _escape(text):
    return text.replace("&", "&amp;").replace('"', "&quot;").replace("<", "&lt;").replace(">", "&gt;")


_TAG = re.compile(r"<([\w:.-]+)((?:\s+[\w:.-]+\s*=\s*(?:\"[^\"]*\"|'[^']*'))*)\s*(/?)>", re.S)
_ATTR = re.compile(r"([\w:.-]+)(\s*=\s*)(\"[^\"]*\"|'[^']*')")


def _line_starts(text):
    starts = [0]
    for m in re.finditer(r"\n", text):
        starts.append(m.end())
    return starts


def _tags_on_line(text, starts, line):
    """Start tags beginning on a 1-based line: (match, {attr: value})."""
    if not 1 <= line <= len(starts):
        return []
    begin = starts[line - 1]
    end = starts[line] if line < len(starts) else len(text)
    out = []
    pos = begin
    while True:
        i = text.find("<", pos, end)
        if i < 0:
            return out
        m = _TAG.match(text, i)
        if m is not None:
            attrs = {a.group(1): a.group(3)[1:-1] for a in _ATTR.finditer(m.group(2))}
            out.append((m, attrs))
        pos = i + 1


def patch_text(text, edits, path="<document>"):
    """Apply [(PanelInput, new value)] to one file's text; returns the new text. Raises MtlxError (one line
    each) for an input whose element is not where the document was read from (the file changed since)."""
    newline = "\r\n" if "\r\n" in text else "\n"
    replacements, problems = [], []      # (start, end, new text)
    starts = _line_starts(text)
    inserts = {}                         # node tag match start -> (match, [lines])
    for item, value in edits:
        value_text = _escape(format_value(item.mtlx_type, value))
        if item.where is not None:
            found = [(m, a) for m, a in _tags_on_line(text, starts, item.where.line)
                     if m.group(1) == "input" and a.get("name") == item.input]
            if len(found) != 1:
                problems.append((item.where, "input '%s' of '%s' is no longer at this line: not saved"
                                 % (item.input, item.node)))
                continue
            m, _ = found[0]
            value_attr = next((a for a in _ATTR.finditer(m.group(2)) if a.group(1) == "value"), None)
            if value_attr is not None:
                quote = value_attr.group(3)[0]
                s = m.start(2) + value_attr.start(3)
                e = m.start(2) + value_attr.end(3)
                replacements.append((s, e, quote + value_text.replace(quote, "&quot;" if quote == '"' else "&apos;")
                                     + quote))
            else:
                at = m.end(2)
                replacements.append((at, at, ' value="%s"' % value_text))
            continue
        loc = item.node_loc
        found = [(m, a) for m, a in _tags_on_line(text, starts, loc.line)] if loc is not None else []
        found = [(m, a) for m, a in found if a.get("name") == item.node and m.group(1) == item.tag]
        if len(found) != 1:
            problems.append((loc or Loc(path, 0), "node '%s' is no longer at this line: input '%s' not saved"
                             % (item.node, item.input)))
            continue
        m, _ = found[0]
        line = '<input name="%s" type="%s" value="%s" />' % (_escape(item.input), item.mtlx_type, value_text)
        inserts.setdefault(m.start(), (m, []))[1].append(line)
    for _, (m, lines) in inserts.items():
        line_begin = text.rfind("\n", 0, m.start()) + 1
        indent = re.match(r"[ \t]*", text[line_begin:]).group(0)
        child = _child_indent(text, m, indent)
        body = "".join(newline + child + ln for ln in lines)
        if m.group(3) == "/":        # <node ... /> becomes <node ...> + inputs + </node>
            close = m.end() - 2
            while close > m.start() and text[close - 1] in " \t\r\n":
                close -= 1
            replacements.append((close, m.end(), ">" + body + newline + indent + "</%s>" % m.group(1)))
        else:
            replacements.append((m.end(), m.end(), body))
    if problems:
        raise MtlxError(problems)
    for s, e, new in sorted(replacements, reverse=True):
        text = text[:s] + new + text[e:]
    return text


def _child_indent(text, m, indent):
    """The indentation of the element's first child line, else the element's own plus two spaces."""
    nxt = text.find("\n", m.end())
    if nxt >= 0 and m.group(3) != "/":
        child = re.match(r"[ \t]*", text[nxt + 1:]).group(0)
        if len(child) > len(indent) and text[nxt + 1 + len(child):nxt + 2 + len(child)] == "<":
            return child
    return indent + "  "


def save_values(edits):
    """Write [(PanelInput, value)] into their files. Returns the files written. Each file is read and written
    as bytes of its own encoding (UTF-8 where it declares none) with its line endings kept."""
    by_file = {}
    for item, value in edits:
        loc = item.where or item.node_loc
        if loc is None or not loc.file:
            raise MtlxError((Loc("<document>", 0), "input '%s' of '%s' is not written in a file: not saved"
                             % (item.input, item.node)))
        from .usdstage import is_usd
        if loc.where is not None or is_usd(loc.file):
            raise MtlxError((loc, "input '%s' of '%s': values are saved into .mtlx documents only, not into "
                                  "a USD stage" % (item.input, item.node)))
        by_file.setdefault(loc.file, []).append((item, value))
    written = []
    texts = {}
    for path, items in by_file.items():
        with open(path, "rb") as f:
            data = f.read()
        encoding = _declared_encoding(data)
        try:
            text = data.decode(encoding)
        except (UnicodeDecodeError, LookupError):
            raise MtlxError((Loc(path, 0), "cannot save: the file is not %s text" % encoding)) from None
        texts[path] = (patch_text(text, items, path), encoding)
    for path, (text, encoding) in texts.items():      # every file patched before any is written
        with open(path, "wb") as f:
            f.write(text.encode(encoding))
        written.append(path)
    return written


def _declared_encoding(data):
    if data.startswith(b"\xef\xbb\xbf"):
        return "utf-8-sig"
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        return "utf-16"
    m = re.match(rb"<\?xml[^>]*?\sencoding\s*=\s*([\"'])(.*?)\1", data)
    return m.group(2).decode("ascii", "replace").lower() if m else "utf-8"
