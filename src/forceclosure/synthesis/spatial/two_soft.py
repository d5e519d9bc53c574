"""Two soft fingers on two faces of a polyhedron (Nguyen 1988, §5.2).

Corollary 3 in space: soft fingers at ``p1`` (face normal ``n1``) and ``p2``
(``n2``) are force-closure iff ``x = p2 - p1`` lies strictly inside both
friction cones, ``x ∈ int C1`` (around ``-n1``) and ``x ∈ int(-C2)``
(around ``n2``): inside the **counter-overlapping cone** ``K = C1 ∩ -C2``.
Force-direction closure needs only the normals: ``K`` has an interior iff
the angle between ``-n1`` and ``n2`` is less than ``alpha1 + alpha2``.

Two regions ``R1``, ``R2`` are independent iff ``R2 - R1 ⊂ int K``. For
convex regions ``R2 - R1`` is the convex hull of the differences of their
vertices, and ``K`` is convex, so checking the vertex pairs is an **exact
certificate** (done here in rational arithmetic). Two constructions:

* ``"nguyen"``, the paper's: each face bounded by a disk, the largest
  circular cone ``K'`` inside ``K``, and a two-sided cone ``I ± K'`` whose
  vertex ``I`` lies between the faces; the regions are the disks cut by the
  two sides (Fig. 8).
* ``"maximal"``, beyond the paper: the regions are regular polygons
  ``c_i + r_i Q`` in the faces, ``K`` is replaced by inscribed pyramids
  (an inner approximation), and then every condition is linear in
  ``(c1, r1, c2, r2)``: the largest pair of equal regions is one linear
  program: the best regions of that shape, found about 140 times faster
  than the paper's vertex search. The two shapes differ (a polygon, a cut
  disk), so either may come out slightly larger (docs/synthesis.md).

Non-convex faces and faces with holes are covered by convex pieces
(:func:`~forceclosure.synthesis.spatial.patches.convex_pieces`) and every pair of
pieces is tried.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable
from dataclasses import dataclass
from fractions import Fraction
from typing import Literal, SupportsInt, overload

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import linprog, minimize

from ...errors import InputError
from ...geometry.clip import clip
from ...geometry.cones import counter_overlap, counter_overlap_angle, friction_forces
from ...geometry.rings import signed_area
from ...objects.polyhedron import PlanarFace, Polyhedron
from ..construction import Construction, Hand
from ..ranked_search import TIE
from ..regions import MARGIN, Certificate, narrowed, proved_once
from .patches import FacePatch, SpatialRegions, convex_pieces

__all__ = ["ANGLE_MARGIN", "PYRAMID_EDGES", "SIDES", "CircularCone", "SoftPairRegions",
           "counter_overlapping_cone", "soft_pair_construction", "soft_pair_regions"]

#: Default margin (radians) taken off each friction cone's half-angle.
ANGLE_MARGIN = MARGIN  # the one margin (regions.check_margin)
#: Sides of the regular polygons that the maximal construction fits.
SIDES = 16
#: Edges of the pyramids that stand in for circular cones in the linear program.
PYRAMID_EDGES = 32


@dataclass(frozen=True)
class CircularCone:
    """A circular cone ``{x : angle(x, axis) <= half_angle}``."""

    axis: NDArray[np.float64]
    half_angle: float

    def contains(self, x: ArrayLike) -> NDArray[np.bool_]:
        """Whether each vector of ``x`` lies strictly inside the cone."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        return x @ self.axis > np.linalg.norm(x, axis=1) * math.cos(self.half_angle)


