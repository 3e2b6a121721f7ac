"""golden check, golden update and batch on a Dask cluster (mtlxgen/apps/cluster.py): a real `dask scheduler` and
`dask worker` processes on loopback ports (and a LocalCluster for local:N); the same results and bytes as the
process pool and this process; a worker killed mid-run; a render that kills its worker twice; the scheduler
stopped mid-run; inputs a worker cannot read. Materials: tools/make_library.py's unlit checkers at 16 pixels
(a tenth of a second each on llvmpipe)."""
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time

import pytest

pytest.importorskip("distributed")

from conftest import ROOT

from mtlxgen.apps import batch, cluster, golden
from mtlxgen.base import images
from mtlxgen.base.diagnostics import MtlxError

sys.path.insert(0, os.path.join(ROOT, "tools"))
from make_library import make_library  # noqa: E402

SIZE = 16
BIN = os.path.dirname(sys.executable)


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    """A scratch project: 12 checker materials and their goldens (made here, in this process)."""
    root = tmp_path_factory.mktemp("cluster_project")
    make_library(12, str(root / "lib"), seed=7, kinds=("checker",))
    gdir = str(root / "golden_images")
    done = golden.update([str(root / "lib")], gdir, settings=batch.RenderSettings(size=SIZE), workers=1,
                         progress=False)
    assert [s for _, s, _ in done] == ["created"] * 12, done
    return root


