"""Which glsl_lib code a shader needs: a glsl_lib file split into its top-level items, and the items reachable
from a shader's own code, so that a stage pastes only the functions (structs, constants, macros) it uses.

An item is a function definition or prototype (overloads share a name), a struct, a global declaration
(`const` tables), a `#define`, a top-level invocation of a function-like macro (what it defines is read from its
expansion), or a top-level `#if`/`#ifdef`/`#ifndef` ... `#endif` group, kept or dropped whole. Each item knows the
names it defines and the identifiers it uses; the comments directly above an item, and anything else between it
and the previous item, travel with it. The reading is a small tokenizer (comments stripped, brackets counted),
not a GLSL parser: anything it cannot place as one of those items is a GlslSplitError, never a dropped function.
Split files are cached per process (split_file).

used_code(files, roots): for glsl_lib files [(rel, text)] in emission order and the texts of the shader's own code
(declarations, main, a document's GLSL pasted whole), [(rel, text)] of the files that contribute something: each
file's header comment followed by its reachable items, in the file's order. MTLXGEN_GLSL_DCE=0 in the environment
keeps whole files (a comparison switch for tests).
"""
import bisect
import os
import re

from mtlxgen.emit import splitcache

__all__ = ["GlslSplitError", "Item", "LibFile", "SWITCHES", "resolve_switches", "split", "split_file", "identifiers",
           "used_code"]


class GlslSplitError(ValueError):
    """A glsl_lib file holds something the splitter cannot place as a top-level item."""


# identifiers, numbers (decimal, float with exponent, hex, unsigned/float suffixes), one-character punctuation
_TOKEN = re.compile(r"""
    (?P<id>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<num>0[xX][0-9A-Fa-f]+[uU]?|(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?[uUfF]?(?:[lL][fF])?)
  | (?P<punct>[^\sA-Za-z0-9_])
""", re.VERBOSE)
_OPEN, _CLOSE = "({[", ")}]"
_CONDITIONALS = ("if", "ifdef", "ifndef")
_COMMENT = re.compile(r"//|/\*")


class Tok:
    __slots__ = ("kind", "text", "start", "end", "line")

    def __init__(self, kind, text, start, end, line):
        self.kind, self.text, self.start, self.end, self.line = kind, text, start, end, line

    def __repr__(self):
        return "Tok(%s %r @%d)" % (self.kind, self.text, self.line)


def _strip_comments(text, where):
    """text with every comment replaced by spaces (newlines kept), so offsets and lines stay those of text."""
    out, i, n = [], 0, len(text)
    while True:
        j = _COMMENT.search(text, i)
        if j is None:
            out.append(text[i:])
            return "".join(out)
        out.append(text[i:j.start()])
        if j.group() == "//":
            k = text.find("\n", j.start())
            k = n if k < 0 else k
            out.append(" " * (k - j.start()))
        else:
            k = text.find("*/", j.start() + 2)
            if k < 0:
                raise GlslSplitError("%s: unterminated /* comment" % where)
            k += 2
            out.append("".join(ch if ch == "\n" else " " for ch in text[j.start():k]))
        i = k


def tokenize(text, where="<glsl>"):
    """Tokens of GLSL text without its comments. A preprocessor line is one token of kind "directive" whose text
    is the whole line (its name and arguments: _directive)."""
    code = _strip_comments(text, where)
    toks = []
    line_no = 0
    pos = 0
    for line in code.split("\n"):
        line_no += 1
        stripped = line.lstrip()
        if stripped.startswith("#"):
            start = pos + len(line) - len(stripped)
            toks.append(Tok("directive", stripped.rstrip(), start, pos + len(line.rstrip()), line_no))
        else:
            for m in _TOKEN.finditer(line):
                toks.append(Tok(m.lastgroup, m.group(), pos + m.start(), pos + m.end(), line_no))
        pos += len(line) + 1
    return toks


def _directive(text):
    """(name, rest) of a directive line: ("define", "NAME(a, b) body")."""
    body = text.strip()[1:].lstrip()
    m = re.match(r"[A-Za-z_]*", body)
    return m.group(), body[m.end():].strip()


