"""Independent regions around a prototype grasp, on any mesh, for any hand (beyond §5).

After Roa and Suárez (2009) and Krug et al. (2010): the prototype grasp is
force-closure, so the convex hull ``H`` of its generating wrenches holds the
origin inside. Shift every facet of ``H`` parallel to itself until it
passes through the origin. For each vertex ``v`` of ``H`` (a generating
wrench of some finger) the **search zone** is the open polyhedral cone

    ``Z_v = {w : a_k . w > 0 for every facet k of H at v}``,

``a_k`` the facet's outward normal. **Any grasp with a wrench in every
search zone is force-closure**: every direction ``a`` lies in the normal
cone of some vertex ``v``, ``a = sum lambda_k a_k`` over the facets at ``v``
with ``lambda >= 0``, so the wrench ``w`` in ``Z_v`` has ``a . w > 0``; no
direction is left unresisted, which is Theorem 1.

Each zone is assigned to the finger that made its vertex. On a planar face
a finger's generating wrenches are affine in the contact point (fixed
normal, torque ``p x f``), so the points where a chosen generator lies in
``Z_v`` form a convex polygon: the face cut by half-planes. A finger's
region grows from the prototype contact over neighbouring faces of the
mesh, patch by patch, while the patches stay connected; the proof checks
each patch's vertices (linear conditions, so that is exact).
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property
from typing import SupportsInt, cast

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import ConvexHull, QhullError

from ...contacts import MODELS, Cone, Model, primitive_wrenches
from ...errors import InputError
from ...geometry.clip import clip
from ...geometry.cones import pyramid_radius
from ...geometry.rings import signed_area
from ...objects.polyhedron import PlanarFace, Polyhedron
from ..regions import MARGIN, Certificate, check_margin, narrowed, proved_once
from .patches import FacePatch, SpatialRegions, convex_pieces, uniform_in_triangles

__all__ = ["AFFINE_BATCH", "EDGES", "MODELS", "ZONE_MARGIN", "Prototype", "SearchZones",
           "ZoneRegions", "best_prototypes", "finger_generators", "prototype_grasps",
           "prototype_samples", "search_zones", "surface_samples", "zone_regions"]

#: Edges of the inscribed friction pyramid (an inner approximation: regions stay valid
#: for the true circular cones).
EDGES = 8
#: Every zone condition holds with at least this margin, ``a_k . w >= ZONE_MARGIN``.
ZONE_MARGIN = 1e-6
#: Largest number of faces whose generators are computed in one call while growing.
AFFINE_BATCH = 4096


def finger_generators(model: str, mu: float, margin: float, edges: int = EDGES
                      ) -> tuple[str, float, bool]:
    """The generators a finger's patches are built and proved with, as
    ``(model, mu, every)``: with friction, the cone narrowed by ``margin``, of which one
    generator per zone is enough; frictionless, every force within ``margin`` of the
    normal, so *every* generator of the pyramid whose faces touch that cone (its edges
    at ``tan(margin) / cos(pi / edges)``) must lie in each zone.

    Examples
    --------
    >>> finger_generators("hard", 0.5, 0.0)
    ('hard', 0.5, False)
    >>> model, mu, every = finger_generators("frictionless", 0.0, 1e-3)
    >>> model, every, bool(mu * np.cos(np.pi / EDGES) >= np.tan(1e-3))
    ('hard', True, True)
    """
    if model != "frictionless":
        return model, narrowed(mu, margin), False
    if margin <= 0:
        return "frictionless", 0.0, False
    return "hard", pyramid_radius(math.tan(margin), edges, True) * (1 + 1e-12), True


@dataclass(frozen=True, eq=False)
class SearchZones:
    """The search zones of a force-closure prototype grasp.

    Attributes
    ----------
    wrenches : (m, 6) array
        The prototype's generating wrenches (torques about ``reference``,
        divided by ``length_scale``).
    finger, generator : (m,) int arrays
        Which finger, and which of its generators, made each wrench.
    facets : (K, 6) array
        Outward unit normals ``a_k`` of the wrench hull's facets.
    offsets : (K,) array
        ``b_k > 0``: the hull is ``{w : a_k . w <= b_k}``.
    simplices : (K, 6) int array
        The wrenches spanning each facet (Qhull's triangulated hull).
    neighbors : (K, 6) int array
        For each facet, the facet across the ridge opposite each of its wrenches.
    reference : (3,) array
    length_scale : float
    """

    wrenches: NDArray[np.float64]
    finger: NDArray[np.int64]
    generator: NDArray[np.int64]
    facets: NDArray[np.float64]
    offsets: NDArray[np.float64]
    simplices: NDArray[np.int64]
    neighbors: NDArray[np.int64]
    reference: NDArray[np.float64]
    length_scale: float

    @cached_property
    def at_vertex(self) -> tuple[NDArray[np.int64], ...]:
        """For each wrench, the facets it lies on (empty: not a hull vertex)."""
        at: list[list[int]] = [[] for _ in range(len(self.wrenches))]
        for f, simplex in enumerate(self.simplices.tolist()):
            for v in simplex:
                at[v].append(f)
        return tuple(np.array(a, dtype=np.int64) for a in at)

    def owned(self, finger: int) -> list[int]:
        """The hull vertices (wrench indices) whose zones ``finger`` must reach."""
        return [k for k in np.flatnonzero(self.finger == finger).tolist()
                if len(self.at_vertex[k])]

    def owned_facets(self, finger: int) -> tuple[list[int], NDArray[np.float64],
                                                 NDArray[np.int64]]:
        """:meth:`owned`, with the facets at those vertices stacked: ``(zones, A, starts)``,
        zone ``zones[i]``'s facets the rows ``starts[i]:starts[i + 1]`` of ``A``. Kept."""
        kept = self.__dict__.setdefault("_owned_facets", {})
        if finger not in kept:
            zones = self.owned(finger)
            sizes = [len(self.at_vertex[k]) for k in zones]
            at = np.concatenate([self.at_vertex[k] for k in zones]) if zones else np.zeros(
                0, dtype=np.int64)
            kept[finger] = (zones, self.facets[at], np.concatenate([[0], np.cumsum(sizes)]))
        return kept[finger]


def _generators(points: NDArray, normals: NDArray, model: str, mu: float, edges: int,
                reference: NDArray, scale: float) -> NDArray[np.float64]:
    """``(k, g, 6)`` generating wrenches of ``k`` contacts, inscribed pyramids."""
    k = len(points)
    W = primitive_wrenches(points, normals, cast(Model, model),  # the callers check it
                           np.full(k, mu), None,
                           np.broadcast_to(reference, (k, 3)), np.full(k, scale),
                           Cone(edges, "inscribed"))
    return np.transpose(W, (0, 2, 1))


def search_zones(points: ArrayLike, normals: ArrayLike, model: str = "hard", mu: float = 0.5,
                 edges: int = EDGES, reference: ArrayLike | None = None,
                 length_scale: float | None = None) -> SearchZones:
    """The search zones of a prototype grasp (Roa and Suárez 2009).

    Parameters
    ----------
    points, normals : (k, 3) arrays
        The prototype's contacts and outward normals.
    model : {"frictionless", "hard", "soft"}
    mu : float
    edges : int
        Edges of the inscribed friction pyramids.
    reference, length_scale :
        Torques are taken about ``reference`` (default: the contacts'
        centroid) and divided by ``length_scale`` (default: the largest
        distance from it), so the zones do not depend on units.

    Raises
    ------
    InputError
        If the prototype is not force-closure with the inscribed pyramids.

    Examples
    --------
    >>> import numpy as np
    >>> p = np.array([[1, 0, 0], [-1, 0.5, 0], [-1, -0.5, 0]])  # three fingers on a box
    >>> n = np.array([[1, 0, 0], [-1, 0, 0], [-1, 0, 0]])
    >>> z = search_zones(p, n, "hard", 0.5)
    >>> bool(np.all(z.offsets > 0)), len(z.owned(0)) > 0
    (True, True)
    """
    P = np.asarray(points, dtype=float)
    N = np.asarray(normals, dtype=float)
    if P.ndim != 2 or P.shape[1] != 3 or N.shape != P.shape:
        raise InputError(f"points and normals must both be (k, 3), got {P.shape} and {N.shape}")
    if model not in MODELS:
        raise InputError(f"model must be one of {', '.join(MODELS)}, got {model!r}")
    N = N / np.linalg.norm(N, axis=1, keepdims=True)
    ref = P.mean(axis=0) if reference is None else np.asarray(reference, dtype=float)
    scale = (float(np.linalg.norm(P - ref, axis=1).max()) if length_scale is None
             else float(length_scale)) or 1.0
    G = _generators(P, N, model, 0.0 if model == "frictionless" else mu, edges, ref, scale)
    k, g, _ = G.shape
    W = G.reshape(-1, 6)
    finger = np.repeat(np.arange(k), g)
    generator = np.tile(np.arange(g), k)
    try:
        hull = ConvexHull(W, qhull_options="Qt")
    except QhullError:
        raise InputError("the prototype grasp is not force-closure: its wrenches do not "
                         "span the six dimensions of wrench space") from None
    normal, offset = hull.equations[:, :6], -hull.equations[:, 6]
    if offset.min() <= 1e-9:
        raise InputError("the prototype grasp is not force-closure: the origin is not "
                         f"inside its wrench hull (closest facet at {offset.min():.3g})")
    return SearchZones(W, finger, generator, normal, offset, hull.simplices, hull.neighbors,
                       ref, scale)


def _affine_wrenches(face: PlanarFace, zones: SearchZones, model: str, mu: float,
                     edges: int) -> tuple[NDArray, NDArray, NDArray]:
    """A finger's generators on ``face`` as affine maps of plane coordinates:
    ``w(uv) = w0 + u wu + v wv``, each ``(g, 6)``."""
    return _affine_batch([face], zones, model, mu, edges)[0]


def _affine_batch(faces: list[PlanarFace], zones: SearchZones, model: str, mu: float,
                  edges: int) -> list[tuple[NDArray, NDArray, NDArray]]:
    """:func:`_affine_wrenches` of many faces in one call (the same numbers: the generators
    are computed row by row)."""
    origin = np.array([f.origin for f in faces])
    axes = np.array([f.axes for f in faces])  # (F, 2, 3)
    # the plane points (0, 0), (1, 0), (0, 1) of each face, as face.to_world makes them
    corners = np.stack([origin + 0.0, origin + axes[:, 0], origin + axes[:, 1]], axis=1)
    normals = np.repeat(np.array([f.normal for f in faces]), 3, axis=0)
    G = _generators(corners.reshape(-1, 3), normals, model, mu, edges, zones.reference,
                    zones.length_scale).reshape(len(faces), 3, -1, 6)
    return [(g[0], g[1] - g[0], g[2] - g[0]) for g in G]


@dataclass(frozen=True, eq=False)
class ZoneRegions(SpatialRegions):
    """Independent regions from a prototype grasp's search zones.

    Attributes
    ----------
    prototype : (k, 3) array
        The prototype grasp's contact points.
    zones : SearchZones
    choices : tuple of tuple of tuple of (int, int)
        For each finger and patch, the (zone, generator) pairs: which of the
        finger's generators reaches which zone there.
    edges : int
        Edges of the inscribed friction pyramids.
    """

    prototype: NDArray[np.float64] | None = None
    zones: SearchZones | None = None
    choices: tuple = ()
    edges: int = EDGES
    margin: float = 0.0

    @property
    def cone_mu(self) -> float:
        """The friction of the cones the regions are built and proved with: ``mu``'s cone
        narrowed by ``margin`` radians (:func:`~forceclosure.synthesis.regions.check_margin`);
        for frictionless fingers, the pyramid around every force within ``margin`` of the
        normal (:func:`finger_generators`)."""
        return finger_generators(self.model, self.mu, self.margin, self.edges)[1]

    @proved_once
    def certify(self) -> Certificate:
        """Exact on the pyramids: the prototype's hull is closed with the origin inside;
        at every vertex of every patch the chosen generator lies in its zone.

        The zone conditions are linear in the contact point on a face, so the
        vertices decide them; values too close to zero for floating point are
        decided in rational arithmetic.
        """
        return _zone_certificate(self)

    def to_dict(self) -> dict[str, object]:
        record = super().to_dict()
        record["prototype"] = None if self.prototype is None else self.prototype.tolist()
        record["margin"] = self.margin
        return record


def _hull_checks(z: SearchZones) -> str | None:
    """Why the facets do not bound a polytope around the origin, or None.

    Checked, not taken from Qhull on trust: every facet's plane passes
    through its own six wrenches and has every wrench on its inner side, the
    origin strictly inside; and the facets close up: across each ridge (a
    facet's wrenches but one) lies a neighbour that holds the ridge and names
    the facet back (the acceptance check of :mod:`forceclosure.kernels.hull`).
    Then the normals' cones at the vertices cover every direction, which is
    what the zones need.
    """
    if z.offsets.min() <= 0:
        return "the origin is not strictly inside the prototype's wrench hull"
    tol = 1e-9 * max(1.0, float(np.abs(z.wrenches).max()))
    slack = z.wrenches @ z.facets.T - z.offsets
    if slack.max() > tol:
        return "a prototype wrench lies outside a facet of its hull"
    if np.abs(np.take_along_axis(slack.T, z.simplices, axis=1)).max() > tol:
        return "a facet's plane misses one of its own wrenches"
    simplices = [set(s) for s in z.simplices.tolist()]
    for f, (simplex, across) in enumerate(zip(z.simplices.tolist(), z.neighbors.tolist(),
                                              strict=True)):
        for k, g in enumerate(across):
            ridge = set(simplex[:k] + simplex[k + 1:])
            if not (0 <= g < len(simplices) and f in z.neighbors[g] and ridge <= simplices[g]):
                return "the hull's facets do not close up (a ridge without its neighbour)"
    return None


def _zone_certificate(r: ZoneRegions) -> Certificate:
    z = r.zones
    if z is None:
        return Certificate(False, "search zones", "no search zones")
    problem = _hull_checks(z)
    if problem:
        return Certificate(False, "search zones", problem)
    if r.model != "frictionless":
        # the cones are narrowed by the margin; a face merged from triangles that turn by more
        # would leave a triangle whose own cone does not hold the generators
        turned = max((r.polyhedron.faces[p.face] for region in r.regions for p in region),
                     key=lambda f: f.spread)
        if turned.spread > r.margin:
            return Certificate(False, "search zones",
                               f"face {turned.index}'s triangles turn by {turned.spread:.3g} "
                               f"rad, more than the margin of {r.margin:g}")
    model, mu, every = finger_generators(r.model, r.mu, r.margin, r.edges)
    checked = _zone_conditions(r, z, model, mu, every)
    if checked is None:  # some value is close to zero or below: decide each one in turn
        failed, checked = _zone_conditions_one_by_one(r, z, model, mu, every)
        if failed is not None:
            return failed
    return Certificate(True, "search zones",
                       f"prototype hull closed around the origin ({len(z.facets)} facets); "
                       f"{checked} linear zone conditions hold at the patch vertices")


def _zone_conditions(r: ZoneRegions, z: SearchZones, model: str, mu: float,
                     every: bool) -> int | None:
    """How many zone conditions hold at the patch vertices, all at once: each finger's
    generators at every vertex of its patches in one call, then each (zone, generator)
    against the vertices of all the patches that chose it. ``None`` when some value is
    not clearly positive (then :func:`_zone_conditions_one_by_one` decides, exactly)."""
    faces = r.polyhedron.faces
    checked = 0
    for region, choices in zip(r.regions, r.choices, strict=True):
        counts = np.array([len(p.points) for p in region])
        points = np.vstack([p.points for p in region])
        normals = np.repeat(np.array([faces[p.face].normal for p in region]), counts, axis=0)
        G = _generators(points, normals, model, mu, r.edges, z.reference, z.length_scale)
        users: dict[tuple[int, int], list[int]] = {}
        for k, chosen in enumerate(choices):
            for zone, gen in chosen:
                for g in range(G.shape[1]) if every else [gen]:
                    users.setdefault((zone, g), []).append(k)
        for (zone, g), patches in users.items():
            mask = np.zeros(len(region), dtype=bool)
            mask[patches] = True
            values = G[np.repeat(mask, counts), g, :] @ z.facets[z.at_vertex[zone]].T
            checked += values.size
            if not np.all(values > 1e-9):
                return None
    return checked


def _zone_conditions_one_by_one(r: ZoneRegions, z: SearchZones, model: str, mu: float,
                                every: bool) -> tuple[Certificate | None, int]:
    """The zone conditions patch by patch, values near zero decided in rationals: the
    first that fails (as a certificate that does not hold), or None, and how many hold."""
    checked = 0
    for finger, (region, choices) in enumerate(zip(r.regions, r.choices, strict=True)):
        for patch, chosen in zip(region, choices, strict=True):
            face = r.polyhedron.faces[patch.face]
            G = _generators(patch.points, np.repeat(face.normal[None], len(patch.points), 0),
                            model, mu, r.edges, z.reference, z.length_scale)
            for zone, gen in chosen:
                for g in range(G.shape[1]) if every else [gen]:
                    values = G[:, g, :] @ z.facets[z.at_vertex[zone]].T  # (vertices, facets)
                    checked += values.size
                    for (vi, fi) in np.argwhere(values <= 1e-9):
                        if _exact_positive(patch.points[vi], face.normal, g, model, mu, r.edges,
                                           z, z.at_vertex[zone][fi]):
                            continue
                        return Certificate(False, "search zones",
                                           f"finger {finger + 1}: at {patch.points[vi].tolist()}"
                                           f" on face {patch.face} a wrench leaves its zone"
                                           ), checked
    return None, checked


def _exact_positive(point, normal, gen, model, mu, edges, z, facet) -> bool:
    """``a_k . w > 0`` in rationals, for the generator's wrench at ``point``."""
    G = _generators(point[None], normal[None], model, mu, edges, z.reference,
                    z.length_scale)[0, gen]
    force = [Fraction(x) for x in G[:3]]
    arm = [(Fraction(p) - Fraction(c)) / Fraction(z.length_scale)
           for p, c in zip(point, z.reference, strict=True)]
    torque = [arm[1] * force[2] - arm[2] * force[1], arm[2] * force[0] - arm[0] * force[2],
              arm[0] * force[1] - arm[1] * force[0]]
    if np.allclose(G[:3], 0):  # a pure torque (soft finger): no lever
        torque = [Fraction(x) for x in G[3:]]
    a = [Fraction(x) for x in z.facets[facet]]
    return sum(x * y for x, y in zip(a, force + torque, strict=True)) > 0


def _patch_for(face: PlanarFace, piece: NDArray, zones: SearchZones, finger: int,
               affine: tuple[NDArray, NDArray, NDArray], hint: NDArray | None,
               every: bool = False):
    """The part of a convex piece where the finger reaches all its zones, and the choices;
    ``affine`` is the finger's generators on the face (:func:`_affine_wrenches`), of which
    one per zone must lie in it, or ``every`` one (:func:`finger_generators`)."""
    w0, wu, wv = affine
    centre = piece.mean(axis=0) if hint is None else hint
    owned, A, starts = zones.owned_facets(finger)
    if not owned:
        return _kept(face, piece, [], [], ())
    # every zone's facets at once: (g, facets) values at the centre, and each generator's
    # least value in each zone (g, zones)
    depth = np.minimum.reduceat((w0 + centre[0] * wu + centre[1] * wv) @ A.T, starts[:-1],
                                axis=1)
    # in each zone the generator deepest in it; ties (symmetric pyramids make exact ones) go
    # to the lowest index, whatever the rounding, so that a moved or scaled object gets the
    # same choice
    deepest = depth.max(axis=0)
    gens = np.argmax(depth >= deepest - 1e-9 * np.abs(deepest), axis=0)
    reached = depth if every else depth[gens, np.arange(len(owned))]
    if reached.min() <= ZONE_MARGIN:
        return None, ()
    along_u, along_v, rhs = [], [], []
    for lo, hi, gen in zip(starts[:-1].tolist(), starts[1:].tolist(), gens.tolist(),
                           strict=True):
        # the half-planes, one product per generator as the zone's own (so that the
        # patches come out the same to the last bit whatever the other zones)
        facets = A[lo:hi].T
        for g in range(len(w0)) if every else [gen]:
            along_u.append(wu[g] @ facets)
            along_v.append(wv[g] @ facets)
            rhs.append(ZONE_MARGIN - w0[g] @ facets)
    rows = np.column_stack([np.concatenate(along_u), np.concatenate(along_v)])
    return _kept(face, piece, [rows], rhs, tuple(zip(map(int, owned), gens.tolist(),
                                                     strict=True)))


def _kept(face: PlanarFace, piece: NDArray, rows: list, rhs: list, chosen: tuple):
    """The piece cut by the half-planes ``rows . y >= rhs`` (lists of blocks), or nothing
    if too little is left."""
    ring = clip(piece, np.vstack(rows), np.concatenate(rhs)) if rows else piece
    if len(ring) < 3 or signed_area(ring) <= 1e-12 * face.plane_size ** 2:
        return None, ()
    return ring, tuple(chosen)


def _touch(a: FacePatch, b: FacePatch, tol: float) -> bool:
    """Whether two patches share a stretch of boundary (or, on one face, overlap)."""
    if a.face == b.face:
        return shapely.Polygon(a.uv).buffer(tol).intersection(shapely.Polygon(b.uv)).area > 0
    close = np.count_nonzero(_segment_distances(a.points, b.points) <= tol)
    close += np.count_nonzero(_segment_distances(b.points, a.points) <= tol)
    return bool(close >= 2)


def _segment_distances(points: NDArray, ring: NDArray) -> NDArray[np.float64]:
    """Distance from each of ``points`` ``(n, 3)`` to the closed polyline ``ring``."""
    d = np.concatenate((ring[1:], ring[:1])) - ring  # (k, 3) edges
    offset = points[:, None, :] - ring  # (n, k, 3)
    t = np.clip(np.einsum("nij,ij->ni", offset, d) / np.maximum(np.einsum("ij,ij->i", d, d),
                                                                 1e-300), 0, 1)
    return np.linalg.norm(t[:, :, None] * d - offset, axis=2).min(axis=1)


@dataclass(frozen=True, eq=False)
class Prototype:
    """A force-closure grasp found by sampling, around which regions are grown.

    Attributes
    ----------
    points : (k, 3) array
        The contact points.
    faces : tuple of int
        The face each point was drawn on. A point on a fin of zero thickness
        lies on two faces with opposite normals; the face says which side.
    epsilon : float
        Its Ferrari–Canny epsilon (the ranking of :func:`prototype_grasps`).
    """

    points: NDArray[np.float64]
    faces: tuple[int, ...]
    epsilon: float


def zone_regions(polyhedron: Polyhedron, prototype: Prototype | ArrayLike, model: str = "hard",
                 mu: float = 0.5, grow: bool = True, edges: int = EDGES,
                 max_patches: int = 5000, construction: str = "search zones",
                 margin: float = MARGIN, result: type[ZoneRegions] | None = None,
                 resolution: float = 0.0) -> ZoneRegions:
    """Independent regions around a force-closure prototype grasp on a polyhedron or mesh.

    Parameters
    ----------
    polyhedron : Polyhedron
        Any triangle mesh (its planar faces merged).
    prototype : Prototype or (k, 3) array
        A force-closure grasp: a :class:`Prototype` (its points stay on its
        faces), or contact points on the surface (each snapped to the
        nearest face).
    model : {"frictionless", "hard", "soft"}
    mu : float
    grow : bool
        Grow each region over neighbouring faces (curved meshes); otherwise
        each region stays on the convex piece of the prototype's face.
    edges : int
        Edges of the inscribed friction pyramids.
    max_patches : int
        Stop growing a region after this many patches.
    margin : float
        Radians each normal may turn: taken off every friction cone's
        half-angle; a frictionless finger holds for every force within it of
        the normal (:func:`finger_generators`); in the construction and in the
        proof (:func:`~forceclosure.synthesis.regions.check_margin`).
    result : type, optional
        The :class:`ZoneRegions` subclass to return (a construction's own).
    resolution : float
        The spacing of the doubles where the object stands, relative to its size
        (:attr:`~forceclosure.synthesis.construction.Hand.resolution`): the faces' convex
        pieces allow for corners rounded by that much (:func:`.patches.convex_pieces`).

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> cube = bundled("cube")
    >>> p = [[0, 0, 1], [0.3, 0.3, -1], [-0.3, -0.3, -1]]   # one finger on top, two below
    >>> r = zone_regions(cube, p, "hard", 0.5, grow=False)
    >>> r.certify().holds, [len(x) for x in r.regions]
    (True, [1, 1, 1])
    """
    pinned = prototype if isinstance(prototype, Prototype) else None
    P = np.asarray(prototype if pinned is None else pinned.points, dtype=float)
    if P.ndim != 2 or P.shape[1] != 3:
        raise InputError(f"points must be (k, 3), got shape {P.shape}")
    if pinned is not None:
        located = [(f, polyhedron.faces[f].to_plane(p), 0.0)
                   for f, p in zip(pinned.faces, P, strict=True)]
    else:
        located = [polyhedron.locate(p) for p in P]
    tol = 1e-6 * polyhedron.size
    for i, (_, _, dist) in enumerate(located):
        if dist > 1e-3 * polyhedron.size:
            raise InputError(f"prototype contact {i + 1} at {P[i].tolist()} is "
                             f"{dist:.3g} away from the surface")
    faces = [polyhedron.faces[f] for f, _, _ in located]
    P = np.array([f.to_world(uv) for f, (_, uv, _) in zip(faces, located, strict=True)])
    N = np.array([f.normal for f in faces])
    mu = 0.0 if model == "frictionless" else float(mu)
    margin = check_margin(margin)
    built, cone_mu, every = finger_generators(model, mu, margin, edges)
    zones = search_zones(P, N, model, 0.0 if every else cone_mu, edges)
    graph = polyhedron.face_neighbors if grow else {}
    rounding = resolution * polyhedron.size
    affines: dict[int, tuple[NDArray, NDArray, NDArray]] = {}  # by face, for every finger

    def affine_of(f_index: int, frontier) -> tuple[NDArray, NDArray, NDArray]:
        """The face's affine generators, computed with those of the faces waiting in the
        frontier (one call for many faces instead of one per face)."""
        if f_index not in affines:
            todo = dict.fromkeys([f_index, *(g for g, _ in frontier if g not in affines)])
            batch = [polyhedron.faces[g] for g in list(todo)[:AFFINE_BATCH]]
            for f, a in zip(batch, _affine_batch(batch, zones, built, cone_mu, edges),
                            strict=True):
                affines[f.index] = a
        return affines[f_index]

    regions, choices = [], []
    for finger, (face, (_, uv, _)) in enumerate(zip(faces, located, strict=True)):
        pieces = convex_pieces(face, rounding)
        start = _containing(pieces, uv)
        affine = affine_of(face.index, ())
        ring, chosen = _patch_for(face, pieces[start], zones, finger, affine, uv, every)
        if ring is None:  # the prototype point itself sits on a zone's boundary
            raise InputError(f"finger {finger + 1}: the prototype is too close to the "
                             "boundary of force closure to grow regions around it")
        patches = [FacePatch.on(face, ring)]
        picks = [chosen]
        by_face = {face.index: [patches[0]]}
        # the other pieces of the prototype's face, then neighbouring faces, breadth first
        frontier: deque[tuple[int, int | None]] = deque(
            [(face.index, k) for k in range(len(pieces)) if k != start] if grow else [])
        frontier += [(g, None) for g in sorted(graph.get(face.index, ()))]
        seen = {face.index}
        while frontier and grow and len(patches) < max_patches:
            f_index, which = frontier.popleft()
            if which is None and f_index in seen:
                continue
            f = polyhedron.faces[f_index]
            if which is None:
                seen.add(f_index)
            f_pieces = convex_pieces(f, rounding)
            f_affine = affine_of(f_index, frontier)
            added = False
            for k in (range(len(f_pieces)) if which is None else [which]):
                ring, chosen = _patch_for(f, f_pieces[k], zones, finger, f_affine, None, every)
                if ring is None:
                    continue
                patch = FacePatch.on(f, ring)
                near = [q for g in (f_index, *graph.get(f_index, ())) for q in by_face.get(g, ())]
                if any(_touch(patch, q, tol) for q in near):
                    patches.append(patch)
                    picks.append(chosen)
                    by_face.setdefault(f_index, []).append(patch)
                    added = True
            if added:
                frontier += [(g, None) for g in sorted(graph.get(f_index, ())) if g not in seen]
        regions.append(tuple(patches))
        choices.append(tuple(picks))
    return (result or ZoneRegions)(polyhedron, model, mu, tuple(regions), construction, P,
                                   zones, tuple(choices), edges, margin)


def _containing(pieces: list[NDArray], uv: NDArray) -> int:
    point = shapely.Point(uv)
    return int(np.argmin([shapely.Polygon(p).distance(point) for p in pieces]))


def surface_samples(polyhedron: Polyhedron, count: int, rng: np.random.Generator,
                    faces: ArrayLike | None = None) -> tuple[NDArray, NDArray]:
    """``count`` points uniformly distributed over the surface (or over ``faces``), and
    the face each lies on."""
    V, T = polyhedron.vertices, polyhedron.triangles
    label = polyhedron.face_of_triangle
    tris = np.arange(len(T)) if faces is None else np.flatnonzero(np.isin(label, faces))
    points, pick = uniform_in_triangles(V[T[tris, 0]], V[T[tris, 1]], V[T[tris, 2]], count,
                                        rng)
    return points, label[tris[pick]]


def prototype_grasps(polyhedron: Polyhedron, fingers: int, model: str = "hard",
                     mu: float = 0.5, count: int = 1, samples: int = 20_000, seed: int = 0,
                     faces: Iterable[SupportsInt] | None = None) -> list[Prototype]:
    """Force-closure prototype grasps found by sampling, best Ferrari–Canny epsilon first.

    ``samples`` random grasps (each finger uniform over the surface, or over
    its own face when ``faces`` gives one per finger) are analysed in a batch
    (:func:`forceclosure.analysis.batch.epsilon_batch`), and the ``count`` with the
    largest epsilon are returned.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> [p] = prototype_grasps(bundled("cube"), 2, "soft", 0.5, samples=2000)
    >>> float(abs(p.points[0] - p.points[1]).max()) == 2.0   # on opposite faces
    True
    """
    from ...analysis.batch import epsilon_batch

    P, F = prototype_samples(polyhedron, fingers, samples, seed, faces)
    N = np.array([f.normal for f in polyhedron.faces])[F]
    # ranked with the pyramids the search zones are built with (the coordinate axes')
    eps = epsilon_batch(P, N, mu=0.0 if model == "frictionless" else mu, model=model,
                        orientation="axes")
    return best_prototypes(P, F, eps, count)


def prototype_samples(polyhedron: Polyhedron, fingers: int, samples: int = 20_000,
                      seed: int = 0, faces: Iterable[SupportsInt] | None = None
                      ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The random grasps :func:`prototype_grasps` analyses: ``(samples, fingers, 3)``
    points and the face of each, drawn from ``seed`` alone (so that the grasps of many
    face tuples can be analysed in one batch and come out as each call would draw them).

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> P, F = prototype_samples(bundled("cube"), 3, 10, faces=[0, 1, 1])
    >>> P.shape, F[0].tolist()
    ((10, 3, 3), [0, 1, 1])
    """
    if fingers < 1:
        raise InputError(f"fingers must be at least 1, got {fingers}")
    if samples < 1:
        raise InputError(f"samples must be at least 1, got {samples}")
    rng = np.random.default_rng(seed)
    if faces is None:
        P, F = surface_samples(polyhedron, samples * fingers, rng)
        return P.reshape(samples, fingers, 3), F.reshape(samples, fingers)
    ids = [int(f) for f in faces]
    if len(ids) != fingers:
        raise InputError(f"{fingers} fingers need {fingers} faces, got {len(ids)}")
    parts = [surface_samples(polyhedron, samples, rng, [f]) for f in ids]
    return np.stack([p for p, _ in parts], axis=1), np.stack([f for _, f in parts], axis=1)


def best_prototypes(P: NDArray, F: NDArray, eps: NDArray, count: int = 1) -> list[Prototype]:
    """The ``count`` grasps of largest epsilon (ties to the first drawn), those closed."""
    order = np.argsort(-eps, kind="stable")
    return [Prototype(P[g], tuple(int(f) for f in F[g]), float(eps[g]))
            for g in order[:count] if eps[g] > 0]
