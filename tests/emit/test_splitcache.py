"""glsl_lib splits kept on disk between processes (emit/splitcache.py): what a later process reads back is what
splitting gives, for every glsl_lib file; a damaged file or an entry that does not fit its text is split again."""
import os

import pytest

from mtlxgen.emit import glsldeps, splitcache
from mtlxgen.emit.emitter import glsl_lib_root, read_lib_file


def _lib_files():
    root = glsl_lib_root()
    for folder, _, names in os.walk(root):
        for n in sorted(names):
            if n.endswith(".glsl"):
                rel = os.path.relpath(os.path.join(folder, n), root).replace(os.sep, "/")
                yield rel, read_lib_file(rel)[0]        # (as the emitter pastes it: macros on one line)


def _shape(lf):
    return (lf.header, [(it.kind, sorted(it.names), sorted(it.uses), it.code_start, it.code_end, it.line, it.start,
                         it.end) for it in lf.items])


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty cache folder and a process that has read nothing yet; read_back() starts the process again."""
    monkeypatch.setenv("MTLXGEN_CACHE", str(tmp_path))
    monkeypatch.setattr(splitcache, "_entries", None)
    monkeypatch.setattr(splitcache, "_added", {})
    monkeypatch.setattr(glsldeps, "_CACHE", {})

    def read_back():
        splitcache._entries = None
        splitcache._added.clear()
        glsldeps._CACHE.clear()
    return read_back


def test_every_glsl_lib_file_reads_back_as_it_splits(fresh_cache, tmp_path):
    files = list(_lib_files())
    assert len(files) > 30
    first = {rel: _shape(glsldeps.split_file(rel, text)) for rel, text in files}
    splitcache.save()
    written = [n for n in os.listdir(tmp_path) if n.startswith("glsl-split-")]
    assert len(written) == 1
    fresh_cache()
    for rel, text in files:
        assert splitcache.find(rel, text) is not None, rel
        assert _shape(glsldeps.split_file(rel, text)) == first[rel], rel
        assert _shape(glsldeps.split(text, rel)) == first[rel], rel


@pytest.mark.parametrize("damage", ["truncate", "garbage", "flip"])
def test_a_damaged_file_is_split_again_and_rewritten(fresh_cache, tmp_path, damage):
    rel, text = next(_lib_files())
    want = _shape(glsldeps.split(text, rel))
    glsldeps.split_file(rel, text)
    splitcache.save()
    path = os.path.join(tmp_path, [n for n in os.listdir(tmp_path) if n.startswith("glsl-split-")][0])
    data = open(path, "rb").read()
    data = {"truncate": data[:len(data) // 2], "garbage": b"\0" * 64,
            "flip": data[:-5] + bytes([data[-5] ^ 0xFF]) + data[-4:]}[damage]
    open(path, "wb").write(data)
    fresh_cache()
    assert splitcache.find(rel, text) is None
    assert _shape(glsldeps.split_file(rel, text)) == want
    splitcache.save()
    fresh_cache()
    assert splitcache.find(rel, text) is not None


def test_an_entry_that_does_not_fit_its_text_is_not_used(fresh_cache):
    rel, text = next(_lib_files())
    glsldeps.split_file(rel, text)
    k = splitcache.key(rel, text)
    header_end, items = splitcache._added[k]
    splitcache._added[k] = (header_end, items[:-1] + ((items[-1][0], items[-1][1], items[-1][2], 0, len(text) + 9,
                                                       1, 0, len(text) + 9),))
    assert splitcache.find(rel, text) is None
    splitcache._added[k] = ("x", items)
    assert splitcache.find(rel, text) is None


def test_threads_splitting_and_saving_at_once_keep_a_sound_file(fresh_cache, tmp_path):
    """The viewer generates on two threads: adds, finds and saves meet; the file read back holds every split."""
    import threading
    files = list(_lib_files())
    errors = []

    def work(part):
        try:
            for rel, text in part:
                splitcache.add(rel, text, glsldeps.split(text, rel))
                splitcache.find(rel, text)
                splitcache.save()
        except Exception as e:          # noqa: BLE001 (reported below)
            errors.append(repr(e))
    threads = [threading.Thread(target=work, args=(files[k::4],)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    fresh_cache()
    assert all(splitcache.find(rel, text) is not None for rel, text in files)