# identifiers, not counting member and swizzle names after a '.' (nor the letters inside numbers: 1.0e5, 0x1fu)
_IDENT = re.compile(r"(?<![.\w])[A-Za-z_]\w*")
# what places items: brackets, ';' and preprocessor lines
_STRUCTURE = re.compile(r"[{}()\[\];]|#[^\n]*")
_SPACE = re.compile(r"\s*")


# ASCII text: every character that can be in no identifier, member name or number ([A-Za-z0-9_.]) made a space
_RUN_BREAKS = str.maketrans({chr(c): " " for c in range(128) if not (chr(c).isalnum() or chr(c) in "_.")})


def identifiers(text):
    """Identifiers used by GLSL text (a stage's declarations and main, a document's own GLSL): what _IDENT finds.

    ASCII text (every shader's own text but a document's GLSL in another script) is read by one translate and a
    split, three times as fast as the regular expression and the same set: a match of _IDENT begins a run of
    [A-Za-z0-9_.] (its previous character is none of those) and ends at the run's first '.', so the identifiers are
    the runs' parts before their first '.' that begin with a letter or '_' (not a digit, nor the '.' of `.5`)."""
    code = _strip_comments(text, "<glsl>")
    if not code.isascii():              # \w of other scripts: the regular expression
        return set(_IDENT.findall(code))
    out = set()
    for run in set(code.translate(_RUN_BREAKS).split()):
        if "." in run:
            run = run.split(".", 1)[0]
        if run and not run[0].isdigit():
            out.add(run)
    return out


class Item:
    """One top-level item of a glsl_lib file: kind ("function", "prototype", "struct", "declaration", "define",
    "macro_call", "conditional"), the names it defines, the identifiers it uses (its own names excluded), the
    line of its first token, [code_start, code_end) of its code and [start, end) of its text in the file (its
    comments above included)."""
    __slots__ = ("kind", "names", "uses", "line", "code_start", "code_end", "start", "end")

    def __init__(self, kind, names, uses, code_start, code_end, line):
        self.kind, self.names, self.code_start, self.code_end, self.line = kind, frozenset(names), code_start, code_end, line
        self.uses = frozenset(set(uses) - self.names)
        self.start = self.end = None

    def __repr__(self):
        return "Item(%s %s line %d)" % (self.kind, "/".join(sorted(self.names)), self.line)


