"""Read .mtlx XML into a small element tree that remembers file and line, expanding xi:include.

Built on the standard library's expat binding; DTDs and entity declarations are refused (no
entity expansion attacks, no external fetches). Included documents' children are spliced in place
of the <xi:include> element, each keeping its own file and line. Documents are read through
files.read_bounded (regular files only, size capped); included files must lie inside the allowed
roots (files.allowed_roots: the document's folder, the search paths, the data libraries).
Elements nest at most MAX_DEPTH levels, includes spliced in counted, so nothing later recurses deeply.
"""
import codecs
import contextlib
import gc
import importlib
import os
import re
import xml.parsers.expat
from mtlxgen.base.records import dataclass

from mtlxgen.base import files
from mtlxgen.base.diagnostics import Loc, MtlxError

MAX_DEPTH = 256          # MaterialX documents nest about 5 levels
MAX_INCLUDES = 1024      # included files read for one document (a diamond of includes multiplies reads)
MAX_ELEMENTS = 500_000   # elements of one document, includes counted (MaterialX's largest library: ~20,000; a graph
                         # of 100,000 nodes with two inputs each: 300,000)
MAX_TOTAL_BYTES = 4 * files.MAX_TEXT_BYTES     # bytes read for one document, includes counted


@dataclass
class _Budget:
    """What reading one document (with its includes) has used so far: every read and element counted."""
    includes: int = 0
    elements: int = 0
    bytes: int = 0
    include_tags: int = 0       # elements that may be includes (tags ending in 'include'): none, nothing to splice
    warnings: list = None       # (Loc, message): slips of the XML itself that MaterialX's reader reads past
    upgrade: object = None      # upgrade(root, warnings) -> root: applied to each included document (read_file)


class gc_paused(contextlib.ContextDecorator):
    """Python's cyclic garbage collector off for a while (a `with` block or a decorated function; nested: the
    outermost turns it back on). Reading and generating a large document builds hundreds of thousands of objects
    that hold no cycles; the collector, run every few hundred new objects, walks them again and again (a
    100,000-node chain took 2-3x as long with it on)."""

    def _recreate_cm(self):         # each call of a decorated function its own state (threads, recursion)
        return type(self)()

    def __enter__(self):
        self._was = gc.isenabled()
        gc.disable()
        return self

    def __exit__(self, *exc):
        if self._was:
            gc.enable()
        return False


class XElement:
    """An element: tag, attributes, where it starts (Loc) and child elements."""
    __slots__ = ("tag", "attrs", "loc", "children")

    def __init__(self, tag, attrs, loc, children=None):
        self.tag = tag
        self.attrs = attrs
        self.loc = loc
        self.children = [] if children is None else children

    def get(self, key, default=None):
        return self.attrs.get(key, default)

    def __repr__(self):
        return "XElement(%r, %r, %r, %d children)" % (self.tag, self.attrs, self.loc, len(self.children))

    def __eq__(self, other):
        if not isinstance(other, XElement):
            return NotImplemented
        return (self.tag, self.attrs, self.loc, self.children) == (other.tag, other.attrs, other.loc, other.children)

    __hash__ = None


class _Refused(Exception):
    pass


# Encodings expat reads directly; single-byte code pages (iso8859-*, cp125x, koi8-*) are decoded by Python.
_ENCODINGS = {"utf-8", "utf-8-sig", "utf-16", "utf-16-le", "utf-16-be", "ascii", "iso8859-1"}
_DECLARATION = re.compile(rb"<\?xml[^>]*?\sencoding\s*=\s*([\"'])(.*?)\1")


def _single_byte(codec):
    try:
        return hasattr(importlib.import_module("encodings." + codec.replace("-", "_")), "decoding_table")
    except ImportError:
        return False


