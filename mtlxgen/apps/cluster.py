"""batch, golden check and golden update on a Dask distributed cluster (`--scheduler ADDRESS`).

ADDRESS is tcp://HOST:PORT (or tls://...), a running `dask scheduler` with `dask worker`s, or local:N, a
LocalCluster of N worker processes started here for the run (one thread each: one GL context per process).
Each task is batch.run_job on consecutive jobs (chunks of one document's elements, batch.CHUNK at most), grouped
so that a task holds up to CHUNK elements while every worker thread still gets several tasks (groups_of): the very
function the process pool runs, with the run's `post` step (golden check compares on the worker, and only a failure's images
come back), so the results are those of a local run, byte for byte.

Inputs are read from the same paths on every worker: documents, the textures and includes they name, the
environment image, --library folders and the goldens are never shipped with the tasks (a document's textures
and includes are only known once it is read). Workers therefore see the client's files where the client sees
them: a shared or identical checkout, and the client's working directory, which each task runs in, so that
relative paths and the lines that name them read as in a local run. Before any task is sent, every worker is
asked whether it reads each document, the environment and each library folder, with the
same size (and for a sample, the same bytes) as here, and runs the same mtlxgen (a digest of its package
files); a worker that does not is one line naming the file (or the worker) and nothing is run.

Faults. A worker that dies mid-run: its tasks run elsewhere (the scheduler reschedules them) and each element
is reported once. A task that kills its worker as often as the scheduler allows
(`distributed.scheduler.allowed-failures`: 1 on the LocalCluster of local:N, so twice; set it on your own
scheduler, e.g. DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES=1, with DASK_DISTRIBUTED__SCHEDULER__WORKER_SATURATION=1.0
so that a worker holds no queued task that its death would count against) ends as KilledWorker: a chunk of several
elements is then split (a group job by job, a job element by element) and each sent alone, and an element that kills its workers again is that
element's failure, one line naming the document and element. A scheduler that goes away (or cannot be reached):
MtlxError, one line naming it; the caller has written nothing yet (the client alone writes goldens, images and
results, and only once every task is in).
"""
from mtlxgen.base import records
import functools
import hashlib
import logging
import os
import time
from contextlib import contextmanager

from mtlxgen.base.diagnostics import Loc, MtlxError

LOCAL = "local:"
SCHEMES = ("tcp://", "tls://")
MAX_LOCAL_WORKERS = 256
CONNECT_TIMEOUT = 10          # seconds to reach a scheduler
PROBE_SAMPLE = 256            # documents whose bytes every worker compares with ours (the others: their size)
RUNNING_EVERY = 0.5           # seconds between asks of the scheduler for the tasks running


def check_address(text):
    """The --scheduler value as given, or ValueError saying what is wrong with it (argparse shows one line)."""
    if text.startswith(LOCAL):
        n = text[len(LOCAL):]
        if not n.isdigit() or not 1 <= int(n) <= MAX_LOCAL_WORKERS:
            raise ValueError("%r: local:N needs N, worker processes, a whole number from 1 to %d"
                             % (text, MAX_LOCAL_WORKERS))
        return text
    if text.startswith(SCHEMES):
        host, _, port = text.split("://", 1)[1].rpartition(":")
        if host and port.isdigit() and 0 < int(port) < 65536:
            return text
    raise ValueError("%r is not a scheduler address: tcp://HOST:PORT (a running dask scheduler) or local:N "
                     "(N worker processes here)" % text)


class Lost(MtlxError):
    """The scheduler went away (or cannot be reached): one line naming it."""


def _lost(address, why):
    return Lost((Loc(address, 0), "%s; nothing was written (run again when the scheduler is back, or without "
                                  "--scheduler)" % why))


def _quiet():
    for name in ("distributed", "distributed.scheduler", "distributed.worker", "distributed.nanny",
                 "distributed.client", "distributed.core", "distributed.comm", "distributed.batched",
                 "distributed.http.proxy", "bokeh", "tornado"):
        logging.getLogger(name).setLevel(logging.CRITICAL)