class _Splitter:
    """Items of one text: the structure (brackets, ';', directives) places them; only an item's outermost level
    (its signature, its declarators) is tokenized, its uses are read with one scan for identifiers."""

    def __init__(self, text, where, macros=None):
        self.text, self.where = text, where
        self.code = _strip_comments(text, where)
        self.newlines = [m.start() for m in re.finditer("\n", self.code)]
        self.marks = [(m.group().rstrip(), m.start(), m.end()) for m in _STRUCTURE.finditer(self.code)]
        for mark, mstart, _ in self.marks:
            if mark[0] == "#" and self.code[self.code.rfind("\n", 0, mstart) + 1:mstart].strip():
                self.fail(mstart, "'#' after code on its line")
        self.k = 0                           # next mark
        self.pos = 0                         # where the code not yet placed begins
        self.macros = dict(macros or {})     # name -> (params, body) of the function-like macros defined so far

    def line(self, pos):
        return bisect.bisect_left(self.newlines, pos) + 1

    def fail(self, pos, message):
        raise GlslSplitError("%s:%d: %s" % (self.where, self.line(pos), message))

    def items(self, stop=()):
        """Items up to a directive named in stop (left unread) or the end."""
        out = []
        while True:
            start = _SPACE.match(self.code, self.pos).end()
            if start >= len(self.code):
                break
            if self.k >= len(self.marks):
                self.fail(start, "top-level item without its end (';' or '}') before the end of the file")
            mark, mstart, mend = self.marks[self.k]
            if mark[0] == "#" and mstart <= start:
                name, rest = _directive(mark)
                if name in stop:
                    return out
                if name in _CONDITIONALS:
                    out.append(self.conditional())
                elif name == "define":
                    out.append(self.define(mark, rest, mstart, mend))
                    self.k += 1
                    self.pos = mend
                else:
                    self.fail(mstart, "top-level #%s is not an item this splitter places (a #define, or #if ... "
                                      "#endif around items)" % name)
            else:
                out.append(self.code_item(start))
        if stop:
            self.fail(len(self.code), "#%s without its #endif" % stop[-1])
        return out

    def conditional(self):
        first, fstart, _ = self.marks[self.k]
        uses = set(_IDENT.findall(first[1:]))
        inner = []
        while True:
            self.pos = self.marks[self.k][2]
            self.k += 1
            inner += self.items(stop=("elif", "else", "endif"))
            mark, _, mend = self.marks[self.k]
            uses |= set(_IDENT.findall(mark[1:]))
            if _directive(mark)[0] == "endif":
                self.k += 1
                self.pos = mend
                break
        names = set().union(*(it.names for it in inner)) if inner else set()
        if not names:
            self.fail(fstart, "a top-level conditional group that defines nothing")
        for it in inner:
            uses |= it.uses
        return Item("conditional", names, uses, fstart, mend, self.line(fstart))

    def define(self, mark, rest, mstart, mend):
        m = re.match(r"([A-Za-z_][A-Za-z0-9_]*)(\()?", rest)
        if m is None:
            self.fail(mstart, "#define without a name")
        name, body = m.group(1), rest[m.end():]
        params = ()
        if m.group(2):                      # function-like: NAME( immediately
            close = body.find(")")
            if close < 0:
                self.fail(mstart, "#define %s( without its )" % name)
            params = [p.strip() for p in body[:close].split(",") if p.strip()]
            body = body[close + 1:]
            self.macros[name] = (params, body)
        uses = set(_IDENT.findall(body)) - set(params)
        start = mstart + len(self.code[mstart:mend]) - len(self.code[mstart:mend].lstrip())
        return Item("define", {name}, uses, start, mend, self.line(mstart))

    def code_item(self, start):
        """The item whose code begins at start: up to ';' or the '}' closing its body at depth 0 (a struct's: the
        ';' after it), or the ')' closing NAME(...) where NAME is a function-like macro or no body follows."""
        code, marks = self.code, self.marks
        depth = 0
        head = None                          # the code before the item's first bracket
        k = self.k
        while k < len(marks):
            mark, mstart, mend = marks[k]
            k += 1
            if mark[0] == "#":
                if depth == 0:
                    self.fail(mstart, "a directive inside a top-level item, outside its braces")
                continue
            if head is None:
                head = code[start:mstart].split()
            if mark in _OPEN:
                depth += 1
            elif mark in _CLOSE:
                depth -= 1
                if depth < 0:
                    self.fail(mstart, "unbalanced '%s'" % mark)
                if depth == 0 and mark == "}" and head[:1] != ["struct"]:
                    return self.finish(start, mend, k, "function")
                if depth == 0 and mark == ")" and len(head) == 1 and _IDENT.fullmatch(head[0]):
                    nxt = _SPACE.match(code, mend).end()
                    after = code[nxt:nxt + 1]
                    if head[0] in self.macros:          # NAME(args) of a macro above, `;` or not
                        if after == ";":
                            return self.finish(start, nxt + 1, k + 1, "macro_call")
                        return self.finish(start, mend, k, "macro_call")
                    if after not in ("{", ";"):
                        return self.finish(start, mend, k, "macro_call")
            elif mark == ";" and depth == 0:
                return self.finish(start, mend, k, None)
        self.fail(start, "top-level item without its end (';' or '}') before the end of the file")

    def outer_tokens(self, start, end):
        """Tokens of code[start:end] outside brackets (the brackets of the outermost level kept)."""
        parts, depth, pos = [], 0, start
        for mark, mstart, mend in self.marks[self.k:]:
            if mstart >= end:
                break
            if mark in _OPEN:
                if depth == 0:
                    parts.append(self.code[pos:mend])
                depth += 1
            elif mark in _CLOSE:
                depth -= 1
                if depth == 0:
                    pos = mstart
        if depth == 0:
            parts.append(self.code[pos:end])
        return [m.group() for m in _TOKEN.finditer(" ".join(parts))]

    def finish(self, start, end, k, kind):
        line = self.line(start)
        if kind == "macro_call":
            item = self.macro_call(start, end, line)
        else:
            toks = self.outer_tokens(start, end)
            if kind == "function":
                names = {self.function_name(toks, start)}
            elif toks[0] == "struct":
                kind = "struct"
                if len(toks) < 3 or not _IDENT.fullmatch(toks[1]):
                    self.fail(start, "struct without a name")
                names = {toks[1]}
            elif self.is_prototype(toks):
                kind = "prototype"
                names = {self.function_name(toks, start)}
            else:
                kind = "declaration"
                names = self.declared_names(toks)
            if not names:
                self.fail(start, "a top-level item that defines no name")
            item = Item(kind, names, _IDENT.findall(self.code, start, end), start, end, line)
        self.k, self.pos = k, end
        return item

    def function_name(self, toks, start):
        for k, t in enumerate(toks):
            if t == "(":
                if k == 0 or not _IDENT.fullmatch(toks[k - 1]):
                    break
                return toks[k - 1]
        self.fail(start, "a function without a name before its '('")

    @staticmethod
    def is_prototype(toks):
        for k, t in enumerate(toks):
            if t in ("=", "["):
                return False
            if t == "(":
                return k > 0 and _IDENT.fullmatch(toks[k - 1]) is not None
        return False

    @staticmethod
    def declared_names(toks):
        """Names declared by `[const] TYPE NAME [= ...][, NAME2 ...];`: the identifier before each declarator's
        `=`, `[` or end (toks: the outermost level only)."""
        names, prev, named = set(), None, False
        for t in toks:
            if t == "[" and prev is not None and _IDENT.fullmatch(prev) and not named:
                names.add(prev)
                named = True
            elif t in ("=", ",", ";"):
                if prev is not None and _IDENT.fullmatch(prev) and not named:
                    names.add(prev)
                named = t == "="          # an initializer follows: no names in it
            prev = t
        return names

    def macro_call(self, start, end, line):
        toks = [m for m in _TOKEN.finditer(self.code, start, end)]
        name = toks[0].group()
        if name not in self.macros:
            self.fail(start, "'%s(...)' at top level is neither a function nor a macro defined above it" % name)
        params, body = self.macros[name]
        args, depth, cur = [], 0, []
        for t in toks[2:-2] if toks[-1].group() == ";" else toks[2:-1]:
            c = t.group()
            if c in _OPEN:
                depth += 1
            elif c in _CLOSE:
                depth -= 1
            if c == "," and depth == 0:
                args.append(cur)
                cur = []
            else:
                cur.append(t)
        args.append(cur)
        if len(args) != len(params):
            self.fail(start, "%s takes %d arguments, given %d" % (name, len(params), len(args)))
        values = {p: self.text[a[0].start():a[-1].end()] if a else "" for p, a in zip(params, args)}
        expansion = _TOKEN.sub(lambda m: values.get(m.group(), m.group()) if m.lastgroup == "id" else m.group(), body)
        inner = _Splitter(expansion, "%s:%d (%s expanded)" % (self.where, line, name), self.macros).items()
        names = set().union(*(it.names for it in inner)) if inner else set()
        if not names:
            self.fail(start, "%s(...) defines nothing" % name)
        uses = set(_IDENT.findall(self.code, start, end))
        for it in inner:
            uses |= it.uses
        return Item("macro_call", names, uses, start, end, line)