def _encoding_of(data, path):
    """The Python codec for a document's bytes: byte-order mark, UTF-16 without one, or the XML declaration."""
    if data.startswith((codecs.BOM_UTF32_LE, codecs.BOM_UTF32_BE)):
        raise MtlxError((Loc(path, 1), "unsupported encoding 'utf-32' (read: UTF-8, UTF-16, ASCII, single-byte)"))
    if data.startswith(codecs.BOM_UTF8):
        return "utf-8-sig"
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return "utf-16"
    if data.startswith(b"<\0"):
        return "utf-16-le"
    if data.startswith(b"\0<"):
        return "utf-16-be"
    m = _DECLARATION.search(data[:1024])        # searched: text before the declaration is read past (a warning)
    if not m:
        return "utf-8"
    name = m.group(2).decode("ascii", "replace")
    try:
        codec = codecs.lookup(name).name
    except (LookupError, ValueError):    # ValueError: a NUL inside the name
        codec = None
    if codec is None or not (codec in _ENCODINGS or _single_byte(codec)):
        raise MtlxError((Loc(path, 1), "unsupported encoding %s (read: UTF-8, UTF-16, ASCII, single-byte)"
                                       % files.quoted(name)))
    return codec


def _decode(data, path):
    if isinstance(data, str):
        return data
    codec = _encoding_of(data, path)
    try:
        return data.decode(codec)
    except UnicodeDecodeError as e:
        line = data[:e.start].decode(codec, "replace").count("\n") + 1
        raise MtlxError((Loc(path, line), "not valid %s text (byte 0x%02x)" % (codec, data[e.start]))) from None


def parse_text(text, path, budget=None):
    """XML text (str, or bytes in the encoding they declare) -> root XElement.

    Raises MtlxError naming file and line on malformed XML, unsupported encodings, entity
    declarations, elements nested deeper than MAX_DEPTH and more than MAX_ELEMENTS elements.
    What MaterialX's reader (pugixml) reads past is read past here too, each a warning in budget.warnings:
    blank lines or text before the XML declaration, text or elements before or after the root element (the
    first <materialx> at the top level is the document)."""
    budget = budget or _Budget()
    text = _decode(text, path)
    # filename tokens are written raw inside attribute values (MaterialX's reader accepts them)
    text = text.replace("<UDIM>", "&lt;UDIM&gt;").replace("<UVTILE>", "&lt;UVTILE&gt;")
    elements = budget.elements
    try:
        return _parse(text, path, budget)
    except _Malformed as e:
        error = e
    budget.elements = elements
    slips = []
    try:
        fragment, declaration = _fragment(text, path, slips)
        root = _parse(fragment, path, budget, slips=slips, declaration=declaration)
    except (_Malformed, MtlxError):
        root = None
    if root is None:            # not something MaterialX reads either: the first error, as the parser said it
        raise MtlxError((Loc(path, error.line), "malformed XML: %s" % error.message)) from None
    if budget.warnings is not None:
        budget.warnings.extend(slips)
    return root


class _Malformed(Exception):
    def __init__(self, line, message):
        super().__init__(message)
        self.line, self.message = line, message


_FRAGMENT = "mtlxgen-top-level"             # the element that holds a document's top level when read leniently
_ANY_DECLARATION = re.compile(r"<\?xml\s[^>]*?\?>")


def _fragment(text, path, slips):
    """(text, the line of a declaration with something before it, else 0) read as pugixml reads a document: a
    declaration anywhere is dropped (blank lines or text before it warned), and the top level held in one
    element, so that text and other elements before and after the root element can be seen (and read past by
    _parse). Lines are kept: nothing adds a line break."""
    m = _ANY_DECLARATION.search(text)
    line = 0
    if m is not None and m.start() > 0:
        before = text[:m.start()]
        line = before.count("\n") + 1
        what = ("%d blank line%s" % (before.count("\n"), "" if before.count("\n") == 1 else "s")
                if not before.strip() else "text %s" % files.quoted(before.strip()[:40]))
        slips.append((Loc(path, line), "the XML declaration is not at the start of the file (%s before it): "
                                       "read on, as MaterialX's reader does" % what))
    if m is not None:
        text = text[:m.start()] + " " * (m.end() - m.start()) + text[m.end():]
    return "<%s>%s</%s>" % (_FRAGMENT, text, _FRAGMENT), line


