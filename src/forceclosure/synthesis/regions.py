"""Independent regions of contact, whatever construction made them, and their proof."""

from __future__ import annotations

import builtins  # builtins.object in annotations inside classes with an `object` property
import functools
import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Literal, SupportsInt, TypeVar, overload

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..objects.polygon import Edge, Polygon

__all__ = ["MARGIN", "TRIMS", "Certificate", "RegionSet", "Regions", "check_edges",
           "check_margin", "exact_inward", "exact_point", "face_middle", "first_proved",
           "narrowed", "proved_once", "rounded", "surely_positive", "tie_rounded"]

_COUNT = {2: "two", 3: "three", 4: "four"}

#: The default margin, in radians: every grasp in the regions stays force-closure when each
#: contact normal turns by up to this angle (see :func:`check_margin`).
MARGIN = 1e-3

#: Fractions of a region's length cut from each of its ends, tried in turn until its proof
#: holds: the optimum of a linear program lies on the boundary of what is force-closure, and
#: rounding (the solver's tolerance, coordinates far from the origin) can put a corner just
#: outside. One cut of 1e-9 is not enough where a region touches a friction cone's boundary
#: with a tiny margin, or where the coordinates round by more than 1e-9 of an edge; the cuts
#: grow by four up to about 0.4 %, the most a region is cut before its site is reported as
#: undecided.
TRIMS = (0.0, *(1e-9 * 4.0 ** k for k in range(12)))


def check_margin(margin: float) -> float:
    """The one meaning of ``margin`` in every construction, validated.

    ``margin`` is an angle in radians: the regions stay force-closure when the
    normal at every contact turns by up to ``margin`` (a finger placed on a
    slightly different surface, or a model of the object slightly off). A
    finger with friction is built with its cone narrowed by ``margin``
    (half-angle ``atan(mu) - margin``), which lies inside the cone around
    every normal within ``margin``; a frictionless finger is built so that
    every force direction within ``margin`` of its normal works.

    Examples
    --------
    >>> check_margin(1e-3)
    0.001
    >>> check_margin(2)
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: margin must be an angle in radians between 0 and pi/2, \
got 2
    """
    if not (isinstance(margin, int | float) and not isinstance(margin, bool)
            and 0 < margin < math.pi / 2):
        raise InputError(f"margin must be an angle in radians between 0 and pi/2, got "
                         f"{margin!r}")
    return float(margin)


def narrowed(mu: float, margin: float) -> float:
    """The friction coefficient of the cone narrowed by ``margin`` radians (0 when nothing
    is left of it); ``mu`` itself for no margin, and otherwise rounded down a little, so that
    a proof with it never rests on a cone wider than the narrowed one.

    Examples
    --------
    >>> round(narrowed(1.0, math.pi / 8), 6)   # tan(pi/4 - pi/8)
    0.414214
    >>> narrowed(0.3, 0.0)
    0.3
    """
    if margin <= 0:
        return mu
    return math.tan(max(math.atan(mu) - margin, 0.0)) * (1 - 1e-14)


#: Weights of a direction no face of a construction's LP lies across (square roots of primes):
#: its two extremes on the optimal face are unique vertices.
_GENERIC = np.sqrt([2.0, 3.0, 5.0, 7.0, 11.0, 13.0, 17.0, 19.0, 23.0, 29.0, 31.0])


def face_middle(A_ub: NDArray, b_ub: NDArray, bounds: list, x: NDArray, z_index: int,
                ) -> NDArray[np.float64]:
    """A point of a maximising LP's optimal face that does not depend on which vertex the
    solver returned: the middle of the face's two extremes along a generic direction.

    The LP maximises ``x[z_index]`` subject to ``A_ub @ x <= b_ub`` and ``bounds``; ``x`` is
    its optimum. When the largest regions can slide (the face is not a vertex), the solver's
    vertex depends on rounding, and a moved copy of the object gets its regions elsewhere.
    With ``x[z_index]`` held within 1e-9 (relative) of the optimum, the extremes of a generic
    linear function are two definite vertices; their middle is feasible (the feasible set is
    convex) and within 1e-9 of the optimum. ``x`` itself when a solve fails.

    Examples
    --------
    >>> A = np.array([[1.0, 1.0]]); b = np.array([1.0])   # u + z <= 1: u slides in [0, 1 - z]
    >>> face_middle(A, b, [(0, None), (0, 0.5)], np.array([0.0, 0.5]), 1).round(9).tolist()
    [0.25, 0.5]
    """
    from scipy.optimize import linprog

    x = np.asarray(x, float)
    n = len(x)
    weights = np.resize(_GENERIC, n)
    weights[z_index] = 0.0
    held = list(bounds)
    z = float(x[z_index])
    held[z_index] = (z - 1e-9 * max(abs(z), 1e-300), held[z_index][1])
    ends = []
    for sign in (1.0, -1.0):
        res = linprog(sign * weights, A_ub=A_ub, b_ub=b_ub, bounds=held, method="highs")
        if res.status != 0:
            return x
        ends.append(res.x)
    return 0.5 * (ends[0] + ends[1])


