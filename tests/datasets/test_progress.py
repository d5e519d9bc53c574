"""Progress everywhere (issue 24, item 9): a line at intervals when standard error is not a
terminal, and one line per worker that compiles the kernels. Counted in events and on a
clock the test gives, never timed."""

from __future__ import annotations

import io
import math
import queue
import sys
from pathlib import Path
from types import SimpleNamespace

import pytest

from forceclosure import kernels
from forceclosure.datasets import Job, one_object, pool, run, run_dataset, workers
from forceclosure.datasets.progress import (
    ENVIRONMENT,
    ProgressLines,
    duration,
    every_from_environment,
)
from forceclosure.errors import InputError

SOFT = Job(contact="soft", mu=0.5, top=1)
QUICK = Job(mode="analyze")   # no hand to check before the run: the driver alone is tested
COMPILING = "compiling the batch kernels (about a minute, once)"
#: A kernel with no compiled code cached (as after installing): numba's cache index missing.
UNCACHED = SimpleNamespace(_cache=SimpleNamespace(_cache_file=SimpleNamespace(
    _index_path="/nonexistent/forceclosure-test.nbi")))


def done(path, job):
    """An object's record, at once (the driver's progress is what is tested)."""
    return one_object.failed_record(Path(path), None, "done")


class Clock:
    """A clock the test sets by hand."""

    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def test_lines_every_interval_with_rate_and_time_left():
    """12 objects, a line every 10 s: objects finish at 3 s intervals, so lines come with
    the 4th (12 s: 4 done, 1/3 per s, 8 left: 24 s), the 8th (24 s) and the 12th (36 s,
    the 11th at 33 s being 9 s after the last line; none left) object; rates and times
    left by hand."""
    clock, said = Clock(), []
    lines = ProgressLines(12, said.append, every=10.0, clock=clock)
    for _ in range(12):
        clock.now += 3.0
        lines.update()
    assert said == ["forceclosure: 4/12 objects (33%), 0.333 objects/s, about 24 s left",
                    "forceclosure: 8/12 objects (67%), 0.333 objects/s, about 12 s left",
                    "forceclosure: 12/12 objects (100%), 0.333 objects/s"]


def test_a_long_run_says_minutes_and_hours():
    clock, said = Clock(), []
    lines = ProgressLines(10_000, said.append, every=60.0, clock=clock)
    clock.now += 90.0
    lines.update(50)   # 50 in 90 s: 9950 left at 5/9 per s = 17910 s = 4 h 58 min 30 s
    assert said == ["forceclosure: 50/10000 objects (0%), 0.556 objects/s, about 4 h 58 min "
                    "left"]
    assert (duration(59.4), duration(60), duration(3599), duration(3600)) == (
        "59 s", "1 min 0 s", "59 min 59 s", "1 h 00 min")


def test_every_zero_says_each_update_and_nothing_on_a_stopped_clock():
    clock, said = Clock(), []
    lines = ProgressLines(2, said.append, every=0.0, clock=clock)
    lines.update()   # no time has passed: no rate yet
    clock.now += 2.0
    lines.update()
    assert said == ["forceclosure: 1/2 objects (50%)", "forceclosure: 2/2 objects (100%), "
                    "1 objects/s"]


def test_interval_from_the_environment(monkeypatch):
    monkeypatch.setenv(ENVIRONMENT, "2.5")
    assert every_from_environment() == 2.5
    monkeypatch.setenv(ENVIRONMENT, "inf")
    assert every_from_environment() == math.inf
    monkeypatch.delenv(ENVIRONMENT)
    assert every_from_environment() == 10.0
    for bad in ("-1", "soon", "nan"):
        monkeypatch.setenv(ENVIRONMENT, bad)
        with pytest.raises(InputError) as e:
            every_from_environment()
        assert str(e.value).startswith(f"{ENVIRONMENT}: must be a number of seconds >= 0")
        assert "\n" not in str(e.value)


class FakeStderr(io.StringIO):
    def __init__(self, terminal: bool) -> None:
        super().__init__()
        self.terminal = terminal

    def isatty(self) -> bool:
        return self.terminal


