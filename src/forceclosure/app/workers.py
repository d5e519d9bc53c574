"""Worker processes that end with their run, and a watchdog for stopped ones.

Two faults would otherwise outlive or stall a run of a process pool: a
worker busy in compiled code when the run is killed goes on computing for
nobody (it takes no signal handler until it returns), and a worker stopped
by ``SIGSTOP`` never finishes its task. :func:`die_with_run` (called in each
worker as it starts) makes the kernel kill the worker when the run ends,
however it ends; :class:`Watchdog` (a thread of the run) kills a worker
that stays stopped, so that the pool replaces it.
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

__all__ = ["Watchdog", "die_with_run", "is_stopped"]


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

        server = forkserver._forkserver
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
