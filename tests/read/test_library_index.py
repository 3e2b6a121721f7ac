"""The nodedef index and the compact library cache (issue 14).

Library.find_nodedef (indexed by category, version and type, memoized by input signature) returns what the
scan it replaced returned, for every nodedef signature of the standard libraries, for a document's own
nodedefs (an overlay: they come first) and for versioned and ambiguous ones. The cache (library_cache.py)
holds what parsing holds, is rebuilt when a library file changes, is another file for another set of
libraries (--library), and a corrupted, truncated or foreign file is rebuilt, never read. `mtlxgen --help`
imports neither the emitter nor the libraries."""
import os
import subprocess
import sys

import pytest

from mtlxgen.read import document, library, library_cache
from mtlxgen import pipeline
from mtlxgen.base.diagnostics import Loc
from util import write_doc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def scan(lib, category, version, node_type, inputs):
    """The lookup find_nodedef replaced (graph.GraphBuilder.nodedef_for before issue 14), as it was."""
    candidates = lib.by_category.get(category) or []
    for nd in candidates:
        if version:
            if nd.version != version:
                continue
        elif nd.version and not nd.isdefaultversion and any(
                o.version is None or o.isdefaultversion for o in candidates if o is not nd):
            continue
        matches_type = node_type in ("multioutput", "") if len(nd.outputs) > 1 else nd.type == node_type
        if not matches_type:
            continue
        if all(i.name in nd.inputs and nd.inputs[i.name].type == i.type for i in inputs.values()):
            return nd
    return None


def ports(pairs):
    return {n: document.Port(name=n, type=t, loc=Loc("x", 1)) for n, t in pairs}


def signatures(nd):
    """Input signatures a node of nd's category may have: none, each input alone, all of them, and one
    input of another type."""
    items = [(i.name, i.type) for i in nd.inputs.values()]
    out = [[], items] + [[it] for it in items]
    if items:
        name, t = items[0]
        out.append([(name, "float" if t != "float" else "color3")])
    out.append([("no_such_input", "float")])
    return out


def check_all(lib, versions=(None,)):
    count = 0
    for category, nds in lib.by_category.items():
        types = {nd.type for nd in nds} | {"multioutput", "", "float"}
        for nd in nds:
            for sig in signatures(nd):
                for t in types:
                    for v in set(versions) | {nd.version}:
                        inputs = ports(sig)
                        assert lib.find_nodedef(category, v, t, inputs) is scan(lib, category, v, t, inputs), \
                            (category, v, t, sig)
                        count += 1
    return count


def test_index_matches_the_scan_for_every_standard_nodedef_signature(library):
    assert check_all(library) > 10000


def test_index_matches_the_scan_for_a_documents_own_versioned_and_ambiguous_nodedefs(tmp_path, library):
    body = """
<nodedef name="ND_add_float_mine" node="add"><input name="in1" type="float" /><input name="in2" type="float" />
  <output name="out" type="float" /></nodedef>
<nodedef name="ND_thing_v1" node="thing" version="1.0"><input name="a" type="float" /><output name="out" type="float" /></nodedef>
<nodedef name="ND_thing_v2" node="thing" version="2.0" isdefaultversion="true"><input name="a" type="float" />
  <input name="b" type="float" /><output name="out" type="float" /></nodedef>
<nodedef name="ND_thing_v3" node="thing" version="3.0"><input name="a" type="float" /><output name="out" type="float" /></nodedef>
<nodedef name="ND_twin_a" node="twin"><input name="x" type="float" /><output name="out" type="float" /></nodedef>
<nodedef name="ND_twin_b" node="twin"><input name="x" type="float" /><output name="out" type="float" /></nodedef>
<nodedef name="ND_split" node="split"><input name="x" type="float" /><output name="o1" type="float" />
  <output name="o2" type="color3" /></nodedef>
<nodedef name="ND_plain_v1" node="plain" version="1.0"><input name="a" type="float" /><output name="out" type="float" /></nodedef>
<nodedef name="ND_plain_v2" node="plain" version="2.0"><input name="a" type="float" /><output name="out" type="float" /></nodedef>
<add name="n" type="float"><input name="in1" type="float" value="1" /></add>
<output name="o" type="float" nodename="n" />"""
    doc = document.load(write_doc(tmp_path, body))
    lib = library.overlay(doc)
    assert lib is not library
    assert lib.find_nodedef("add", None, "float", ports([("in1", "float")])).name == "ND_add_float_mine"
    assert library.find_nodedef("add", None, "float", ports([("in1", "float")])).name == "ND_add_float"
    assert lib.find_nodedef("thing", None, "float", ports([("a", "float")])).name == "ND_thing_v2"
    assert lib.find_nodedef("thing", "3.0", "float", ports([("a", "float")])).name == "ND_thing_v3"
    assert lib.find_nodedef("thing", "1.0", "float", ports([("a", "float"), ("b", "float")])) is None
    # two of one signature: the first in the category's order, as the scan took it (a document's own
    # definitions go first, each before the one above it)
    twin = lib.find_nodedef("twin", None, "float", ports([("x", "float")]))
    assert twin is scan(lib, "twin", None, "float", ports([("x", "float")])) and twin.name == "ND_twin_b"
    assert lib.find_nodedef("split", None, "multioutput", ports([])).name == "ND_split"
    plain = lib.find_nodedef("plain", None, "float", ports([]))       # versions, none the default: the first
    assert plain is scan(lib, "plain", None, "float", ports([])) and plain.name == "ND_plain_v2"
    assert check_all(lib, versions=(None, "1.0", "2.0", "3.0")) > 10000
    # and graph building takes the document's own add
    g = pipeline.build_graph(doc, library, "o")
    assert [n.nodedef.name for n in g.nodes] == ["ND_add_float_mine"]


