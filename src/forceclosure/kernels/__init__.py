"""Compiled batch kernels (numba) behind :mod:`forceclosure.batch` and :mod:`.two_finger`.

They answer the same questions as the reference path, with the same
tolerance, many grasps at a time and in parallel; compiled code is cached on
disk, so only the first run of a new installation pays for compilation.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray


def kernel_array(a: ArrayLike, dtype: type = np.float64) -> NDArray:
    """``a`` as the kernels take it: C-contiguous and writeable.

    A read-only or broadcast view would make numba compile another signature.
    """
    return np.require(a, dtype=dtype, requirements=["C", "W"])
