"""The best grasps on any object, by the construction that fits the hand (§5).

:func:`synthesize` is what ``forceclosure synthesize`` and ``forceclosure
dataset`` run: given an object and a hand (fingers, contact model,
friction), it picks the paper's construction — two, three or four fingers
on the edges of a polygon (§5.1, §5.4); two soft, three hard or seven
frictionless fingers on the faces of a polyhedron (§5.2, §5.3, §5.5) — or
grows regions on the mesh around sampled prototypes for any other hand or
a curved object, and returns the best region sets, largest smallest region
first. A hand it cannot construct is refused with one line that says why.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import InputError
from ..objects import Polygon, Polyhedron
from .construction import Construction, Hand
from .ranked_search import search
from .regions import MARGIN, RegionSet, check_margin, narrowed
from .table import DEFAULT, construction_for, constructions, names

__all__ = ["CONTACTS", "MAX_FINGERS", "RESOLUTION", "SIZES", "Synthesis", "check_hand",
           "check_resolution", "default_fingers", "default_fingers_reason", "synthesize"]

CONTACTS = ("hard", "soft", "frictionless")


@dataclass(frozen=True)
class Synthesis:
    """The best region sets found on one object, and how they were found.

    Attributes
    ----------
    found : list
        Region sets, best first (:class:`~forceclosure.synthesis.Regions` on
        polygons, :class:`~forceclosure.synthesis.spatial.patches.SpatialRegions` on
        polyhedra).
    method : str
        ``"edges"`` (polygons), ``"faces"`` (the paper's constructions on a
        polyhedron) or ``"mesh"`` (regions grown around sampled prototypes).
    fingers : int
    contact : str
    mu : float
        0 for frictionless fingers.
    construction : Construction
        The table's entry that built them (its ``paper`` section, and what was
        ``searched``).
    undecided : int
        Sites the search could not decide (regions there, none provable in the
        coordinates given): grasps may be missing (:attr:`complete` is False).
    """

    found: list[RegionSet]
    method: str
    fingers: int
    contact: str
    mu: float
    construction: Construction
    undecided: int = 0

    @property
    def complete(self) -> bool:
        """Whether nothing the hand can do is missing: the construction is complete on the
        sites it covers (``construction.complete``) and decided every one of them."""
        return bool(self.construction.complete) and self.undecided == 0

    @property
    def searched(self) -> str:
        """What was searched, in words; a completeness the search does not have (a site
        undecided) is not claimed."""
        if self.undecided == 0:
            return self.construction.described
        return (f"{self.construction.searched}; not complete: {self.undecided} site"
                f"{'s' if self.undecided != 1 else ''} undecided (regions there could not be "
                "proved in the coordinates given)")

    def to_dict(self) -> dict[str, Any]:
        """The record ``forceclosure synthesize --json`` and the dataset's records hold: the
        hand, the method, the construction (its name, its section of the paper, what was
        searched), whether the search is complete, and each region set's record.

        Examples
        --------
        >>> from forceclosure import bundled
        >>> record = synthesize(bundled("square"), 2, "hard", 0.3, top=1).to_dict()
        >>> record["construction"]["name"], record["complete"], len(record["grasps"])
        ('maximal', True, 1)
        """
        return {"fingers": self.fingers, "contact": self.contact, "mu": self.mu,
                "method": self.method,
                "construction": {"name": self.construction.name,
                                 "paper": self.construction.paper,
                                 "searched": self.searched},
                "complete": self.complete, "undecided": self.undecided,
                "grasps": [r.to_dict() for r in self.found]}


def default_fingers(dim: int, contact: str) -> int:
    """The fewest fingers of a contact model that can hold an object: 2 with friction
    in the plane (4 frictionless); in space 2 soft, 3 hard, 7 frictionless.

    The one default of :func:`synthesize`, ``forceclosure synthesize`` and ``forceclosure
    dataset`` (:func:`default_fingers_reason` says why).

    Examples
    --------
    >>> default_fingers(2, "hard"), default_fingers(3, "hard"), default_fingers(3, "soft")
    (2, 3, 2)
    """
    if dim == 2:
        return 4 if contact == "frictionless" else 2
    return {"soft": 2, "hard": 3, "frictionless": 7}[contact]


def default_fingers_reason(dim: int, contact: str) -> str:
    """Why :func:`default_fingers` is the fewest that can hold a ``dim``-D object, in words.

    Examples
    --------
    >>> default_fingers_reason(3, "hard")
    '3 hard fingers, the fewest that can hold a polyhedron: two cannot resist rotation \
about the line between them'
    """
    n = default_fingers(dim, contact)
    if dim == 2:
        why = ("without friction the plane needs four (§5.4)" if contact == "frictionless"
               else "two with friction can (Corollary 3)")
        return f"{n} {contact} fingers, the fewest that can hold a polygon: {why}"
    why = {"soft": "two soft fingers with friction can (§5.2)",
           "hard": "two cannot resist rotation about the line between them",
           "frictionless": "six cannot (Lakshminarayana 1978)"}[contact]
    return f"{n} {contact} fingers, the fewest that can hold a polyhedron: {why}"


#: Most fingers of a hand synthesis serves (beyond the paper's hands: segments grown around
#: sampled prototypes on polygons, the mesh method in space).
#: The paper's hands are 2 soft, 3 hard and 7 frictionless; the mesh method takes any, its
#: time growing steeply with them (measured on a shared 2-core machine, the cube with soft
#: fingers and the default 20,000 samples, the whole command: 3 in 12 s, 4 in 20 s, 6 in
#: 120 s, 10 did not finish in 300 s). Beyond it a hand is refused in one line: 8 keeps the
#: paper's hands and one more than its largest (7 frictionless).
MAX_FINGERS = 8


def check_hand(dim: int, fingers: int | None, contact: str = "hard", mu: float = 0.3, *,
               top: int = 5, construction: str | Construction = DEFAULT,
               method: str = "auto") -> int:
    """Refuse, in one line, a hand the constructions cannot serve on a ``dim``-D object;
    return the number of fingers (``None``: :func:`default_fingers`).

    Examples
    --------
    >>> check_hand(3, None, "frictionless")
    7
    >>> check_hand(3, 2, "hard")
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: fingers=2, contact='hard': a spatial grasp needs at \
least 3 hard fingers (two cannot resist rotation about the line between them)

    The messages name this function's parameters; ``forceclosure synthesize`` says them as its
    flags (``--fingers 2 --contact hard: ...``).
    """
    if contact not in CONTACTS:
        raise InputError(f"contact must be one of {', '.join(CONTACTS)}, got {contact!r}")
    if fingers is None:
        fingers = default_fingers(dim, contact)
    frictionless = contact == "frictionless"
    if not frictionless and not (mu > 0 and np.isfinite(mu)):
        raise InputError(f"mu must be a positive number, got {mu:g}")
    if isinstance(construction, str) and construction not in names():
        raise InputError(f"construction must be one of {', '.join(names())} (the table's "
                         f"names), got {construction!r}")
    if not isinstance(construction, str | Construction):
        raise InputError(f"construction must be a name or a Construction, got "
                         f"{construction!r}")
    if method not in ("auto", "faces", "mesh"):
        raise InputError(f"method must be auto, faces or mesh, got {method!r}")
    if not isinstance(top, int | np.integer) or isinstance(top, bool) or top < 1:
        raise InputError(f"top must be a positive integer, got {top!r}")
    table = constructions()
    if dim == 2:
        hard = "frictionless" if frictionless else "hard"  # a soft finger acts as a hard one
        if not isinstance(fingers, int | np.integer) or isinstance(fingers, bool):
            raise InputError(f"fingers must be a whole number, got {fingers!r}")
        if fingers > MAX_FINGERS:
            raise InputError(f"fingers={fingers}: at most {MAX_FINGERS} fingers a hand are "
                             "synthesized (the time grows steeply with them)")
        least = default_fingers(2, contact)
        if fingers < least:
            why = (" (the plane needs four without friction: Reuleaux, §5.4)" if frictionless
                   else "")
            raise InputError(f"fingers={fingers}, contact={contact!r}: a planar grasp needs at "
                             f"least {least} {hard} fingers{why}")
        if construction == "nguyen" and (2, fingers, hard, "nguyen") not in {
                c.key for c in table}:
            raise InputError(f"construction='nguyen': the paper's construction on a polygon "
                             f"is for {_hands(_nguyen(table, 2))} fingers; {fingers} use "
                             "construction='maximal'")
        construction_for(2, fingers, hard, construction)  # a name the table has for the hand
        return fingers
    if not isinstance(fingers, int | np.integer) or isinstance(fingers, bool):
        raise InputError(f"fingers must be a whole number, got {fingers!r}")
    if fingers > MAX_FINGERS:
        raise InputError(f"fingers={fingers}: at most {MAX_FINGERS} fingers a hand are "
                         "synthesized (the time grows steeply with them)")
    minimum = default_fingers(3, contact)
    if fingers < minimum:
        why = {"soft": "", "hard": " (two cannot resist rotation about the line between "
               "them)", "frictionless": " (Lakshminarayana 1978)"}[contact]
        raise InputError(f"fingers={fingers}, contact={contact!r}: a spatial grasp needs at "
                         f"least {minimum} {contact} fingers{why}")
    faces = sorted({(c.fingers or 0, c.contact) for c in table if c.method == "faces"})
    if method == "faces" and (fingers, contact) not in faces:
        raise InputError(f"method='faces': the paper constructs {_hands(faces)} fingers on "
                         f"faces, not {fingers} {contact}; use method='mesh'")
    if construction == "nguyen" and (fingers, contact) not in _nguyen(table, 3):
        raise InputError(f"construction='nguyen': in space the paper's two-sided cone is for "
                         f"{_hands(_nguyen(table, 3))} fingers (§5.2)")
    construction_for(3, fingers, contact, construction, method)  # the table has it for the hand
    return fingers


def _nguyen(table: tuple[Construction, ...], dim: int) -> list[tuple[int, str]]:
    return sorted({(c.fingers or 0, c.contact) for c in table
                   if c.dim == dim and c.name == "nguyen"})


def _hands(hands: list[tuple[int, str]]) -> str:
    """``[(2, "soft"), (3, "hard")]`` as ``2 soft or 3 hard``."""
    words = [f"{n} {contact}" for n, contact in hands]
    return ", ".join(words[:-1]) + (" or " if len(words) > 1 else "") + words[-1]


#: The sizes (bounding-box diagonals) of the objects synthesis serves: regions are the
#: same, relative to the object, from 1e-6 to 1e6 (tests/objects/test_objects_as_given.py); far
#: outside, absolute tolerances in the constructions lose grasps.
SIZES = (1e-6, 1e6)

#: The coarsest spacing of floating-point numbers at an object's coordinates, relative to its
#: size, that synthesis accepts: farther from the origin, its corners and the regions' ends
#: (which are proved as printed) cannot be placed finer than this (an object 4 across at
#: 1e14 is resolved to 0.4 % of its size).
RESOLUTION = 1e-4


def check_resolution(obj: Polygon | Polyhedron) -> None:
    """Refuse, in one line, an object so far from the origin for its size that doubles
    cannot resolve it to :data:`RESOLUTION` of its size.

    Examples
    --------
    >>> from forceclosure.objects import Polygon
    >>> check_resolution(Polygon.from_points([[1e8, 0], [1e8 + 3, 0], [1e8, 3]]))
    >>> check_resolution(Polygon.from_points([[1e14, 0], [1e14 + 3, 0], [1e14, 3]]))
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: polygon: coordinates up to 1e+14 on an object 4.24 \
across: floating-point numbers there are 0.0156 apart, 0.37% of its size (more than 0.01%); \
move it nearer the origin (its regions move with it)
    """
    far = float(np.abs(obj.bounds).max())
    spacing = float(np.spacing(far))
    if spacing > RESOLUTION * obj.size:
        raise InputError(f"{obj.name}: coordinates up to {far:.3g} on an object "
                         f"{obj.size:.3g} across: floating-point numbers there are "
                         f"{spacing:.3g} apart, {spacing / obj.size:.2%} of its size (more "
                         f"than {RESOLUTION:.2%}); move it nearer the origin (its regions "
                         "move with it)")


def synthesize(obj: Polygon | Polyhedron | Any, fingers: int | None = None,
               contact: str = "hard", mu: float = 0.3, *, top: int = 5, margin: float = MARGIN,
               construction: str | Construction = DEFAULT, method: str = "auto",
               samples: int = 20_000, seed: int = 0, allow_open: bool = False,
               progress: Callable[[int], object] | None = None) -> Synthesis:
    """The ``top`` best force-closure grasps on ``obj`` with their independent regions.

    Parameters
    ----------
    obj : Polygon, Polyhedron, or what :func:`~forceclosure.objects.io.load_object` reads
        A ``trimesh.Trimesh``, a shapely polygon, a file path or a bundled name.
    fingers : int, optional
        Default: the fewest that can hold the object (:func:`default_fingers`).
    contact : {"hard", "soft", "frictionless"}
        In the plane a soft finger acts as a hard one.
    mu : float
        Friction coefficient (ignored for frictionless fingers).
    top : int
    margin : float
        Radians: the regions stay force-closure when every contact normal
        turns by up to this angle; every construction with friction narrows
        its cones by it, four frictionless fingers in the plane hold for every
        force direction within it, seven frictionless fingers in space keep
        the signs of their minors for every normal within it
        (:func:`~forceclosure.synthesis.regions.check_margin`).
    construction : str or Construction
        A name in the table of constructions (:mod:`~forceclosure.synthesis.table`) that
        serves the hand: ``"maximal"`` (the default: the largest regions, or the mesh
        method for a hand no construction on faces serves), ``"nguyen"`` (the paper's
        two-sided cones: two or four fingers in the plane, two soft fingers in space),
        ``"vertices"`` (two fingers in the plane, a soft one on a convex vertex),
        ``"mesh"`` (regions grown on a polyhedron's mesh); or a :class:`Construction`
        of one's own. Another name is refused in one line listing the table's names for
        the hand.
    method : {"auto", "faces", "mesh"}
        Polyhedra: the paper's constructions on faces, or regions grown on
        the mesh; ``auto`` takes faces unless the object is curved (most faces
        one triangle) or the hand is not one the paper constructs.
    samples, seed : int
        Random grasps sampled for prototypes, and the seed.
    allow_open : bool
        Accept an open or non-manifold mesh given as a file or a ``trimesh.Trimesh``
        (as :func:`~forceclosure.objects.io.load_object`).
    progress : callable, optional
        Called with 1 for each candidate site the search takes up, before building its
        regions (the CLI's counter of sites).

    Returns
    -------
    Synthesis

    Raises
    ------
    InputError
        For a hand that cannot be served (:func:`check_hand`), or a construction the table
        does not have for it.

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, §4.1, Corollary 3
       (two opposing fingers); §5 (independent regions of contact in 2D and 3D;
       Algorithm 1 in §5.1)

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> s = synthesize(bundled("cube"), 2, "soft", 0.5, top=1)
    >>> s.method, s.found[0].certify().holds
    ('faces', True)
    >>> import trimesh
    >>> synthesize(trimesh.creation.box(), 2, "soft", 0.5, top=1).found[0].certify().holds
    True
    """
    from ..objects.io import load_object

    obj = load_object(obj, allow_open=allow_open)
    low, high = SIZES
    if not low <= obj.size <= high:
        raise InputError(f"{obj.name}: the object is {obj.size:.3g} across; synthesis is made "
                         f"and tested for objects {low:g} to {high:g} across (some of its "
                         "tolerances are absolute): rescale it, and the regions with it")
    check_resolution(obj)
    fingers = check_hand(obj.dim, fingers, contact, mu, top=top, construction=construction,
                         method=method)
    check_margin(margin)
    # an object read from curves (chords) or curved primitives (facets) has normals that
    # turn by up to its spread: build with at least that margin so that the proofs, which
    # narrow the cones by it, can hold
    spread = (obj.spread if isinstance(obj, Polygon)
              else max((f.spread for f in obj.faces), default=0.0))
    needed = min(1.001 * spread, math.pi / 2 * 0.999)
    mu = 0.0 if contact == "frictionless" else float(mu)
    if contact != "frictionless" and narrowed(mu, max(margin, needed)) <= 0:
        why = (f"the margin {margin:g} rad" if margin >= needed else
               f"{needed:.3g} rad, as far as the object's normals turn from its chords or "
               "facets")
        raise InputError(f"mu {mu:g}: its friction cone (atan(mu) = {math.atan(mu):.3g} rad) "
                         f"leaves nothing once narrowed by {why}")
    margin = max(margin, needed)
    curved = isinstance(obj, Polyhedron) and bool(
        np.mean([len(f.triangles) == 1 for f in obj.faces]) > 0.5)
    chosen = construction_for(obj.dim, fingers, contact, construction, method, curved)
    found = search(chosen, obj, Hand(fingers, contact, mu, margin, samples, seed, top),
                   progress=progress)
    return Synthesis(list(found), chosen.method, fingers, contact, mu, chosen,
                     getattr(found, "undecided", 0))
