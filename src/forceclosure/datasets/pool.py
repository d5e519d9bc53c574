"""A dataset on a local pool of killable worker processes (pebble's ``ProcessPool``): each
worker forked from a clean server process, dying with its run, its kernels loaded before
its first object; time limits held inside compiled code; a worker's death costing only
its object, run again on a fresh worker."""

from __future__ import annotations

import multiprocessing
import os
import queue
import threading
from collections.abc import Callable, Iterable
from concurrent.futures import Future
from concurrent.futures import TimeoutError as FutureTimeout
from contextlib import suppress
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..objects.io import POLYGON_SUFFIXES
from .job import Job, LabelJob
from .one_object import failed_record, process_object
from .workers import Relay, Watchdog, die_with_run, number_worker, tell_compiling

__all__ = ["HARD_GRACE", "MAX_CRASHES", "STALL_SECONDS", "Pending", "local_pool",
           "object_dims", "pool_context", "warm_up", "worker_init"]

#: A worker may die this many times on one object before it is recorded as failed.
MAX_CRASHES = 3
#: Seconds past the time limit after which a worker that has not stopped is killed.
HARD_GRACE = 2.0
#: Seconds a worker may stay stopped (SIGSTOP) before the watchdog kills it.
STALL_SECONDS = 30.0


@dataclass
class Pending:
    """The driver's state: the objects still to do, and how often each killed its worker."""

    todo: dict[str, Path]
    crashes: dict[str, int] = field(default_factory=dict)


def pool_context() -> multiprocessing.context.BaseContext:
    """Workers forked from a clean server process: forking this one is unsafe once its
    compiled kernels have started OpenMP threads."""
    context = multiprocessing.get_context("forkserver")
    context.set_forkserver_preload(["forceclosure.datasets.pool", "forceclosure.synthesis"])
    return context


def worker_init(job: Job | LabelJob, dims: tuple[int, ...] = (2, 3), notices: Any = None,
                 counter: Any = None) -> None:
    """A pool worker: dies with the run; its kernels run on one thread (the pool already
    uses every core); and they are loaded before its first object, whose time limit would
    otherwise pay for it (seconds: a fresh worker, the one replacing a killed worker too,
    timed out its first object under a short limit). If that compiles them, it tells the
    run so on ``notices`` (a queue), naming itself by ``counter``'s next number."""
    import numba

    die_with_run()
    _process_local_numba_lock()
    numba.set_num_threads(1)
    if notices is not None:
        notices.cancel_join_thread()  # a line not yet sent never holds up the worker's end
        who = f"worker {number_worker(counter)}" if counter is not None else (
            f"worker {os.getpid()}")
        tell_compiling(notices.put, who)
    warm_up(job, dims)


def _process_local_numba_lock() -> None:
    """In a pool worker, before numba starts its threads: give numba's threading-layer
    start-up a lock of this process only.

    Numba takes a multiprocessing ``RLock`` for that start-up when the start
    method's name contains "fork" -- "forkserver" does -- a named semaphore
    registered with the run's ``resource_tracker`` and unregistered only by
    the worker's exit handlers. A worker the pool ends (a time limit, or its
    ``stop`` at the end of the run) runs none, and the tracker then printed
    "There appear to be 1 leaked semaphore objects to clean up at shutdown"
    on the run's standard error. The lock only guards a start-up inside this
    process (a worker starts no processes), so a thread lock does its work.
    """
    with suppress(Exception):  # numba's private module state; without it, the old way
        from numba.np.ufunc import parallel

        if getattr(parallel, "_backend_init_process_lock", False) is None:
            # numba's module types it None (its first value); it holds a lock once set
            parallel._backend_init_process_lock = threading.RLock()  # type: ignore[assignment]


def warm_up(job: Job | LabelJob, dims: tuple[int, ...]) -> None:
    """Run the job's compiled kernels once on small bundled objects of the dimensions
    ``dims`` (errors ignored)."""
    from dataclasses import replace

    with suppress(Exception):
        if job.mode == "gripper":
            job.warm_up()
            return
        if job.mode == "synthesize":
            small = replace(job, samples=min(job.samples, 200), top=1, timeout=None)
            for name in [("square", "cube")[d - 2] for d in dims]:
                process_object(name, small)
            return
        from ..analysis.batch import analyze_batch, epsilon_batch

        pinches = {2: (np.array([[[-1.0, 0.0], [1.0, 0.1]]]),
                       np.array([[[-1.0, 0.0], [1.0, 0.0]]])),
                   3: (np.array([[[-1.0, 0, 0], [1, 0.1, 0], [0, 1, 0]]]),
                       np.array([[[-1.0, 0, 0], [1, 0, 0], [0, 1, 0]]]))}
        for P, N in (pinches[d] for d in dims):
            closed = analyze_batch(P, N, mu=0.5)
            if len(closed.code):
                epsilon_batch(P, N, mu=0.5)


