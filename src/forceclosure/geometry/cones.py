"""Friction cones: their angles, whether two counter-overlap, and the friction pyramid.

A contact with outward unit normal ``n`` and friction ``mu`` pushes along the
friction cone ``C`` of axis ``-n`` and half-angle ``alpha = atan(mu)``. Two
cones *counter-overlap* when ``C_i ∩ -C_j`` has an interior (Lemma 1, §5.2,
§5.3): the angle between ``-n_i`` and ``n_j`` is below ``alpha_i + alpha_j``.
This module holds the one test of that, :func:`counter_overlap`, and the one
builder of a cone's generating forces, :func:`friction_forces` (exact in the
plane, a ``k``-edge pyramid in space), whose edge angles :func:`fill_rim` and
radius :func:`pyramid_divisor` are plain arithmetic that the compiled kernels
(:mod:`forceclosure.kernels.theorem1`) compile from this same source, so that
both paths build bit-for-bit the same wrenches (tests/kernels/test_wrench_builders.py).

numba keys a cached kernel by its own file only: after editing :func:`fill_rim`
or :func:`pyramid_divisor`, touch ``kernels/theorem1.py`` (or clear numba's
cache) and run ``forceclosure warmup``, or the kernels keep the old code (and
the bit-for-bit test fails, as it should).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["angle_between", "counter_overlap", "counter_overlap_angle", "fill_rim",
           "friction_forces", "pyramid_divisor", "pyramid_radius", "pyramid_rim",
           "tangent_basis"]


def angle_between(u: ArrayLike, v: ArrayLike) -> NDArray[np.float64]:
    """Angle between vectors along the last axis (2-D or 3-D), stable near 0 and pi.

    ``atan2(|u x v|, u . v)``: neither vector needs to be a unit vector.

    Examples
    --------
    >>> round(float(angle_between([1.0, 0.0], [1.0, 1.0])), 12) == round(math.pi / 4, 12)
    True
    >>> angle_between([[0, 0, 2.0], [1.0, 0, 0]], [[0, 0, -1.0], [1.0, 0, 0]]).tolist()
    [3.141592653589793, 0.0]
    """
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    dot = np.sum(u * v, axis=-1)
    if u.shape[-1] == 2:
        cross = np.abs(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])
    else:
        cross = np.linalg.norm(np.cross(u, v), axis=-1)
    return np.arctan2(cross, dot)


def counter_overlap_angle(n_i: ArrayLike, n_j: ArrayLike) -> NDArray[np.float64]:
    """Angle between the axes of ``C_i`` and ``-C_j``: between ``-n_i`` and ``n_j``.

    0 for contacts on opposite sides facing each other (normals antiparallel),
    pi for two contacts on one face.

    Examples
    --------
    >>> float(counter_overlap_angle([0, 0, 1.0], [0, 0, -1.0]))
    0.0
    """
    return angle_between(-np.asarray(n_i, dtype=float), n_j)


def counter_overlap(n_i: ArrayLike, n_j: ArrayLike, mu_i: ArrayLike,
                    mu_j: ArrayLike | None = None) -> NDArray[np.bool_]:
    """Whether the friction cones at two contacts counter-overlap: ``C_i ∩ -C_j`` has an
    interior, that is ``angle(-n_i, n_j) < atan(mu_i) + atan(mu_j)`` with both frictions
    positive (a frictionless cone is a ray: it has no interior to share).

    Vectorised over leading axes (normals ``(..., d)``, ``d`` 2 or 3; friction
    broadcast against ``(...)``); ``mu_j`` defaults to ``mu_i``. Normals need
    not be unit vectors. The test on the normals alone: in the plane it is
    Lemma 1's ``S = C_p ∩ -C_q`` being non-empty, in space the paper's
    force-direction closure of two soft fingers (Theorem 2, §5.2) and a
    counter-overlapping pair of §5.3.

    Examples
    --------
    >>> bool(counter_overlap([0, 0, 1], [0, 0, -1], 0.1))   # opposite faces
    True
    >>> bool(counter_overlap([0, 0, 1], [1, 0, 0], 0.9))    # at right angles: needs mu > 1
    False
    >>> counter_overlap([[-1, 0], [-1, 0]], [[0, 1], [1, 0]], 1.01).tolist()
    [True, True]
    >>> bool(counter_overlap([0, 1], [0, -1], 0.0, 5.0))   # a ray inside a cone: no interior
    False
    """
    mu_i = np.asarray(mu_i, dtype=float)
    mu_j = mu_i if mu_j is None else np.asarray(mu_j, dtype=float)
    limit = np.arctan(mu_i) + np.arctan(mu_j)
    return (counter_overlap_angle(n_i, n_j) < limit) & (mu_i > 0) & (mu_j > 0)


def tangent_basis(normals: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Two unit tangents ``t1, t2`` with ``(t1, t2, n)`` right-handed, for ``(..., 3)`` normals.

    ``t1`` is built from the coordinate axis least aligned with ``n``, so an
    axis-aligned normal gets axis-aligned tangents (exact in floating point).

    Examples
    --------
    >>> t1, t2 = tangent_basis(np.array([0.0, 0.0, 1.0]))
    >>> (t1 + 0.0).tolist(), (t2 + 0.0).tolist()
    ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0])
    """
    n = np.asarray(normals, dtype=float)
    axis = np.argmin(np.abs(n), axis=-1)
    e = np.zeros_like(n)
    np.put_along_axis(e, np.asarray(axis)[..., None], 1.0, axis=-1)
    t1 = np.cross(e, n)
    t1 /= np.linalg.norm(t1, axis=-1, keepdims=True)
    t2 = np.cross(n, t1)
    return t1, t2


