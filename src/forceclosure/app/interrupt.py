"""Ctrl-C that stops a command within a second or two, even inside compiled code.

Python handles a signal between bytecodes of the main thread: a command busy
in one long compiled call (a numba kernel, Qhull, a HiGHS LP) saw Ctrl-C only
when that call returned, minutes later. :func:`run_interruptible` runs the
command in a worker thread while the main thread waits in short slices, so
that SIGINT is handled at once; then it

1. raises ``KeyboardInterrupt`` in the worker (between its bytecodes, as the
   signal did before: the commands' own Ctrl-C paths run as they did, saving
   what is done);
2. waits :data:`GRACE` seconds for the worker to end, and as long as it is
   inside :func:`holding` (a save: never cut short, a second Ctrl-C included);
3. if the worker is still busy (a compiled call that has not returned),
   prints ``forceclosure: interrupted``, flushes, and ends the process with
   status 130 (``os._exit``). Files are written atomically (a temporary,
   then a rename), so a write the exit cuts short never replaces a good file.
"""

from __future__ import annotations

import ctypes
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from typing import Any

__all__ = ["GRACE", "holding", "run_interruptible"]

#: Seconds a command gets after Ctrl-C to end on its own (its compiled call to return and
#: the saving to begin) before the process exits.
GRACE = 1.5
#: Seconds between two looks of the waiting main thread.
SLICE = 0.05

_held: list[object] = []  # one token per save in progress (list.append/remove: atomic)


@contextmanager
def holding() -> Iterator[None]:
    """A block that Ctrl-C never cuts short (a save of work done): the process waits
    for it before exiting on Ctrl-C.

    Examples
    --------
    >>> with holding():
    ...     saving()
    True
    >>> saving()
    False
    """
    token = object()
    try:
        _held.append(token)  # inside the try: an exception after it still removes it
        yield
    finally:
        with suppress(ValueError):
            _held.remove(token)


def saving() -> bool:
    """Whether a :func:`holding` block is running."""
    return bool(_held)


def _raise_in(thread: threading.Thread) -> None:
    """``KeyboardInterrupt`` in ``thread``, at its next bytecode."""
    if thread.ident is not None:
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread.ident),
                                                   ctypes.py_object(KeyboardInterrupt))


def run_interruptible(work: Callable[[], int], grace: float = GRACE,
                      line: str = "forceclosure: interrupted") -> int:
    """Run ``work`` (a command) so that Ctrl-C stops it within about ``grace`` seconds.

    Parameters
    ----------
    work : callable
        The command; returns its exit status. What it raises is raised here.
    grace : float
        Seconds ``work`` gets after Ctrl-C to end on its own (not counting time
        inside :func:`holding`) before the process exits with status 130.
    line : str
        Printed on standard error when the process exits that way.

    Returns
    -------
    int
        The status ``work`` returned.

    Examples
    --------
    >>> run_interruptible(lambda: 3)
    3
    """
    if threading.current_thread() is not threading.main_thread():
        return work()  # signals are the main thread's: nothing to gain
    outcome: dict[str, Any] = {}
    ended = threading.Event()

    def target() -> None:
        try:
            outcome["status"] = work()
        except BaseException as e:  # handed to the main thread as it is
            outcome["error"] = e
        finally:
            ended.set()

    worker = threading.Thread(target=target, name="forceclosure-command", daemon=True)
    worker.start()
    asked, deadline = False, None
    # not worker.join(timeout): Ctrl-C inside it marks the thread as ended while it runs
    # (Python 3.11's threading, bpo-45274); a sleep is interrupted cleanly
    while not ended.is_set():
        try:
            time.sleep(SLICE)
            if asked and deadline is None and not saving():  # the save Ctrl-C came in is over
                deadline = time.monotonic() + grace
                _raise_in(worker)
            if deadline is not None and time.monotonic() > deadline and not saving():
                _exit(line)
        except KeyboardInterrupt:
            if not asked:
                asked = True  # stopped at once, or after the save under way
            elif not saving():  # a second Ctrl-C: now, unless a save is under way
                _exit(line)
    if "error" in outcome:
        error = outcome.pop("error")
        try:
            raise error
        finally:
            del error
    return outcome["status"]


def _exit(line: str) -> None:
    """Print ``line`` on standard error, flush, and end the process with status 130."""
    with suppress(Exception):
        sys.stdout.flush()
    with suppress(Exception):
        print(line, file=sys.stderr)
        sys.stderr.flush()
    os._exit(130)
