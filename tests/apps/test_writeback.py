"""The panel's Save cannot lose or misplace data (docedit.save_values): the file keeps its encoding, byte-order
mark and line endings and every byte outside the edited values; a value the encoding lacks is a character
reference; an input is found by its name path in a scan that steps over comments, CDATA sections and processing
instructions, checked against the XML reader's element and line; a file changed since the inputs were listed is
refused (one FILE:LINE line, file untouched); a failed write leaves the old file whole. A property test runs
generated documents, encodings, line endings, edits, outside changes and failed writes through it."""
import codecs
import errno
import html
import os
import re
import stat
import tempfile
from unittest import mock

import pytest

from mtlxgen.apps import docedit
from mtlxgen import pipeline
from mtlxgen.read import xmlreader
from mtlxgen.base.diagnostics import Loc, MtlxError
from mtlxgen.graph.graphtypes import Origin

hypothesis = pytest.importorskip("hypothesis", reason="hypothesis is a test dependency (pip install -e '.[test]')")
from hypothesis import HealthCheck, event, given, seed, settings, strategies as st  # noqa: E402

# two images mixed into an unlit surface: 'a' and 'b' both have an input named 'file'
MIXED = """<?xml version="1.0"{decl}?>
<!-- {comment} -->
<materialx version="1.39">
  <image name="a" type="color3"><input name="file" type="filename" value="a.png" /></image>
  <image name="b" type="color3"><input name="file" type="filename" value="b.png" /></image>
  <mix name="mx" type="color3">
    <input name="fg" type="color3" nodename="a" />
    <input name="bg" type="color3" nodename="b" />
    <input name="mix" type="float" value="0.5" />
  </mix>
  <surface_unlit name="U" type="surfaceshader">
    <input name="emission_color" type="color3" nodename="mx" />
    <input name="emission" type="float" value="0.8" />
  </surface_unlit>
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="U" />
  </surfacematerial>
</materialx>
"""


def mixed(decl="", comment="a comment", newline="\n"):
    return MIXED.format(decl=decl, comment=comment).replace("\n", newline)


def put(tmp_path, data, name="doc.mtlx"):
    path = str(tmp_path / name)
    with open(path, "wb") as f:
        f.write(data)
    return path


def read(path):
    with open(path, "rb") as f:
        return f.read()


def listed(path, element="M"):
    return {i.uniform: i for i in docedit.public_inputs(pipeline.Session(path), element)}


def refused(edits):
    with pytest.raises(MtlxError) as e:
        docedit.save_values(edits)
    return e.value.lines()


# ------------------------------------------------------------------ the reported losses and misplacements

def test_a_value_the_encoding_lacks_is_written_as_a_character_reference(tmp_path):
    """ISO-8859-1 cannot hold '€': it is written as &#8364; (no UnicodeEncodeError, no emptied file), the rest of
    the bytes as they were, and the document reads back with the value; the file's mode is kept."""
    old = mixed(' encoding="ISO-8859-1"', "caf\xe9 na\xefve").encode("latin-1")
    path = put(tmp_path, old)
    os.chmod(path, 0o640)
    got = listed(path)
    assert docedit.save_values([(got["a_file"], "textures/\u20ac.png")]) == [path]
    assert read(path) == old.replace(b'value="a.png"', b'value="textures/&#8364;.png"')
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o640
    assert listed(path)["a_file"].value == "textures/\u20ac.png"


@pytest.mark.parametrize("fail", ["os.replace", "os.fsync"])
def test_a_failed_write_leaves_the_old_file_whole(tmp_path, fail):
    path = put(tmp_path, mixed().encode())
    got = listed(path)
    with mock.patch(fail, side_effect=OSError(errno.ENOSPC, "No space left on device")):
        lines = refused([(got["a_file"], "new.png")])
    assert lines == ["%s:4: cannot write the file (No space left on device): not saved" % path]
    assert read(path) == mixed().encode()
    assert os.listdir(str(tmp_path)) == ["doc.mtlx"]          # no temporary file left behind