def fill_rim(rim: NDArray[np.float64], edges: int) -> None:
    """Write the cosines and sines of a ``edges``-edge pyramid's edge angles
    ``2 pi r / edges`` into ``rim[0, :edges]`` and ``rim[1, :edges]``.

    Plain scalar arithmetic, so the compiled kernels compile this very
    function (``math.cos`` is the C library's in both).

    Examples
    --------
    >>> rim = np.zeros((2, 4))
    >>> fill_rim(rim, 4)
    >>> np.round(rim, 12).tolist()
    [[1.0, 0.0, -1.0, -0.0], [0.0, 1.0, 0.0, -1.0]]
    """
    for r in range(edges):
        theta = 2.0 * np.pi * r / edges
        rim[0, r] = math.cos(theta)
        rim[1, r] = math.sin(theta)


@lru_cache(maxsize=64)
def pyramid_rim(edges: int) -> NDArray[np.float64]:
    """``(2, edges)``: cosines and sines of the pyramid's edge angles (:func:`fill_rim`).

    Examples
    --------
    >>> pyramid_rim(3).shape
    (2, 3)
    """
    rim = np.empty((2, edges))
    fill_rim(rim, edges)
    rim.setflags(write=False)
    return rim


def pyramid_divisor(edges: int, circumscribed: bool) -> float:
    """What ``mu`` is divided by for the pyramid's edge radius: 1 for the inscribed
    pyramid (edges on the circular cone), ``cos(pi / edges)`` for the circumscribed one
    (faces tangent to it).

    Examples
    --------
    >>> pyramid_divisor(8, False), round(pyramid_divisor(4, True) ** 2, 12)
    (1.0, 0.5)
    """
    return math.cos(math.pi / edges) if circumscribed else 1.0


def pyramid_radius(mu: float, edges: int, circumscribed: bool) -> float:
    """Distance of the pyramid's edges from the cone axis at unit normal force.

    Examples
    --------
    >>> round(pyramid_radius(0.5, 8, True), 6)   # mu / cos(pi/8)
    0.541196
    """
    return mu / pyramid_divisor(edges, circumscribed)


def friction_forces(normals: ArrayLike, radius: ArrayLike | None,
                    edges: int = 8) -> NDArray[np.float64]:
    """The generating forces of friction cones, ``(N, g, d)``, with unit normal component.

    For outward normals ``(N, d)``: ``radius`` None gives the frictionless
    force ``-n`` (``g = 1``); in the plane ``-n + r t`` and ``-n - r t`` with
    ``t = (-n_y, n_x)`` (``g = 2``, exact); in space the ``edges`` edges
    ``-n + r (cos θ t1 + sin θ t2)`` of a pyramid (:func:`tangent_basis`,
    :func:`pyramid_rim`). ``radius`` (``(N,)`` or a number) is ``mu`` for the
    exact planar cone and the inscribed pyramid, :func:`pyramid_radius` for the
    circumscribed one.

    Examples
    --------
    >>> friction_forces(np.array([[0.0, 1.0]]), 0.5).tolist()
    [[[-0.5, -1.0], [0.5, -1.0]]]
    >>> f = friction_forces(np.array([[0.0, 0.0, 1.0]]), 0.5, edges=4)
    >>> (np.round(f[0], 12) + 0.0).tolist()   # t1 = -y, t2 = +x
    [[0.0, -0.5, -1.0], [0.5, 0.0, -1.0], [0.0, 0.5, -1.0], [-0.5, 0.0, -1.0]]
    """
    normals = np.asarray(normals, dtype=float)
    inward = -normals
    if radius is None:
        return inward[:, None, :]
    r = np.broadcast_to(np.asarray(radius, dtype=float), normals.shape[:1])[:, None, None]
    if normals.shape[-1] == 2:
        tangent = np.stack([-normals[:, 1], normals[:, 0]], axis=-1)
        return inward[:, None, :] + r * np.stack([tangent, -tangent], axis=1)
    t1, t2 = tangent_basis(normals)
    cos, sin = pyramid_rim(edges)
    rim = cos[None, :, None] * t1[:, None, :] + sin[None, :, None] * t2[:, None, :]
    return inward[:, None, :] + r * rim