class LibFile:
    """A glsl_lib file split: header (its leading comment block), items (with their text spans)."""

    def __init__(self, rel, text, header, items):
        self.rel, self.text, self.header, self.items = rel, text, header, items

    def item_text(self, item):
        return self.text[item.start:item.end]


def _line_start(text, pos):
    return text.rfind("\n", 0, pos) + 1


def split(text, rel="<glsl>"):
    """LibFile of glsl_lib text: header + the items' texts, in order, are the text exactly."""
    items = _Splitter(text, "glsl_lib/" + rel).items()
    lines = text.split("\n")
    # each item's text runs from the line after the previous item's last token (its comments above, and anything
    # between) to the next item's start; two items on one line are parted at the second's first token
    prev_end = 0
    for it in items:
        ls = _line_start(text, it.code_start)
        if text[ls:it.code_start].strip() or ls < prev_end:
            it.start = max(it.code_start, prev_end)
        else:
            it.start = max(prev_end, 0)
        nl = text.find("\n", it.code_end)
        prev_end = len(text) if nl < 0 else nl + 1
    for a, b in zip(items, items[1:]):
        a.end = b.start
    if items:
        items[-1].end = len(text)
    # the file's header: its leading comment lines up to the first blank line (all of them when they run on to the
    # first item) travel with the file, not with the first item
    header_end = 0
    if items:
        first = items[0]
        pos, cut = 0, None
        for line in lines:
            if pos >= first.code_start or line.strip() and not line.lstrip().startswith("//"):
                break
            if not line.strip():
                cut = pos + len(line) + 1
                break
            pos += len(line) + 1
        header_end = cut if cut is not None else _line_start(text, first.code_start)
        header_end = min(max(header_end, first.start), _line_start(text, first.code_start))
        first.start = header_end
    else:
        header_end = len(text)
    return LibFile(rel, text, text[:header_end], items)