@overload
def check_edges(polygon: Polygon, edges: Iterable[SupportsInt],
                count: Literal[2]) -> tuple[int, int]: ...
@overload
def check_edges(polygon: Polygon, edges: Iterable[SupportsInt],
                count: Literal[3]) -> tuple[int, int, int]: ...
@overload
def check_edges(polygon: Polygon, edges: Iterable[SupportsInt],
                count: Literal[4]) -> tuple[int, int, int, int]: ...
def check_edges(polygon: Polygon, edges: Iterable[SupportsInt], count: int) -> tuple[int, ...]:
    """``count`` different edge indices of ``polygon``, or one InputError line saying why."""
    ids = tuple(int(e) for e in edges)
    if len(ids) != count or len(set(ids)) != count:
        raise InputError(f"{_COUNT[count]} fingers need {_COUNT[count]} different edges, "
                         f"got {ids}")
    for e in ids:
        if not 0 <= e < len(polygon.edges):
            raise InputError(f"{polygon.name}: no edge {e}; edges are numbered 0 to "
                             f"{len(polygon.edges) - 1}")
    return ids


def exact_inward(edge: Edge) -> list[Fraction]:
    """The edge's inward normal direction in exact rationals, not of unit length.

    The outward normal of the edge vector ``(dx, dy)`` between two vertices
    of the object as given is ``(dy, -dx)``; the friction-cone and cofactor
    conditions are positively homogeneous in it, so no rounded square root
    enters a certificate.
    """
    dx, dy = (Fraction(float(b)) - Fraction(float(a)) for a, b in zip(edge.start, edge.end,
                                                                        strict=True))
    return [-dy, dx]


def surely_positive(value: float, magnitude: float, roundings: int) -> bool:
    """Whether an expression of sums and products, evaluated in doubles as ``value``, is
    certainly positive in exact arithmetic: a static filter (as in exact geometric
    predicates) that answers ``False`` when it cannot tell, so that the caller decides in
    rationals.

    ``magnitude`` is the same expression evaluated with every input and every product made
    non-negative (``|a| |b| + |c| |d|`` for ``a b - c d``), and ``roundings`` the most
    roundings on any path from an input to the result (inputs rounded once count one). The
    error of ``value`` is then at most ``γ(roundings) · magnitude`` (Higham, *Accuracy and
    Stability of Numerical Algorithms*, §3.1), ``γ(k) = k u / (1 − k u)``, ``u = 2⁻⁵³``; the
    test asks for twice that, plus an absolute term for products that underflow.

    Examples
    --------
    >>> surely_positive(1.0 - 0.5, 1.5, 2), surely_positive(1e-17, 1.0, 2)
    (True, False)
    """
    if not (math.isfinite(value) and math.isfinite(magnitude) and magnitude < 1e300):
        return False
    u = 2.0 ** -53
    return value > 4.0 * roundings * u * magnitude + 2.0 ** -1000


def exact_point(edge: Edge, t: float) -> list[Fraction]:
    """The point at parameter ``t`` exactly as it is printed and returned (the float value of
    :meth:`Edge.point`), as rationals: certificates are about the numbers users get."""
    return [Fraction(float(x)) for x in edge.point(t)]


def tie_rounded(value: float) -> float:
    """``value`` to eight significant digits, for ranking: sizes that differ by less (as
    the rounding of far-away or scaled coordinates makes them) are ties, which a stable sort
    then breaks by index, so that a moved or scaled object ranks as the original does.

    Examples
    --------
    >>> tie_rounded(0.125) == tie_rounded(0.124999999935)
    True
    """
    return float(f"{value:.8g}")