def _unit(v: ArrayLike) -> NDArray[np.float64]:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def counter_overlapping_cone(n1: ArrayLike, mu1: float, n2: ArrayLike,
                             mu2: float | None = None) -> CircularCone | None:
    """The largest circular cone inside ``C1 ∩ -C2`` (§5.2), or None if they do not overlap.

    ``C1`` is the friction cone at a contact with outward normal ``n1``
    (axis ``-n1``, half-angle ``atan(mu1)``); ``-C2`` has axis ``n2``. With
    ``theta`` the angle between the axes, the largest cone inside both has
    half-angle ``(alpha1 + alpha2 - theta) / 2`` (or the smaller cone, if one
    contains the other), and its axis lies on the arc between theirs. None
    means the two soft fingers lack force-direction closure (Theorem 2): the
    cones do not counter-overlap
    (:func:`forceclosure.geometry.cones.counter_overlap`, the one test of that; this
    function adds the cone).

    Examples
    --------
    >>> k = counter_overlapping_cone([0, 0, 1], 0.5, [0, 0, -1])   # opposite faces
    >>> (k.axis + 0.0).tolist(), round(k.half_angle, 6) == round(math.atan(0.5), 6)
    ([0.0, 0.0, -1.0], True)
    >>> counter_overlapping_cone([0, 0, 1], 0.5, [1, 0, 0]) is None   # faces at a right angle
    True
    """
    mu2 = mu1 if mu2 is None else mu2
    if not counter_overlap(n1, n2, mu1, mu2):
        return None
    a, b = -_unit(n1), _unit(n2)
    a1, a2 = math.atan(mu1), math.atan(mu2)
    theta = float(counter_overlap_angle(n1, n2))
    if theta + min(a1, a2) <= max(a1, a2):  # one cone holds the other
        return CircularCone(a if a1 <= a2 else b, min(a1, a2))
    beta = (a1 + a2 - theta) / 2
    phi = a1 - beta  # from a towards b
    side = b - (a @ b) * a
    side = side / np.linalg.norm(side) if np.linalg.norm(side) > 0 else np.zeros(3)
    return CircularCone(math.cos(phi) * a + math.sin(phi) * side, beta)


def _pyramid_facets(axis: NDArray, half_angle: float, edges: int) -> NDArray[np.float64]:
    """Inward unit normals ``h`` of the pyramid inscribed in a circular cone:
    ``{x : h . x >= 0 for every h}``. Its edges are the friction pyramid of
    :func:`forceclosure.geometry.cones.friction_forces` about ``axis``."""
    g = friction_forces(-np.asarray(axis, dtype=float)[None], math.tan(half_angle), edges)[0]
    h = np.cross(g, np.roll(g, -1, axis=0))
    h *= np.sign(h @ axis)[:, None]
    return h / np.linalg.norm(h, axis=1, keepdims=True)


def _halfplanes(ring: NDArray) -> tuple[NDArray, NDArray]:
    """``(N, c)`` with the convex CCW ring = ``{y : N y <= c}``."""
    d = np.roll(ring, -1, axis=0) - ring
    outward = np.column_stack([d[:, 1], -d[:, 0]])
    return outward, np.einsum("ij,ij->i", outward, ring)


@dataclass(frozen=True, eq=False)
class SoftPairRegions(SpatialRegions):
    """Independent regions for two soft fingers on two faces (§5.2).

    Attributes
    ----------
    apex : (3,) array or None
        Vertex ``I`` of the two-sided cone (Nguyen's construction only).
    """

    apex: NDArray[np.float64] | None = None

    @proved_once
    def certify(self) -> Certificate:
        """Exact: every vertex pair ``(a, b)`` has ``b - a`` strictly inside both friction
        cones (Corollary 3), decided in rational arithmetic; every vertex lies on its face.
        Each cone is narrowed by its face's ``spread``, so the proof holds for the normal of
        every triangle the face was merged from."""
        f1, f2 = (self.polyhedron.faces[r[0].face] for r in self.regions)
        # each cone narrowed by its face's spread: it then lies inside the cone around the
        # normal of every triangle of the face
        mu1, mu2 = (Fraction(narrowed(self.mu, f.spread)) for f in (f1, f2))
        n1 = [Fraction(x) for x in f1.normal]
        n2 = [Fraction(x) for x in f2.normal]
        nn1, nn2 = (sum(c * c for c in n) for n in (n1, n2))  # not exactly 1 in floats
        A = [[Fraction(x) for x in p] for p in self.regions[0][0].points]
        B = [[Fraction(x) for x in p] for p in self.regions[1][0].points]
        for (i, a), (j, b) in itertools.product(enumerate(A), enumerate(B)):
            x = [bb - aa for aa, bb in zip(a, b, strict=True)]
            norm2 = sum(c * c for c in x)
            d1 = sum(c * n for c, n in zip(x, n1, strict=True))
            d2 = sum(c * n for c, n in zip(x, n2, strict=True))
            if not (d1 < 0 < d2 and d1 * d1 * (1 + mu1 * mu1) > norm2 * nn1
                    and d2 * d2 * (1 + mu2 * mu2) > norm2 * nn2):
                return Certificate(False, "exact vertex pairs",
                                   f"vertex {i} of region 1 and vertex {j} of region 2: the "
                                   "segment between them leaves a friction cone")
        for k, (patch, face) in enumerate(((self.regions[0][0], f1), (self.regions[1][0], f2))):
            if not _on_face(patch, face):
                return Certificate(False, "exact vertex pairs",
                                   f"region {k + 1} leaves face {face.index}")
        pairs = len(A) * len(B)
        return Certificate(True, "exact vertex pairs",
                           f"all {pairs} vertex pairs strictly inside both friction cones "
                           "(rational arithmetic); regions convex, so every pair of points is")


