"""files.py's rules on their own: what a read refuses before any library opens a file (kinds, size caps, dangling
links, loops), which folders admit files into output (a shared folder like /tmp admits only the document owner's
files), and writes that never follow a symlink, never leave half a file, and give ordinary modes."""
import os
import stat

import pytest

from mtlxgen.base import files
from mtlxgen.read import xmlreader
from mtlxgen.base.diagnostics import Loc, MtlxError


def test_kinds_and_caps_named_before_reading(tmp_path):
    big = tmp_path / "big.png"
    with open(big, "wb") as f:
        f.truncate(files.MAX_BYTES["image"] + 1)           # sparse: costs no disk, would take minutes to read
    assert files.regular_file_problem(str(big), "image").startswith("larger than 512 MB")
    assert files.regular_file_problem(str(big)) is None      # no cap asked: a regular file
    os.symlink(str(tmp_path / "nowhere"), tmp_path / "dangling")
    assert files.regular_file_problem(str(tmp_path / "dangling")) == "a dangling symbolic link"
    os.symlink(str(tmp_path / "b"), tmp_path / "a")
    os.symlink(str(tmp_path / "a"), tmp_path / "b")
    assert files.regular_file_problem(str(tmp_path / "a")) == "a symbolic link loop"
    os.mkfifo(tmp_path / "fifo")
    assert files.regular_file_problem(str(tmp_path / "fifo")) == "a FIFO"
    assert files.regular_file_problem(str(tmp_path / "absent")) == "missing (no such file)"
    with pytest.raises(MtlxError) as e:
        files.check_regular(str(big), Loc(str(big), 3), "texture 'big.png'", max_bytes="image")
    assert e.value.lines()[0].startswith("%s:3: texture 'big.png' is larger than 512 MB" % big)


def _shared_folder(tmp_path):
    shared = tmp_path / "shared"
    shared.mkdir()
    os.chmod(shared, 0o1777)                 # as /tmp: anyone may put a file here
    return shared


def test_a_shared_folder_admits_only_the_owners_files(tmp_path):
    shared = _shared_folder(tmp_path)
    doc = shared / "doc.mtlx"
    doc.write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n'
                   '  <xi:include href="planted.mtlx" />\n</materialx>\n')
    planted = shared / "planted.mtlx"
    planted.write_text('<?xml version="1.0"?>\n<materialx version="1.39"/>\n')
    roots = files.allowed_roots(str(doc))
    assert files.is_inside(str(planted), roots)              # the document's owner's own file
    if os.geteuid() != 0:
        pytest.skip("planting a file of another user needs root (chown)")
    os.chown(planted, 65534, 65534)          # another user's file (nobody), planted beside the document
    assert not files.is_inside(str(planted), files.allowed_roots(str(doc)))
    with pytest.raises(MtlxError) as e:
        xmlreader.read_file(str(doc))
    assert len(e.value.lines()) == 1 and "%s:3:" % doc in e.value.lines()[0] and "outside" in e.value.lines()[0]


def test_a_private_folder_is_a_plain_root(tmp_path):
    doc = tmp_path / "doc.mtlx"
    doc.write_text("<materialx/>")
    roots = files.allowed_roots(str(doc))
    assert str(tmp_path) in roots and getattr(roots[0], "owner", None) is None


def test_write_atomic_replaces_a_symlink_never_its_target(tmp_path):
    target = tmp_path / "elsewhere.txt"
    target.write_text("keep me")
    link = tmp_path / "M.frag"
    os.symlink(str(target), link)
    files.write_atomic(str(link), "generated")
    assert target.read_text() == "keep me"
    assert not os.path.islink(link) and link.read_text() == "generated"


def test_write_atomic_modes(tmp_path):
    old = os.umask(0o022)
    try:
        new = tmp_path / "new.json"
        files.write_atomic(str(new), b"{}")
        assert stat.S_IMODE(os.stat(new).st_mode) == 0o644       # not mkstemp's 0600
        kept = tmp_path / "kept.mtlx"
        kept.write_text("old")
        os.chmod(kept, 0o640)
        files.write_atomic(str(kept), "new")
        assert stat.S_IMODE(os.stat(kept).st_mode) == 0o640 and kept.read_text() == "new"
    finally:
        os.umask(old)


def test_a_crash_mid_write_leaves_the_old_bytes(tmp_path, monkeypatch):
    path = tmp_path / "doc.mtlx"
    path.write_bytes(b"old bytes")

    def crash(src, dst):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(os, "replace", crash)
    with pytest.raises(OSError):
        files.write_atomic(str(path), b"new bytes that never land")
    assert path.read_bytes() == b"old bytes"
    assert os.listdir(tmp_path) == ["doc.mtlx"]              # no temporary file left behind


def test_write_through_temp_for_libraries_that_write_files(tmp_path):
    import numpy as np
    from mtlxgen.base.images import read_image, write_image
    target = tmp_path / "secret.png"
    target.write_bytes(b"not to be overwritten")
    os.symlink(str(target), tmp_path / "out.png")
    write_image(str(tmp_path / "out.png"), np.full((2, 2, 3), 0.25, np.float32))
    assert target.read_bytes() == b"not to be overwritten"
    assert read_image(str(tmp_path / "out.png")).shape == (2, 2, 3)
    assert sorted(os.listdir(tmp_path)) == ["out.png", "secret.png"]


def test_a_refused_write_names_the_output_not_the_temporary_file(tmp_path):
    (tmp_path / "M.frag").mkdir()                   # a folder where the file goes: the rename is refused
    with pytest.raises(OSError) as e:
        files.write_atomic(str(tmp_path / "M.frag"), "x")
    assert e.value.filename == str(tmp_path / "M.frag")
    with pytest.raises(OSError) as e:
        files.write_atomic(str(tmp_path / "missing" / "M.frag"), "x")
    assert e.value.filename == str(tmp_path / "missing" / "M.frag")
    assert sorted(os.listdir(tmp_path)) == ["M.frag"]


def test_a_scratch_write_without_fsync_still_replaces_a_symlink(tmp_path):
    target = tmp_path / "elsewhere.txt"
    target.write_text("keep me")
    os.symlink(str(target), tmp_path / "s.frag")
    files.write_atomic(str(tmp_path / "s.frag"), "scratch", durable=False)
    assert target.read_text() == "keep me" and (tmp_path / "s.frag").read_text() == "scratch"
    assert not os.path.islink(tmp_path / "s.frag")