@dataclass(frozen=True)
class Certificate:
    """The proof that a region set is force-closure, and what it checked."""

    holds: bool
    method: str
    detail: str


def proved_once(certify):
    """Keep a frozen region set's proof: ``certify`` runs once per object and later calls
    return the same :class:`Certificate` (a region set's proof is asked for when it is
    ranked, printed and written; on a large mesh each proof costs seconds).

    Each decorated method keeps its own result (by its qualified name, so that a region
    set with its proofs pickles), and a subclass's proof that calls its parent's gets both
    right.

    Examples
    --------
    >>> class Once:
    ...     calls = 0
    ...     @proved_once
    ...     def certify(self):
    ...         Once.calls += 1
    ...         return Certificate(True, "example", "")
    >>> r = Once()
    >>> r.certify() is r.certify(), Once.calls
    (True, 1)
    """
    key = certify.__qualname__

    @functools.wraps(certify)
    def once(self):
        proofs = self.__dict__.setdefault("_proofs", {})
        if key not in proofs:
            proofs[key] = certify(self)
        return proofs[key]

    return once


Cut = TypeVar("Cut", bound="RegionSet")


def first_proved(cut: Callable[[float], Cut], trims: Sequence[float] = TRIMS) -> Cut | None:
    """The regions ``cut(trim)`` for the first ``trim`` of :data:`TRIMS` whose proof holds
    (:meth:`RegionSet.certify`), or None when no cut is proved: the one "trim and certify
    again" rule of the constructions of regions (Nguyen 1988, §4 and §5), which return only
    proved region sets.

    Parameters
    ----------
    cut : callable
        The region set with each end of each region cut by the fraction ``trim`` of it.
    trims : sequence of float
        The cuts tried, in turn (by default :data:`TRIMS`).

    Returns
    -------
    RegionSet or None

    Examples
    --------
    On opposite sides of a square of side 2, with friction 0.3, aligned segments 0.6 long
    are on the boundary of Corollary 3 (``0.3 / 2 = tan(atan 0.3) / 2``): the first cut proves
    them.

    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis.planar.edge_pair import IndependentRegions
    >>> square = bundled("square")
    >>> def cut(trim):
    ...     ends = (0.7 + trim * 0.6, 1.3 - trim * 0.6)
    ...     return IndependentRegions(square, (0, 2), (ends, ends), "example", (0.3, 0.3))
    >>> cut(0.0).certify().holds, first_proved(cut).segments[0][0] > 0.7
    (False, True)
    """
    for trim in trims:
        regions = cut(trim)
        if regions.certify().holds:
            return regions
    return None


class RegionSet:
    """What every construction returns: one region per finger (a segment of an edge, a
    patch of one or more faces, or a vertex), such that every choice of one point per
    region is force-closure, and the proof of it.

    Subclasses give ``kinds``, ``sizes`` (a length per finger on a polygon,
    an area on a polyhedron), :meth:`describe`, :meth:`certify` (decorated
    with :func:`proved_once`: a region set keeps its proof, which the search,
    the printer and the record all ask for) and :meth:`to_dict`; the rest is
    common, so that printers, dataset rows and pictures read any region set
    alike.
    """

    @property
    def object(self):  # pragma: no cover - every subclass defines it
        """The polygon or polyhedron the regions are on."""
        raise NotImplementedError

    @property
    def sizes(self) -> tuple[float, ...]:  # pragma: no cover - every subclass defines it
        """Each finger's region: its length on a polygon, its area on a polyhedron."""
        raise NotImplementedError

    @property
    def kinds(self) -> tuple[str, ...]:  # pragma: no cover - every subclass defines it
        """What each finger stands on: ``"segment"`` (of an edge), ``"patch"`` (of one or more
        faces) or ``"vertex"``."""
        raise NotImplementedError

    @property
    def min_size(self) -> float:
        """The smallest region: the finger-placement error the grasp tolerates."""
        return min(self.sizes)

    @property
    def relative_min_size(self) -> float:
        """:attr:`min_size` over the object's size (its bounding-box diagonal) to the power
        of the regions' dimension: what the search ranks by, the same for a scaled object."""
        obj = self.object
        return self.min_size / obj.size ** (obj.dim - 1)

    def describe(self) -> list[str]:  # pragma: no cover - every subclass defines it
        """Each finger's region in words, for people (coordinates :func:`rounded`)."""
        raise NotImplementedError

    def notes(self) -> list[str]:
        """Facts a construction adds about its regions, in words (none by default)."""
        return []

    def certify(self) -> Certificate:  # pragma: no cover - every subclass defines it
        raise NotImplementedError

    def to_dict(self) -> dict[str, builtins.object]:  # pragma: no cover - every subclass
        """The JSON record: the construction's own keys and :meth:`_common`'s."""
        raise NotImplementedError

    def _common(self) -> dict[str, builtins.object]:
        """The keys every region set's JSON record has (``to_dict`` adds its own)."""
        cert = self.certify()
        return {"kinds": list(self.kinds), "sizes": list(self.sizes), "min_size": self.min_size,
                "relative_min_size": self.relative_min_size,
                "certificate": {"holds": cert.holds, "method": cert.method,
                                "detail": cert.detail}}