def _on_face(patch: FacePatch, face: PlanarFace) -> bool:
    # relative to the face, and never below the rounding of its coordinates (far from the
    # origin a float point cannot lie closer to a slanted plane than that)
    tol = 1e-9 * max(face.polygon.size, 1e-300) + 8 * float(np.spacing(
        np.abs(face.origin).max()))
    plane = np.abs((patch.points - face.origin) @ face.normal).max() <= tol
    inside = shapely.covers(face.polygon.to_shapely().buffer(tol), shapely.points(patch.uv))
    return bool(plane and np.all(inside))


@overload
def check_faces(poly: Polyhedron, faces: Iterable[SupportsInt],
                 count: Literal[2]) -> tuple[int, int]: ...
@overload
def check_faces(poly: Polyhedron, faces: Iterable[SupportsInt],
                 count: Literal[3]) -> tuple[int, int, int]: ...
def check_faces(poly: Polyhedron, faces: Iterable[SupportsInt], count: int) -> tuple[int, ...]:
    """``count`` face indices of ``poly`` as ints, or one InputError line naming the wrong
    count or the missing face."""
    names = {2: "two", 3: "three", 7: "seven"}
    ids = tuple(int(f) for f in faces)
    if len(ids) != count:
        raise InputError(f"{names.get(count, count)} fingers need {count} faces, got {ids}")
    for f in ids:
        if not 0 <= f < len(poly.faces):
            raise InputError(f"{poly.name}: no face {f}; faces are numbered 0 to "
                             f"{len(poly.faces) - 1}")
    return ids


def check_mu_margin(mu: float, margin: float) -> None:
    """Refuse, in one line, a friction coefficient that is not positive and finite, or an
    angular margin outside ``[0, atan(mu))``."""
    if not (math.isfinite(mu) and mu > 0):
        raise InputError(f"mu must be a positive number, got {mu!r}")
    if not 0 <= margin < math.atan(mu):
        raise InputError(f"margin must be at least 0 and below atan(mu) = "
                         f"{math.atan(mu):.4g}, got {margin!r}")


def _regular(sides: int) -> NDArray[np.float64]:
    t = 2 * np.pi * (np.arange(sides) + 0.5) / sides
    return np.column_stack([np.cos(t), np.sin(t)])