@pytest.mark.parametrize("terminal, progress, every, expected", [
    (False, None, 0.0, 2),        # piped: a line per object (interval 0)
    (False, None, math.inf, 0),   # piped, no lines asked for
    (False, False, 0.0, 0),       # no progress at all
    (True, None, 0.0, 0),         # a terminal: the bar, not lines
])
def test_a_piped_run_prints_progress_lines(tmp_path, monkeypatch, terminal, progress, every,
                                           expected):
    monkeypatch.setattr(sys, "stderr", FakeStderr(terminal))
    monkeypatch.setattr(run, "process_object", done)
    said: list[str] = []
    summary = run_dataset(["square", "cube"], tmp_path, QUICK, workers=1,
                          progress=progress, progress_every=every, log=said.append)
    assert summary.done == 2
    progress_lines = [line for line in said if " objects (" in line]
    assert len(progress_lines) == expected
    assert [line.split(" objects")[0] for line in progress_lines] == [
        f"forceclosure: {k}/2" for k in range(1, expected + 1)]


def test_a_run_in_this_process_says_when_it_compiles(tmp_path, monkeypatch):
    """Two objects computed here, the kernels not compiled yet (a kernel with no cache
    index): one line, before the first object's record."""
    monkeypatch.setattr(kernels, "_announced", False)
    monkeypatch.setattr(kernels, "_tell", [])
    order: list[str] = []

    def first_use(path, job):
        kernels.announce_compiling(UNCACHED)
        order.append(f"object {path}")
        return done(path, job)

    monkeypatch.setattr(run, "process_object", first_use)
    summary = run_dataset(["cube", "square"], tmp_path, QUICK, workers=1, progress=False,
                          log=order.append)
    assert summary.done == 2
    assert order == [kernels.COMPILING, "object cube", "object square"]  # said once
    assert kernels._tell == []  # the run's callback is gone with it


def test_a_pool_worker_tells_its_run_through_a_process_queue(monkeypatch):
    """What a pool worker does when its kernels compile (its initializer's
    tell_compiling), through a real multiprocessing queue to the run's relay thread: one
    line naming the worker, however many kernels announce."""
    monkeypatch.setattr(kernels, "_announced", False)
    monkeypatch.setattr(kernels, "_tell", [])
    context = pool.pool_context()
    notices, counter = context.Queue(), context.Value("i", 0)
    said: list[str] = []
    relay = workers.Relay(notices, said.append)
    relay.start()
    assert [workers.number_worker(counter) for _ in range(2)] == [1, 2]
    workers.tell_compiling(notices.put, f"worker {workers.number_worker(counter)}")
    kernels.announce_compiling(UNCACHED)
    kernels.announce_compiling(UNCACHED)
    relay.stop()
    notices.close()
    assert said == [f"forceclosure: worker 3: {COMPILING}"]


@pytest.mark.long
def test_a_dask_worker_tells_its_run(tmp_path, monkeypatch):
    """A Dask worker (in this process) whose kernels compile on its first object: the run
    says one line naming it, from the cluster's events."""
    from distributed import Client, LocalCluster

    monkeypatch.setattr(kernels, "_announced", False)
    monkeypatch.setattr(kernels, "_tell", [])
    monkeypatch.setattr(workers, "_dask_told", [])
    real = run.process_object

    def first_use(path, job):
        kernels.announce_compiling(UNCACHED)
        return real(path, job)

    monkeypatch.setattr(run, "process_object", first_use)
    said: list[str] = []
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        name = next(iter(cluster.workers.values())).name
        summary = run_dataset(["cube", "square"], tmp_path, SOFT,
                              executor=client.get_executor(), progress=False,
                              log=said.append)
    assert summary.done == 2
    assert said == [f"forceclosure: worker {name}: {COMPILING}"]


def test_relay_says_what_is_left_when_stopped():
    lines: queue.Queue = queue.Queue()
    said: list[str] = []
    relay = workers.Relay(lines, said.append)
    relay.halt.set()            # stopped before reading anything
    relay.start()
    for k in range(3):
        lines.put(f"line {k}")
    relay.stop()
    assert said == ["line 0", "line 1", "line 2"]