def test_a_lone_cr_in_a_comment_counts_as_a_line_break(tmp_path):
    """The reader counts the CR as a line break: the input is a line lower than a count of LFs says, where the
    next node's input of the same name sits. The edit lands in the node it belongs to."""
    old = mixed(comment="first\rsecond").encode()
    path = put(tmp_path, old)
    got = listed(path)
    assert got["a_file"].where.line == 5
    docedit.save_values([(got["a_file"], "new.png")])
    assert read(path) == old.replace(b'"a.png"', b'"new.png"')


def test_lines_are_the_readers_for_every_line_ending(tmp_path):
    """CR LF, lone CR and a mix: an <input> added to a node ends its line as the node's line ends."""
    for newline in ("\r\n", "\r", "mixed"):
        text = mixed()
        if newline == "mixed":
            parts = text.split("\n")
            text = "".join(p + ("\r", "\r\n", "\n")[i % 3] for i, p in enumerate(parts[:-1])) + parts[-1]
        else:
            text = text.replace("\n", newline)
        path = put(tmp_path, text.encode())
        got = listed(path)
        docedit.save_values([(got["b_file"], "b2.png"), (got["U_emission"], 0.25), (got["U_opacity"], 0.5)])
        start = text.index('  <surface_unlit name="U" type="surfaceshader">')
        end = text.index(">", start) + 1
        ending = re.compile(r"\r\n|\r|\n").match(text, end).group(0)
        expected = (text[:end] + ending + '    <input name="opacity" type="float" value="0.5" />' + text[end:]) \
            .replace('value="b.png"', 'value="b2.png"').replace('value="0.8"', 'value="0.25"')
        assert read(path).decode() == expected, newline


def test_a_node_moved_since_the_inputs_were_listed_is_refused(tmp_path):
    """An editor swapped the two images: b's input now sits where a's was. Nothing is written into b."""
    old = mixed()
    path = put(tmp_path, old.encode())
    got = listed(path)
    line_a = '  <image name="a" type="color3"><input name="file" type="filename" value="a.png" /></image>\n'
    line_b = '  <image name="b" type="color3"><input name="file" type="filename" value="b.png" /></image>\n'
    moved = old.replace(line_a + line_b, line_b + line_a).encode()
    put(tmp_path, moved)
    assert refused([(got["a_file"], "new.png")]) == [
        "%s:4: changed on disk since it was read: not saved; reload first" % path]
    assert read(path) == moved


def test_an_outside_change_to_the_same_input_is_not_overwritten(tmp_path):
    path = put(tmp_path, mixed().encode())
    got = listed(path)
    changed = mixed().replace('value="0.8"', 'value="0.9"').encode()
    put(tmp_path, changed)
    assert refused([(got["U_emission"], 0.1)]) == [
        "%s:13: changed on disk since it was read: not saved; reload first" % path]
    assert read(path) == changed


def test_after_the_file_is_read_again_saving_works(tmp_path):
    """The hash is taken when the inputs are listed: listing them again (as the viewer does after it reads the
    changed file) takes the new one."""
    path = put(tmp_path, mixed().encode())
    got = listed(path)
    changed = mixed().replace('value="0.8"', 'value="0.9"').encode()
    put(tmp_path, changed)
    refused([(got["U_emission"], 0.1)])
    got = listed(path)
    docedit.save_values([(got["U_emission"], 0.1)])
    assert read(path) == changed.replace(b'value="0.9"', b'value="0.1"')


@pytest.mark.parametrize("bom,codec", [(codecs.BOM_UTF16_BE, "utf-16-be"), (codecs.BOM_UTF16_LE, "utf-16-le"),
                                       (b"", "utf-16-be"), (b"", "utf-16-le"), (codecs.BOM_UTF8, "utf-8")],
                         ids=["utf16be-bom", "utf16le-bom", "utf16be", "utf16le", "utf8-bom"])
