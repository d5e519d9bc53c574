"""Ctrl-C that stops a command within a second or two, even inside compiled code.

Python handles a signal between bytecodes of the main thread: a command busy
in one long compiled call (a numba kernel, Qhull, a HiGHS LP) saw Ctrl-C only
when that call returned, minutes later. :func:`run_interruptible` runs the
command in a worker thread while the main thread waits in short slices, so
that SIGINT is handled at once; then it

1. raises ``KeyboardInterrupt`` in the worker (between its bytecodes, as the
   signal did before: the commands' own Ctrl-C paths run as they did, saving
   what is done);
2. waits :data:`GRACE` seconds for the worker to take it (to run Python
   again), then as long as the worker ends on its own (its Ctrl-C path: a
   pool stopped, tables written); a second Ctrl-C ends the process then,
   unless the worker is inside :func:`~forceclosure.files.saves.holding` (a save:
   never cut short);
3. if the worker has not taken it (a compiled call that has not returned),
   prints ``forceclosure: interrupted``, flushes, and ends the process with
   status 130 (``os._exit``) -- unless the command is inside
   :func:`~forceclosure.files.saves.patient` (it saves its work when interrupted):
   then it says it waits for the call, and a second Ctrl-C ends the process. Files
   are written atomically (a temporary, then a rename), so a write the exit cuts
   short never replaces a good file.
"""

from __future__ import annotations

import ctypes
import os
import sys
import threading
import time
from collections.abc import Callable
from contextlib import suppress
from typing import Any

from ..files.saves import patient_blocks, saving

__all__ = ["GRACE", "CommandInterrupted", "run_interruptible"]

#: Seconds a command gets after Ctrl-C to end on its own (its compiled call to return and
#: the saving to begin) before the process exits.
GRACE = 1.5
#: Seconds between two looks of the waiting main thread.
SLICE = 0.05

_received = threading.Event()


class CommandInterrupted(KeyboardInterrupt):
    """Ctrl-C, raised in the command's thread. Made when that thread runs Python again
    (its compiled call returned): from then on, it ends on its own (its Ctrl-C paths)."""

    def __init__(self, *args: object) -> None:
        super().__init__(*args)
        _received.set()


def _raise_in(thread: threading.Thread) -> None:
    """:class:`CommandInterrupted` in ``thread``, at its next bytecode."""
    if thread.ident is not None:
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread.ident),
                                                   ctypes.py_object(CommandInterrupted))


def run_interruptible(work: Callable[[], int], grace: float | None = None,
                      line: str = "forceclosure: interrupted") -> int:
    """Run ``work`` (a command) so that Ctrl-C stops it within about ``grace`` seconds.

    Parameters
    ----------
    work : callable
        The command; returns its exit status. What it raises is raised here.
    grace : float, optional
        Seconds ``work`` gets after Ctrl-C to take it (to return from a compiled
        call) before the process exits with status 130; :data:`GRACE` by default.
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
    grace = GRACE if grace is None else grace
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

    _received.clear()
    worker = threading.Thread(target=target, name="forceclosure-command", daemon=True)
    worker.start()
    asked, deadline, told = False, None, False
    # not worker.join(timeout): Ctrl-C inside it marks the thread as ended while it runs
    # (Python 3.11's threading, bpo-45274); an event's wait is interrupted cleanly, and
    # returns as soon as the command ends
    while not ended.is_set():
        try:
            ended.wait(SLICE)
            if asked and deadline is None and not saving():  # the save Ctrl-C came in is over
                deadline = time.monotonic() + grace
                _raise_in(worker)
            if (deadline is not None and time.monotonic() > deadline and not saving()
                    and not _received.is_set()):  # still in a compiled call
                if not patient_blocks():
                    _exit(line)
                if not told:
                    told = _say("forceclosure: stopping when the current step returns, "
                                "to save what is done (Ctrl-C again: quit without saving)")
        except KeyboardInterrupt:
            if not asked:
                asked = True  # stopped at once, or after the save under way
            elif not saving():  # a second Ctrl-C: now (its cleaning up cut short, its
                _exit(line)      # files atomic), unless a save is under way
    if "error" in outcome:
        error = outcome.pop("error")
        try:
            raise error
        finally:
            del error
    return outcome["status"]


def _say(line: str) -> bool:
    """Print ``line`` on standard error (True)."""
    with suppress(Exception):
        print(line, file=sys.stderr, flush=True)
    return True


def _exit(line: str) -> None:
    """Print ``line`` on standard error, flush, and end the process with status 130."""
    with suppress(Exception):
        sys.stdout.flush()
    with suppress(Exception):
        print(line, file=sys.stderr)
        sys.stderr.flush()
    os._exit(130)
