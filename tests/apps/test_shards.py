"""golden check --shard K/N (a stable hash of each element's source and element) and golden report, which merges
the shards' results.json into one report (report.merge_shards)."""
import json
import os
import shutil
import sys

import pytest

from conftest import ROOT

from mtlxgen.apps import batch, golden, report
from mtlxgen.base import images
from mtlxgen.apps.cli import main

sys.path.insert(0, os.path.join(ROOT, "tools"))
from make_library import make_library  # noqa: E402


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    root = tmp_path_factory.mktemp("shard_project")
    make_library(10, str(root / "lib"), seed=3, kinds=("checker",))
    gdir = str(root / "golden_images")
    done = golden.update([str(root / "lib")], gdir, settings=batch.RenderSettings(size=12), workers=1, progress=False)
    assert [s for _, s, _ in done] == ["created"] * 10
    png = os.path.join(gdir, "checker_00004__M_00004.png")      # one golden that fails
    img = golden.read_png8(png)
    img[5, 5, :3] = 255 - img[5, 5, :3]
    images.write_image(png, img)
    return root


def test_shards_split_the_elements_disjointly_and_stay_put_as_documents_come_and_go(project):
    index = golden.Index(str(project / "golden_images"))
    tgts = golden.targets(index)
    shard = {t.name: golden.shard_of(index, t, 3) for t in tgts}
    assert sorted(shard) == sorted(t.name for t in tgts) and set(shard.values()) <= {0, 1, 2}
    assert len(set(shard.values())) > 1                         # (10 elements: not all in one shard)
    # the same element, another checkout's absolute path and another index: the same shard
    copy = project.parent / ("copy_" + project.name)
    shutil.copytree(str(project), str(copy), dirs_exist_ok=True)
    other = golden.Index(str(copy / "golden_images"))
    for t in golden.targets(other):
        assert golden.shard_of(other, t, 3) == shard[t.name]
    # a document more: every other element keeps its shard
    extra = copy / "lib" / "m000" / "added.mtlx"
    shutil.copyfile(str(copy / "lib" / "m000" / "checker_00000.mtlx"), str(extra))
    moved = [t.name for t in golden.targets(other, [str(copy / "lib")]) if t.name in shard
             and golden.shard_of(other, t, 3) != shard[t.name]]
    assert moved == []


def test_shard_checks_merge_into_the_whole_checks_report(project, tmp_path, capsys):
    gdir = str(project / "golden_images")
    whole = golden.check(None, gdir, str(tmp_path / "whole"), workers=1, progress=False)
    outs = []
    for k in (1, 2, 3):
        out = str(tmp_path / ("s%d" % k))
        assert main(["golden", "check", "--goldens", gdir, "-o", out, "--shard", "%d/3" % k, "-j", "1",
                     "--no-progress"]) in (0, 1)
        outs.append(out)
    parts = [json.load(open(os.path.join(o, "results.json"))) for o in outs]
    assert sum(len(p["results"]) for p in parts) == 10
    assert [p["shard"] for p in parts] == [{"index": k, "count": 3, "elements": 10} for k in (1, 2, 3)]
    capsys.readouterr()
    merged_dir = str(tmp_path / "merged")
    assert main(["golden", "report"] + outs + ["-o", merged_dir]) == 1             # one golden fails
    assert "not merged" not in capsys.readouterr().err
    merged = report.load_results(merged_dir)                                       # (the report's own schema)
    by_name = {r["name"]: r for r in merged["results"]}
    assert {n: r["status"] for n, r in by_name.items()} == {r["name"]: r["status"] for r in whole.results}
    failed = by_name["checker_00004__M_00004"]
    assert failed["status"] == "fail" and failed["files"]
    for key, name in failed["files"].items():                  # its images came along, the same bytes
        assert open(os.path.join(merged_dir, name), "rb").read() == open(os.path.join(whole.out_dir, name),
                                                                          "rb").read()
    html = open(os.path.join(merged_dir, "report.html")).read()
    assert html.count('<section class="material') == 10 and "data:image/png;base64," in html

    # a shard left out: the report says so and the status is 1, even where the others all passed
    passing = [o for o, p in zip(outs, parts) if all(r["status"] == "pass" for r in p["results"])]
    if passing:
        assert main(["golden", "report", passing[0], "-o", str(tmp_path / "partial")]) == 1
        assert "not merged" in capsys.readouterr().err
    # the same shard twice, or a shard of another count: one line naming the file
    assert main(["golden", "report", outs[0], outs[0], "-o", str(tmp_path / "twice")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(os.path.join(outs[0], "results.json") + ":0: results[0]: ")
    other = str(tmp_path / "other")
    assert main(["golden", "check", "--goldens", gdir, "-o", other, "--shard", "1/2", "-j", "1", "--no-progress"]) in (0, 1)
    capsys.readouterr()
    assert main(["golden", "report", outs[1], other, "-o", str(tmp_path / "mixed")]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and ("shards of one check of one commit merge" in err[0] or "is also in" in err[0]), err


def test_an_empty_shard_passes_with_no_results(project, tmp_path):
    gdir = str(project / "golden_images")
    index = golden.Index(gdir)
    counts = {}
    for t in golden.targets(index):
        counts[golden.shard_of(index, t, 40)] = 1
    empty = next(k for k in range(40) if k not in counts)
    run = golden.check(None, gdir, str(tmp_path / "e"), workers=1, progress=False, shard=(empty + 1, 40))
    assert run.results == [] and run.ok
    assert report.load_results(str(tmp_path / "e"))["shard"] == {"index": empty + 1, "count": 40, "elements": 10}