def _parse(text, path, budget, slips=None, declaration=0):
    """Expat over `text`; slips is None for a well-formed document, else the list that receives what the
    top level of a fragment (_fragment) holds besides the root element (text before the declaration's
    line: said by _fragment)."""
    parser = xml.parsers.expat.ParserCreate("UTF-8")     # decoded above: the declared encoding is overridden
    parser.SetParamEntityParsing(xml.parsers.expat.XML_PARAM_ENTITY_PARSING_NEVER)
    root_holder = []
    stack = []
    push, pop = stack.append, stack.pop
    lenient = slips is not None
    max_depth = MAX_DEPTH + lenient
    room = [MAX_ELEMENTS - budget.elements]      # elements this document may still add
    locs = {}                                    # line -> Loc: elements on one line share it
    top = XElement(_FRAGMENT, {}, Loc(path, 1))

    def start(tag, attrs):
        if len(stack) >= max_depth:
            raise _Refused("elements nest more than %d levels deep" % MAX_DEPTH)
        room[0] -= 1
        if room[0] < 0:
            raise _Refused("more than %d elements (includes counted)" % MAX_ELEMENTS)
        line = parser.CurrentLineNumber
        loc = locs.get(line)
        if loc is None:
            loc = locs[line] = Loc(path, line)
        el = XElement(tag, attrs, loc)
        if tag.endswith("include"):
            budget.include_tags += 1
        if stack:
            stack[-1].children.append(el)
        elif lenient and tag == _FRAGMENT:
            el = top
        else:
            root_holder.append(el)
        push(el)

    def end(tag):
        pop()

    def text_at_top(data):
        if len(stack) == 1 and data.strip():
            top.children.append(XElement("#text", {"text": data.strip()}, Loc(path, parser.CurrentLineNumber)))

    def refuse_entity(*args):
        raise _Refused("entity declarations are not allowed")

    def refuse_external(*args):
        raise _Refused("external entities are not allowed")

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.EntityDeclHandler = refuse_entity
    parser.ExternalEntityRefHandler = refuse_external
    if lenient:
        parser.CharacterDataHandler = text_at_top
    try:
        with gc_paused():           # the tree holds no cycles
            parser.Parse(text.encode("utf-8"), True)
    except xml.parsers.expat.ExpatError as e:
        raise _Malformed(e.lineno, xml.parsers.expat.ErrorString(e.code)) from None
    except _Refused as e:
        raise MtlxError((Loc(path, parser.CurrentLineNumber), str(e))) from None
    finally:
        budget.elements = MAX_ELEMENTS - room[0]
    if lenient:
        return _top_level_root(top, slips, declaration)
    if not root_holder:
        raise MtlxError((Loc(path, 1), "empty document"))
    return root_holder[0]


def _top_level_root(top, slips, declaration):
    """The root element of a fragment's top level (its first <materialx>, as MaterialX takes it; else its first
    element), each other thing at the top level a warning (text before the line of the declaration aside)."""
    elements = [c for c in top.children if c.tag != "#text"]
    if not elements:
        raise MtlxError((top.loc, "empty document"))
    root = next((c for c in elements if c.tag == "materialx"), elements[0])
    where = "before"
    for c in top.children:
        if c is root:
            where = "after"
            continue
        if c.tag == "#text" and c.loc.line < declaration:
            continue
        what = ("text %s" % files.quoted(c.attrs["text"][:40]) if c.tag == "#text" else "element <%s>" % c.tag)
        slips.append((c.loc, "%s %s the root element <%s>: ignored, as MaterialX's reader ignores it"
                             % (what, where, root.tag)))
    return root


