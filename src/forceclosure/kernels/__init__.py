"""Compiled batch kernels (numba) behind :mod:`forceclosure.batch` and :mod:`.two_finger`.

They answer the same questions as the reference path, with the same
tolerance, many grasps at a time and in parallel; compiled code is cached on
disk, so only the first run of a new installation pays for compilation.
"""