def test_utf16_and_byte_order_marks_are_kept(tmp_path, bom, codec):
    text = mixed(' encoding="UTF-16"' if "16" in codec else "", "\u4e2d\u6587 \U0001f600", "\r\n")
    path = put(tmp_path, bom + text.encode(codec))
    got = listed(path)
    docedit.save_values([(got["a_file"], "\u20ac\U0001f600.png"), (got["mx_mix"], 0.25)])
    assert read(path) == bom + text.replace('"a.png"', '"\u20ac\U0001f600.png"').replace(
        'value="0.5"', 'value="0.25"').encode(codec)


def test_copies_in_comments_cdata_and_instructions_are_not_inputs(tmp_path):
    """An input line that also holds a commented-out copy of itself (and one in a CDATA section, and in a
    processing instruction): the real element is edited, the copies stay as they were."""
    copy = '<!-- <input name="file" type="filename" value="old.png" /> -->'
    text = mixed().replace('value="a.png" /></image>',
                           'value="a.png" />%s<![CDATA[<input name="file" value="c.png"/>]]>'
                           '<?note <input name="file" value="p.png"/>?></image>' % copy)
    path = put(tmp_path, text.encode())
    got = listed(path)
    docedit.save_values([(got["a_file"], "new.png")])
    assert read(path) == text.replace('value="a.png"', 'value="new.png"').encode()


def test_a_second_save_edits_the_input_the_first_one_added(tmp_path):
    path = put(tmp_path, mixed().encode())
    got = listed(path)
    docedit.save_values([(got["U_opacity"], 0.5)])
    docedit.save_values([(got["U_opacity"], 0.75), (got["U_emission"], 0.3)])
    text = read(path).decode()
    assert text.count('name="opacity"') == 1 and '<input name="opacity" type="float" value="0.75" />' in text
    assert listed(path)["U_opacity"].value == 0.75


def test_a_value_xml_cannot_hold_is_refused(tmp_path):
    path = put(tmp_path, mixed().encode())
    got = listed(path)
    assert refused([(got["a_file"], "a\x01.png"), (got["U_emission"], 0.1)]) == [
        "%s:4: input 'file' of 'a': the value holds U+0001, which XML cannot hold: not saved" % path]
    assert read(path) == mixed().encode()


def test_a_symlinked_document_is_written_through_its_link(tmp_path):
    real = put(tmp_path, mixed().encode(), "real.mtlx")
    os.chmod(real, 0o604)
    link = str(tmp_path / "link.mtlx")
    os.symlink("real.mtlx", link)
    got = listed(link)
    assert docedit.save_values([(got["a_file"], "new.png")]) == [link]
    assert os.path.islink(link) and read(real) == mixed().replace('"a.png"', '"new.png"').encode()
    assert stat.S_IMODE(os.stat(real).st_mode) == 0o604


def test_every_file_is_checked_before_any_is_written(tmp_path):
    """Edits in two files: one changed on disk since, the other is not written either."""
    one = put(tmp_path, mixed().encode(), "one.mtlx")
    two = put(tmp_path, mixed().encode(), "two.mtlx")
    a, b = panel_inputs(one), panel_inputs(two)
    put(tmp_path, mixed(comment="edited").encode(), "two.mtlx")
    assert refused([(a[("a", "file")], "x.png"), (b[("b", "file")], "y.png")]) == [
        "%s:5: changed on disk since it was read: not saved; reload first" % two]
    assert read(one) == mixed().encode() and read(two) == mixed(comment="edited").encode()


def test_an_input_not_confirmed_when_listed_is_refused(tmp_path):
    """The document was read before an editor moved the input: listing finds another element at its line."""
    path = put(tmp_path, mixed().encode())
    items = panel_inputs(path)
    item = items[("a", "file")]
    put(tmp_path, mixed().replace('  <image name="a"', '\n  <image name="a"').encode())
    docedit.record_sources([item])          # listed again against the changed bytes, the old lines kept
    assert item.source is None
    assert refused([(item, "x.png")]) == [
        "%s:4: input 'file' of 'a': the file changed while the document was read: not saved; reload first" % path]


# ------------------------------------------------------------------ generated documents

