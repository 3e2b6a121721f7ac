"""Elements per second of batch rendering: the process pool against a Dask LocalCluster of 1 and 2 workers
(--scheduler), the scaling from 1 to 2 workers, and the memory of each worker over many elements.

    python benchmarks/bench_cluster.py [--elements N] [--rounds R] [--size PX] [--kinds checker,...]

A library of N materials is written with tools/make_library.py (seed 1). Each configuration renders it (as
`mtlxgen batch` does: post step srgb8_drawn) once to warm up (library load, GL context: paid once per process)
and --repeat times timed, the best taken. The cluster runs on a LocalCluster started once per worker count (its start is reported
apart: a long-lived cluster pays it once). Memory: R rounds of the N elements on the same 2 workers, each
worker's resident set after each round (psutil); growth is the last round's over the first's.
Prints the load average before and after: on a shared machine the ratios are what to compare.
"""
import argparse
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tools"))


def jobs_of(paths, size):
    from mtlxgen.apps import batch
    return [batch.Job(p, (), batch.RenderSettings(size=size)) for p in paths]


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return time.perf_counter() - t, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--elements", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=5, help="rounds of the library for the memory measure")
    ap.add_argument("--size", type=int, default=32)
    ap.add_argument("--kinds", default="checker")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs of each configuration; the best is taken "
                    "(a shared machine's load only ever adds time)")
    args = ap.parse_args(argv)
    import distributed
    import psutil

    from make_library import make_library
    from mtlxgen.apps import batch, cluster

    print("load average before: %.2f %.2f %.2f; %d cores" % (os.getloadavg() + (os.cpu_count(),)))
    tmp = tempfile.mkdtemp(prefix="bench_cluster_")
    paths = make_library(args.elements, os.path.join(tmp, "lib"), seed=1, kinds=tuple(args.kinds.split(",")))
    jobs = jobs_of(paths, args.size)
    n = len(paths)

    def run(**kw):
        items = batch.render_jobs(jobs, progress=False, post=batch.srgb8_drawn, **kw)
        assert all(it.ok for it in items), [it.error for it in items if not it.ok][:3]
        return items

    rate = {}
    for workers in (1, 2):
        run(workers=workers)                                  # (spawned afresh each call: its start is in the time)
        s = min(timed(lambda: run(workers=workers))[0] for _ in range(args.repeat))
        rate["pool %d" % workers] = n / s
        print("%s: %6.1f s  %6.2f elements/s%s" % ("this process (workers=1)" if workers == 1 else
                                                   "process pool, 2 workers", s, n / s,
                                                   "" if workers == 1 else " (processes started in the time)"))
    cluster._quiet()
    rss = {}
    for workers in (1, 2):
        start, lc = timed(lambda: distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                                           dashboard_address=None, silence_logs=50))
        try:
            address = lc.scheduler_address
            run(scheduler=address)                            # warm: each worker's library and GL context
            s = min(timed(lambda: run(scheduler=address))[0] for _ in range(args.repeat))
            rate["cluster %d" % workers] = n / s
            print("LocalCluster, %d worker%s: %6.1f s  %6.2f elements/s (cluster start %.1f s, apart)"
                  % (workers, "" if workers == 1 else "s", s, n / s, start))
            if workers == 2:
                with distributed.Client(address) as c:
                    for r in range(args.rounds):
                        run(scheduler=address)
                        for w, v in c.run(lambda: psutil.Process().memory_info().rss).items():
                            rss.setdefault(w, []).append(v / 2 ** 20)
        finally:
            lc.close()
    print("cluster (2) / pool (2) wall time: %.2fx   scaling 1 -> 2 workers: cluster %.2fx, pool (against this "
          "process) %.2fx" % (rate["pool 2"] / rate["cluster 2"], rate["cluster 2"] / rate["cluster 1"],
                             rate["pool 2"] / rate["pool 1"]))
    for w, series in sorted(rss.items()):
        print("worker %s resident MiB after each round of %d: %s  (growth %+.1f%% from round 1)"
              % (w, n, " ".join("%.0f" % v for v in series), 100 * (series[-1] / series[0] - 1)))
    print("per element: pool(2) %.1f ms, cluster(2) %.1f ms of wall time"
          % (1000 / rate["pool 2"], 1000 / rate["cluster 2"]))
    print("load average after: %.2f %.2f %.2f" % os.getloadavg())
    return 0


if __name__ == "__main__":
    sys.exit(main())