def object_dims(paths: Iterable[Path]) -> tuple[int, ...]:
    """The dimensions of the objects at ``paths``, as their names tell (polygon files and
    bundled polygons are planar)."""
    from ..objects import POLYGONS

    return tuple(sorted({2 if p.suffix.lower() in POLYGON_SUFFIXES or str(p) in POLYGONS
                         else 3 for p in paths}))


def local_pool(workers: int, run: Pending, job: Job | LabelJob,
                finish: Callable[[str, dict[str, Any]], None],
                say: Callable[[str], object]) -> None:
    """Everything on a local pool of killable worker processes (pebble's ``ProcessPool``).

    Each object's time limit is enforced twice: in its worker, by
    :func:`deadline` (between bytecodes, leaving the worker alive), and by
    the pool, which kills the worker :data:`HARD_GRACE` seconds later (inside
    compiled code). An object whose worker dies is run again on a fresh one;
    after :data:`MAX_CRASHES` deaths it is recorded as failed.
    """
    from pebble import ProcessExpired, ProcessPool
    from pebble.common import CONSTS

    # pebble stops a worker over its time limit with SIGTERM, then waits this long before
    # SIGKILL, holding the lock all workers need to hand in results: a worker stuck in
    # compiled code (deaf to SIGTERM) stalled the whole pool 3 s, and pushed others over
    # their limits. Our workers have nothing to clean up.
    CONSTS.term_timeout = min(CONSTS.term_timeout, 0.2)
    hard = None if job.timeout is None else job.timeout + HARD_GRACE
    context = pool_context()
    notices, counter = context.Queue(), context.Value("i", 0)
    relay = Relay(notices, say)
    relay.start()
    pool = ProcessPool(workers, context=context, initializer=worker_init,
                       initargs=(job, object_dims(run.todo.values()), notices, counter))
    arrived: queue.SimpleQueue[tuple[str, Future]] = queue.SimpleQueue()
    pending = 0

    def submit(name: str) -> None:
        nonlocal pending
        future = pool.schedule(process_object, (run.todo[name], job), timeout=hard)
        pending += 1
        future.add_done_callback(lambda f: arrived.put((name, f)))  # name: this call's

    watchdog = Watchdog(STALL_SECONDS, say)
    watchdog.start()
    try:
        for name in list(run.todo):
            submit(name)
        while pending:
            try:  # in slices: Ctrl-C, raised in this thread (app/interrupt), lands at once
                name, future = arrived.get(timeout=0.2)
            except queue.Empty:
                continue
            pending -= 1
            path = run.todo[name]
            try:
                record = future.result()
            except FutureTimeout:
                record = failed_record(path, f"{path.name}: over the time limit of "
                                             f"{job.timeout:g} s (its worker did not stop, and "
                                             "was killed)", "timeout")
            except ProcessExpired as e:
                run.crashes[name] = run.crashes.get(name, 0) + 1
                if run.crashes[name] < MAX_CRASHES:
                    submit(name)
                    continue
                why = (f"killed by signal {-e.exitcode}" if e.exitcode and e.exitcode < 0
                       else f"exit status {e.exitcode}")
                record = failed_record(path, f"{path.name}: its worker process died {MAX_CRASHES} "
                                       f"times on it (last: {why}; out of memory?)")
            except Exception as e:  # the pool could not run it (e.g. a broken pool)
                first = str(e).splitlines()[0] if str(e) else ""
                record = failed_record(path, f"{path.name}: internal error: {type(e).__name__}: "
                                       f"{first}")
            finish(name, record)
        pool.close()  # all done: the workers end as they would
    finally:
        watchdog.halt.set()
        pool.stop()  # Ctrl-C, a full disk: end the workers now
        pool.join()
        watchdog.join()
        relay.stop()
        notices.close()
