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

import dataclasses
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from ...errors import InputError
from ...objects.polyhedron import Polyhedron
from ..construction import Construction, Hand
from ..regions import MARGIN, Certificate, check_margin, proved_once
from .patches import FacePatch
from .zones import Prototype, ZoneRegions, prototype_grasps, zone_regions

__all__ = ["BISECTIONS", "FILTER", "MAX_CORNERS", "SMALLEST", "SevenRegions",
           "cofactor_signs", "minors_hold",
           "seven_frictionless_regions"]

#: Corners kept per region, so that a minor is checked at ``MAX_CORNERS ** 6`` tuples.
MAX_CORNERS = 6
#: The smallest shrinking of the regions tried, and the bisection steps above it.
SMALLEST, BISECTIONS = 1.0 / 64, 5
#: Floating-point determinants smaller than this (relative to Hadamard's bound) are
#: recomputed in rational arithmetic.
FILTER = 1e-9


def _minors_matrices(P: NDArray, N: NDArray) -> NDArray:
    """``(t, 6, 6)``: for each tuple, the frictionless wrenches ``(-n, p x -n)`` as columns."""
    f = np.broadcast_to(-N, P.shape)
    return np.concatenate([f, np.cross(P, f)], axis=2).transpose(0, 2, 1)


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


def _vertex_tuples(sizes: list[int]) -> NDArray[np.int64]:
    """Every tuple of vertex indices, one per region, as rows."""
    grids = np.meshgrid(*[np.arange(k) for k in sizes], indexing="ij")
    return np.stack([g.ravel() for g in grids], axis=1)


def _reach(M: NDArray, d: NDArray, P: NDArray, N: NDArray, turn: NDArray) -> NDArray:
    """An upper bound on how far the minors ``d = det(M)`` move when each column's normal
    turns by up to ``turn`` (see :func:`cofactor_signs`)."""
    norms = np.linalg.norm(M, axis=1)  # (t, 6): the columns' lengths
    adj = d[:, None, None] * np.linalg.inv(M)  # row k: the gradient of det in column k
    # a column (f, p x f) with f = -n' changes det at the rate h . df, h = g_f + g_tau x p
    h = adj[:, :, :3] + np.cross(adj[:, :, 3:], P)
    along = np.einsum("tkj,kj->tk", h, N)
    across = np.linalg.norm(h - along[..., None] * N, axis=2)
    linear = np.sum(np.sin(turn) * across + (1 - np.cos(turn)) * np.abs(along), axis=1)
    # the terms of two or more moved columns, by Hadamard: |e_k| <= |df| sqrt(1 + |p|^2)
    r = 2 * np.sin(turn / 2) * np.sqrt(1 + np.sum(P**2, axis=2)) / norms
    sym = np.zeros((len(d), 7))
    sym[:, 0] = 1.0
    for k in range(6):  # elementary symmetric sums of r
        sym[:, 1:] = sym[:, 1:] + r[:, k:k + 1] * sym[:, :-1]
    return linear + np.prod(norms, axis=1) * np.sum(sym[:, 2:], axis=1)


def _minor_signs(regions: tuple[NDArray, ...], normals: NDArray, turn: NDArray,
                 i: int) -> NDArray:
    """Signs (+1, -1, or 0 where not sure) of the i-th signed minor at every vertex tuple
    of the six other regions."""
    others = [k for k in range(7) if k != i]
    combos = _vertex_tuples([len(regions[k]) for k in others])
    P = np.stack([regions[k][combos[:, c]] for c, k in enumerate(others)], axis=1)  # (t,6,3)
    N = normals[others]
    if not turn[others].any():
        M = _minors_matrices(P, N)
        d = np.linalg.det(M)
        unsure = np.abs(d) <= FILTER * np.prod(np.linalg.norm(M, axis=1), axis=1)
        for t in np.flatnonzero(unsure):
            exact = _det_exact(M[t])
            d[t] = float((exact > 0) - (exact < 0))
        return np.sign(d) * (-1) ** i
    # Moving the origin and scaling the torques multiply every minor by one positive number:
    # bound in centred, unit-size coordinates, where Hadamard's bound is not swamped by far
    # or large coordinates.
    centre = np.mean(np.concatenate(regions), axis=0)
    size = max(float(np.max(np.abs(np.concatenate(regions) - centre))), 1e-300)
    P = (P - centre) / size
    M = _minors_matrices(P, N)
    d = np.linalg.det(M)
    bound = np.prod(np.linalg.norm(M, axis=1), axis=1)
    sure = np.abs(d) > FILTER * bound
    reach = np.full_like(d, np.inf)
    reach[sure] = _reach(M[sure], d[sure], P[sure], N, turn[others])
    # twice the bound: room for the rounding of the inverse where |d| > FILTER * bound
    return np.where(np.abs(d) > 2 * reach + FILTER * bound, np.sign(d), 0.0) * (-1) ** i


