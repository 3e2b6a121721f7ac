"""A document's inline GLSL (`<implementation sourcecode="...">`), checked before it is pasted.

The sourcecode becomes the right-hand side of `TYPE var = EXPRESSION;` with its {{fields}} expanded
(nodes/__init__.py lists them). It is checked as one GLSL expression over the node's inputs: fields that
name inputs, output types or geometric streams; literals GLSL can hold; identifiers that are GLSL's
built-in functions, constructors or the document's structs (members and swizzles after '.'); operators
and balanced brackets. Type errors (a swizzle a float lacks, a vec3 for a float output) are the
compiler's to find.
"""
import re

from mtlxgen.base import mxtypes, streams
from mtlxgen.read.library import GLSL_BUILTIN_FUNCTIONS

_CONSTRUCTORS = frozenset(
    ["float", "int", "uint", "bool", "double", "true", "false"]
    + ["%svec%d" % (p, n) for p in ("", "i", "u", "b", "d") for n in (2, 3, 4)]
    + ["%smat%d" % (p, n) for p in ("", "d") for n in (2, 3, 4)]
    + ["%smat%dx%d" % (p, a, b) for p in ("", "d") for a in (2, 3, 4) for b in (2, 3, 4)]
    + ["BSDF", "VDF", "surfaceshader", "volumeshader", "displacementshader", "lightshader"])
_FRAGMENT_INPUTS = frozenset(["gl_FragCoord", "gl_FrontFacing"])
FIELD = "mg_FIELD"          # stands for an expanded field while the expression is checked

_TOKEN = re.compile(r"""\s*(?:
    (?P<num>0[xX][0-9A-Fa-f]+[uU]?|(?:\d+\.\d*|\.\d+|\d+)(?:[eE][+-]?\d+)?(?:[fF]|lf|LF|[uU])?)
  | (?P<id>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<bad>\+\+|--|\S(?<![-+*/%<>!&|^~?:.,()\[\]]))
  | (?P<op><<|>>|<=|>=|==|!=|&&|\|\||\^\^|[-+*/%<>!&|^~?:.,()\[\]])
  )""", re.X | re.ASCII)


def problem(template, nodedef, structs=()):
    """Why `template` cannot implement `nodedef` (a line of text), or None."""
    expression = _expand_fields(template, nodedef)
    if not expression.startswith(FIELD + "!"):
        return _expression_problem(template, expression, structs)
    return expression[len(FIELD) + 1:]


def _expand_fields(template, nodedef):
    """The template with each field replaced by FIELD, or FIELD + '!' + the problem of a bad field."""
    out, i = [], 0
    while True:
        j = template.find("{{", i)
        if j < 0:
            return "".join(out) + template[i:]
        k = template.find("}}", j + 2)
        if k < 0:
            return FIELD + "!unterminated '{{' in sourcecode %r" % template
        f = template[j + 2:k].strip()
        name = f[1:] if f[:1] in ("=", "@") else f[6:] if f.startswith("$type:") else None if f == "$type" else f
        if f.startswith("@"):
            try:
                streams.lookup(name)
            except KeyError:
                return FIELD + "!sourcecode field '{{%s}}' names no geometric stream (%s)" % (f, streams.NAMES)
        elif name is not None and name not in nodedef.inputs:
            return FIELD + "!sourcecode field '{{%s}}' names no input of %s (inputs: %s)" % (
                f, nodedef.name, ", ".join(nodedef.inputs) or "none")
        elif f.startswith("=") and nodedef.inputs[name].type in ("string", "filename", "geomname"):
            # mtlxgen's own templates paste an enum string as a name they define; a document's cannot
            return FIELD + "!sourcecode field '{{%s}}' pastes a %s as GLSL" % (f, nodedef.inputs[name].type)
        out.append(template[i:j] + " %s " % FIELD)
        i = k + 2


_UNARY = ("+", "-", "!", "~")


def _expression_problem(template, text, structs):
    def not_one(why):
        return "sourcecode %r is not one GLSL expression (%s)" % (template, why)

    tokens = [(m.lastgroup, m.group(m.lastgroup)) for m in _TOKEN.finditer(text)]
    if not tokens:
        return "empty sourcecode"
    brackets, prev, prev_tok = [], None, None   # prev: what came before: "operand", ".", "op" or None (start)
    for kind, tok in tokens:
        if kind == "bad":
            return not_one("it holds %r" % tok)      # also ++ and --: inputs are read-only
        if kind == "num":
            why = _literal_problem(tok)
            if why:
                return "sourcecode %r: %s" % (template, why)
        if kind == "id" and prev != "." and tok != FIELD and tok not in GLSL_BUILTIN_FUNCTIONS \
                and tok not in _CONSTRUCTORS and tok not in _FRAGMENT_INPUTS and tok not in structs:
            return ("sourcecode %r names '%s', which is neither a field nor one of GLSL's built-in functions "
                    "and types" % (template, tok))
        if prev == "." and kind != "id":
            return not_one("'.' is not followed by a member name")
        if kind in ("num", "id"):
            if prev == "operand":
                return not_one("'%s' follows a value without an operator" % tok)
            prev = "operand"
        elif tok == "(":
            if prev == "operand" and not (prev_tok == FIELD or re.match(r"[A-Za-z_]", prev_tok)):
                return not_one("'(' follows a value that is no function")
            brackets.append(tok)
            prev = "op"
        elif tok in _UNARY and prev != "operand":
            if prev == ".":
                return not_one("'.' is not followed by a member name")
            prev = "op"
        else:
            if prev != "operand":                   # binary and postfix operators, ')', ']', ',', '.'
                return not_one("'%s' follows no value" % tok)
            if tok == "[":
                brackets.append(tok)
            elif tok in ")]" and (not brackets or brackets.pop() != {")": "(", "]": "["}[tok]):
                return "sourcecode %r has unbalanced brackets" % template
            elif tok == "," and not brackets:       # `T v = a, b;` would declare b
                return not_one("it holds ',' outside brackets")
            prev = "operand" if tok in ")]" else "." if tok == "." else "op"
        prev_tok = tok
    if brackets:
        return "sourcecode %r has unbalanced brackets" % template
    if prev != "operand":
        return not_one("it ends in '%s'" % tokens[-1][1])
    return None


def _literal_problem(tok):
    """Why a numeric literal is no GLSL literal, or None."""
    t = tok.rstrip("fFuU").rstrip("lL") if not tok[:2].lower() == "0x" else tok.rstrip("uU")
    if tok[:2].lower() == "0x":
        value = int(t, 16)
    elif re.fullmatch(r"\d+", t):
        if len(t) > 1 and t[0] == "0" and not re.fullmatch(r"[0-7]+", t):
            return "%r is no octal literal" % tok
        value = int(t, 8 if len(t) > 1 and t[0] == "0" else 10)
    else:
        return None if abs(float(t)) <= mxtypes.FLOAT_MAX else "%r is beyond the range of a 32-bit float" % tok
    return None if value <= 0xFFFFFFFF else "%r does not fit in 32 bits" % tok
