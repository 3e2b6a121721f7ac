"""Texts with fields: what emitcache.py and elementcache.py record. An emission run over sentinel names writes a text
in which each sentinel stands for a value a later use supplies; FieldText keeps that text as the pieces between the
sentinels and fills them in by a list join (about 5x str.format's speed on a shader's 700 fields, and no braces
to escape).

SEP joins texts recorded together into one FieldText (split again after filling): it is in no emitted GLSL, name or
manifest, and the recorders refuse a text that holds it."""
import operator

SEP = "\x1f"


class FieldText:
    """`text` with each match of `pattern` a field: fill(args) is the text with the match replaced by
    args[field(match)]. literals: the pieces of text between the fields (what a recorder checks for stray
    sentinels)."""
    __slots__ = ("parts", "get", "one")

    def __init__(self, text, pattern, field):
        parts, fields, last = [], [], 0
        for m in pattern.finditer(text):
            parts += [text[last:m.start()], ""]
            fields.append(field(m))
            last = m.end()
        parts.append(text[last:])
        self.parts, self.one = parts, len(fields) == 1
        self.get = operator.itemgetter(*fields) if fields else None

    @property
    def literals(self):
        return self.parts[0::2]

    def fill(self, args):
        out = self.parts[:]
        if self.get is not None:
            out[1::2] = (self.get(args),) if self.one else self.get(args)
        return "".join(out)