class Dask:
    """`dask scheduler` and `dask worker`s (no nanny: a killed worker stays dead) on 127.0.0.1."""

    def __init__(self, tmp, workers=2):
        self.env = dict(os.environ, DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES="1")
        sfile = str(tmp / "scheduler.json")
        self.scheduler = subprocess.Popen([os.path.join(BIN, "dask"), "scheduler", "--host", "127.0.0.1", "--port",
                                           "0", "--no-dashboard", "--scheduler-file", sfile], env=self.env,
                                          stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        for _ in range(300):
            if os.path.exists(sfile) and os.path.getsize(sfile):
                break
            time.sleep(0.1)
        time.sleep(0.2)
        self.address = json.load(open(sfile))["address"]
        self.workers = [subprocess.Popen([os.path.join(BIN, "dask"), "worker", self.address, "--nthreads", "1",
                                          "--no-nanny", "--no-dashboard", "--host", "127.0.0.1"], env=self.env,
                                         stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                        for _ in range(workers)]
        import distributed
        with distributed.Client(self.address, timeout=30) as c:
            c.wait_for_workers(workers, timeout=60)

    def close(self):
        for p in self.workers + [self.scheduler]:
            if p.poll() is None:
                p.kill()
            p.wait()


@pytest.fixture
def dask_cluster(tmp_path):
    d = Dask(tmp_path)
    yield d
    d.close()


def _statuses(run):
    return {r["name"]: (r["status"], r["metrics"].get("failing_pixels"), r["message"]) for r in run.results}


def _files(out):
    return {name: open(os.path.join(out, name), "rb").read() for name in sorted(os.listdir(out))
            if name.endswith((".png", ".exr"))}


def _spoil(gdir, name):
    """One golden with a block of pixels recoloured: its check fails and writes new, golden and diff images."""
    png = os.path.join(gdir, name + ".png")
    img = golden.read_png8(png)
    img[6:10, 6:10, :3] = 255 - img[6:10, 6:10, :3]
    images.write_image(png, img)


def test_cluster_pool_and_this_process_give_the_same_results_and_bytes(project, dask_cluster, tmp_path):
    gdir = str(project / "goldens_spoiled")      # (sources are relative to the golden folder's parent)
    shutil.rmtree(gdir, ignore_errors=True)
    shutil.copytree(str(project / "golden_images"), gdir)
    spoiled = sorted(n[:-4] for n in os.listdir(gdir) if n.endswith(".png"))[3]
    _spoil(gdir, spoiled)
    runs = {}
    for how, kw in (("here", {"workers": 1}), ("pool", {"workers": 2}), ("cluster", {"scheduler": dask_cluster.address})):
        out = str(tmp_path / how)
        runs[how] = (golden.check(None, gdir, out, progress=False, **kw), out)
    here, pool, dask = (runs[k][0] for k in ("here", "pool", "cluster"))
    assert len(here.results) == 12 and [r["status"] for r in here.results].count("fail") == 1
    assert _statuses(here) == _statuses(pool) == _statuses(dask)
    files = {how: _files(out) for how, (_, out) in runs.items()}
    assert set(files["here"]) >= {spoiled + ".new.png", spoiled + ".diff.png", spoiled + ".golden.png"}
    assert files["here"] == files["pool"] == files["cluster"]
    # update on the cluster: the spoiled golden rewritten with this process's bytes, the others left as they are
    done = golden.update(None, gdir, workers=None, progress=False, scheduler=dask_cluster.address)
    assert sorted(s for _, s, _ in done) == ["unchanged"] * 11 + ["updated"], done
    assert open(os.path.join(gdir, spoiled + ".png"), "rb").read() == open(
        str(project / "golden_images" / (spoiled + ".png")), "rb").read()
    # batch: the written images, byte for byte
    outs = {}
    for how, extra in (("here", ["-j", "1"]), ("cluster", ["--scheduler", dask_cluster.address])):
        outs[how] = str(tmp_path / ("batch_" + how))
        p = subprocess.run([os.path.join(BIN, "mtlxgen"), "batch", str(project / "lib"), "-o", outs[how], "--size",
                            str(SIZE), "--no-progress"] + extra, capture_output=True, text=True, timeout=120)
        assert p.returncode == 0, p.stderr
    assert len(_files(outs["here"])) == 12 and _files(outs["here"]) == _files(outs["cluster"])


def _run_until_progress(cmd, cwd, then):
    """Start `cmd`; at its first progress line with some done and more to do, call then(); its
    (returncode, stdout, stderr, whether then() ran while it was running)."""
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    err, fired = [], []

    def read():
        for line in p.stderr:
            err.append(line)
            if not fired and line.startswith("render: ") and not line.startswith("render: 0/") and "(100%)" not in line:
                fired.append(p.poll() is None)
                then()
    t = threading.Thread(target=read)
    t.start()
    out = p.stdout.read()
    p.wait(timeout=120)
    t.join()
    return p.returncode, out, "".join(err), fired == [True]


def test_a_worker_killed_mid_run_then_the_scheduler_stopped(project, dask_cluster, tmp_path):
    """A worker killed mid-run: its tasks run on the other, each element reported once, all pass. Then, the
    scheduler stopped mid-run: one line naming it, exit 1, no results written."""
    out = str(tmp_path / "out")
    check = [os.path.join(BIN, "mtlxgen"), "golden", "check", "--goldens", str(project / "golden_images"), "-o", out,
             "--scheduler", dask_cluster.address]
    victim = dask_cluster.workers[0]
    rc, stdout, stderr, mid = _run_until_progress(check, str(project), lambda: victim.send_signal(signal.SIGKILL))
    assert mid, "the worker was not killed while the check ran:\n" + stderr
    assert victim.wait(timeout=10) == -signal.SIGKILL
    assert rc == 0, stdout + stderr
    results = json.load(open(os.path.join(out, "results.json")))["results"]
    names = [r["name"] for r in results]
    assert len(names) == len(set(names)) == 12 and {r["status"] for r in results} == {"pass"}
    assert "golden check: 12 passed" in stdout

    out = str(tmp_path / "out2")
    check[check.index("-o") + 1] = out
    alive = [w for w in dask_cluster.workers if w.poll() is None]

    def stop_scheduler():
        # the workers paused first: the renders left cannot finish in the moment the scheduler takes to die (12
        # small renders take ~0.2 s; a result already on its way would make the run complete)
        for w in alive:
            w.send_signal(signal.SIGSTOP)
        dask_cluster.scheduler.send_signal(signal.SIGKILL)
    try:
        rc, stdout, stderr, mid = _run_until_progress(check, str(project), stop_scheduler)
    finally:
        for w in alive:
            w.send_signal(signal.SIGCONT)
    assert mid, "the scheduler was not stopped while the check ran:\n" + stderr
    assert rc == 1, stdout + stderr
    last = [line for line in stderr.splitlines() if not line.startswith("render: ")]
    assert len(last) == 1 and last[0].startswith(dask_cluster.address + ":0: lost the Dask scheduler"), stderr
    assert "nothing was written" in last[0] and "Traceback" not in stderr
    assert not os.path.exists(out) or not os.listdir(out)


def crash_on_third(item, _):
    """A post step that kills the process drawing M_00002 (as a GL driver's crash would)."""
    if item.element == "M_00002":
        os._exit(17)


@pytest.mark.parametrize("per_thread", [cluster.TASKS_PER_THREAD, 1], ids=["one-job-tasks", "grouped-tasks"])
def test_a_render_that_kills_its_worker_twice_is_that_elements_failure(project, per_thread, monkeypatch):
    """Found alone however it was sent: grouped with other documents' jobs (1 task a thread: two jobs a task), the
    group is split job by job first."""
    monkeypatch.setattr(cluster, "TASKS_PER_THREAD", per_thread)
    docs = sorted(os.path.join(root, f) for root, _, fs in os.walk(str(project / "lib")) for f in fs
                  if f.endswith(".mtlx"))[:4]
    jobs = [batch.Job(p, (), batch.RenderSettings(size=SIZE)) for p in docs]
    items = batch.render_jobs(jobs, progress=False, post=crash_on_third, scheduler="local:2")
    assert [it.element for it in items] == ["M_00000", "M_00001", "M_00002", "M_00003"]
    bad = items[2]
    assert not bad.ok and len(bad.error) == 1, bad.error
    assert bad.error[0].startswith(docs[2] + ":0: M_00002: ") and "KilledWorker" in bad.error[0]
    assert all(it.ok and not it.error for it in items[:2] + items[3:])


def test_tasks_group_consecutive_jobs_up_to_the_chunk_and_every_thread_gets_several():
    jobs = [batch.Job("d%d.mtlx" % i, ("a",) * n) for i, n in enumerate([1] * 100 + [16, 3])]
    groups = cluster.groups_of(jobs, threads=2, chunk=16)
    assert [i for g in groups for i in g] == list(range(102))          # every job once, in order
    assert all(sum(len(jobs[i].elements) for i in g) <= 16 or len(g) == 1 for g in groups)
    assert max(len(g) for g in groups) == 14                             # 119 elements // (2 threads * 4)
    assert len(cluster.groups_of(jobs[:6], threads=2, chunk=16)) == 6     # few elements: one job a task
    assert cluster.groups_of([], threads=2, chunk=16) == []


def test_a_worker_that_cannot_read_an_input_refuses_the_run(tmp_path):
    doc = tmp_path / "a.mtlx"
    doc.write_text("<materialx version=\"1.39\"/>\n")
    want = cluster.manifest([str(doc)], [str(tmp_path)])
    assert cluster.probe(want) is None
    doc.write_text("<materialx version=\"1.39\"></materialx>\n")          # another commit on the worker
    path, why = cluster.probe(want)
    assert path == str(doc) and "other bytes" in why
    doc.unlink()
    path, why = cluster.probe(want)
    assert path == str(doc) and "cannot read" in why and "client's paths" in why
    lost = dict(want, package="0" * 64)
    assert "another mtlxgen" in cluster.probe(lost)[1]

    class Seen:                 # what client.run returns: a problem per worker
        def run(self, fn, arg):
            return {"tcp://10.0.0.2:4000": fn(arg)}
    with pytest.raises(MtlxError) as e:
        cluster._check_workers(Seen(), "tcp://10.0.0.1:8786", want)
    assert e.value.lines() == ["%s:0: worker tcp://10.0.0.2:4000: %s" % (doc, why)]


def test_an_unreachable_scheduler_is_one_line(tmp_path, monkeypatch):
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", 1)
    doc = os.path.join(ROOT, "examples", "unlit_checker.mtlx")
    with pytest.raises(MtlxError) as e:
        batch.render_jobs([batch.Job(doc)], progress=False, scheduler="tcp://127.0.0.1:9")
    (line,) = e.value.lines()
    assert line.startswith("tcp://127.0.0.1:9:0: cannot reach the Dask scheduler")


@pytest.mark.parametrize("args,problem", [
    (["batch", "x", "-o", "o", "--scheduler", "127.0.0.1:8786"], "is not a scheduler address"),
    (["batch", "x", "-o", "o", "--scheduler", "local:0"], "local:N needs N"),
    (["golden", "check", "--shard", "3/2"], "is not K/N"),
    (["golden", "check", "--shard", "0/2"], "is not K/N"),
])
def test_bad_scheduler_and_shard_values_are_one_line(args, problem, capsys):
    from mtlxgen.apps.cli import main
    assert main(args) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and problem in err[0]