def _maximal(f1: PlanarFace, f2: PlanarFace, ring1: NDArray, ring2: NDArray,
             facets: NDArray, axis: NDArray, size: float, sides: int) -> tuple[float, NDArray,
                                                                               NDArray] | None:
    """The largest equal regular polygons ``c_i + r Q`` in two convex pieces with every
    difference inside the pyramid cone ``{h . x >= 0}``: a linear program."""
    Q = _regular(sides)
    # variables: c1 (2), r1, c2 (2), r2, t
    rows, rhs = [], []
    A1, A2 = f1.axes, f2.axes
    base = f2.origin - f1.origin
    for h in [*facets, axis]:
        g1, g2 = A1 @ h, A2 @ h  # h . (c A) = g . c
        # h.(b - a) = h.base + g2.c2 - g1.c1 + r2 min_q g2.q - r1 max_q g1.q >= floor
        floor = 1e-6 * size if h is axis else 0.0
        rows.append([*g1, (Q @ g1).max(), *(-g2), -(Q @ g2).min(), 0.0])
        rhs.append(float(h @ base) - floor)
    for ring, offset in ((ring1, 0), (ring2, 3)):
        N, c = _halfplanes(ring)
        for normal, bound in zip(N, c, strict=True):
            row = [0.0] * 7
            row[offset:offset + 3] = [*normal, (Q @ normal).max()]
            rows.append(row)
            rhs.append(float(bound))
    rows += [[0, 0, -1, 0, 0, 0, 1], [0, 0, 0, 0, 0, -1, 1]]
    rhs += [0.0, 0.0]
    res = linprog([0, 0, 0, 0, 0, 0, -1], A_ub=np.array(rows), b_ub=np.array(rhs),
                  bounds=[(None, None)] * 2 + [(0, None)] + [(None, None)] * 2
                  + [(0, None)] * 2, method="highs")
    if res.status != 0 or res.x[6] <= 1e-9 * size:
        return None
    # the largest radius is one number, its centres often a family (parallel faces): of those,
    # the ones nearest (L1) the pieces' middles, so that a moved copy gets its regions in the
    # same places, not wherever its rounding tips the solver; variables x (7) and d (4),
    # |x_c - middle| <= d
    middles = [*ring1.mean(axis=0), *ring2.mean(axis=0)]
    A = np.hstack([np.array(rows), np.zeros((len(rows), 4))])
    pick = np.zeros((4, 11))
    pick[[0, 1, 2, 3], [0, 1, 3, 4]] = 1.0
    pick[:, 7:] = -np.eye(4)
    flip = pick.copy()
    flip[:, :7] *= -1
    least = np.zeros(11)
    least[6] = -1.0  # t >= r (1 - 1e-9)
    A = np.vstack([A, pick, flip, least])
    b = np.concatenate([rhs, middles, -np.array(middles), [-res.x[6] * (1 - 1e-9)]])
    second = linprog(np.r_[np.zeros(7), np.ones(4)], A_ub=A, b_ub=b,
                     bounds=[(None, None)] * 2 + [(0, None)] + [(None, None)] * 2
                     + [(0, None)] * 2 + [(0, None)] * 4, method="highs")
    x = second.x if second.status == 0 else res.x
    r = x[6]  # both regions at the common radius: the smaller one bounds the tolerance
    return r, x[0:2] + r * Q, x[3:5] + r * Q


def _cut(disk: NDArray, face: PlanarFace, facets: NDArray, apex: NDArray,
         sign: float) -> NDArray[np.float64]:
    """The disk polygon on ``face`` cut by the cone side ``apex + sign P`` (``P`` the
    pyramid ``{h . x >= 0}``): ``origin + uv A`` is in it iff
    ``sign (A h) . uv >= sign h . (apex - origin)`` for every facet ``h``."""
    return clip(disk, sign * facets @ face.axes.T, sign * facets @ (apex - face.origin))


