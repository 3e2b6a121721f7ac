"""Read .mtlx XML into a small element tree that remembers file and line, expanding xi:include.

Built on the standard library's expat binding; DTDs and entity declarations are refused (no
entity expansion attacks, no external fetches). Included documents' children are spliced in place
of the <xi:include> element, each keeping its own file and line.
"""
import os
import xml.parsers.expat
from dataclasses import dataclass, field

from .diagnostics import Loc, MtlxError


@dataclass
class XElement:
    tag: str
    attrs: dict
    loc: Loc
    children: list = field(default_factory=list)

    def get(self, key, default=None):
        return self.attrs.get(key, default)


class _Refused(Exception):
    pass


def parse_text(text, path):
    """XML text -> root XElement. Raises MtlxError naming file and line on malformed XML."""
    parser = xml.parsers.expat.ParserCreate()
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)
    root_holder = []
    stack = []

    def start(tag, attrs):
        el = XElement(tag, attrs, Loc(path, parser.CurrentLineNumber))
        if stack:
            stack[-1].children.append(el)
        else:
            root_holder.append(el)
        stack.append(el)

    def end(tag):
        stack.pop()

    def refuse_entity(*args):
        raise _Refused("entity declarations are not allowed")

    def refuse_external(*args):
        raise _Refused("external entities are not allowed")

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.EntityDeclHandler = refuse_entity
    parser.ExternalEntityRefHandler = refuse_external
    try:
        if isinstance(text, str):
            text = text.encode("utf-8")
        # filename tokens are written raw inside attribute values (MaterialX's reader accepts them)
        text = text.replace(b"<UDIM>", b"&lt;UDIM&gt;").replace(b"<UVTILE>", b"&lt;UVTILE&gt;")
        parser.Parse(text, True)
    except xml.parsers.expat.ExpatError as e:
        raise MtlxError((Loc(path, e.lineno), "malformed XML: %s" % xml.parsers.expat.ErrorString(e.code))) from None
    except _Refused as e:
        raise MtlxError((Loc(path, parser.CurrentLineNumber), str(e))) from None
    if not root_holder:
        raise MtlxError((Loc(path, 1), "empty document"))
    return root_holder[0]


def read_file(path, search_paths=(), _including=None, _from=None):
    """Read a .mtlx file, splicing xi:include'd documents. Returns the root XElement."""
    path = os.path.abspath(path)
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        where = _from or Loc(path, 0)
        raise MtlxError((where, "cannot read %s: %s" % (path, e.strerror or e))) from None
    root = parse_text(data, path)
    if root.tag != "materialx":
        raise MtlxError((root.loc, "root element is <%s>, expected <materialx>" % root.tag))
    including = (_including or ()) + (path,)
    root.children = _expand_includes(root.children, path, search_paths, including)
    return root


def _is_include(el):
    return el.tag == "xi:include" or el.tag.endswith(":include") or el.tag == "include"


def _expand_includes(children, path, search_paths, including):
    out = []
    for child in children:
        if not _is_include(child):
            child.children = _expand_includes(child.children, path, search_paths, including)
            out.append(child)
            continue
        href = child.get("href")
        if not href:
            raise MtlxError((child.loc, "xi:include without href"))
        target = find_file(href, os.path.dirname(path), search_paths)
        if target is None:
            raise MtlxError((child.loc, "included file not found: %s" % href))
        if os.path.abspath(target) in including:
            raise MtlxError((child.loc, "include cycle: %s includes itself" % href))
        sub = read_file(target, search_paths, including, child.loc)
        # the included document's own version and prefixes apply to what came from it
        for grand in sub.children:
            for key in ("fileprefix", "geomprefix", "colorspace"):
                if key in sub.attrs and key not in grand.attrs:
                    grand.attrs[key] = sub.attrs[key]
        out.extend(sub.children)
    return out


def find_file(name, base_dir, search_paths=()):
    if os.path.isabs(name):
        return name if os.path.exists(name) else None
    for base in [base_dir, *search_paths]:
        cand = os.path.join(base, name)
        if os.path.exists(cand):
            return cand
    return None
