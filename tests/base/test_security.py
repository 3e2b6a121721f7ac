"""Documents from strangers: which files their includes and implementation files may read (files.py), reads
that cannot hang or exhaust memory, encodings, nesting, and XML attacks. Every refusal is one FILE:LINE line."""
import contextlib
import os
import re
import signal
import uuid

import pytest

from mtlxgen.apps import cli
from mtlxgen.read import document, xmlreader
from mtlxgen.base import files
from mtlxgen.draw import ies
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import MtlxError
from mtlxgen.base.images import read_image
from mtlxgen.read.xmlreader import parse_text
from util import write_doc

FILE_LINE = re.compile(r"^\S.*:\d+: \S")


@contextlib.contextmanager
def deadline(seconds=10):
    """Fail instead of hanging: a blocked read (FIFO, /dev/stdin) is interrupted by the alarm."""
    def expired(signum, frame):
        raise TimeoutError("still reading after %d s" % seconds)
    old = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


def run_cli(capsys, *args):
    with deadline(60):
        code = cli.main(list(args))
    return code, capsys.readouterr().err


def assert_one_file_line(err, pattern):
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert FILE_LINE.match(lines[0]), lines[0]
    assert re.search(pattern, lines[0]), lines[0]
    assert "Traceback" not in err and "internal error" not in err


def output_bytes(folder):
    out = b""
    for dp, _, fs in os.walk(folder):
        for f in fs:
            with open(os.path.join(dp, f), "rb") as fh:
                out += fh.read()
    return out


IMPL_DOC = """
  <nodedef name="ND_halve_color3" node="halve">
    <input name="in" type="color3" value="1, 0, 0" />
    <output name="out" type="color3" />
  </nodedef>
  <implementation name="IM_halve" nodedef="ND_halve_color3" file="%s" function="halve" target="genglsl" />
  <halve name="n" type="color3" />
  <output name="o" type="color3" nodename="n" />"""

HALVE = "void halve(vec3 i, out vec3 o) { o = i * 0.5; }  // %s\n"


@pytest.fixture
def tree(tmp_path):
    """A document folder `doc/` and a folder beside it `outside/` holding a canary GLSL file."""
    (tmp_path / "doc").mkdir()
    (tmp_path / "outside").mkdir()
    canary = "CANARY_" + uuid.uuid4().hex
    (tmp_path / "outside" / "canary.glsl").write_text(HALVE % canary)
    return tmp_path, canary


# ---------------------------------------------------------------- implementation files

def test_implementation_file_in_a_subfolder_of_the_document_is_pasted_into_the_shader(tree, capsys):
    root, _ = tree
    (root / "doc" / "glsl").mkdir()
    marker = "INSIDE_" + uuid.uuid4().hex
    (root / "doc" / "glsl" / "halve.glsl").write_text(HALVE % marker)
    path = write_doc(root / "doc", IMPL_DOC % "glsl/halve.glsl")
    code, err = run_cli(capsys, "generate", path, "-o", str(root / "out"))
    assert code == 0, err
    assert marker.encode() in output_bytes(root / "out")


@pytest.mark.parametrize("how", ["relative", "absolute"])
def test_implementation_file_outside_the_document_folder_is_refused_and_never_copied(tree, capsys, how):
    root, canary = tree
    name = "../outside/canary.glsl" if how == "relative" else str(root / "outside" / "canary.glsl")
    path = write_doc(root / "doc", IMPL_DOC % name)
    code, err = run_cli(capsys, "generate", path, "-o", str(root / "out"))
    assert code == 1
    assert_one_file_line(err, r"doc\.mtlx:8: implementation file '.*canary\.glsl' is outside the document's folder")
    assert canary.encode() not in output_bytes(root / "out") if (root / "out").exists() else True


@pytest.mark.parametrize("name", ["/etc/passwd", "/proc/self/environ", "../../../../../../../etc/passwd"])
def test_system_files_as_implementation_files_are_refused(tmp_path, capsys, name):
    path = write_doc(tmp_path, IMPL_DOC % name)
    code, err = run_cli(capsys, "generate", path, "-o", str(tmp_path / "out"))
    assert code == 1
    assert_one_file_line(err, r"doc\.mtlx:8: implementation file '%s' is not a GLSL source" % re.escape(name))
    assert not (tmp_path / "out").exists() or b"root:" not in output_bytes(tmp_path / "out")


