"""The measured tables of the documentation (docs/materials.md), read back so the tests that print a table can
assert it is the page's.

A table is found by its header row; rows come back as lists of cell texts (the separator row dropped).
Numbers are compared within a tolerance the caller states; every other text must be equal.
"""
import os
import re

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAGE = os.path.join(ROOT, "docs", "materials.md")     # the furnace, reciprocity and Enterprise PBR tables
_NUMBER = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(.*)$", re.S)


def page_text(page=PAGE):
    with open(page, encoding="utf-8") as f:
        return f.read()


def cells(line):
    """The cells of one markdown table row; `\\|` inside a cell is a literal bar."""
    inner = line.strip()
    assert inner.startswith("|") and inner.endswith("|"), "not a table row: %r" % line
    parts = re.split(r"(?<!\\)\|", inner[1:-1])
    return [p.strip() for p in parts]


def table_rows(markdown, header_start):
    """Rows of the first table in `markdown` whose header row starts with `header_start`, header included."""
    lines = markdown.splitlines()
    for i, line in enumerate(lines):
        if line.startswith(header_start):
            rows = []
            for row in lines[i:]:
                if not row.startswith("|"):
                    break
                if not re.fullmatch(r"\|(\s*:?-+:?\s*\|)+", row.strip()):
                    rows.append(cells(row))
            return rows
    raise AssertionError("no table whose header starts with %r" % header_start)


def page_table(header_start, page=PAGE):
    """Rows of the first table of the page (docs/materials.md) whose header row starts with `header_start`."""
    return table_rows(page_text(page), header_start)


def number(cell):
    """(the number a cell starts with or None, the text after it): '1.0473 (xfail: ...)' -> (1.0473, ' (xfail: ...)')."""
    m = _NUMBER.match(cell)
    return (float(m.group(1)), m.group(2)) if m else (None, cell)


def table_differences(printed, documented, close):
    """Lines saying where two tables (lists of cell lists, header first) differ. Cells that start with a
    number are equal when close(column, printed number, the page's number) holds and their texts after
    the number are equal (`close` may return None to skip that text comparison); others must be equal."""
    out = []
    if printed[0] != documented[0]:
        out.append("header: printed %s, page %s" % (printed[0], documented[0]))
    names_p, names_r = [r[0] for r in printed[1:]], [r[0] for r in documented[1:]]
    if names_p != names_r:
        out.append("rows: printed %s, page %s" % (names_p, names_r))
    by_name = {r[0]: r for r in documented[1:]}
    for row in printed[1:]:
        theirs = by_name.get(row[0])
        if theirs is None:
            continue
        if len(theirs) != len(row):
            out.append("%s: %d cells printed, %d on the page" % (row[0], len(row), len(theirs)))
            continue
        for col, (a, b) in enumerate(zip(row, theirs)):
            (na, ra), (nb, rb) = number(a), number(b)
            if na is not None and nb is not None:
                ok = close(col, na, nb)
                if ok is None:
                    continue
                if not ok or ra != rb:
                    out.append("%s, column '%s': printed %s, page %s" % (row[0], printed[0][col], a, b))
            elif a != b:
                out.append("%s, column '%s': printed %r, page %r" % (row[0], printed[0][col], a, b))
    return out
