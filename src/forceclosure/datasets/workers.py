"""Worker processes that end with their run, a watchdog for stopped ones, and what
workers tell their run.

Two faults would otherwise outlive or stall a run of a process pool: a
worker busy in compiled code when the run is killed goes on computing for
nobody (it takes no signal handler until it returns), and a worker stopped
by ``SIGSTOP`` never finishes its task. :func:`die_with_run` (called in each
worker as it starts) makes the kernel kill the worker when the run ends,
however it ends; :class:`Watchdog` (a thread of the run) kills a worker
that stays stopped, so that the pool replaces it.

A worker compiling the batch kernels on first use (about a minute, once per
installation) says so to its run in one line, ``forceclosure: worker 2:
compiling the batch kernels (about a minute, once)``: a pool's workers
through a queue the run reads (:class:`Relay`), a Dask worker's through the
cluster's events (:func:`tell_dask_run`, topic :data:`TOPIC`).
"""

from __future__ import annotations

import ctypes
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections.abc import Callable
from contextlib import suppress
from typing import Any

__all__ = ["COMPILING", "TOPIC", "Relay", "Watchdog", "die_with_run", "is_stopped",
           "number_worker", "tell_compiling", "tell_dask_run"]

#: What a worker says, after its name, before it compiles the batch kernels.
COMPILING = "compiling the batch kernels (about a minute, once)"
#: The Dask event topic a worker tells its run on.
TOPIC = "forceclosure-notices"


def tell_compiling(send: Callable[[str], object], who: str) -> None:
    """In a worker process: when its kernels are about to compile (the notice of
    :func:`forceclosure.kernels.announce_compiling`, once per process), ``send`` the run
    one line, ``forceclosure: <who>: compiling the batch kernels (about a minute, once)``.
    A line that cannot be sent is dropped: it never stops the work.

    Examples
    --------
    >>> from forceclosure import kernels
    >>> previous = kernels.on_compiling(None)
    >>> tell_compiling(print, "worker 2")
    >>> kernels._tell[0](kernels.COMPILING)   # what announce_compiling does
    forceclosure: worker 2: compiling the batch kernels (about a minute, once)
    >>> _ = kernels.on_compiling(previous)
    """
    from ..kernels import on_compiling

    line = f"forceclosure: {who}: {COMPILING}"

    def tell(_: str) -> None:
        with suppress(Exception):
            send(line)

    on_compiling(tell)


def number_worker(counter: Any) -> int:
    """The next number of a shared counter (a ``multiprocessing.Value``): a pool worker's
    number, 1, 2, ... in the order they start (a replaced worker takes the next)."""
    with counter.get_lock():
        counter.value += 1
        return int(counter.value)


_dask_told: list[bool] = []


def tell_dask_run() -> None:
    """On a Dask worker (a no-op elsewhere): have its compile notice sent to the run as a
    cluster event on :data:`TOPIC` (the run subscribes to it), once per worker process."""
    if _dask_told:
        return
    _dask_told.append(True)
    try:
        from distributed import get_worker

        worker = get_worker()
    except (ImportError, ValueError):  # not on a Dask worker: the logger says it
        return
    tell_compiling(lambda line: worker.log_event(TOPIC, line), f"worker {worker.name}")


class Relay(threading.Thread):
    """A thread of the run that says each line its workers put on ``lines`` (a
    ``multiprocessing`` queue), until :meth:`stop`; lines left then are said too.

    Examples
    --------
    >>> import queue
    >>> lines = queue.Queue()
    >>> relay = Relay(lines, print); relay.start()
    >>> lines.put("forceclosure: worker 1: compiling the batch kernels (about a minute, once)")
    >>> relay.stop()
    forceclosure: worker 1: compiling the batch kernels (about a minute, once)
    """

    def __init__(self, lines: Any, say: Callable[[str], object]) -> None:
        super().__init__(name="forceclosure-relay", daemon=True)
        self.lines, self.say = lines, say
        self.halt = threading.Event()

    def run(self) -> None:
        import queue

        while not self.halt.is_set():
            try:
                line = self.lines.get(timeout=0.2)
            except queue.Empty:
                continue
            except (OSError, EOFError, ValueError):  # the queue is closed or broken
                self.halt.wait(0.2)
                continue
            self.say(str(line))

    def stop(self) -> None:
        """Stop reading, and say what is left."""
        import queue

        self.halt.set()
        self.join()
        while True:
            try:
                line = self.lines.get_nowait()
            except (queue.Empty, OSError, EOFError, ValueError):
                return
            self.say(str(line))


