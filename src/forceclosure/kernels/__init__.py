"""Compiled batch kernels (numba) behind :mod:`forceclosure.analysis.batch` and
:mod:`forceclosure.analysis.two_finger`.

They answer the same questions as the reference path, with the same
tolerance, many grasps at a time and in parallel; compiled code is cached on
disk, so only the first run of a new installation pays for compilation.
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable, Iterator
from contextlib import contextmanager

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["COMPILE_AFTER", "COMPILING", "announce_compiling", "cached", "compiling_announced",
           "kernel_array", "on_compiling", "pool_for", "use_compiled"]

_log = logging.getLogger("forceclosure")
_announced = False

#: What :func:`announce_compiling` says (on the ``forceclosure`` logger, or to the callback
#: given to :func:`on_compiling`).
COMPILING = ("forceclosure: warning: compiling the batch kernels for this machine, once "
             "(about a minute; cached for later runs; `forceclosure warmup` does it ahead)")
_tell: list[Callable[[str], object]] = []


def on_compiling(tell: Callable[[str], object] | None) -> Callable[[str], object] | None:
    """Have :func:`announce_compiling` call ``tell`` with its line instead of logging it
    (None: log it again); returns the callback this replaces. A dataset's workers tell
    their run this way (:mod:`forceclosure.datasets.workers`).

    Examples
    --------
    >>> previous = on_compiling(print)
    >>> on_compiling(previous) is print
    True
    """
    previous = _tell[0] if _tell else None
    _tell[:] = [] if tell is None else [tell]
    return previous


def compiling_announced() -> None:
    """Take compilation as announced: for callers that report it themselves."""
    global _announced
    _announced = True


def cached(kernel) -> bool:
    """Whether ``kernel`` has compiled code cached on disk (numba's cache index) or in this
    process: False on the first run after installing. An unknown numba layout counts as
    cached (nothing is said or avoided on a guess)."""
    if getattr(kernel, "overloads", None):  # compiled in this process (what ``signatures``
        return True                          # lists, without building the list)
    try:
        index = kernel._cache._cache_file._index_path
    except AttributeError:
        return True
    return os.path.exists(index)


#: Grasps left to the reference path (milliseconds each) on a machine with no compiled kernel
#: cached yet, before :func:`use_compiled` has them compiled (about a minute, once per
#: installation): single grasps and small batches get a first answer at once, longer runs
#: the kernels' microseconds. 0: compile at the first use (``forceclosure warmup``, tests).
COMPILE_AFTER = 100
_uncompiled_uses = 0


def use_compiled(*kernels, grasps: int = 1) -> bool:
    """Whether a call deciding ``grasps`` grasps should run these kernels: yes once they are
    compiled (on disk or in this process); before that, no while the process has left at
    most :data:`COMPILE_AFTER` grasps to the reference path, these included (the caller
    takes its reference path), then yes, with the compile notice (tested in
    ``tests/test_startup.py``)."""
    global _uncompiled_uses
    if all(cached(kernel) for kernel in kernels):
        return True
    if _uncompiled_uses + grasps <= COMPILE_AFTER:
        _uncompiled_uses += grasps
        return False
    announce_compiling(*kernels)
    return True


def announce_compiling(*kernels) -> None:
    """Say once per process, as a warning on the ``forceclosure`` logger (standard error
    unless configured; or to the callback of :func:`on_compiling`), that compilation is
    about to take a while: called just before
    these kernels run, when one has no compiled code cached on disk (numba's cache index),
    as on the first run after installing.
    """
    global _announced
    if _announced:
        return
    if not all(cached(kernel) for kernel in kernels):
        _announced = True
        if _tell:
            _tell[0](COMPILING)
        else:
            _log.warning(COMPILING)


def kernel_array(a: ArrayLike, dtype: type = np.float64) -> NDArray:
    """``a`` as the kernels take it: C-contiguous and writeable.

    A read-only or broadcast view would make numba compile another signature.
    """
    if (isinstance(a, np.ndarray) and a.dtype == dtype and a.flags.c_contiguous
            and a.flags.writeable):  # as it is (np.require's answer too, in a fraction)
        return a
    return np.require(a, dtype=dtype, requirements=["C", "W"])


@contextmanager
def pool_for(n: int, block: int | None = None) -> Iterator[None]:
    """Run the parallel kernels called inside on the calling thread alone when the batch has
    ``n`` items or fewer than one ``block`` (default ``theorem1.BLOCK`` grasps): waking the
    thread pool for one block gains nothing and, measured, doubles the CPU time of a
    one-grasp call (its idle workers spin).
    Numba's thread count is per calling thread, so other threads are not affected.

    Examples
    --------
    >>> import numba
    >>> with pool_for(1):
    ...     numba.get_num_threads()
    1
    """
    import numba

    from .theorem1 import BLOCK

    if n > (BLOCK if block is None else block):
        yield
        return

    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        yield
    finally:
        numba.set_num_threads(before)