def _nguyen(f1: PlanarFace, f2: PlanarFace, ring1: NDArray, ring2: NDArray,
            cone: CircularCone) -> tuple[float, NDArray, NDArray, NDArray] | None:
    """The paper's construction: disks bounding the pieces, the two-sided cone ``I ± K'``
    with the vertex that maximises the smaller of the two cut regions."""
    disks = []
    for ring in (ring1, ring2):
        N, c = _halfplanes(ring)
        scale = np.linalg.norm(N, axis=1)
        res = linprog([0, 0, -1], A_ub=np.column_stack([N, scale]), b_ub=c,
                      bounds=[(None, None), (None, None), (0, None)], method="highs")
        disks.append((res.x[:2], res.x[2]))
    circle = _regular(64)
    polys = [centre + radius * circle for centre, radius in disks]
    facets = _pyramid_facets(cone.axis, cone.half_angle, PYRAMID_EDGES)
    o1, o2 = f1.to_world(disks[0][0]), f2.to_world(disks[1][0])

    def worst(apex):
        return -min(signed_area(_cut(polys[0], f1, facets, apex, -1.0)),
                    signed_area(_cut(polys[1], f2, facets, apex, 1.0)))

    scale = float(np.linalg.norm(o2 - o1))
    for s in (0.5, 0.25, 0.75):  # the middle first; the others only if it sees nothing
        best = minimize(worst, o1 + s * (o2 - o1), method="Nelder-Mead",
                        options={"xatol": 1e-6 * scale, "fatol": 1e-9 * scale**2,
                                 "maxiter": 400})
        if best.fun < 0:
            break
    else:
        return None
    apex = best.x
    return (-best.fun, _cut(polys[0], f1, facets, apex, -1.0),
            _cut(polys[1], f2, facets, apex, 1.0), apex)


def soft_pair_regions(polyhedron: Polyhedron, face1: int, face2: int, mu: float,
                      margin: float = ANGLE_MARGIN,
                      construction: str = "maximal", sides: int = SIDES,
                      certified: bool = True) -> SoftPairRegions | None:
    """Independent regions for two soft fingers on two faces (§5.2), or None.

    Parameters
    ----------
    polyhedron : Polyhedron
    face1, face2 : int
        The faces, indices into ``polyhedron.faces``.
    mu : float
        Friction coefficient of both fingers.
    margin : float
        Radians taken off each cone's half-angle, so that every grasp in the
        regions is strictly force-closure.
    construction : {"maximal", "nguyen"}
        The linear program over regular polygons, or the paper's two-sided
        cone between disks.
    sides : int
        Sides of the maximal construction's polygons.
    certified : bool
        Return the regions only if their exact certificate holds (the search
        of :func:`soft_pair_construction` proves only those it returns).

    Returns
    -------
    SoftPairRegions or None
        None when the faces admit no force-closure grasp with margin, or none
        that the exact certificate proves.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> cube = bundled("cube")   # side 2; faces 0 and 1 are opposite
    >>> r = soft_pair_regions(cube, 0, 1, mu=0.5)
    >>> r.certify().holds, round(r.min_area, 2)   # 16-gons of radius about tan(alpha) = 0.5
    (True, 0.76)
    >>> soft_pair_regions(cube, 0, 2, mu=0.5) is None   # adjacent faces at a right angle
    True
    """
    face1, face2 = check_faces(polyhedron, (face1, face2), 2)
    if face1 == face2:
        raise InputError(f"two fingers need two different faces, got {face1} twice")
    check_mu_margin(mu, margin)
    if construction not in ("maximal", "nguyen"):
        raise InputError(f"construction must be 'maximal' or 'nguyen', got {construction!r}")
    f1, f2 = polyhedron.faces[face1], polyhedron.faces[face2]
    a1 = math.atan(mu) - margin
    cone = counter_overlapping_cone(f1.normal, math.tan(a1), f2.normal, math.tan(a1))
    if cone is None:
        return None
    size = polyhedron.size
    if construction == "maximal":
        facets = np.vstack([_pyramid_facets(-f1.normal, a1, PYRAMID_EDGES),
                            _pyramid_facets(f2.normal, a1, PYRAMID_EDGES)])
    best = None  # (score, ring1, ring2[, apex]) of the best pair of convex pieces
    for ring1, ring2 in itertools.product(convex_pieces(f1), convex_pieces(f2)):
        found = (_maximal(f1, f2, ring1, ring2, facets, cone.axis, size, sides)
                 if construction == "maximal" else _nguyen(f1, f2, ring1, ring2, cone))
        # a later pair of pieces must beat the best by more than a tie (ranked_search.TIE):
        # pieces of equal regions (an L's two arms) keep the first, wherever the object stands
        if found is not None and (best is None or found[0] > best[0] * (1 + TIE)):
            best = found
    if best is None:
        return None
    patches = ((FacePatch.on(f1, best[1]),), (FacePatch.on(f2, best[2]),))
    apex = best[3] if len(best) == 4 else None  # Nguyen's construction gives its apex
    regions = SoftPairRegions(polyhedron, "soft", float(mu), patches, construction, apex)
    return regions if not certified or regions.certify().holds else None