def cofactor_signs(regions: tuple[NDArray, ...], normals: NDArray,
                   turn: ArrayLike | None = None) -> tuple[int, int, int]:
    """The signs of the seven signed minors at every tuple of region vertices.

    Parameters
    ----------
    regions : seven (k_i, 3) arrays
        Each region's vertices in object coordinates.
    normals : (7, 3) array
    turn : (7,) array, optional
        Radians each finger's normal may turn (the margin, plus a face's
        ``spread`` when it was merged from triangles whose normals differ).
        A minor then counts only when no such turn can move it to zero. A
        determinant is linear in each column, and the column ``(f, p x f)``
        linear in the force ``f = -n'``; so a turn moves the minor by its
        gradient along the turn (sine of the turn across the normal, one minus
        its cosine along it) plus the terms in which two or more columns
        move, each bounded by Hadamard's inequality with ``|df| <= 2 sin(t/2)``.
        Without ``turn`` the signs are exact (rational arithmetic where
        floating point is in doubt).

    Returns
    -------
    (positive, negative, zero) : counts over all minors and vertex tuples;
        ``zero`` counts minors that are zero or that a turn could make zero.

    Examples
    --------
    The cube of ``examples/spatial.json`` (side 2), seven fingers on its six faces
    (Fig. 11): every minor has one sign for these normals, and for every normal within
    1e-3 rad of them, but not within 0.1 rad.

    >>> import numpy as np
    >>> points = np.array([[0, .5, -1], [.5, 0, 1], [-.5, -1, .5], [.5, -1, .5],
    ...                    [1, -.5, .5], [-.5, 1, 0], [-1, 0, 0]])
    >>> normals = np.array([[0, 0, -1], [0, 0, 1], [0, -1, 0], [0, -1, 0], [1, 0, 0],
    ...                     [0, 1, 0], [-1, 0, 0]])
    >>> cofactor_signs(tuple(p[None] for p in points), normals)
    (7, 0, 0)
    >>> cofactor_signs(tuple(p[None] for p in points), normals, 1e-3)
    (7, 0, 0)
    >>> cofactor_signs(tuple(p[None] for p in points), normals, 0.1)[2] > 0
    True
    """
    normals = np.asarray(normals, dtype=float)
    regions = tuple(np.asarray(r, dtype=float) for r in regions)
    turn = np.zeros(7) if turn is None else np.broadcast_to(np.asarray(turn, float), (7,))
    signs = [_minor_signs(regions, normals, turn, i) for i in range(7)]
    return (sum(int((s > 0).sum()) for s in signs), sum(int((s < 0).sum()) for s in signs),
            sum(int((s == 0).sum()) for s in signs))


def minors_hold(regions: tuple[NDArray, ...], normals: NDArray, turn: ArrayLike) -> bool:
    """Whether the seven signed minors keep one strict sign at every vertex tuple for every
    turn of the normals up to ``turn`` (:func:`cofactor_signs`), stopping at the first
    minor that does not."""
    normals = np.asarray(normals, dtype=float)
    regions = tuple(np.asarray(r, dtype=float) for r in regions)
    turn = np.broadcast_to(np.asarray(turn, float), (7,))
    sign = 0.0
    for i in range(7):
        s = _minor_signs(regions, normals, turn, i)
        if np.any(s == 0) or np.any(s != s[0]) or s[0] == -sign:
            return False
        sign = s[0]
    return True


@dataclass(frozen=True, eq=False)
class SevenRegions(ZoneRegions):
    """Independent regions for seven frictionless fingers on faces (§5.5)."""

    @proved_once
    def certify(self) -> Certificate:
        """Exact: the seven signed minors keep one strict sign at every tuple of region
        vertices; they are multi-affine in the contact points, so they keep it
        everywhere in the regions. With a ``margin``, and on a face merged from
        triangles whose normals differ (its ``spread``), a minor counts only when no
        turn of the normal by the margin plus the spread can reach zero
        (:func:`cofactor_signs`)."""
        corners, normals, turn = self._minors_input()
        pos, neg, zero = cofactor_signs(corners, normals, turn)
        total = pos + neg + zero
        within = f" for normals turned by up to {self.margin:g} rad" if self.margin else ""
        if zero == 0 and (pos == 0 or neg == 0):
            return Certificate(True, "exact multi-affine minors",
                               f"all 7 signed minors {'positive' if pos else 'negative'} at "
                               f"all {total} vertex tuples{within}")
        return Certificate(False, "exact multi-affine minors",
                           f"of {total} minor values at vertex tuples{within}: {pos} "
                           f"positive, {neg} negative, {zero} zero or within reach of zero")

    def _minors_input(self) -> tuple[tuple[NDArray, ...], NDArray, NDArray]:
        faces = [self.polyhedron.faces[r[0].face] for r in self.regions]
        return (tuple(region[0].points for region in self.regions),
                np.array([f.normal for f in faces]),
                np.array([self.margin + f.spread for f in faces]))