def panel_inputs(path, extra=()):
    """{(owner, input): PanelInput} of every <input> of a file as the XML reader reads them (owner: the node or
    nodegraph holding it, 'doc' for the document's own), plus `extra` (node, input, type) not authored; each
    with the Origin the graph gives its uniform (the owner's name path, the input), confirmed by
    docedit.record_sources as public_inputs does."""
    root = xmlreader.parse_text(read(path), path)
    out, owners, work = {}, {}, [(root, "")]
    while work:
        el, at = work.pop()
        owner = el.get("name") or "doc"
        owners[owner] = (el, at)
        for c in el.children:
            if c.tag == "input":
                out[(owner, c.get("name"))] = docedit.PanelInput(
                    uniform="%s_%s" % (owner, c.get("name")), node=owner, input=c.get("name"),
                    mtlx_type=c.get("type"), value=None, where=c.loc, node_loc=None if el is root else el.loc,
                    tag=el.tag, origin=Origin(at, c.get("name")))
            elif c.get("name"):
                work.append((c, at + "/" + c.get("name") if at else c.get("name")))
    for node, name, mtlx_type in extra:
        c, at = owners[node]
        out[(node, name)] = docedit.PanelInput(uniform="%s_%s" % (node, name), node=node, input=name,
                                               mtlx_type=mtlx_type, value=None, node_loc=c.loc, tag=c.tag,
                                               origin=Origin(at, name, False))
    docedit.record_sources(list(out.values()))
    return out


# (codec, byte-order mark, encoding declared, characters the document's own text may hold)
ENCODINGS = [
    ("utf-8", b"", None, "\u00e9\u20ac\u4e2d\U0001f600"),
    ("utf-8", codecs.BOM_UTF8, "UTF-8", "\u00e9\u20ac\u4e2d"),
    ("utf-16-le", codecs.BOM_UTF16_LE, "UTF-16", "\u00e9\u4e2d\U0001f600"),
    ("utf-16-be", codecs.BOM_UTF16_BE, None, "\u00e9\u20ac"),
    ("utf-16-le", b"", "UTF-16", "\u00e9\u4e2d"),
    ("utf-16-be", b"", None, "\u20ac\U0001f600"),
    ("iso8859-1", b"", "ISO-8859-1", "\u00e9\u00ff"),
    ("cp1252", b"", "windows-1252", "\u00e9\u20ac"),
]
VALUE_CHARS = list('ab. "&<>\'\t\n\u00e9\u20ac\u4e2d\U0001f600') + ["<UDIM>"]
TAGS = ["image", "mix", "constant"]


