"""Text from documents, stages and result files written into generated HTML, JavaScript, JSON and GLSL: one
escaping function per context, so a name, path, colour space or message can only ever be data there.

Documents come from strangers: an element name, a texture's file name, a `colorspace` attribute or USD
`colorSpace` metadata may hold `*/`, `</script>`, `<!--`, quotes, backticks, `${`, line breaks or U+2028.
Every such string that reaches generated output goes through the function for where it lands:

    html_text(s)        text content of an HTML element (also <title>): & < > " ' as character references
    html_attr(s)        a quoted HTML attribute value: the same references (either quote style is safe)
    json_in_script(v)   JSON text (still valid JSON, and a JavaScript literal of the same value) that is safe
                        inside an HTML <script> element and in a JavaScript module: ASCII only, with < > &
                        written \\u003c \\u003e \\u0026 (no `</script>`, `<!--` or `-->` can form) and U+2028/U+2029
                        escaped (a line terminator to older JavaScript)
    js_string(s)        a JavaScript string literal of s (json_in_script of a string)
    js_comment(v)       a JSON-able value as text for inside a JavaScript comment (/* */ or //): its
                        json_in_script text with every "/" written "\\/", so no `*/` can end the comment, on one
                        line; still valid JSON, so a reader can recover the value
    glsl_comment(s)     text for inside a GLSL `//` comment: printable ASCII only; line breaks, control
                        characters, backslashes (a line continuation) and anything outside ASCII become "?", and
                        `*/` becomes `*?`
"""
import json

_SCRIPT_UNSAFE = (("<", "\\u003c"), (">", "\\u003e"), ("&", "\\u0026"), ("\u2028", "\\u2028"),
                  ("\u2029", "\\u2029"))


def html_text(text):
    """`text` as the text content of an HTML element: &, <, >, " and ' written as character references."""
    return (str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")
            .replace("'", "&#x27;"))


def html_attr(text):
    """`text` as an HTML attribute value inside quotes (double or single): the references html_text writes."""
    return html_text(text)


def json_in_script(value, indent=None, separators=(",", ":"), sort_keys=False):
    """JSON text of a JSON-able value, safe inside an HTML <script> element and in JavaScript source: ASCII only,
    <, >, & and U+2028/U+2029 as \\u escapes. Those characters occur in JSON text only inside strings, where
    the escapes mean the same characters, so the text stays valid JSON of the same value."""
    text = json.dumps(value, ensure_ascii=True, indent=indent, separators=separators, sort_keys=sort_keys)
    for raw, escaped in _SCRIPT_UNSAFE:
        text = text.replace(raw, escaped)
    return text


def js_string(text):
    """A JavaScript (and JSON) string literal of `text`, safe inside an HTML <script> element."""
    return json_in_script(str(text))


def js_comment(value):
    """A JSON-able value (a string: quoted) as one line of text that can sit inside a JavaScript comment of
    either kind: json_in_script's text with "/" written "\\/" (a valid JSON escape), so no `*/` can end a
    block comment, and no line terminator can end a line comment."""
    return json_in_script(value, separators=(", ", ": ")).replace("/", "\\/")


def glsl_comment(text):
    """`text` for inside a GLSL `//` comment: printable ASCII only (line breaks, other control characters,
    backslashes, which continue a line, and non-ASCII become "?"), and no `*/`."""
    return "".join(c if " " <= c <= "~" and c != "\\" else "?" for c in str(text)).replace("*/", "*?")