def test_memo_is_dropped_when_the_library_changes(tmp_path, library):
    lib = library.overlay(document.load(write_doc(tmp_path, '<nodedef name="ND_x" node="x"><output name="out" '
                                                            'type="float" /></nodedef>')))
    assert lib.find_nodedef("add", None, "float", ports([("in1", "float")])).name == "ND_add_float"
    later = document.load(write_doc(tmp_path, '<nodedef name="ND_add_later" node="add"><input name="in1" '
                                              'type="float" /><output name="out" type="float" /></nodedef>',
                                    name="later.mtlx"))
    lib.add_document(later, overlay=True)
    assert lib.find_nodedef("add", None, "float", ports([("in1", "float")])).name == "ND_add_later"


# ---------------------------------------------------------------- the cache

def same_library(a, b):
    for table in ("nodedefs", "nodegraphs", "graph_impls", "implementations", "geompropdefs", "unitdefs", "structs"):
        x, y = getattr(a, table), getattr(b, table)
        assert list(x) == list(y), table
        for k in x:
            assert x[k] == y[k], (table, k)
            if hasattr(x[k], "__dict__"):
                assert vars(x[k]) == vars(y[k]), (table, k)
    assert list(a.by_category) == list(b.by_category)
    for cat in a.by_category:
        assert [n.name for n in a.by_category[cat]] == [n.name for n in b.by_category[cat]]
    assert a.files == b.files


@pytest.fixture
def cache(tmp_path, monkeypatch):
    folder = tmp_path / "cache"
    monkeypatch.setenv("MTLXGEN_CACHE", str(folder))
    monkeypatch.setattr(library, "_MEMO", {})
    return folder


def fresh(extra=()):
    library._MEMO.clear()
    return library.load_library(extra)


def cache_files(folder):
    return sorted(p for p in os.listdir(folder) if p.endswith(".mxlib")) if os.path.isdir(folder) else []


def test_cached_library_holds_what_parsing_holds(cache):
    parsed = fresh()
    assert len(cache_files(cache)) == 1
    cached = fresh()
    assert isinstance(cached.nodedefs, library_cache.LazyTable)
    same_library(parsed, cached)
    # an entry decoded once is one object wherever it is reached
    nd = cached.nodedefs["ND_standard_surface_surfaceshader"]
    assert nd in cached.by_category["standard_surface"]
    assert any(x is nd for x in cached.by_category["standard_surface"])
    g = cached.graph_impls["ND_standard_surface_surfaceshader"]
    assert g is cached.nodegraphs[g.name]


def test_overlay_copies_of_a_cached_library_are_independent(cache, tmp_path):
    fresh()
    base = fresh()
    doc = document.load(write_doc(tmp_path, '<nodedef name="ND_add_float" node="add"><input name="in1" type="float" />'
                                            '<output name="out" type="float" /></nodedef>'))
    over = base.overlay(doc)
    assert over.nodedefs["ND_add_float"] is doc.nodedefs["ND_add_float"]
    assert base.nodedefs["ND_add_float"] is not doc.nodedefs["ND_add_float"]
    assert [n.name for n in over.by_category["add"]].count("ND_add_float") == 1
    assert all(n is not doc.nodedefs["ND_add_float"] for n in base.by_category["add"])
    assert over.nodedefs["ND_multiply_float"] is base.nodedefs["ND_multiply_float"]


def extra_library(folder, body):
    os.makedirs(folder, exist_ok=True)
    return write_doc(folder, body, name="extra.mtlx")


def test_cache_is_rebuilt_when_a_library_file_changes(cache, tmp_path):
    extra = str(tmp_path / "extra")
    path = extra_library(extra, '<nodedef name="ND_mine" node="mine"><input name="a" type="float" value="1" />'
                                '<output name="out" type="float" /></nodedef>')
    assert fresh([extra]).nodedefs["ND_mine"].inputs["a"].value == 1.0
    assert fresh([extra]).nodedefs["ND_mine"].inputs["a"].value == 1.0        # from the cache
    with open(path) as f:
        text = f.read()
    with open(path, "w") as f:
        f.write(text.replace('value="1"', 'value="2.5"'))
    st = os.stat(path)
    os.utime(path, ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000))
    assert fresh([extra]).nodedefs["ND_mine"].inputs["a"].value == 2.5