def face_pair_sites(polyhedron: Polyhedron, hand: Hand):
    """Step 1: every pair of faces ``i < j``, as rows."""
    i, j = np.triu_indices(len(polyhedron.faces), k=1)
    yield np.stack([i, j], axis=1).astype(np.int64)


def counter_overlapping_prune(polyhedron: Polyhedron, sites: NDArray,
                              hand: Hand) -> NDArray[np.bool_]:
    """Step 2: the two cones, narrowed by the margin, can counter-overlap: ``-n_i`` and
    ``n_j`` less than ``2 alpha`` apart (necessary for :func:`counter_overlapping_cone`)."""
    normals = np.array([f.normal for f in polyhedron.faces])
    alpha = math.atan(hand.mu) - hand.margin
    return counter_overlap(normals[sites[:, 0]], normals[sites[:, 1]],
                           math.tan(max(alpha, 0.0)))


def _inscribed_bound(factor: float):
    """Step 3: the largest region inside a disk of radius ``r`` (the smaller face's
    inscribed disk) is ``factor r²``: a regular polygon's, or the disk's."""
    def bound(polyhedron: Polyhedron, sites: NDArray, hand: Hand) -> NDArray:
        inradius = {int(f): _inradius(polyhedron.faces[f]) for f in np.unique(sites)}
        r = np.array([min(inradius[int(a)], inradius[int(b)]) for a, b in sites])
        return factor * r**2 / polyhedron.size**2
    return bound


def soft_pair_construction(construction: str, sides: int = SIDES) -> Construction:
    """The table's construction for two soft fingers on faces (§5.2): the search steps of
    :func:`soft_pair_regions` with ``construction`` (``"maximal"`` or ``"nguyen"``) and
    ``sides`` (the table's entries, :data:`MAXIMAL` and :data:`NGUYEN`, have the default).

    Every pair of faces is screened by force-direction closure of its normals
    (vectorised over all pairs); the pairs left are visited in decreasing order of an upper
    bound on their regions (the smaller inscribed disk of the two faces), and the search
    stops when the bound falls below the ``top``-th region found: branch and bound.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import synthesize
    >>> found = synthesize(bundled("cube"), 2, "soft", 0.5, top=3,
    ...                    construction=soft_pair_construction("maximal", sides=8)).found
    >>> [sorted(r.faces[0] + r.faces[1]) for r in found]   # the three pairs of opposite faces
    [[0, 1], [2, 4], [3, 5]]

    References
    ----------
    V.-D. Nguyen, "Constructing force-closure grasps", IJRR 7(3), 1988, §5.2.
    """
    def build(polyhedron: Polyhedron, site: NDArray, hand: Hand) -> SoftPairRegions | None:
        return soft_pair_regions(polyhedron, int(site[0]), int(site[1]), hand.mu,
                                 margin=hand.margin, construction=construction, sides=sides,
                                 certified=False)

    factor = sides * math.tan(math.pi / sides) if construction == "maximal" else math.pi
    return Construction(
        dim=3, fingers=2, contact="soft", name=construction,
        paper="§5.2" + (", two-sided cone" if construction == "nguyen" else ""),
        method="faces", sites=face_pair_sites, prune=counter_overlapping_prune,
        bound=_inscribed_bound(factor), build=build,
        searched="every pair of faces whose friction cones can counter-overlap")


MAXIMAL = soft_pair_construction("maximal")
NGUYEN = soft_pair_construction("nguyen")


def _inradius(face: PlanarFace) -> float:
    """An upper bound on the radius of any disk inside the face: the largest inscribed
    circle found by shapely, plus its tolerance."""
    shape = face.polygon.to_shapely()
    tolerance = 1e-3 * face.polygon.size
    return float(shapely.maximum_inscribed_circle(shape, tolerance).length) + tolerance