def test_glsl_named_system_file_is_refused_by_the_folder_rule(tmp_path, capsys):
    """The extension is not the guard: a symlink named .glsl to /etc/passwd still points out of the tree."""
    os.symlink("/etc/passwd", str(tmp_path / "passwd.glsl"))
    path = write_doc(tmp_path, IMPL_DOC % "passwd.glsl")
    code, err = run_cli(capsys, "generate", path, "-o", str(tmp_path / "out"))
    assert code == 1
    assert_one_file_line(err, r"doc\.mtlx:8: implementation file 'passwd\.glsl' is outside the document's folder")


def test_symlink_out_of_the_document_tree_is_refused(tree, capsys):
    root, canary = tree
    os.symlink(str(root / "outside" / "canary.glsl"), str(root / "doc" / "link.glsl"))
    path = write_doc(root / "doc", IMPL_DOC % "link.glsl")
    code, err = run_cli(capsys, "generate", path, "-o", str(root / "out"))
    assert code == 1
    assert_one_file_line(err, r"doc\.mtlx:8: implementation file 'link\.glsl' is outside the document's folder")
    assert not (root / "out").exists() or canary.encode() not in output_bytes(root / "out")


def test_implementation_file_from_the_search_path_is_allowed(tree, monkeypatch):
    root, canary = tree
    monkeypatch.setenv("MATERIALX_SEARCH_PATH", str(root / "outside"))
    path = write_doc(root / "doc", IMPL_DOC % str(root / "outside" / "canary.glsl"))
    shader, = pipeline.generate(path)
    assert canary in shader.fragment


def test_fifo_implementation_file_is_refused_without_blocking(tmp_path):
    os.mkfifo(str(tmp_path / "pipe.glsl"))
    path = write_doc(tmp_path, IMPL_DOC % "pipe.glsl")
    with deadline(10), pytest.raises(MtlxError, match=r"doc\.mtlx:8: implementation file 'pipe\.glsl' is a FIFO"):
        pipeline.generate(path)


# ---------------------------------------------------------------- includes

def include(href):
    return '<xi:include href="%s" />' % href


def test_include_outside_the_document_folder_is_refused(tree, capsys):
    root, _ = tree
    write_doc(root / "outside", '<constant name="c" type="float" />', name="other.mtlx")
    for href in ("../outside/other.mtlx", str(root / "outside" / "other.mtlx")):
        path = write_doc(root / "doc", include(href))
        code, err = run_cli(capsys, "generate", path, "-o", str(root / "out"))
        assert code == 1
        assert_one_file_line(err, r"doc\.mtlx:3: xi:include '%s' is outside the document's folder and the "
                                  r"search paths" % re.escape(href))


@pytest.mark.parametrize("name", ["a&#10;b", "../x&#13;y", "/etc/&#10;passwd"])
def test_names_with_line_breaks_stay_on_one_problem_line(tmp_path, capsys, name):
    for body, line in ((include(name + ".mtlx"), 3), (IMPL_DOC % (name + ".glsl"), 8)):
        path = write_doc(tmp_path, body)
        code, err = run_cli(capsys, "generate", path, "-o", str(tmp_path / "out"))
        assert code == 1
        assert_one_file_line(err, r"doc\.mtlx:%d: .*'[^']*\\[nr][^']*'" % line)


def test_any_prefix_include_follows_the_same_rule(tree):
    root, _ = tree
    write_doc(root / "outside", '<constant name="c" type="float" />', name="other.mtlx")
    path = write_doc(root / "doc", '<foo:include href="../outside/other.mtlx" />')
    with pytest.raises(MtlxError, match="is outside the document's folder"):
        document.load(path)


