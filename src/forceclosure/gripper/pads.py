"""Where flat, slightly compliant pads touch a mesh when the jaws close.

A parallel-jaw finger does not touch the object where a ray from its pad's
centre meets it: its pad is a flat rectangle, and closing along the jaws'
axis it first meets the object at the highest point within the pad's
footprint; on a curved surface met at a slant that is on the pad's rim,
and a point contact at the centre would put the rest of the pad inside the
object. A real pad then presses on, as an elastic layer ``compliance``
deep (pressure proportional to the local penetration, a Winkler
foundation): :func:`pad_contacts` takes the part of the surface within
``compliance`` of the first touch as the pressed region, its centre of
pressure, and, as the contact, the pressed point nearest that centre (in
the pad's plane), with the outward normal of the face it lies on (a normal
the surface has there; at an edge or vertex, one of its faces'). Only faces
turned towards the pad are pressed (those turned away lie behind them), so
a contact's normal always opposes its pad's push. On a curved surface the
contact stays by the first touch, where the surface faces the pad; on a
flat face pressed flat it is the pad's centre; with ``compliance`` 0 it is
a first-touch point. The passes are exact on the mesh as given
(:mod:`forceclosure.kernels.pads`).

The pad resists twisting about the contact's normal by friction over the
pressed region: at most ``μ`` times the normal force times the region's
pressure-weighted mean distance from the normal's axis through the contact
(``lever``). That mean is taken from below (the distance is convex, so the
centre of pressure of each small piece of the pressed polygons stands for
its points: Jensen), so the torsion a label relies on is never more than the
pressed pad gives.

In the jaw frame (x the approach axis, y the closing axis, z = x × y, the
origin on the line the jaws close along), the pad is the rectangle ``x ∈
[depth - pad_length, depth]``, ``z ∈ [-pad_height / 2, pad_height / 2]``
(its far edge at the fingertips, ``depth`` past the line). Jaw 1 closes
along +y, so its first touch is the lowest ``y`` of the surface over the
rectangle and its pressed layer ``y ≤ first + compliance``; jaw 2's are the
highest and ``y ≥ first - compliance``. ``y`` is affine on each triangle, so
the first touch over a triangle clipped to the rectangle is at one of the
clipped polygon's corners, and the pressed part of a triangle is a convex
polygon (the triangle clipped to the rectangle and the layer).

The contact's wrenches are among those of the pressed region (a point of
it, with a normal the surface has there), so a verdict of force closure for
the contact pair holds for the pads as they press.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..kernels import announce_compiling
from ..kernels.pads import (
    line_pairs,
    minimum_at,
    pad_extremes,
    pad_lever,
    pad_nearest,
    pad_pressure,
    pad_touch,
)

__all__ = ["COINCIDE_RTOL", "PadContacts", "line_candidates", "pad_contacts", "pad_reach"]

#: Pads whose first touches are closer than this share of the object's size hold nothing
#: (two contacts that nearly coincide, across a crease or a sliver).
COINCIDE_RTOL = 1e-6

#: The thinnest pressed layer, relative to the object's size (rigid pads: the first touch,
#: to rounding).
TIE_RTOL = 1e-9

#: Each pressed polygon's fan triangles are split into 4 ** this pieces for the torsional
#: lever's lower bound (:func:`pad_contacts`; finer pieces, a tighter bound).
LEVER_SPLITS = 2

#: Pairs of (pose, triangle) handled at a time.
BLOCK = 1 << 17


@dataclass(frozen=True, eq=False)
class PadContacts:
    """The first touches of ``M`` poses' two pads.

    ``points`` and ``normals`` are ``(M, 2, 3)`` (jaw 1's contact, then
    jaw 2's; outward unit normals), ``triangles`` ``(M, 2)`` (the triangle
    touched; -1 where nothing is under the pad), ``touched`` ``(M,)``:
    whether anything of the object lies under the pads, ``first`` ``(M, 2)``:
    where along the closing axis (from the pose's origin) each pad first
    touches: the pads' faces as the jaws meet the object; ``lever`` ``(M, 2)``:
    the pressure-weighted mean distance of the pressed region from the axis of
    the contact's normal, from below (:func:`pad_contacts`): the pad's
    torsional friction per unit normal force and friction coefficient.
    """

    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    triangles: NDArray[np.int64]
    touched: NDArray[np.bool_]
    first: NDArray[np.float64]
    lever: NDArray[np.float64]

    def holds(self, width_max: float, size: float) -> NDArray[np.bool_]:
        """Whether each pose's pads hold the object: both touch it, no wider apart than
        ``width_max`` and not nearly at one point (:data:`COINCIDE_RTOL` of ``size``)."""
        width = self.first[:, 1] - self.first[:, 0]
        return self.touched & (width <= width_max) & (width >= COINCIDE_RTOL * size)


def pad_reach(depth: ArrayLike, pad_length: float, pad_height: float) -> float:
    """How far from its closing line a pad reaches at the fingertip ``depth`` (one or
    several): the farthest corner of its rectangle (:func:`line_candidates`' radius)."""
    depth = np.asarray(depth, dtype=float)
    if not depth.size:
        return 0.5 * float(pad_height)
    return float(np.hypot(np.maximum(np.abs(depth), np.abs(depth - pad_length)).max(),
                          0.5 * pad_height))


def line_candidates(mesh, origins: NDArray, directions: NDArray, radius: float | NDArray
                    ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """``(line, triangle)`` pairs: the triangles that may come within ``radius`` (one, or
    one per line) of each line (through ``origins[i]`` along the unit
    ``directions[i]``), by their bounding spheres about their centroids; a superset,
    never missing one."""
    V, F = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces)
    centroid = V[F].mean(axis=1)
    spread = np.sqrt(((V[F] - centroid[:, None]) ** 2).sum(axis=2).max(axis=1))
    radius = np.ascontiguousarray(np.broadcast_to(np.asarray(radius, dtype=float),
                                                  (len(origins),)))
    announce_compiling(line_pairs)
    return line_pairs(centroid, spread, np.ascontiguousarray(origins, dtype=float),
                      np.ascontiguousarray(directions, dtype=float), radius)


def pad_contacts(mesh, origin: NDArray, closing: NDArray, approach: NDArray, depth: NDArray,
                 pad_length: float, pad_height: float, pose_of: NDArray, tri_of: NDArray,
                 size: float, compliance: float = 0.0, levers: bool = True, *,
                 engine: str = "fused") -> PadContacts:
    """The contacts of the two pads of ``M`` jaw poses (module text).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        The object's outer surface, faces oriented outward.
    origin, closing, approach : (M, 3) arrays
        Each pose's point on the closing line, unit closing axis (jaw 1 → jaw 2), and
        unit approach axis perpendicular to it.
    depth : (M,) array
        How far past the closing line the fingertips (the pads' far edges) reach.
    pad_length, pad_height : float
        The pads' size along the approach axis and across it.
    pose_of, tri_of : (K,) int arrays
        The (pose, triangle) pairs to test: every triangle that may lie under a pose's
        pads must be among its pairs (:func:`line_candidates` gives a superset).
    size : float
        The object's size (the pressed layer is at least :data:`TIE_RTOL` of it thick).
    compliance : float
        How deep a pad presses past its first touch.
    levers : bool
        Compute the torsional levers (False: zeros; the contacts are the same).
    engine : {"fused", "batched"}
        "fused": one compiled pass over the poses
        (:func:`~forceclosure.kernels.pads.pad_touch`; pairs given by pose, as
        :func:`line_candidates` gives them, else "batched"); "batched": a kernel per step
        over all the pairs. The same results to the bit.

    Examples
    --------
    A square pad 0.5 wide closing on the 2-unit cube's x faces, tilted by 0.1
    rad about z: rigid, jaw 1 first meets the face x = -1 with the pad's rim,
    and the contact is there; pressing 0.01 deep, at the centre of pressure of
    the pressed strip along the rim (a third of its width in); pressing 0.05,
    the whole pad presses, hardest at the rim, and the contact is a third of
    the pad in.

    >>> import trimesh
    >>> cube = trimesh.creation.box(extents=[2, 2, 2])
    >>> c = np.array([[np.cos(0.1), np.sin(0.1), 0.0]])
    >>> a = np.array([[0.0, 0.0, 1.0]])
    >>> for press in (0.0, 0.01, 0.05):
    ...     pc = pad_contacts(cube, np.zeros((1, 3)), c, a, np.array([0.25]), 0.5, 0.5,
    ...                       np.zeros(12, int), np.arange(12), 3.46, press)
    ...     print(pc.points[0, 0].round(4).tolist(), pc.normals[0, 0].tolist())
    [-1.0, -0.3516, 0.0] [-1.0, 0.0, 0.0]
    [-1.0, -0.3182, 0.0] [-1.0, 0.0, 0.0]
    [-1.0, -0.1846, 0.0] [-1.0, 0.0, 0.0]
    """
    V, F = np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces)
    FN = np.asarray(mesh.face_normals, dtype=float)
    m = len(origin)
    side_axis = np.cross(approach, closing)
    R = np.stack([approach, closing, side_axis], axis=1)  # rows: the frame's axes, (M, 3, 3)
    points = np.zeros((m, 2, 3))
    normals = np.zeros((m, 2, 3))
    triangles = np.full((m, 2), -1, np.int64)
    touched = np.zeros(m, bool)
    if m == 0 or not len(pose_of):
        return PadContacts(points, normals, triangles, touched, np.zeros((m, 2)),
                           np.zeros((m, 2)))
    depth = np.asarray(depth, dtype=float)
    args = (float(pad_length), float(pad_height))
    press = max(float(compliance), TIE_RTOL * size)
    pose_of, tri_of = np.asarray(pose_of, dtype=np.int64), np.asarray(tri_of, dtype=np.int64)
    if engine not in ("fused", "batched"):
        raise InputError(f"engine must be 'fused' or 'batched', got {engine!r}")
    if engine == "fused" and np.all(pose_of[1:] >= pose_of[:-1]):  # pairs by pose
        announce_compiling(pad_touch)
        starts = np.searchsorted(pose_of, np.arange(m + 1))
        contiguous = [np.ascontiguousarray(a, dtype=float) for a in (origin, closing, depth)]
        return PadContacts(*pad_touch(V, F, np.ascontiguousarray(FN), starts, tri_of,
                                      contiguous[0], np.ascontiguousarray(R), contiguous[1],
                                      contiguous[2], *args, press, bool(levers), LEVER_SPLITS,
                                      BLOCK))
    announce_compiling(pad_extremes, pad_pressure, pad_nearest, pad_lever, minimum_at)
    first = np.full((m, 2), np.inf)
    for lo in range(0, len(pose_of), BLOCK):
        pi, ti = pose_of[lo:lo + BLOCK], tri_of[lo:lo + BLOCK]
        minimum_at(first, pi, pad_extremes(V, F, pi, ti, origin, R, depth, *args))
    touched = np.isfinite(first).all(axis=1)
    lever = np.zeros((m, 2))
    facing = np.einsum("ij,ij->i", FN[tri_of], closing[pose_of])
    for jaw in (0, 1):
        level = np.where(touched, first[:, jaw] + press, 0.0) * (1.0 if jaw == 0 else -1.0)
        # only faces turned towards the pad are pressed (those turned away lie behind them)
        toward = facing < 0 if jaw == 0 else facing > 0
        pose_j, tri_j = pose_of[toward], tri_of[toward]
        # the centre of pressure of the pressed layer (x, z), then its nearest pressed point
        moments = np.zeros((m, 3))
        for lo in range(0, len(pose_j), BLOCK):
            pi, ti = pose_j[lo:lo + BLOCK], tri_j[lo:lo + BLOCK]
            part = pad_pressure(V, F, pi, ti, origin, R, depth, *args, level, jaw)
            for k in range(3):
                moments[:, k] += np.bincount(pi, weights=part[:, k], minlength=m)
        centre = np.zeros((m, 2))
        loaded = moments[:, 0] > 0
        centre[loaded] = moments[loaded, 1:] / moments[loaded, :1]
        centre[~loaded, 0] = depth[~loaded] - 0.5 * pad_length  # a layer of no area
        best = np.full(m, np.inf)
        found = []
        for lo in range(0, len(pose_j), BLOCK):
            pi, ti = pose_j[lo:lo + BLOCK], tri_j[lo:lo + BLOCK]
            dist, pt = pad_nearest(V, F, pi, ti, origin, R, depth, *args, level, jaw, centre)
            minimum_at(best, pi, dist)
            found.append((pi, ti, dist, pt))
        for pi, ti, dist, pt in found:
            win = np.flatnonzero(np.isfinite(dist) & (dist <= best[pi]))
            # the first pair reaching the least distance, per pose
            pose, at = np.unique(pi[win][::-1], return_index=True)
            win = win[::-1][at]
            fresh = triangles[pose, jaw] < 0
            pose, win = pose[fresh], win[fresh]
            points[pose, jaw] = origin[pose] + np.einsum("nji,nj->ni", R[pose], pt[win])
            normals[pose, jaw] = FN[ti[win]]
            triangles[pose, jaw] = ti[win]
        if not levers:
            continue
        # the pressed region's mean lever about the contact's normal, from below (the
        # lever is convex in the point: Jensen over small pieces of the pressed polygons)
        lever_sum = np.zeros(m)
        local = np.einsum("nij,nj->ni", R, points[:, jaw] - origin)
        axis = np.einsum("nij,nj->ni", R, normals[:, jaw])
        for lo in range(0, len(pose_j), BLOCK):
            pi, ti = pose_j[lo:lo + BLOCK], tri_j[lo:lo + BLOCK]
            lever_sum += np.bincount(pi, minlength=m, weights=pad_lever(
                V, F, pi, ti, origin, R, depth, *args, level, jaw, local, axis, LEVER_SPLITS))
        lever[:, jaw] = np.where(loaded, lever_sum / np.where(loaded, moments[:, 0], 1.0),
                                 0.0)
    touched &= (triangles >= 0).all(axis=1)
    levels = np.where(touched[:, None], first * np.array([1.0, -1.0]), 0.0)
    return PadContacts(points, normals, triangles, touched, levels, lever)
