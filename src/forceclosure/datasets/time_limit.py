"""One object's time limit: raised in the thread that computes it, between bytecodes."""

from __future__ import annotations

import ctypes
import signal
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType

__all__ = ["REPEAT", "ObjectTimeout", "deadline", "importing", "timed_out"]


class ObjectTimeout(BaseException):
    """An object ran over its time limit. A ``BaseException``, like ``KeyboardInterrupt``,
    so that no ``except Exception`` on the way (in a file reader, say) swallows it."""


#: Seconds between repeats of :class:`ObjectTimeout` once the time limit has passed: code
#: that catches every exception (trimesh's optional imports catch ``BaseException``) may
#: swallow one, never the next.
REPEAT = 0.1


def importing(frame: FrameType | None) -> bool:
    """Whether ``frame`` runs inside an import: a limit raised there would leave the module
    half initialised, and every later object of the process failing on it (numba imports
    its type modules on first use: "partially initialized module 'numba.core.types'")."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib"):
            return True
        frame = frame.f_back
    return False


@contextmanager
def deadline(seconds: float | None) -> Iterator[None]:
    """Raise :class:`ObjectTimeout` in this thread after ``seconds``, and again every
    :data:`REPEAT` seconds until it leaves the block.

    The main thread (a process-pool worker) uses ``SIGALRM``; another thread
    (a Dask worker's) gets the exception raised in it asynchronously. Either
    way it arrives between Python bytecodes, so one long call into compiled
    code (a hull of a huge mesh) finishes first; and not inside an import
    (:func:`importing`): the next repeat after the import raises it.
    """
    if seconds is None:
        yield
        return
    if threading.current_thread() is threading.main_thread():
        armed = [True]

        def alarm(signum, frame):
            # a repeat landing while the block is left raises nothing
            if armed[0] and not importing(frame):
                raise ObjectTimeout

        previous = signal.signal(signal.SIGALRM, alarm)
        outer, _ = signal.setitimer(signal.ITIMER_REAL, seconds, REPEAT)
        start = time.monotonic()
        try:
            yield
        finally:
            armed[0] = False
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, previous)
            if outer > 0:  # an alarm set around ours (a test runner's time limit) goes on
                signal.setitimer(signal.ITIMER_REAL,
                                 max(outer - (time.monotonic() - start), 1e-3))
        return
    ident, lock, done = threading.get_ident(), threading.Lock(), threading.Event()

    def fire() -> None:
        wait = seconds
        while not done.wait(wait):
            with lock:
                if done.is_set():
                    return
                # (the thread may start an import between this look and the exception's
                # arrival: a window of a few bytecodes, where the main thread's has none)
                if not importing(sys._current_frames().get(ident)):
                    ctypes.pythonapi.PyThreadState_SetAsyncExc(
                        ctypes.c_ulong(ident), ctypes.py_object(ObjectTimeout))
            wait = REPEAT

    timer = threading.Thread(target=fire, daemon=True)
    timer.start()
    try:
        yield
    finally:
        with lock:
            done.set()
        # an exception set but not yet raised must not escape the block
        ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(ident), None)


def timed_out(error: BaseException) -> bool:
    """Whether ``error`` is the time limit, or carries it: a limit landing inside a call
    into compiled code (a numba kernel's dispatcher) comes out of it as ``SystemError: ...
    returned a result with an exception set``, the :class:`ObjectTimeout` its cause."""
    seen: set[int] = set()
    link: BaseException | None = error  # then its cause or context, to the chain's end
    while link is not None and id(link) not in seen:
        if isinstance(link, ObjectTimeout):
            return True
        seen.add(id(link))
        link = link.__cause__ or link.__context__
    return False