def test_relative_includes_between_subfolders_of_the_document_are_allowed(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    write_doc(tmp_path / "b", '<constant name="deep" type="float" />', name="leaf.mtlx")
    write_doc(tmp_path / "a", include("../b/leaf.mtlx"), name="mid.mtlx")
    path = write_doc(tmp_path, include("a/mid.mtlx"))
    doc = document.load(path)
    assert doc.nodes["deep"].loc.file == str(tmp_path / "b" / "leaf.mtlx")


def test_includes_from_a_library_folder_and_the_search_path_are_allowed(tree, capsys, monkeypatch):
    root, _ = tree
    write_doc(root / "outside", '<constant name="fromlib" type="float" />\n'
                                '<output name="o" type="float" nodename="fromlib" />', name="lib.mtlx")
    path = write_doc(root / "doc", include("lib.mtlx"))
    code, err = run_cli(capsys, "generate", path, "-o", str(root / "out1"), "--library", str(root / "outside"))
    assert code == 0, err
    assert (root / "out1" / "o.frag").exists()
    monkeypatch.setenv("MATERIALX_SEARCH_PATH", str(root / "outside"))
    code, err = run_cli(capsys, "generate", path, "-o", str(root / "out2"))
    assert code == 0, err
    assert (root / "out2" / "o.frag").exists()


def test_symlinked_include_pointing_out_of_the_tree_is_refused(tree):
    root, _ = tree
    write_doc(root / "outside", '<constant name="c" type="float" />', name="other.mtlx")
    os.symlink(str(root / "outside" / "other.mtlx"), str(root / "doc" / "inside.mtlx"))
    path = write_doc(root / "doc", include("inside.mtlx"))
    with pytest.raises(MtlxError, match=r"doc\.mtlx:3: xi:include 'inside\.mtlx' is outside"):
        document.load(path)


@pytest.mark.parametrize("href", ["/dev/zero", "/dev/stdin", "/dev/urandom", "/proc/self/environ"])
def test_device_and_proc_includes_are_refused_quickly(tmp_path, capsys, href):
    path = write_doc(tmp_path, include(href))
    code, err = run_cli(capsys, "generate", path, "-o", str(tmp_path / "out"))
    assert code == 1
    assert_one_file_line(err, r"doc\.mtlx:3: xi:include '%s' is outside" % re.escape(href))


def test_device_inside_the_document_folder_is_refused_as_a_device(tmp_path):
    """Inside the tree the folder rule lets it through; the regular-file rule does not (no hang, no MemoryError)."""
    os.mkfifo(str(tmp_path / "pipe.mtlx"))
    path = write_doc(tmp_path, include("pipe.mtlx"))
    with deadline(10), pytest.raises(MtlxError, match=r"doc\.mtlx:3: xi:include 'pipe\.mtlx' is a FIFO"):
        document.load(path)


def test_document_that_is_a_fifo_is_refused_without_blocking(tmp_path):
    os.mkfifo(str(tmp_path / "pipe.mtlx"))
    with deadline(10), pytest.raises(MtlxError, match=r"pipe\.mtlx:0: the document is a FIFO"):
        xmlreader.read_file(str(tmp_path / "pipe.mtlx"))


def test_oversize_include_is_refused(tmp_path):
    big = tmp_path / "big.mtlx"
    with open(big, "wb") as f:       # sparse: costs no disk
        f.truncate(files.MAX_TEXT_BYTES + 1)
    path = write_doc(tmp_path, include("big.mtlx"))
    with deadline(20), pytest.raises(MtlxError, match=r"doc\.mtlx:3: xi:include 'big\.mtlx' is larger than 32 MB"):
        document.load(path)


def test_read_bounded_takes_exactly_up_to_the_limit(tmp_path):
    p = tmp_path / "f.txt"
    p.write_bytes(b"x" * 100)
    assert files.read_bounded(str(p), None, "f", limit=100) == b"x" * 100
    with pytest.raises(MtlxError, match="larger than"):
        files.read_bounded(str(p), None, "f", limit=99)


def test_include_fan_out_is_bounded(tmp_path):
    """Each file including the next twice: 2^11 reads from 12 tiny files, an include bomb."""
    for k in range(11):
        write_doc(tmp_path, include("f%d.mtlx" % (k + 1)) + "\n" + include("f%d.mtlx" % (k + 1)), name="f%d.mtlx" % k)
    write_doc(tmp_path, '<constant name="c" type="float" />', name="f11.mtlx")
    with deadline(30), pytest.raises(MtlxError, match="more than %d included files" % xmlreader.MAX_INCLUDES):
        document.load(str(tmp_path / "f0.mtlx"))


def test_elements_are_counted_across_includes(tmp_path, monkeypatch):
    monkeypatch.setattr(xmlreader, "MAX_ELEMENTS", 100)
    write_doc(tmp_path, "<a/>" * 60, name="part.mtlx")
    once = write_doc(tmp_path, include("part.mtlx"), name="once.mtlx")
    assert len(xmlreader.read_file(once).children) == 60
    twice = write_doc(tmp_path, include("part.mtlx") + "\n" + include("part.mtlx"), name="twice.mtlx")
    with pytest.raises(MtlxError, match=r"part\.mtlx:3: more than 100 elements \(includes counted\)"):
        xmlreader.read_file(twice)


def test_bytes_read_are_counted_across_includes(tmp_path, monkeypatch):
    part = write_doc(tmp_path, " " * 600, name="part.mtlx")
    monkeypatch.setattr(xmlreader, "MAX_TOTAL_BYTES", 2 * os.path.getsize(part))
    twice = write_doc(tmp_path, include("part.mtlx") + "\n" + include("part.mtlx"), name="twice.mtlx")
    with pytest.raises(MtlxError, match=r"twice\.mtlx:4: the document and its includes are larger than"):
        xmlreader.read_file(twice)


def test_the_largest_data_library_reads_within_the_caps():
    from mtlxgen.read.library import library_files
    biggest = max(library_files(), key=os.path.getsize)
    assert xmlreader.read_file(biggest).children


# ---------------------------------------------------------------- textures: any regular file, no devices

@pytest.mark.parametrize("name", ["/dev/zero", "/proc/self/environ"])
def test_texture_reads_refuse_devices_and_proc(name):
    with deadline(10):
        with pytest.raises(MtlxError, match=r"^%s:0: image file is a system file" % re.escape(name)):
            read_image(name)
        with pytest.raises(MtlxError, match=r"^%s:0: IES file is a system file" % re.escape(name)):
            ies.parse(name)


def test_texture_outside_the_document_folder_is_still_read(tmp_path):
    """Images are decoded, never copied, so they may live anywhere the document points."""
    from mtlxgen.base.images import write_image
    import numpy as np
    img = tmp_path / "elsewhere" / "t.png"
    write_image(str(img), np.full((2, 2, 3), 0.5, dtype=np.float32))
    assert read_image(str(img)).shape == (2, 2, 3)


def test_image_whose_header_claims_too_many_pixels_is_refused(tmp_path, monkeypatch):
    from mtlxgen.base import images
    import numpy as np
    p = str(tmp_path / "t.png")
    images.write_image(p, np.zeros((4, 4, 3), dtype=np.float32))
    monkeypatch.setattr(images, "MAX_IMAGE_PIXELS", 15)
    with pytest.raises(MtlxError, match=r"t\.png:0: image of 4x4 pixels"):
        images.read_image(p)


def test_rendering_a_texture_from_dev_zero_fails_with_one_line(tmp_path, capsys):
    path = write_doc(tmp_path, """
  <image name="img" type="color3">
    <input name="file" type="filename" value="/dev/zero" />
  </image>
  <output name="o" type="color3" nodename="img" />""")
    code, err = run_cli(capsys, "render", path, "-o", str(tmp_path / "out"), "--size", "16")
    assert code == 1        # at the input naming it; the file never opened, the image's default drawn
    assert_one_file_line(err, r"^%s:5: texture '/dev/zero' is a system file \(under /dev\)" % re.escape(path))


# ---------------------------------------------------------------- XML: entities, encodings, nesting

def test_external_entity_is_refused():
    text = ('<?xml version="1.0"?>\n<!DOCTYPE m [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'
            '<materialx><constant name="&x;" type="float"/></materialx>')
    with pytest.raises(MtlxError, match=r"x\.mtlx:2: entity declarations are not allowed"):
        parse_text(text, "x.mtlx")


def test_billion_laughs_is_refused_at_once():
    decls = '<!ENTITY l0 "lol">' + "".join('<!ENTITY l%d "%s">' % (k, ("&l%d;" % (k - 1)) * 10) for k in range(1, 10))
    text = '<?xml version="1.0"?>\n<!DOCTYPE m [%s]>\n<materialx a="&l9;"/>' % decls
    with deadline(10), pytest.raises(MtlxError, match="entity declarations are not allowed"):
        parse_text(text, "x.mtlx")


def test_undeclared_entity_is_malformed_xml():
    with pytest.raises(MtlxError, match=r"x\.mtlx:2: malformed XML: undefined entity"):
        parse_text('<?xml version="1.0"?>\n<materialx a="&x;"/>', "x.mtlx")


@pytest.mark.parametrize("codec", ["utf-16", "utf-16-le", "utf-16-be", "utf-8-sig"])
def test_unicode_documents_with_and_without_byte_order_marks_are_read(codec):
    text = ('<?xml version="1.0" encoding="%s"?>\n<materialx version="1.39">\n'
            '  <image name="caf\u00e9" type="color3">'
            '<input name="file" type="filename" value="t.<UDIM>.png"/></image>\n'
            '</materialx>\n') % codec.replace("-sig", "")
    root = parse_text(text.encode(codec), "x.mtlx")
    assert root.children[0].get("name") == "caf\u00e9"
    assert root.children[0].loc.line == 3
    assert root.children[0].children[0].get("value") == "t.<UDIM>.png"


@pytest.mark.parametrize("codec", ["latin-1", "cp1252", "koi8-r", "us-ascii"])
def test_single_byte_encodings_are_read_as_declared(codec):
    text = '<?xml version="1.0" encoding="%s"?>\n<materialx><constant name="%s" type="float"/></materialx>\n'
    name = "caf\u00e9" if codec != "us-ascii" else "cafe"
    if codec == "koi8-r":
        name = "\u0436"
    root = parse_text((text % (codec, name)).encode(codec), "x.mtlx")
    assert root.children[0].get("name") == name


@pytest.mark.parametrize("name", ["utf-7", "UTF-7", "utf-32", "shift_jis", "hz", "rot13", "no-such-encoding", "utf\x00-7"])
def test_unsupported_encodings_are_refused_with_file_and_line(tmp_path, capsys, name):
    p = tmp_path / "enc.mtlx"
    p.write_bytes(('<?xml version="1.0" encoding="%s"?>\n<materialx version="1.39">\n</materialx>\n' % name).encode())
    code, err = run_cli(capsys, "generate", str(p), "-o", str(tmp_path / "out"))
    assert code == 1
    shown = name.encode("unicode_escape").decode()          # a NUL in the name is shown escaped
    assert_one_file_line(err, r"enc\.mtlx:1: unsupported encoding '%s'" % re.escape(shown))


def test_utf32_byte_order_mark_is_refused():
    with pytest.raises(MtlxError, match=r"x\.mtlx:1: unsupported encoding 'utf-32'"):
        parse_text('<materialx/>'.encode("utf-32"), "x.mtlx")


def test_bytes_invalid_in_the_declared_encoding_name_their_line():
    data = b'<?xml version="1.0"?>\n<materialx>\n<constant name="\xff" type="float"/>\n</materialx>\n'
    with pytest.raises(MtlxError, match=r"x\.mtlx:3: not valid utf-8 text \(byte 0xff\)"):
        parse_text(data, "x.mtlx")


def test_elements_nested_a_thousand_levels_are_refused_with_file_and_line(tmp_path, capsys):
    p = tmp_path / "deep.mtlx"
    p.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n' + "<a>\n" * 1000 + "</a>\n" * 1000
                 + "</materialx>\n")
    code, err = run_cli(capsys, "generate", str(p), "-o", str(tmp_path / "out"))
    assert code == 1
    # the root is level 1: the first <a> too deep is level MAX_DEPTH + 1, on line MAX_DEPTH + 2
    assert_one_file_line(err, r"deep\.mtlx:%d: elements nest more than %d levels deep"
                              % (xmlreader.MAX_DEPTH + 2, xmlreader.MAX_DEPTH))


def test_nesting_limit_counts_levels_brought_in_by_includes(tmp_path):
    half = xmlreader.MAX_DEPTH // 2 + 10
    write_doc(tmp_path, "<a>" * half + "</a>" * half, name="inner.mtlx")
    body = "<a>" * half + include("inner.mtlx") + "</a>" * half
    path = write_doc(tmp_path, body)
    with pytest.raises(MtlxError, match=r"inner\.mtlx:3: elements nest more than %d levels deep \(with includes\)"
                                        % xmlreader.MAX_DEPTH):
        document.load(path)


def test_nesting_at_the_limit_is_read(tmp_path):
    depth = xmlreader.MAX_DEPTH - 1          # below the root
    p = tmp_path / "ok.mtlx"
    p.write_text('<materialx version="1.39">' + "<a>" * depth + "</a>" * depth + "</materialx>")
    root = xmlreader.read_file(str(p))
    n, el = 1, root
    while el.children:
        el, n = el.children[0], n + 1
    assert n == xmlreader.MAX_DEPTH