@contextmanager
def connect(address):
    """A distributed.Client of the scheduler at `address` (local:N: a LocalCluster started for the run and
    closed after it). MtlxError, one line, when it cannot be reached."""
    import dask
    import distributed
    _quiet()
    cluster = None
    # worker-saturation 1.0: a worker holds only the task it runs (the scheduler queues the rest), so a task that kills
    # its worker takes no queued bystander's allowed failure with it
    settings = {"distributed.scheduler.allowed-failures": 1, "distributed.scheduler.worker-saturation": 1.0, "distributed.comm.timeouts.connect": "%ds" %
                CONNECT_TIMEOUT, "distributed.worker.daemon": False, "distributed.admin.tick.limit": "1h",
                "distributed.worker.multiprocessing-method": "spawn",      # never a process holding a GL context
                "distributed.client.heartbeat": "1s"}
    with dask.config.set(settings):
        try:
            if address.startswith(LOCAL):
                cluster = distributed.LocalCluster(n_workers=int(address[len(LOCAL):]), threads_per_worker=1,
                                                   processes=True, dashboard_address=None,
                                                   silence_logs=logging.CRITICAL)
                client = distributed.Client(cluster, set_as_default=False)
            else:
                client = distributed.Client(address, timeout=CONNECT_TIMEOUT, set_as_default=False)
        except (OSError, TimeoutError) as e:
            if cluster is not None:
                cluster.close()
            raise _lost(address, "cannot reach the Dask scheduler (%s)" % _why(e)) from None
        try:
            yield client
        finally:
            try:
                client.close(timeout=5)
            except Exception:       # (the scheduler is gone: nothing left to close)
                pass
            if cluster is not None:
                cluster.close(timeout=10)


def _why(e):
    return " ".join(("%s" % e).split()) or type(e).__name__


# ---------------------------------------------------------------- what every worker must see as we do

@functools.lru_cache(maxsize=None)
def package_digest():
    """sha256 of this mtlxgen's own files (its modules and GLSL library): workers must run the same."""
    from mtlxgen.base.files import PACKAGE as root
    from mtlxgen.read.library import glsl_lib_root
    h = hashlib.sha256()
    for top in (root, glsl_lib_root()):
        for base, dirs, names in os.walk(top):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__")
            for name in sorted(names):
                if name.endswith((".py", ".glsl", ".mtlx")):        # what draws (not the web pages' assets)
                    path = os.path.join(base, name)
                    h.update(os.path.relpath(path, top).encode("utf-8", "surrogatepass") + b"\0")
                    with open(path, "rb") as f:
                        h.update(f.read())
    return h.hexdigest()