@st.composite
def documents(draw):
    """(text, {(node, input): (value start, value end, quote) or ('add', where)}, {node: (start tag end, closed,
    where '/>' begins with the spaces before it, tag)}, the codec, mark, the line breaks used)."""
    codec, bom, declared, chars = draw(st.sampled_from(ENCODINGS))
    breaks = draw(st.sampled_from([["\n"], ["\r\n"], ["\r"], ["\n", "\r\n", "\r"]]))
    pick = draw(st.lists(st.integers(0, len(breaks) - 1), min_size=64, max_size=64))
    text_alphabet = st.sampled_from(list("ab xyz") + list(chars))
    state = {"text": "", "breaks": 0}
    spans, nodes = {}, {}

    def emit(s):
        state["text"] += s

    def nl():
        state["breaks"] += 1
        emit(breaks[pick[state["breaks"] % 64]])

    def noise(top=False):
        kind = draw(st.sampled_from(["", "", "comment", "pi"] + ([] if top else ["cdata"])))
        fake = '<input name="in%d" type="filename" value="fake" />' % draw(st.integers(0, 2))
        words = draw(st.text(text_alphabet, max_size=6))
        if kind == "comment":
            emit("<!-- %s%s%s -->" % (words, draw(st.sampled_from(["\r", "\r\n", ""])), fake))
        elif kind == "cdata":
            emit("<![CDATA[%s\r%s]]>" % (fake, words))
        elif kind == "pi":
            emit("<?note %s %s?>" % (fake, words))

    def attr(name, value, quote):
        return " %s=%s%s%s" % (name, quote, value, quote)

    def inputs(owner, indent, count):
        for k in range(count):
            nl()
            emit(indent + "<input")
            quote = draw(st.sampled_from("\"'"))
            first = [attr("name", "in%d" % k, quote), attr("type", "filename", quote)]
            if draw(st.booleans()):
                first.reverse()
            emit("".join(first))
            if draw(st.integers(0, 4)):
                emit(" value=" + quote)
                start = len(state["text"])
                emit(draw(st.text(text_alphabet, max_size=8)))
                spans[(owner, "in%d" % k)] = (start, len(state["text"]), quote)
                emit(quote)
            else:
                spans[(owner, "in%d" % k)] = ("add", len(state["text"]))
            emit(draw(st.sampled_from([" />", "/>"])))
            noise()

    def node(name, indent):
        tag = draw(st.sampled_from(TAGS))
        count = draw(st.integers(0, 3))
        emit("%s<%s" % (indent, tag) + attr("name", name, draw(st.sampled_from("\"'"))) + ' type="color3"')
        if count == 0:
            close_at = len(state["text"])
            emit(draw(st.sampled_from(["/>", " />", "  />"])))
            nodes[name] = (len(state["text"]), True, close_at, tag)
            noise()
            nl()
            return
        emit(">")
        nodes[name] = (len(state["text"]), False, None, tag)
        noise()
        inputs(name, indent + "  ", count)
        nl()
        emit("%s</%s>" % (indent, tag))
        noise()
        nl()

    if declared or codec.startswith("utf-16") and not bom or draw(st.booleans()):
        emit('<?xml version="1.0"%s?>' % (' encoding="%s"' % declared if declared else ""))
        nl()
    noise(top=True)
    nl()
    emit('<materialx version="1.39">')
    inputs("doc", "  ", draw(st.integers(0, 1)))       # the document's own inputs
    nl()
    count = 0
    for _ in range(draw(st.integers(1, 4))):
        if draw(st.integers(0, 3)) == 0:
            graph = "g%d" % count
            emit('  <nodegraph name="%s">' % graph)
            nodes[graph] = (len(state["text"]), False, None, "nodegraph")
            noise()
            inputs(graph, "    ", draw(st.integers(0, 2)))    # its interface
            nl()
            for _ in range(draw(st.integers(1, 2))):
                node("n%d" % count, "    ")
                count += 1
            emit("  </nodegraph>")
            nl()
        else:
            node("n%d" % count, "  ")
            count += 1
    emit("</materialx>")
    if draw(st.booleans()):
        nl()
    return state["text"], spans, nodes, codec, bom, breaks


def _settings(fn):
    examples = int(os.environ.get("MTLXGEN_FUZZ_EXAMPLES", "150"))
    s = settings(max_examples=examples, deadline=None, database=None,
                 derandomize=os.environ.get("MTLXGEN_FUZZ_SEED") is None,
                 suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])(fn)
    return seed(int(os.environ["MTLXGEN_FUZZ_SEED"]))(s) if os.environ.get("MTLXGEN_FUZZ_SEED") else s


INSERTED = r'(?:%s)[ \t]*<input name="(x\d)" type="filename" value="([^"]*)" />'


def check_result(old, new, regions, breaks):
    """`new` is `old` with each region replaced as the edit says and every other character the same:
    regions (start, end, kind, payload) in order; kind 'value': the value between its quotes; 'add': a value
    attribute added; 'insert': <input> lines after an open start tag; 'open': a self-closed element opened
    around them."""
    br = "|".join(re.escape(b) for b in breaks)
    o = n = 0
    for start, end, kind, payload in regions:
        assert new[n:n + start - o] == old[o:start]
        n += start - o
        if kind == "value":
            quote, value = payload
            j = new.index(quote, n)
            assert html.unescape(new[n:j]) == value
            n = j
        elif kind == "add":
            m = re.compile(r' value="([^"]*)"').match(new, n)
            assert m and html.unescape(m.group(1)) == payload
            n = m.end()
        else:
            lines, tag = payload
            pattern = "(?:%s)+" % INSERTED % br
            if kind == "open":
                pattern = ">(%s)(?:%s)[ \t]*</%s>" % (pattern, br, tag)
            m = re.compile(pattern).match(new, n)
            assert m, (kind, new[n:n + 200])
            got = dict((a, html.unescape(v)) for a, v in re.findall(INSERTED % br, m.group(0)))
            assert got == lines
            n = m.end()
        o = end
    assert new[n:] == old[o:]