# Paste switches: a glsl_lib file may test these names with `#ifdef NAME` / `#ifndef NAME` ... [`#else` ...] `#endif`,
# inside a function too. The emitter resolves them when it pastes the file (resolve_switches, before the split), so
# a shader holds the branch its switch set selects, without the directive lines, and nothing that only the dropped
# branch reaches. Library code pasted by hand (emit.lib_source) keeps the directives, the names undefined.
#   MG_NO_THIN_FILM  no closure of the shader has a thin film (every thinfilm_thickness a literal <= 0)
#   MG_ENV_PREFILTERED, MG_REFRACTION_PREFILTERED  the environment method is the split sum (--environment
#                    prefiltered; emit.ENVIRONMENT_SWITCHES): a fis shader holds none of its code
#   MG_ENV_ONE_FRAME  progressive refinement's pair is constant (a reduced shader that keeps neither: Graph.app_constants):
#                    the sample points are one frame's Hammersley set, without the progressive frames' code
SWITCHES = ("MG_NO_THIN_FILM", "MG_ENV_PREFILTERED", "MG_REFRACTION_PREFILTERED", "MG_ENV_ONE_FRAME")
_DIRECTIVE = re.compile(r"\s*#\s*(ifdef|ifndef|if|else|elif|endif)\b\s*(\w*)")


_RESOLVED = {}
_SWITCHED = {}          # text -> whether it names a switch at all


def resolve_switches(text, defined=()):
    """text with its #ifdef/#ifndef groups on SWITCHES resolved for the names in `defined` (a group on another name
    passes through whole, with the switch groups inside it resolved). Cached per (text, defined) for the process."""
    switched = _SWITCHED.get(text)
    if switched is None:                    # (a scan of the whole text: once per text)
        if len(_SWITCHED) > 4096:
            _SWITCHED.clear()
        switched = _SWITCHED[text] = any(name in text for name in SWITCHES)
    if not switched:
        return text
    key = (text, frozenset(defined))
    done = _RESOLVED.get(key)
    if done is None:
        if len(_RESOLVED) > 4096:          # glsl_lib's few files, documents' own code too: bounded
            _RESOLVED.clear()
        done = _RESOLVED[key] = _resolve(text, defined)
    return done


def _resolve(text, defined):
    out = []
    stack = []      # per open group: None (not a switch: passed through) or [keeping, this branch kept]
    for line in text.split("\n"):
        m = _DIRECTIVE.match(line)
        keeping = all(g is None or g[1] for g in stack)
        if m:
            kind, name = m.groups()
            if kind in _CONDITIONALS:
                if kind != "if" and name in SWITCHES:
                    stack.append([keeping, (name in defined) == (kind == "ifdef")])
                    continue
                stack.append(None)
            elif kind in ("else", "elif") and stack and stack[-1] is not None:
                if kind == "elif":
                    raise GlslSplitError("#elif in a paste-switch group (%s): not supported" % ", ".join(SWITCHES))
                stack[-1][1] = not stack[-1][1]
                continue
            elif kind == "endif" and stack:
                if stack.pop() is not None:
                    continue
        if keeping:
            out.append(line)
    return "\n".join(out)