def _shrunk(patch: FacePatch, face, towards: NDArray, scale: float) -> FacePatch:
    return FacePatch.on(face, towards + scale * (patch.uv - towards))


def seven_frictionless_regions(polyhedron: Polyhedron, prototype: Prototype | ArrayLike,
                               margin: float = MARGIN) -> SevenRegions:
    """Independent regions for seven frictionless fingers around a prototype grasp (§5.5).

    The prototype's search zones give the regions; each is cut to at most
    :data:`MAX_CORNERS` corners and, where the minors do not keep their sign
    for every normal turned by ``margin``, shrunk towards the prototype
    (bisection on one common scale) until they do. The result is certified
    unless even a tiny neighbourhood of the prototype is not robust.

    Parameters
    ----------
    polyhedron : Polyhedron
    prototype : Prototype or (7, 3) array
        A force-closure prototype: one contact per finger, on the surface.
    margin : float
        Radians each normal may turn (:func:`~forceclosure.synthesis.regions.check_margin`).

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
    margin = check_margin(margin)
    P = np.asarray(prototype.points if isinstance(prototype, Prototype) else prototype,
                   dtype=float)
    if P.shape != (7, 3):
        raise InputError(f"seven frictionless fingers need seven points (7, 3), got shape "
                         f"{P.shape}")
    r = zone_regions(polyhedron, prototype, "frictionless", 0.0, grow=False,
                     construction="search zones on faces, minors certified (§5.5)",
                     result=SevenRegions)
    assert isinstance(r, SevenRegions)
    faces = [polyhedron.faces[region[0].face] for region in r.regions]
    patches = [_fewer_corners(region[0], face, MAX_CORNERS)
               for region, face in zip(r.regions, faces, strict=True)]
    centres = []
    for patch, face, p in zip(patches, faces, P, strict=True):
        uv = face.to_plane(p)
        inside = shapely.Polygon(patch.uv).covers(shapely.Point(uv))
        centres.append(uv if inside else patch.uv.mean(axis=0))
    normals = np.array([f.normal for f in faces])
    turn = np.array([margin + f.spread for f in faces])

    def at(scale: float) -> tuple[tuple[FacePatch], ...]:
        return tuple((_shrunk(q, f, c, scale),) for q, f, c in zip(patches, faces, centres,
                                                                    strict=True))

    def holds(scale: float) -> bool:
        return minors_hold(tuple(q[0].points for q in at(scale)), normals, turn)

    scale = 1.0
    if not holds(1.0):
        low, high = 0.0, 1.0
        if holds(SMALLEST):
            low = SMALLEST
            for _ in range(BISECTIONS):
                mid = (low + high) / 2
                low, high = (mid, high) if holds(mid) else (low, mid)
        scale = max(low, SMALLEST)
    return dataclasses.replace(r, regions=at(scale), margin=margin)


def _prototype_sites(polyhedron: Polyhedron, hand: Hand):
    """Step 1: the best ``20 top`` of ``samples`` random grasps by epsilon, one per set of
    faces."""
    seen: set[tuple[int, ...]] = set()
    sites = []
    for p in prototype_grasps(polyhedron, 7, "frictionless", 0.0, count=20 * hand.top,
                              samples=hand.samples, seed=hand.seed):
        if (faces := tuple(sorted(p.faces))) not in seen:
            seen.add(faces)
            sites.append(p)
    yield sites


def _build(polyhedron: Polyhedron, prototype: Prototype, hand: Hand) -> SevenRegions | None:
    try:
        return seven_frictionless_regions(polyhedron, prototype, hand.margin)
    except InputError:  # a prototype on the boundary of closure
        return None


SEVEN = Construction(
    dim=3, fingers=7, contact="frictionless", name="maximal", paper="§5.5", method="faces",
    sites=_prototype_sites, build=_build, enough=3,
    searched="around the best sampled seven-finger grasps by epsilon, one per set of faces")
