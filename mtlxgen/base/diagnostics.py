"""Problems found in input documents: every one names the file and line of the XML that caused it (for a USD
stage, which has no lines, the layer and the prim path or attribute: FILE:/Prim/Path.inputs:name).

Warnings are slips that MaterialX reads on (a value with text after its number, a color3 input fed by a vector3,
an input its named nodedef lacks): read as MaterialX reads them and printed as `FILE:LINE: warning: ...`;
strict mode (--strict) turns each into a problem."""
from mtlxgen.base.records import dataclass


@dataclass(frozen=True)
class Loc:
    file: str
    line: int = 0
    where: str = None       # instead of the line, where a file has none (USD: PRIM_PATH.ATTRIBUTE)

    def __str__(self):
        if self.where is not None:
            return "%s:%s" % (self.file, self.where)
        return "%s:%d" % (self.file, self.line)


UNKNOWN = Loc("<unknown>", 0)


class MtlxError(Exception):
    """One or more problems in input. `problems` holds (Loc, message) pairs, printed one a line."""

    def __init__(self, problems, warnings=()):
        if isinstance(problems, tuple):
            problems = [problems]
        self.problems = list(problems)
        self.warnings = list(warnings)      # (Loc, message) met before the problems stopped the work
        super().__init__("\n".join(self.lines()))

    def lines(self):
        return [_one_line("%s: %s" % (loc, msg)) for loc, msg in self.problems]


def _one_line(text):
    """A problem is one line: line breaks and other control characters a document put into a name or
    value are shown escaped, as Python writes them."""
    return text if text.isprintable() else "".join(c if c.isprintable() else ascii(c)[1:-1] for c in text)


class _Collector:
    """(Loc, message) items, once per location and message, in the order found."""

    def __init__(self):
        self.items = []

    def add(self, loc, message):
        item = (loc or UNKNOWN, message)
        if item not in self.items:
            self.items.append(item)

    def __bool__(self):
        return bool(self.items)

    def __len__(self):
        return len(self.items)


class Problems(_Collector):
    """Collects problems during a stage so that one run reports all of them, then raises once."""

    def extend(self, error):
        for loc, msg in error.problems:
            self.add(loc, msg)

    def raise_if_any(self):
        if self.items:
            raise MtlxError(self.items)


class Warnings(_Collector):
    """Collects warnings (slips MaterialX reads on); printed as `FILE:LINE: warning:` lines."""

    def extend(self, items):
        for loc, msg in items:
            self.add(loc, msg)

    def lines(self):
        return warning_lines(self.items)


def warning_lines(items):
    """`FILE:LINE: warning: MESSAGE` lines of (Loc, message) warnings."""
    return [_one_line("%s: warning: %s" % (loc, msg)) for loc, msg in items]


STRICT_NOTE = " (a warning; an error with --strict)"


def strict_error(items):
    """The MtlxError --strict makes of warnings: each one a problem at its own location."""
    return MtlxError([(loc, msg + STRICT_NOTE) for loc, msg in items])


def did_you_mean(name, names):
    """ "; did you mean 'X'?" naming the closest of `names` to `name` (up to three), or "" where none is close."""
    import difflib
    close = difflib.get_close_matches(name, list(dict.fromkeys(n for n in names if n)), n=3, cutoff=0.6)
    if not close:
        lowered = {n.lower(): n for n in names if n}
        close = [lowered[name.lower()]] if name.lower() in lowered else []
    return "; did you mean %s?" % " or ".join("'%s'" % c for c in close) if close else ""