_CACHE = {}


def split_file(rel, text):
    """split(text, rel), once per process for each (rel, text), and kept on disk between processes (splitcache)."""
    key = (rel, text)
    lf = _CACHE.get(key)
    if lf is None:
        lf = _stored_split(rel, text)
        if lf is None:
            lf = split(text, rel)
            splitcache.add(rel, text, lf)
        _CACHE[key] = lf
    return lf


def _stored_split(rel, text):
    """The LibFile of `text` from its stored split (splitcache.find), or None."""
    entry = splitcache.find(rel, text)
    if entry is None:
        return None
    header_end, stored = entry
    items = []
    for kind, names, uses, code_start, code_end, line, start, end in stored:
        it = Item(kind, names, uses, code_start, code_end, line)
        it.start, it.end = start, end
        items.append(it)
    return LibFile(rel, text, text[:header_end], items)


def _index(libs):
    """name -> [items defining it] over LibFiles libs."""
    index = {}
    for lf in libs:
        for it in lf.items:
            for n in it.names:
                index.setdefault(n, []).append(it)
    return index


def reachable(libs, roots, by_name=None):
    """The items of LibFiles libs reachable from the identifier set roots: {id(item)}. by_name: _index(libs), where
    the caller keeps it (used_code)."""
    if by_name is None:
        by_name = _index(libs)
    keep, seen, todo = set(), set(), [n for n in roots if n in by_name]
    seen.update(todo)
    while todo:
        for it in by_name[todo.pop()]:
            if id(it) in keep:
                continue
            keep.add(id(it))
            for u in it.uses:
                if u in by_name and u not in seen:
                    seen.add(u)
                    todo.append(u)
    return keep


# used_code's results kept per process: files (the tuple of (rel, text), which determines the split files and
# their index) -> (the split files, their index, the names they define, {the root identifiers among those names:
# [(rel, text)]}). What
# the files paste depends on nothing else: the items reachable from the names they define that the roots use.
_USED = {}
_USED_MAX = 256          # sets of files (switches, documents' code aside, a few dozen): bounded, cleared when full
_USED_PER_FILES = 4096   # root name sets of one set of files


def used_code(files, roots, known=frozenset()):
    """[(rel, text)] of glsl_lib files [(rel, text)] that the root texts reach: each file's header and its kept items
    in order, files that keep nothing left out. known: identifiers of more roots, read before (a function's body:
    emit.FunctionCode.identifiers). Kept per process for each (files, root identifiers among the names the files
    define): a repeat is the identifier scan and two dictionary look-ups."""
    if os.environ.get("MTLXGEN_GLSL_DCE", "1") == "0":
        return list(files)
    key = tuple(files)
    entry = _USED.get(key)
    if entry is None:
        if len(_USED) >= _USED_MAX:
            _USED.clear()
        libs = [split_file(rel, text) for rel, text in files]
        splitcache.save()                   # the splits made here kept for the next process
        index = _index(libs)
        entry = _USED[key] = (libs, index, frozenset(index), {})
    libs, index, defined, done = entry
    names = set(known)
    for r in roots:
        names |= identifiers(r)
    names = frozenset(names & defined)
    out = done.get(names)
    if out is None:
        keep = reachable(libs, names, index)
        out = []
        for lf in libs:
            kept = [lf.item_text(it) for it in lf.items if id(it) in keep]
            if kept:
                out.append((lf.rel, lf.header + "".join(kept)))
        if len(done) >= _USED_PER_FILES:
            done.clear()
        done[names] = out
    return list(out)


def compact(text, where="<glsl>"):
    """Library code without its comments, trailing spaces and blank lines: what a reduced shader (a shader made for
    one use, not for reading) pastes. Every line that holds code stays a line of its own (preprocessor lines
    included), so the code is the same token for token."""
    lines = (line.rstrip() for line in _strip_comments(text, where).split("\n"))
    return "\n".join(line for line in lines if line)