def test_another_set_of_libraries_is_another_cache_file(cache, tmp_path):
    fresh()
    extra = str(tmp_path / "extra")
    extra_library(extra, '<nodedef name="ND_mine" node="mine"><output name="out" type="float" /></nodedef>')
    lib = fresh([extra])
    assert "ND_mine" in lib.nodedefs and "ND_mine" not in fresh().nodedefs
    assert len(cache_files(cache)) == 2


@pytest.mark.parametrize("damage", ["flip", "truncate", "garbage", "empty", "other_format"])
def test_a_damaged_cache_file_is_rebuilt_not_read(cache, damage):
    parsed = fresh()
    name, = cache_files(cache)
    path = os.path.join(cache, name)
    with open(path, "rb") as f:
        data = f.read()
    if damage == "flip":                # one bit of the body: the digest no longer matches
        i = len(data) // 2
        data = data[:i] + bytes([data[i] ^ 1]) + data[i + 1:]
    elif damage == "truncate":
        data = data[:len(data) // 3]
    elif damage == "garbage":
        data = b"\x80\x04\x95" + os.urandom(4000)        # a pickle's opening: never unpickled
    elif damage == "empty":
        data = b""
    else:                               # a sound file of another format: its digest matches, its body is refused
        import marshal
        body = marshal.dumps({"format": library_cache.FORMAT + 1})
        data = library_cache.MAGIC + library_cache.digest(body) + body
    with open(path, "wb") as f:
        f.write(data)
    rebuilt = fresh()
    assert not isinstance(rebuilt.nodedefs, library_cache.LazyTable)      # parsed again
    same_library(parsed, rebuilt)
    assert library_cache._read(path) is not None                          # and written anew
    same_library(parsed, fresh())


def test_a_cache_file_that_is_a_link_is_not_followed(cache, tmp_path):
    fresh()
    name, = cache_files(cache)
    path = os.path.join(cache, name)
    target = tmp_path / "elsewhere.mxlib"
    os.replace(path, target)
    os.symlink(target, path)
    assert library_cache._read(path) is None
    fresh()                                                     # rebuilt: the link replaced by a file
    assert not os.path.islink(path) and library_cache._read(path) is not None


def test_an_unwritable_cache_folder_still_loads(cache, monkeypatch, tmp_path):
    blocked = tmp_path / "file-not-folder"
    blocked.write_text("x")
    monkeypatch.setenv("MTLXGEN_CACHE", str(blocked / "cache"))
    lib = fresh()
    assert "ND_add_float" in lib.nodedefs


def test_old_cache_files_are_pruned(cache):
    os.makedirs(cache)
    for i in range(library_cache.KEEP + 5):
        p = os.path.join(cache, "library-old%02d.pickle" % i)
        with open(p, "wb") as f:
            f.write(b"x")
        os.utime(p, (1000 + i, 1000 + i))
    fresh()
    left = [n for n in os.listdir(cache) if n.startswith("library-")]
    assert len(left) == library_cache.KEEP and len(cache_files(cache)) == 1


def test_cache_folder_is_the_users_not_site_packages(monkeypatch, tmp_path):
    monkeypatch.delenv("MTLXGEN_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert library_cache.cache_dir() == str(tmp_path / "xdg" / "mtlxgen")
    monkeypatch.delenv("XDG_CACHE_HOME")
    assert library_cache.cache_dir() == os.path.join(os.path.expanduser("~"), ".cache", "mtlxgen")


# ---------------------------------------------------------------- lazy imports

def test_help_imports_neither_the_emitter_nor_the_libraries():
    code = ("import sys; sys.argv = ['mtlxgen', '--help']\nfrom mtlxgen.apps import cli\ntry:\n    cli.main()\n"
            "except SystemExit:\n    pass\nprint(sorted(m for m in sys.modules if m.startswith('mtlxgen')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT).stdout
    loaded = eval(out.strip().splitlines()[-1])
    assert not {"mtlxgen.emit.emitter", "mtlxgen.read.library", "mtlxgen.graph.build", "mtlxgen.read.usdstage"} & set(loaded), loaded


def test_constants_kept_beside_their_modules_agree():
    from mtlxgen import USD_EXTENSIONS, is_usd
    from mtlxgen.apps import cli
    from mtlxgen.emit import emitter as emit
    from mtlxgen.read import usdstage
    assert cli.ENVIRONMENT_METHODS == emit.ENVIRONMENT_METHODS
    assert USD_EXTENSIONS == usdstage.USD_EXTENSIONS
    for name in ("a.usd", "b.USDA", "c.usdc", "d.usdz", "e.mtlx", "f.usd.mtlx", "usd"):
        assert is_usd(name) == usdstage.is_usd(name)