def _read_document(path, loc, what, budget):
    data = files.read_bounded(path, loc, what)
    budget.bytes += len(data)
    if budget.bytes > MAX_TOTAL_BYTES:
        raise MtlxError((loc, "the document and its includes are larger than %d MB" % (MAX_TOTAL_BYTES // 2 ** 20)))
    root = parse_text(data, path, budget)
    if root.tag != "materialx":
        raise MtlxError((root.loc, "root element is <%s>, expected <materialx>" % root.tag))
    return root


def read_file(path, search_paths=(), warnings=None, upgrade=None):
    """Read a .mtlx file, splicing xi:include'd documents. Returns the root XElement.

    Included files must be inside the document's folder, the search paths or the data libraries.
    warnings: a list that receives (Loc, message) for each slip of the XML that is read past.
    upgrade(root, warnings) -> root: applied to each included document, from its own version, before it is
    spliced in (as MaterialX reads an included document; document.load hands in upgrade.upgrade_tree). None: the
    included elements as written (the viewer's and docedit's walks over what the files say)."""
    path = os.path.abspath(path)
    budget = _Budget(warnings=warnings, upgrade=upgrade)
    root = _read_document(path, Loc(path, 0), "the document", budget)
    if budget.include_tags:         # else nothing to splice (and the parse bounded the nesting)
        roots = files.allowed_roots(path, search_paths)
        _expand_includes(root, path, search_paths, roots, budget)
    return root


def _is_include(el):
    return el.tag == "xi:include" or el.tag.endswith(":include") or el.tag == "include"


def _expand_includes(root, path, search_paths, roots, budget):
    """Splice included documents in place, walking the tree with a work list (no recursion per level).
    Each element carries the chain of files that included it, for cycle detection."""
    work = [(root, 1, (os.path.realpath(path),))]
    while work:
        el, depth, chain = work.pop()
        pending = [(c, chain) for c in reversed(el.children)]
        out = []
        while pending:
            child, child_chain = pending.pop()
            if _is_include(child):
                target, sub = _read_include(child, search_paths, roots, child_chain, budget)
                pending.extend((g, child_chain + (target,)) for g in reversed(sub.children))
                continue
            if depth >= MAX_DEPTH:
                raise MtlxError((child.loc, "elements nest more than %d levels deep (with includes)" % MAX_DEPTH))
            out.append(child)
            work.append((child, depth + 1, child_chain))
        el.children = out


def _read_include(el, search_paths, roots, chain, budget):
    """(real path, root XElement) of the document an include element names, its prefixes passed down."""
    href = el.get("href")
    if not href:
        raise MtlxError((el.loc, "xi:include without href"))
    what = "xi:include %s" % files.quoted(href)
    target = find_file(href, os.path.dirname(el.loc.file), search_paths)
    if target is None:
        raise MtlxError((el.loc, "included file not found: %s" % files.quoted(href)))
    files.check_inside(target, roots, el.loc, what)
    real = os.path.realpath(target)
    if real in chain:
        raise MtlxError((el.loc, "include cycle: %s includes itself" % files.quoted(href)))
    budget.includes += 1
    if budget.includes > MAX_INCLUDES:
        raise MtlxError((el.loc, "more than %d included files" % MAX_INCLUDES))
    sub = _read_document(os.path.abspath(target), el.loc, what, budget)
    if budget.upgrade is not None:      # from its own version: MaterialX upgrades each document it reads
        sub = budget.upgrade(sub, budget.warnings)
    # the included document's own version and prefixes apply to what came from it
    for grand in sub.children:
        for key in ("fileprefix", "geomprefix", "colorspace"):
            if key in sub.attrs and key not in grand.attrs:
                grand.attrs[key] = sub.attrs[key]
    return real, sub


def find_file(name, base_dir, search_paths=()):
    if os.path.isabs(name):
        return name if os.path.lexists(name) else None
    for base in [base_dir, *search_paths]:
        cand = os.path.join(base, name)
        if os.path.lexists(cand):
            return cand
    return None
