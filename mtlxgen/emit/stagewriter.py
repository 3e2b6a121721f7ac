"""The stage writer: statements of a shader stage's `main`, one a line, at the depth of the scope they are in.

Everything a stage's body holds goes through `line`; `open_scope` / `close_scope` write a braced block one
level deeper, `indented` the single statement of an `if` without braces. A comment holds no text from a
document that could end it or continue it onto the next line (comment_text).
"""
from contextlib import contextmanager

INDENT = "    "


def comment_text(text):
    """Document text (names, file names) made safe for a `//` comment: no line breaks or other control
    characters, no trailing backslash (a line continuation), nothing outside ASCII."""
    return "".join(c if " " <= c <= "~" and c != "\\" else "?" for c in text).replace("*/", "*?")


class StageWriter:
    def __init__(self, depth=1):
        self.lines = []               # the statements written, each indented
        self.depth = depth            # 1: directly inside main()

    def line(self, text):
        """Append a statement at the current depth."""
        self.lines.append(INDENT * self.depth + text)

    def comment(self, text):
        self.line("// " + comment_text(text))

    def open_scope(self, comment=None):
        """`{` (after a comment line, if given); what follows is one level deeper."""
        if comment:
            self.comment(comment)
        self.line("{")
        self.depth += 1

    def close_scope(self):
        self.depth -= 1
        self.line("}")

    @contextmanager
    def indented(self):
        """Lines written inside are one level deeper (the statement of an `if` without braces)."""
        self.depth += 1
        try:
            yield
        finally:
            self.depth -= 1