@dataclass(frozen=True, eq=False)
class Regions(RegionSet):
    """One segment per finger, such that every choice of one point per segment is
    force-closure. Subclasses give :meth:`certify`, the proof.

    Attributes
    ----------
    polygon : Polygon
    edges : tuple of int
        The edge each finger touches.
    segments : tuple of (u, v)
        Edge parameters (distances from each edge's start) of the segments.
    construction : str
    """

    polygon: Polygon
    edges: tuple[int, ...]
    segments: tuple[tuple[float, float], ...]
    construction: str

    @property
    def object(self) -> Polygon:
        return self.polygon

    @property
    def lengths(self) -> tuple[float, ...]:
        """Lengths of the segments."""
        return tuple(v - u for u, v in self.segments)

    sizes = lengths

    @property
    def kinds(self) -> tuple[str, ...]:
        return ("segment",) * len(self.edges)

    @property
    def min_length(self) -> float:
        """The finger-placement error the grasp tolerates."""
        return min(self.lengths)

    def describe(self) -> list[str]:
        """``edge 3: [x, y] to [x, y]`` for each finger (:func:`rounded`)."""
        return [f"edge {e}: {a} to {b}" for e, (a, b) in
                zip(self.edges, rounded(self.points, self.polygon.size), strict=True)]

    @property
    def points(self) -> NDArray[np.float64]:
        """``(fingers, 2, 2)``: each segment's ends in object coordinates."""
        return np.array([[self.polygon.edges[e].point(t) for t in seg]
                         for e, seg in zip(self.edges, self.segments, strict=True)])

    def friction(self) -> tuple[float, ...]:
        """The friction coefficient at each finger (0 for frictionless fingers)."""
        return (0.0,) * len(self.edges)

    def cone_rays(self, length: float) -> NDArray[np.float64]:
        """``(r, 2, 2)`` segments of the given length, for drawing: from both ends of every
        segment, the edges of the cone of forces its finger can push with (one ray along the
        inward normal for a frictionless finger)."""
        rays = []
        for (a, b), e, mu in zip(self.points, (self.polygon.edges[k] for k in self.edges),
                                 self.friction(), strict=True):
            push = -e.normal
            for s in ((-1, 1) if mu > 0 else (0,)):
                c, d = np.cos(s * np.arctan(mu)), np.sin(s * np.arctan(mu))
                ray = length * np.array([c * push[0] - d * push[1], d * push[0] + c * push[1]])
                rays += [(a, a + ray), (b, b + ray)]
        return np.array(rays)

    def to_dict(self) -> dict[str, builtins.object]:
        """The JSON record: edges, segments, points, lengths, construction, certificate, and
        the keys every region set has (``sizes``, ``min_size``, ``relative_min_size``)."""
        return {"edges": list(self.edges), "segments": [list(s) for s in self.segments],
                "points": self.points.tolist(), "lengths": list(self.lengths),
                "min_length": self.min_length,
                "relative_min_length": self.min_length / self.polygon.size,
                "construction": self.construction, **self._common()}


def rounded(values, size: float) -> list:
    """Coordinates for people: to 1e-4 of the object's size, whatever its scale (JSON
    records keep the exact values that were certified).

    Examples
    --------
    >>> rounded([0.123456, 12.3], 10.0)
    [0.123, 12.3]
    """
    decimals = max(0, 4 - int(np.floor(np.log10(size)))) if size > 0 else 4
    return np.round(np.asarray(values, dtype=float), decimals).tolist()