def _digest(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def manifest(files, folders=()):
    """What a worker must see: [(path, size, sha256 or None)] of the files (a sample of PROBE_SAMPLE with their
    digest), the folders, and this mtlxgen's digest. Paths relative to the working directory stay so."""
    files = sorted({f for f in files if os.path.isfile(f)})
    step = max(1, -(-len(files) // PROBE_SAMPLE))
    listed = [(f, os.path.getsize(f), _digest(f) if i % step == 0 else None) for i, f in enumerate(files)]
    return {"cwd": os.getcwd(), "files": listed, "folders": sorted({d for d in folders if os.path.isdir(d)}),
            "package": package_digest()}


def probe(want):
    """Run on a worker: the first reason it does not see `want` (manifest()) as the client does, or None."""
    cwd = want["cwd"]
    if not os.path.isdir(cwd):
        return cwd, "the working directory is not on this worker (cluster workers read inputs at the client's paths)"
    if package_digest() != want["package"]:
        return "mtlxgen", "this worker runs another mtlxgen (its package files differ from the client's); install " \
                          "the same version on every worker"
    for d in want["folders"]:
        if not os.path.isdir(os.path.join(cwd, d)):
            return d, "not a folder this worker sees (cluster workers read inputs at the client's paths)"
    for path, size, digest in want["files"]:
        full = os.path.join(cwd, path)
        try:
            if os.path.getsize(full) != size or (digest is not None and _digest(full) != digest):
                return path, "this worker reads other bytes here than the client (a checkout of another commit?)"
            with open(full, "rb"):
                pass
        except OSError as e:
            return path, "this worker cannot read it (%s; cluster workers read inputs at the client's paths)" % (
                e.strerror or e)
    return None


def _check_workers(client, address, want):
    try:
        seen = client.run(probe, want)
    except (OSError, TimeoutError) as e:
        raise _lost(address, "lost the Dask scheduler (%s)" % _why(e)) from None
    if not seen:
        raise _lost(address, "the Dask scheduler has no workers")
    for worker, problem in sorted(seen.items()):
        if problem is not None:
            raise MtlxError((Loc(problem[0], 0), "worker %s: %s" % (worker, problem[1])))


# ---------------------------------------------------------------- running the tasks

def in_cwd(run, cwd, jobs, options, post, post_args):
    """[run(job, ...) for each of `jobs`] (batch.run_job) in the client's working directory (a task: relative
    paths read, and are named, as there); post_args: one per job."""
    if os.getcwd() != cwd:
        os.chdir(cwd)
    return [run(job, options, post, args) for job, args in zip(jobs, post_args)]


TASKS_PER_THREAD = 4        # tasks a worker thread gets at least (balance), before they grow up to batch.CHUNK


def groups_of(tasks, threads, chunk):
    """Consecutive task indices grouped into cluster tasks of about E / (threads * TASKS_PER_THREAD) elements, at
    most `chunk` (E: the elements of all tasks). A cluster task costs the scheduler and the comms a few ms: one per
    cheap element was twice the process pool's time; grouped, the balance stays and the cost is spread."""
    sizes = [len(t.elements) or 1 for t in tasks]
    want = max(1, min(chunk, sum(sizes) // max(1, threads * TASKS_PER_THREAD)))
    out, group, n = [], [], 0
    for i, size in enumerate(sizes):
        if group and n + size > want:
            out.append(tuple(group))
            group, n = [], 0
        group.append(i)
        n += size
    if group:
        out.append(tuple(group))
    return out


def run_tasks(address, tasks, done, bar, run, failed, options=None, post=None, args_of=None, chunk=32):
    """Run batch jobs `tasks` on the cluster at `address`; done(i, [Item]) for each as it comes in (in any
    order; every task once). bar: the batch.Progress (its `running` is kept up to date). run: the per-job
    function (batch.run_job, sent by reference); failed(job, element, error): the Items of a job (or of its one
    element) that could not run, error an exception or a sentence. (Both handed in by batch, which imports this
    module: nothing here imports batch.) chunk: the most elements of one cluster task (groups_of).

    A cluster task that kills its worker (Dask's KilledWorker: it was retried as the scheduler allows) is run again
    split: a group job by job, a job element by element; the element that kills its worker alone is that element's
    failure."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker
    files = [t.path for t in tasks] + [t.settings.environment for t in tasks]
    library_dirs = options.library_dirs if options is not None else ()
    want = manifest(files, list(library_dirs) + [os.path.dirname(os.path.abspath(t.path)) for t in tasks[:1]])
    cwd = want["cwd"]
    args_of = args_of or (lambda task: None)
    with connect(address) as client:
        _check_workers(client, address, want)

        def submit(jobs):
            key = "mtlxgen-%s-%s" % (os.path.basename(jobs[0].path)[:40], hashlib.sha1(repr(jobs).encode(
                "utf-8", "surrogatepass")).hexdigest()[:12])
            return client.submit(in_cwd, run, cwd, tuple(jobs), options, post,
                                 tuple(args_of(job) for job in jobs), key=key, pure=False, retries=0)

        futures = {}                # future -> (task indices, element): element None, or the one of a split job
        threads = sum(client.nthreads().values()) or 1
        for group in groups_of(tasks, threads, chunk):
            futures[submit([tasks[i] for i in group])] = (group, None)
        parts = {}                  # task index -> {element: [Item]} of a split chunk, until all its parts are in
        # with_results: the results are gathered as they finish, in the background (a result() per task is a round
        # trip of its own); raise_errors=False: a failed task's exception
        ac = as_completed(list(futures), loop=client.loop, with_results=True, raise_errors=False)
        last = 0.0

        def resubmit(jobs, where):
            fut = submit(jobs)
            futures[fut] = where
            ac.add(fut)

        try:
            for fut, result in ac:
                group, element = futures.pop(fut)
                if fut.status == "finished":
                    outcome = list(zip(group, result))
                elif fut.status == "cancelled" or client.status not in ("running", "connecting"):
                    raise _lost(address, "lost the Dask scheduler")
                else:
                    e = result if isinstance(result, BaseException) else fut.exception()
                    task = tasks[group[0]]
                    if isinstance(e, KilledWorker) and len(group) > 1:
                        for i in group:                 # each job alone, then each element alone
                            resubmit([tasks[i]], ((i,), None))
                        fut.release()
                        continue
                    if isinstance(e, KilledWorker) and element is None and len(task.elements) > 1:
                        parts[group[0]] = {}
                        for el in task.elements:        # each alone: the one that kills its workers is found
                            resubmit([records.replace(task, elements=(el,))], (group, el))
                        fut.release()
                        continue
                    if isinstance(e, KilledWorker):
                        why = ("drawing it killed the worker process, and again where it was run once more (Dask "
                               "KilledWorker); not drawn")
                        outcome = [(i, failed(tasks[i], element, why)) for i in group]
                    else:
                        outcome = [(i, failed(tasks[i], element, e)) for i in group]
                fut.release()
                now = time.perf_counter()
                if now - last > RUNNING_EVERY:
                    last = now
                    try:
                        threads = client.nthreads()         # (queued on a worker is not running)
                        bar.running = sum(min(len(keys), threads.get(w, 1))
                                          for w, keys in client.processing().items())
                    except Exception:
                        bar.running = len(futures)
                for i, items in outcome:
                    if element is not None:
                        parts[i][element] = items
                        if len(parts[i]) < len(tasks[i].elements):
                            continue
                        items = [it for el in tasks[i].elements for it in parts.pop(i)[el]]
                    done(i, items)
        except (OSError, TimeoutError) as e:
            raise _lost(address, "lost the Dask scheduler (%s)" % _why(e)) from None
        except Exception as e:
            if type(e).__name__ in ("CancelledError", "FuturesCancelledError", "CommClosedError"):
                raise _lost(address, "lost the Dask scheduler (%s)" % _why(e)) from None
            raise
        bar.running = 0
