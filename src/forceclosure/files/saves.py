"""Saves of work done that Ctrl-C never cuts short, and blocks that save their work when
interrupted: the marks the command line's Ctrl-C handling
(:mod:`forceclosure.app.interrupt`) reads before it ends a process."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager, suppress

__all__ = ["holding", "patient", "patient_blocks", "saving"]

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


_patient: list[object] = []  # one token per block that saves its work when interrupted


@contextmanager
def patient() -> Iterator[None]:
    """A block that saves the work done when interrupted (``analyze FILE.npz --out``):
    on Ctrl-C the process waits for its compiled call to return, however long, saying so
    in one line; a second Ctrl-C ends it at once, without that save.

    Examples
    --------
    >>> with patient():
    ...     patient_blocks()
    True
    """
    token = object()
    try:
        _patient.append(token)
        yield
    finally:
        with suppress(ValueError):
            _patient.remove(token)


def saving() -> bool:
    """Whether a :func:`holding` block is running."""
    return bool(_held)


def patient_blocks() -> bool:
    """Whether a :func:`patient` block is running."""
    return bool(_patient)
