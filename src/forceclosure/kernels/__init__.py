"""Compiled batch kernels (numba) behind :mod:`forceclosure.batch` and :mod:`.two_finger`.

They answer the same questions as the reference path, with the same
tolerance, many grasps at a time and in parallel; compiled code is cached on
disk, so only the first run of a new installation pays for compilation.
"""

from __future__ import annotations

import logging
import os

import numpy as np
from numpy.typing import ArrayLike, NDArray

_log = logging.getLogger("forceclosure")
_announced = False


def compiling_announced() -> None:
    """Take compilation as announced: for callers that report it themselves."""
    global _announced
    _announced = True


def announce_compiling(*kernels) -> None:
    """Say once per process, as a warning on the ``forceclosure`` logger (standard error
    unless configured), that compilation is about to take a while: called just before
    these kernels run, when one has no compiled code cached on disk (numba's cache index),
    as on the first run after installing.
    """
    global _announced
    if _announced:
        return
    for kernel in kernels:
        try:
            index = kernel._cache._cache_file._index_path
        except AttributeError:  # another numba's layout: say nothing rather than guess
            return
        if not os.path.exists(index):
            _announced = True
            _log.warning("forceclosure: warning: compiling the batch kernels for this machine, "
                         "once (about a minute; cached for later runs; `forceclosure warmup` "
                         "does it ahead)")
            return


def kernel_array(a: ArrayLike, dtype: type = np.float64) -> NDArray:
    """``a`` as the kernels take it: C-contiguous and writeable.

    A read-only or broadcast view would make numba compile another signature.
    """
    return np.require(a, dtype=dtype, requirements=["C", "W"])
