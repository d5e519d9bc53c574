"""Seven frictionless fingers on faces of a polyhedron (Nguyen 1988, §5.5).

A frictionless finger at ``p`` on a face with outward normal ``n`` pushes
with the single wrench ``w(p) = (-n, p x -n)``, **affine in p**. Seven
wrenches in ``R^6`` of rank 6 have a one-dimensional null space, spanned by
the signed minors ``C_i = (-1)^i det(W without column i)``, and
``sum C_i w_i = 0`` always. So the grasp is force-closure (Theorem 1) iff
the seven ``C_i`` are nonzero with one sign (a nonzero minor gives rank 6).

A determinant is linear in each column, so ``C_i`` is **multi-affine** in the
six other contact points: affine in each one when the others are held. Over
a product of convex polygons such a function takes its extreme values at
vertex tuples. Hence: if every ``C_i`` has the same strict sign at every
tuple of region vertices, every choice of one point per region is
force-closure. That is the exact certificate of :class:`SevenRegions`,
decided in floating point where that is safe and in rationals otherwise.

The regions themselves come from a prototype's search zones
(:mod:`.zones`), whose conditions are linear for frictionless fingers, each
cut down to at most :data:`MAX_CORNERS` corners so that the vertex tuples
stay few (``6^6`` per minor). Prototypes are found by sampling, which is the
paper's search over face 7-tuples with its ``O(n^c c 2^c)`` cost replaced by
the batch analysis of random grasps.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..objects.polyhedron import Polyhedron
from .patches import FacePatch
from .regions import Certificate
from .zones import Prototype, ZoneRegions, prototype_grasps, zone_regions

#: Corners kept per region, so that a minor is checked at ``MAX_CORNERS ** 6`` tuples.
MAX_CORNERS = 6
#: Floating-point determinants smaller than this (relative to Hadamard's bound) are
#: recomputed in rational arithmetic.
FILTER = 1e-9


def _wrench(p: NDArray, n: NDArray) -> NDArray:
    f = np.broadcast_to(-n, p.shape)
    return np.concatenate([f, np.cross(p, f)], axis=-1)


def _fewer_corners(patch: FacePatch, face, keep: int) -> FacePatch:
    """Drop corners, the one losing least area first, until ``keep`` remain (the result
    lies inside the patch)."""
    uv = patch.uv
    while len(uv) > keep:
        prev, nxt = np.roll(uv, 1, axis=0), np.roll(uv, -1, axis=0)
        a, b = uv - prev, nxt - uv
        loss = np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        uv = np.delete(uv, int(np.argmin(loss)), axis=0)
    return FacePatch.on(face, uv)


def _det_exact(M: NDArray) -> Fraction:
    """Determinant in rationals (Bareiss-free Gaussian elimination on Fractions)."""
    A = [[Fraction(x) for x in row] for row in M]
    n, det = len(A), Fraction(1)
    for c in range(n):
        pivot = next((r for r in range(c, n) if A[r][c] != 0), None)
        if pivot is None:
            return Fraction(0)
        if pivot != c:
            A[c], A[pivot] = A[pivot], A[c]
            det = -det
        det *= A[c][c]
        for r in range(c + 1, n):
            f = A[r][c] / A[c][c]
            if f:
                A[r] = [x - f * y for x, y in zip(A[r], A[c], strict=True)]
    return det


def cofactor_signs(regions: tuple[NDArray, ...], normals: NDArray,
                   turn: ArrayLike | None = None) -> tuple[int, int, int]:
    """The signs of the seven signed minors at every tuple of region vertices.

    Parameters
    ----------
    regions : seven (k_i, 3) arrays
        Each region's vertices in object coordinates.
    normals : (7, 3) array
    turn : (7,) array, optional
        Radians each finger's normal may turn (a face merged from triangles
        whose normals differ by up to its ``spread``). A minor then counts
        only when it is farther from zero than any such turn can move it:
        a turn of ``t`` moves the column ``(f, p x f)`` by at most
        ``2 sin(t / 2) sqrt(1 + |p|^2)``, and a determinant whose columns
        move by ``e_k`` moves by at most ``prod(|m_k| + e_k) - prod(|m_k|)``
        (multilinearity and Hadamard's inequality). Minors too close count
        as zero.

    Returns
    -------
    (positive, negative, zero) : counts over all minors and vertex tuples.
    """
    W = [_wrench(np.asarray(r, dtype=float), normals[i]) for i, r in enumerate(regions)]
    turn = np.zeros(7) if turn is None else np.asarray(turn, dtype=float)
    shift = [2 * np.sin(turn[i] / 2) * np.sqrt(1 + np.sum(np.asarray(r, float) ** 2, axis=1))
             for i, r in enumerate(regions)]
    pos = neg = zero = 0
    for i in range(7):
        others = [k for k in range(7) if k != i]
        combos = np.array(list(itertools.product(*[range(len(W[k])) for k in others])))
        M = np.stack([W[k][combos[:, c]] for c, k in enumerate(others)], axis=2)  # (t, 6, 6)
        d = np.linalg.det(M) * (-1) ** i
        norms = np.linalg.norm(M, axis=1)  # (t, 6): the columns' lengths
        bound = np.prod(norms, axis=1)  # Hadamard
        moved = np.stack([shift[k][combos[:, c]] for c, k in enumerate(others)], axis=1)
        reach = bound * np.expm1(np.sum(np.log1p(moved / norms), axis=1))  # how far turns go
        unsure = np.abs(d) <= FILTER * bound
        for t in np.flatnonzero(unsure):
            d[t] = float(np.sign(_det_exact(M[t]))) * (-1) ** i
        d[np.abs(d) <= 1.001 * reach + FILTER * bound * (reach > 0)] = 0.0
        pos += int((d > 0).sum())
        neg += int((d < 0).sum())
        zero += int((d == 0).sum())
    return pos, neg, zero


@dataclass(frozen=True, eq=False)
class SevenRegions(ZoneRegions):
    """Independent regions for seven frictionless fingers on faces (§5.5)."""

    def certify(self) -> Certificate:
        """Exact: the seven signed minors keep one strict sign at every tuple of region
        vertices; they are multi-affine in the contact points, so they keep it
        everywhere in the regions. A face merged from triangles whose normals differ
        (its ``spread``) counts a minor only when no such turn of the normal can
        reach zero (:func:`cofactor_signs`)."""
        corners = tuple(region[0].points for region in self.regions)
        faces = [self.polyhedron.faces[r[0].face] for r in self.regions]
        normals = np.array([f.normal for f in faces])
        pos, neg, zero = cofactor_signs(corners, normals, [f.spread for f in faces])
        total = pos + neg + zero
        if zero == 0 and (pos == 0 or neg == 0):
            return Certificate(True, "exact multi-affine minors",
                               f"all 7 signed minors {'positive' if pos else 'negative'} at "
                               f"all {total} vertex tuples")
        return Certificate(False, "exact multi-affine minors",
                           f"of {total} minor values at vertex tuples: {pos} positive, "
                           f"{neg} negative, {zero} zero")


def seven_frictionless_regions(polyhedron: Polyhedron,
                               prototype: Prototype | ArrayLike) -> SevenRegions:
    """Independent regions for seven frictionless fingers around a prototype grasp (§5.5).

    Parameters
    ----------
    polyhedron : Polyhedron
    prototype : Prototype or (7, 3) array
        A force-closure prototype: one contact per finger, on the surface.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import prototype_grasps
    >>> cube = bundled("cube")
    >>> [p] = prototype_grasps(cube, 7, "frictionless", samples=5000)
    >>> r = seven_frictionless_regions(cube, p)
    >>> r.certify().holds, len({q[0].face for q in r.regions}) == 6   # Fig. 11: all faces
    (True, True)
    """
    P = np.asarray(prototype.points if isinstance(prototype, Prototype) else prototype,
                   dtype=float)
    if P.shape != (7, 3):
        raise InputError(f"seven frictionless fingers need seven points (7, 3), got shape "
                         f"{P.shape}")
    r = zone_regions(polyhedron, prototype, "frictionless", 0.0, grow=False,
                     construction="search zones on faces, minors certified (§5.5)")
    regions = tuple((_fewer_corners(region[0], polyhedron.faces[region[0].face],
                                    MAX_CORNERS),) for region in r.regions)
    r = replace(r, regions=regions)
    return SevenRegions(**{f: getattr(r, f) for f in r.__dataclass_fields__})


def best_seven_frictionless_regions(polyhedron: Polyhedron, top: int = 3,
                                    samples: int = 20_000, seed: int = 0
                                    ) -> list[SevenRegions]:
    """The ``top`` grasps by seven frictionless fingers with the largest regions.

    Random seven-point grasps are analysed in a batch; the best by epsilon
    (one per set of faces) become prototypes, and each gets its regions.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> found = best_seven_frictionless_regions(bundled("cube"), top=1, samples=5000)
    >>> len(found), found[0].certify().holds
    (1, True)
    """
    if top < 1:
        raise InputError(f"top must be at least 1, got {top}")
    candidates = prototype_grasps(polyhedron, 7, "frictionless", 0.0, count=20 * top,
                                  samples=samples, seed=seed)
    found, seen = [], set()
    for p in candidates:
        faces = tuple(sorted(p.faces))
        if faces in seen:
            continue
        seen.add(faces)
        try:
            r = seven_frictionless_regions(polyhedron, p)
        except InputError:
            continue
        if r.certify().holds:
            found.append(r)
        if len(found) >= 3 * top:
            break
    return sorted(found, key=lambda r: -r.min_area)[:top]
