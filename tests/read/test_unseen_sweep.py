"""tools/unseen_sweep.py, the scoreboard's measure over any folder (issue 16), on tests/data/unseen: MaterialX
documents outside the scoreboard's corpus that were off parity before a fix of ours. Every element MaterialX
generates is generated, compiles and reaches parity with MaterialX's render (its colour management on); the table
counts what it says."""
import os
import sys

import pytest

from conftest import ROOT, TEST_SIZE

sys.path.insert(0, os.path.join(ROOT, "tools"))
UNSEEN = os.path.join(ROOT, "tests", "data", "unseen")


@pytest.fixture(scope="module")
def swept(tmp_path_factory):
    import unseen_sweep
    sweep = unseen_sweep.Sweep(size=TEST_SIZE, out=str(tmp_path_factory.mktemp("unseen")))
    results = []
    for path in unseen_sweep.documents([UNSEEN]):
        rows, note = sweep.document(path)
        results.append((path, rows, note))
    sweep.harness.close()
    return results


def test_every_document_is_swept(swept):
    names = sorted(os.path.basename(p) for p, _, _ in swept)
    assert names == sorted(f for f in os.listdir(UNSEEN) if f.endswith(".mtlx"))
    assert all(rows for _, rows, _ in swept)


def test_every_element_materialx_generates_is_at_parity(swept):
    rows = [r for _, rs, _ in swept for r in rs]
    counted = [r for r in rows if r["mx"]]
    assert len(counted) == len(rows) == 4
    off = ["%s %s: %s" % (os.path.basename(r["file"]), r["element"], r.get("error") or
                          "mean %s, %s > 8/255 (%s)" % (r.get("mean"), r.get("fraction"), r.get("image")))
           for r in counted if not (r["generated"] and r["compiled"] and r["parity"])]
    assert not off, off


def test_table_counts_generated_compiled_parity(swept):
    import unseen_sweep
    text, totals = unseen_sweep.table(swept, UNSEEN)
    assert totals == [4, 4, 4, 4, 4]
    assert "| surface_unlit_toon.mtlx | 1 | 1 | 1 | 1 | 1 |" in text


def test_an_element_whose_materialx_shader_does_not_compile_is_not_counted(tmp_path):
    """A float input connected to a colour (MaterialXPlayground's type-mismatch.mtlx): we refuse it, MaterialX
    generates GLSL that does not compile ('uniform float x = 0.5, 0.5, 0.5;'), so the element is not counted."""
    import unseen_sweep
    from util import write_doc
    path = write_doc(tmp_path, '<constant name="c" type="color3"><input name="value" type="color3" '
                               'value="0.5, 0.5, 0.5" /></constant><surface_unlit name="s" type="surfaceshader">'
                               '<input name="opacity" type="float" nodename="c" /></surface_unlit>'
                               '<surfacematerial name="m" type="material"><input name="surfaceshader" '
                               'type="surfaceshader" nodename="s" /></surfacematerial>')
    sweep = unseen_sweep.Sweep(size=TEST_SIZE, out=str(tmp_path))
    try:
        rows, _ = sweep.document(path)
    finally:
        sweep.harness.close()
    assert len(rows) == 1 and not rows[0]["mx"] and "does not compile" in rows[0]["mx_error"], rows


# ---------------------------------------------------------------- a fresh set (issue 26)

def test_copies_of_known_documents_are_left_out(tmp_path):
    """A public project's copy of a corpus document (re-indented) is not a document nobody has seen."""
    import unseen_sweep
    known = tmp_path / "known"
    known.mkdir()
    (known / "a.mtlx").write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n  <output name="o" '
                                  'type="float" value="1" />\n</materialx>\n')
    new = tmp_path / "new"
    new.mkdir()
    (new / "copy.mtlx").write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n\t\t<output name="o"  '
                                   'type="float" value="1" />\n</materialx>')
    (new / "other.mtlx").write_text('<?xml version="1.0"?>\n<materialx version="1.39">\n  <output name="o" '
                                    'type="float" value="2" />\n</materialx>\n')
    (new / "stage.usda").write_text("#usda 1.0\n")
    files = unseen_sweep.documents([str(new)], usd=True)
    assert [os.path.basename(f) for f in files] == ["copy.mtlx", "other.mtlx", "stage.usda"]
    assert [os.path.basename(f) for f in unseen_sweep.documents([str(new)])] == ["copy.mtlx", "other.mtlx"]
    keep, copies = unseen_sweep.fresh(files, unseen_sweep.known_texts([str(known)]))
    assert [os.path.basename(f) for f in keep] == ["other.mtlx", "stage.usda"]
    assert [os.path.basename(f) for f in copies] == ["copy.mtlx"]


def test_tables_by_source_and_of_stages():
    import unseen_sweep
    base = "/sweep"

    def row(mx, gen, comp, par, usd=False):
        return {"mx": mx, "generated": gen, "compiled": comp, "parity": par, "usd": usd}
    results = [("/sweep/projA/x/a.mtlx", [row(True, True, True, True), row(False, False, False, False)], ""),
               ("/sweep/projA/b.mtlx", [row(True, False, False, False)], ""),
               ("/sweep/projB/c.mtlx", [row(True, True, True, False)], ""),
               ("/sweep/projB/s.usda", [row(False, True, True, False, True), row(False, True, False, False, True)], "")]
    text, tot = unseen_sweep.source_table(results, base, 1)
    assert "| projA | 2 | 3 | 2 | 1 | 1 | 1 |" in text and "| projB | 1 | 1 | 1 | 1 | 1 | 0 |" in text
    assert tot == [3, 4, 3, 2, 2, 1]
    text, tot = unseen_sweep.usd_table(results, base)
    assert tot == [2, 2, 1] and "| projB/s.usda | 2 | 2 | 1 |" in text
    assert unseen_sweep.table(results, base)[1] == [4, 3, 2, 2, 1]      # stages are not in the documents' table


def test_a_stage_is_swept_for_generated_and_compiled(tmp_path):
    """Our stage with a shader output its definition declares (tests/data/unseen3): three materials, each
    generated and compiled."""
    import unseen_sweep
    sweep = unseen_sweep.Sweep(size=TEST_SIZE, out=str(tmp_path))
    try:
        rows, note = sweep.document(os.path.join(ROOT, "tests", "data", "unseen3", "preview_displacement_output.usda"))
    finally:
        sweep.harness.close()
    assert note == "" and len(rows) == 3
    assert all(r["usd"] and r["generated"] and r["compiled"] for r in rows), rows