def die_with_run() -> None:
    """In a worker started by a ``forkserver`` pool: be killed (``SIGKILL``) when the run
    that started it ends, however it ends; Linux.

    A worker's parent is the fork server, which exits when no process holds
    the write end of its "alive" pipe: the run, and every process the server
    started (each inherits it, to start processes of its own). A worker
    starts none, so it lets go of its copy; then the server exits with the
    run, and the kernel kills the worker (``PR_SET_PDEATHSIG``), a signal no
    compiled code can delay. A thread watching the run (its sentinel) does
    the same where the kernel cannot, as long as the worker's code lets
    threads run. Do not call it in a process that starts processes.
    """
    with suppress(Exception):  # a private attribute of multiprocessing.forkserver
        from multiprocessing import forkserver

        # Any: typeshed's ForkServer stub leaves out its private attributes
        server: Any = forkserver._forkserver
        if server._forkserver_alive_fd is not None:
            os.close(server._forkserver_alive_fd)
            server._forkserver_alive_fd = None
    if sys.platform.startswith("linux"):
        with suppress(OSError, AttributeError):
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    parent = multiprocessing.parent_process()
    if parent is None:
        return
    if not parent.is_alive():  # the run died before this
        os._exit(1)

    def watch() -> None:
        from multiprocessing.connection import wait

        wait([parent.sentinel])
        os.kill(os.getpid(), signal.SIGKILL)

    threading.Thread(target=watch, name="forceclosure-run-watch", daemon=True).start()


def is_stopped(pid: int) -> bool:
    """Whether process ``pid`` is stopped (``SIGSTOP``, ``SIGTSTP``, traced); Linux
    (``/proc``), False elsewhere.

    Examples
    --------
    >>> is_stopped(os.getpid())
    False
    """
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            return f.read().rpartition(b")")[2].split()[0] in (b"T", b"t")
    except (OSError, IndexError):
        return False


class Watchdog(threading.Thread):
    """A thread that kills (``SIGKILL``) each child process named ``prefix...`` that stays
    stopped ``seconds``, saying so in one line; a pool then replaces it and reports its task
    as lost (pebble: ``ProcessExpired``).

    Examples
    --------
    >>> dog = Watchdog(30.0, print)
    >>> dog.start(); dog.halt.set(); dog.join(); dog.killed
    set()
    """

    def __init__(self, seconds: float, say: Callable[[str], object],
                 prefix: str = "pebble_pool_worker") -> None:
        super().__init__(name="forceclosure-watchdog", daemon=True)
        self.seconds, self.say, self.prefix = seconds, say, prefix
        self.halt = threading.Event()
        self.killed: set[int] = set()

    def run(self) -> None:
        since: dict[int, float] = {}
        while not self.halt.wait(min(0.5, self.seconds / 4)):
            now = time.monotonic()
            pids = {p.pid for p in multiprocessing.active_children()
                    if p.name.startswith(self.prefix) and p.pid is not None}
            for pid in pids:
                if not is_stopped(pid):
                    since.pop(pid, None)
                    continue
                since.setdefault(pid, now)
                if now - since[pid] >= self.seconds and pid not in self.killed:
                    self.say(f"forceclosure: warning: worker {pid} stopped for "
                             f"{self.seconds:g} s; killed, its object is run again")
                    with suppress(OSError):
                        os.kill(pid, signal.SIGKILL)
                    self.killed.add(pid)
            since = {pid: t for pid, t in since.items() if pid in pids}
