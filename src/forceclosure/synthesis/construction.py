"""The table of constructions: what each of the paper's constructions needs, and its steps.

Every way of building independent regions of contact — the paper's on edges
(§5.1, §5.4) and faces (§5.2, §5.3, §5.5), and the mesh method beyond it —
is one :class:`Construction`, registered under ``(dimension, fingers,
contact, name)`` by the module that implements it. Each gives the same four
steps, which :func:`~forceclosure.synthesis.ranked_search.search` runs:

1. ``sites(obj, hand)``: the candidate tuples (edge pairs, face triples,
   sampled prototype grasps…);
2. ``prune(obj, sites, hand)``: a vectorised necessary condition (the
   force-direction closure of the normals), a boolean mask;
3. ``bound(obj, sites, hand)``: optionally, an upper bound on each site's
   relative smallest region, for branch and bound;
4. ``build(obj, site, hand)``: the regions on one site, ``None`` (none there), or an
   :class:`Undecided` (the site has regions by the bound, but none could be proved in the
   coordinates given: the search then says it is not complete).

:func:`construction_for` is the front door's table lookup.

Examples
--------
>>> c = construction_for(2, 2, "hard")
>>> c.name, c.paper, c.method
('maximal', '§5.1, Corollary 3', 'edges')
>>> construction_for(3, 4, "hard").name      # no construction on faces: the mesh method
'mesh'
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from .regions import MARGIN

__all__ = ["Construction", "Hand", "Undecided", "construction_for", "register", "registered"]


@dataclass(frozen=True)
class Hand:
    """The hand a construction serves, with the search's own settings.

    Attributes
    ----------
    fingers : int
    contact : {"hard", "soft", "frictionless"}
    mu : float
        0 for frictionless fingers.
    margin : float
        Radians (:func:`~forceclosure.synthesis.regions.check_margin`).
    samples, seed : int
        Random grasps sampled by the constructions that start from prototypes.
    top : int
        Region sets wanted.
    """

    fingers: int
    contact: str
    mu: float
    margin: float = MARGIN
    samples: int = 20_000
    seed: int = 0
    top: int = 5


Sites = Sequence[Any]


@dataclass(frozen=True)
class Undecided:
    """What a construction's ``build`` returns for a site it could not decide: its regions
    exist (by the bound, or a linear program) but no cut of them could be proved force-closure
    in the coordinates given (numbers too coarse for the margin, far from the origin).

    Attributes
    ----------
    reason : str
        Why, in words.
    """

    reason: str


@dataclass(frozen=True)
class Construction:
    """One construction of independent regions, and the four steps of its search.

    Attributes
    ----------
    dim : {2, 3}
    fingers : int or None
        ``None``: any number of fingers (the mesh method).
    contact : str
        ``"hard"``, ``"soft"`` or ``"frictionless"``; ``"any"`` for the mesh method.
    name : str
        ``"maximal"`` (largest regions), ``"nguyen"`` (the paper's two-sided
        cones), ``"vertices"``, ``"mesh"``.
    paper : str
        The section or result of Nguyen (1988) it implements.
    method : {"edges", "faces", "mesh"}
        Where it builds regions (``Synthesis.method``).
    sites, build : callable
        Steps 1 and 4 (see the module's docstring).
    prune, bound : callable or None
        Steps 2 and 3.
    enough : int or None
        For a construction without a bound whose sites are sampled: stop once
        ``enough * top`` certified region sets are built.
    searched : str
        What a search covers, in words: what "none found" means.
    complete : bool
        Whether the search finds every grasp of the hand on the sites it covers (the best
        regions on each, exactly), so that a site it did not decide leaves it incomplete.
    """

    dim: int
    fingers: int | None
    contact: str
    name: str
    paper: str
    method: str
    sites: Callable[[Any, Hand], Sites]
    build: Callable[[Any, Any, Hand], Any]
    searched: str
    prune: Callable[[Any, Sites, Hand], NDArray[np.bool_]] | None = None
    bound: Callable[[Any, Sites, Hand], NDArray[np.float64]] | None = None
    enough: int | None = None
    complete: bool = False
    #: Why the search is complete, in words (with ``complete``): said after ``searched``.
    completeness: str = ""

    @property
    def described(self) -> str:
        """What it searches, in words, with why that is complete where it is."""
        return (f"{self.searched} (complete: {self.completeness})" if self.completeness
                else self.searched)

    @property
    def key(self) -> tuple[int, int | None, str, str]:
        """``(dim, fingers, contact, name)``, its place in the table."""
        return (self.dim, self.fingers, self.contact, self.name)


_TABLE: dict[tuple[int, int | None, str, str], Construction] = {}
_loaded = False


def register(construction: Construction) -> Construction:
    """Enter a construction in the table (each construction's module calls it once).

    A second construction under the same key is refused: the table has one
    entry per problem.
    """
    if construction.key in _TABLE and _TABLE[construction.key] is not construction:
        raise ValueError(f"a construction is already registered for {construction.key}")
    _TABLE[construction.key] = construction
    return construction


def registered() -> tuple[Construction, ...]:
    """Every registered construction, after importing every module of the package, in the
    order of their keys.

    Examples
    --------
    >>> sorted({c.method for c in registered()})
    ['edges', 'faces', 'mesh']
    """
    global _loaded
    if not _loaded:  # once: the modules register themselves as they are imported
        package = importlib.import_module(__package__)
        for info in pkgutil.walk_packages(package.__path__, f"{__package__}."):
            importlib.import_module(info.name)
        _loaded = True
    return tuple(sorted(_TABLE.values(), key=lambda c: (c.dim, c.fingers or 99, c.contact,
                                                         c.name)))


def construction_for(dim: int, fingers: int, contact: str, name: str = "maximal",
                     method: str = "auto", curved: bool = False) -> Construction:
    """The construction for a hand on a ``dim``-D object: the table's entry, else the mesh
    method on a polyhedron, regions grown around prototypes on a polygon.

    In the plane a soft finger acts as a hard one. ``method="mesh"`` asks for
    the mesh method, ``"faces"`` for a construction on faces; ``"auto"`` takes
    the construction unless the object is ``curved`` (most of its faces one
    triangle).

    Raises
    ------
    InputError
        When no construction serves the hand.
    """
    registered()
    if dim == 2 and contact == "soft":
        contact = "hard"
    entry = _TABLE.get((dim, fingers, contact, name))
    if dim == 3 and (method == "mesh" or entry is None or (method == "auto" and curved)):
        if method == "faces":
            raise InputError(f"method='faces': the paper constructs two soft, three hard or "
                             f"seven frictionless fingers on faces, not {fingers} {contact}; "
                             "use method='mesh'")
        return _TABLE[(3, None, "any", "mesh")]
    if entry is None and dim == 2 and name == "maximal":  # regions grown around prototypes
        return _TABLE[(2, None, "any", "grown")]
    if entry is None:
        raise InputError(f"construction={name!r}: none for {fingers} {contact} fingers on a "
                         f"{'polygon' if dim == 2 else 'polyhedron'}")
    return entry