@_settings
@given(doc=documents(), data=st.data())
def test_generated_documents_keep_every_byte_outside_the_edits(doc, data):
    text, spans, nodes, codec, bom, breaks = doc
    old = bom + text.encode(codec)
    extra = data.draw(st.lists(st.tuples(st.sampled_from(sorted(nodes)), st.sampled_from(["x0", "x1"])),
                               min_size=0 if spans else 1, max_size=3, unique=True))
    targets = sorted(spans) + extra
    chosen = data.draw(st.lists(st.sampled_from(targets), min_size=1, max_size=4, unique=True))
    values = {t: "".join(data.draw(st.lists(st.sampled_from(VALUE_CHARS), max_size=6))) for t in chosen}
    scenario = data.draw(st.sampled_from(["save", "save", "save", "outside", "replace fails", "fsync fails"]))
    event(scenario)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "doc.mtlx")
        with open(path, "wb") as f:
            f.write(old)
        items = panel_inputs(path, [(n, i, "filename") for n, i in extra])
        edits = [(items[t], values[t]) for t in chosen]
        assert all(item.source is not None for item, _ in edits)
        if scenario == "outside":
            outside = data.draw(st.sampled_from(["value", "line", "comment"]))
            if outside == "value" and spans and any(len(s) == 3 for s in spans.values()):
                start, end, _ = next(s for s in spans.values() if len(s) == 3)
                changed = text[:start] + "changed" + text[end:]
            elif outside == "line":
                at = text.index("<materialx")
                changed = text[:at] + breaks[0] + text[at:]
            else:
                changed = text + "<!-- edited -->"
            with open(path, "wb") as f:
                f.write(bom + changed.encode(codec))
            with pytest.raises(MtlxError) as e:
                docedit.save_values(edits)
            assert e.value.lines() and all(re.match(re.escape(path) + r":\d+: .*not saved", ln)
                                           for ln in e.value.lines())
            assert read(path) == bom + changed.encode(codec)
            return
        if scenario != "save":
            target = "os.replace" if scenario == "replace fails" else "os.fsync"
            with mock.patch(target, side_effect=OSError(errno.EIO, "I/O error")):
                with pytest.raises(MtlxError) as e:
                    docedit.save_values(edits)
            assert len(e.value.lines()) == 1 and e.value.lines()[0].startswith(path + ":")
            assert read(path) == old and os.listdir(folder) == ["doc.mtlx"]
            return
        assert docedit.save_values(edits) == [path]
        new = read(path)
        assert new.startswith(bom)
        regions, inserts = [], {}
        for t in chosen:
            value = values[t]
            if t in spans and spans[t][0] == "add":
                regions.append((spans[t][1], spans[t][1], "add", value))
            elif t in spans:
                regions.append((spans[t][0], spans[t][1], "value", (spans[t][2], value)))
            else:
                inserts.setdefault(t[0], {})[t[1]] = value
        for name, lines in inserts.items():
            end, closed, close_at, tag = nodes[name]
            if closed:
                regions.append((close_at, end, "open", (lines, tag)))
            else:
                regions.append((end, end, "insert", (lines, tag)))
        for region in regions:
            event("%s (%s)" % (region[2], codec))
        check_result(text, new[len(bom):].decode(codec), sorted(regions, key=lambda r: r[:2]), breaks)
        # and the XML reader reads the values set, every other input as it was
        expected = input_values(old, path)
        expected.update(values)
        assert input_values(new, path) == expected


def input_values(data, path):
    """{(node, input): value attribute} of every <input> in a document's bytes, as the XML reader reads them."""
    out, work = {}, [(xmlreader.parse_text(data, path), None)]
    while work:
        el, parent = work.pop()
        work.extend((c, el) for c in el.children)
        if el.tag == "input":
            out[(parent.get("name") or "doc", el.get("name"))] = el.get("value")
    return out


def test_inputs_of_an_included_file_are_written_into_it(tmp_path):
    """A node from an xi:include'd file: its input's name path is its path in that file, and the edit goes
    there; an outside change to either file refuses both."""
    lib = put(tmp_path, b'<?xml version="1.0"?>\n<materialx version="1.39">\n'
                        b'  <image name="a" type="color3"><input name="file" type="filename" value="a.png" /></image>\n'
                        b'</materialx>\n', "lib.mtlx")
    main = mixed().replace('  <image name="a" type="color3"><input name="file" type="filename" value="a.png" />'
                           '</image>\n', '  <xi:include href="lib.mtlx" />\n')
    path = put(tmp_path, main.encode())
    got = listed(path)
    assert got["a_file"].where == Loc(lib, 3) and got["a_file"].element_path == ("a", "file")
    assert got["b_file"].source.path == path and got["a_file"].source.path == lib
    old_lib = read(lib)
    with open(lib, "ab") as f:
        f.write(b"<!-- touched -->\n")
    assert refused([(got["b_file"], "b2.png"), (got["a_file"], "a2.png")]) == [
        "%s:3: changed on disk since it was read: not saved; reload first" % lib]
    assert read(path) == main.encode()
    put(tmp_path, old_lib, "lib.mtlx")
    assert docedit.save_values([(got["b_file"], "b2.png"), (got["a_file"], "a2.png")]) == [path, lib]
    assert read(lib) == old_lib.replace(b'"a.png"', b'"a2.png"')
    assert read(path) == main.replace('"b.png"', '"b2.png"').encode()


def test_an_unauthored_input_of_an_included_node_is_added_in_its_file(tmp_path):
    """A node from an xi:include'd file leaves an input to its nodedef: the uniform's Origin names the node, its
    element is found in the included file (its own FILE:LINE), and the <input> is added there."""
    lib_text = (b'<?xml version="1.0"?>\n<materialx version="1.39">\n'
                b'  <image name="a" type="color3"><input name="file" type="filename" value="a.png" /></image>\n'
                b'</materialx>\n')
    lib = put(tmp_path, lib_text, "lib.mtlx")
    main = mixed().replace('  <image name="a" type="color3"><input name="file" type="filename" value="a.png" />'
                           '</image>\n', '  <xi:include href="lib.mtlx" />\n')
    path = put(tmp_path, main.encode())
    got = {(i.origin.element, i.input): i for i in docedit.public_inputs(pipeline.Session(path), "M")}
    item = got[("a", "default")]
    assert item.where is None and item.node_loc == Loc(lib, 3) and item.element_path == ("a", "default")
    assert item.source.path == lib and not item.origin.authored
    assert docedit.save_values([(item, (0.25, 0.5, 1.0))]) == [lib]
    assert read(path) == main.encode()
    assert read(lib) == lib_text.replace(b'<image name="a" type="color3">',
                                         b'<image name="a" type="color3">\n    <input name="default" '
                                         b'type="color3" value="0.25, 0.5, 1" />')
    g = pipeline.Session(path).graph("M")
    assert [u.value for u in g.uniforms.values()
            if (u.origin.element, u.origin.input, u.origin.authored) == ("a", "default", True)] == [(0.25, 0.5, 1.0)]


def test_an_input_is_confirmed_against_its_origin(tmp_path):
    """The element at the input's line must be the input its Origin names (element name path and input): an item
    whose origin names another node's input of the same name at another line, or no origin, is not confirmed and
    not saved."""
    path = put(tmp_path, mixed().encode())
    items = panel_inputs(path)
    a, b = items[("a", "file")], items[("b", "file")]
    assert a.element_path == ("a", "file") and b.element_path == ("b", "file")
    a.origin = Origin("b", "file")              # b's origin at a's line
    b.origin = None
    docedit.record_sources([a, b])
    assert a.source is None and a.element_path is None and b.source is None
    assert refused([(a, "x.png")]) == [
        "%s:4: input 'file' of 'a': the file changed while the document was read: not saved; reload first" % path]
    assert read(path) == mixed().encode()
