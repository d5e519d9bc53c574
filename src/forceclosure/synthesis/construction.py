"""The construction contract: what a construction of independent regions gives, and its steps.

Every way of building independent regions of contact — the paper's on edges
(§5.1, §5.4) and faces (§5.2, §5.3, §5.5), and the mesh method beyond it —
is one :class:`Construction` in one module, listed once in the table
(:mod:`~forceclosure.synthesis.table`) under ``(dimension, fingers, contact,
name)``. Each gives the same four steps, which
:func:`~forceclosure.synthesis.ranked_search.search` runs:

1. ``sites(obj, hand)``: the candidate tuples (edge pairs, face triples,
   sampled prototype grasps…), in blocks;
2. ``prune(obj, sites, hand)``: a vectorised necessary condition (the
   force-direction closure of the normals), a boolean mask;
3. ``bound(obj, sites, hand)``: optionally, an upper bound on each site's
   relative smallest region, for branch and bound;
   ``levels(obj, hand, prune)`` may give steps 1 to 3 at once, lazily: the pruned sites in
   levels of one bound, by decreasing bound (for tuples of edges bounded by their shortest
   edge: :func:`~forceclosure.synthesis.planar.edge_sites.by_shortest_edge`), so that the
   search reaches its best sites without listing all of them first;
4. ``build(obj, site, hand)``: the regions on one site, ``None`` (none there), or an
   :class:`Undecided` (the site has regions by the bound, but none could be proved in the
   coordinates given: the search then says it is not complete).

Every step is given the :class:`Hand`, which carries the search's own
:attr:`Hand.memo`: what one step leaves for a later one of the same search (no
state is kept between searches).

Examples
--------
>>> from forceclosure.synthesis.table import construction_for
>>> c = construction_for(2, 2, "hard")
>>> c.key, c.paper
((2, 2, 'hard', 'maximal'), '§5.1, Corollary 3')

References
----------
V.-D. Nguyen, "Constructing force-closure grasps", IJRR 7(3), 1988, §5.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .regions import MARGIN

__all__ = ["Construction", "Hand", "Undecided"]


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
    resolution : float
        The spacing of the doubles where the object stands, relative to its size (about
        1e-16 at the origin, 1e-7 for an object 0.15 across at 1e8): what a moved copy's
        rounding may change, which the steps allow for (sizes that differ by less than a
        few of it rank as ties; a face's corner made reflex by it is not a cut).
        :func:`~forceclosure.synthesis.ranked_search.search` sets it from the object.
    memo : dict
        The search's own memory: what one step of a construction leaves for a later step
        of the same search (the bound's solve of every edge pair, which the builds read).
        :func:`~forceclosure.synthesis.ranked_search.search` gives each search an empty
        one; it takes no part in comparing or hashing hands.
    """

    fingers: int
    contact: str
    mu: float
    margin: float = MARGIN
    samples: int = 20_000
    seed: int = 0
    top: int = 5
    resolution: float = 0.0
    memo: dict[str, Any] = field(default_factory=dict, compare=False, hash=False, repr=False)


#: A block of candidate sites, of the construction's own kind: an integer array of index
#: rows (edge pairs, face tuples) or a list (vertex sites, sampled prototypes). The search
#: passes each block back to the same construction's steps and never looks inside it.
Sites = Any
#: What ``build`` returns for one site: its regions, none there, or undecided.
Built = Any  # a RegionSet, None or an Undecided (RegionSet lives in regions.py, above Hand)


@dataclass(frozen=True)
class Undecided:
    """What a construction's ``build`` returns for a site it could not decide: its regions
    exist (by the bound, or a linear program) but no cut of them could be proved force-closure
    in the coordinates given (numbers too coarse for the margin, far from the origin).

    Attributes
    ----------
    reason : str
        Why, in words.
    size : float or None
        The most the site's regions could measure, relative to the object (as
        :attr:`~forceclosure.synthesis.regions.RegionSet.relative_min_size`), when the
        construction knows it: a site that could not rank among the best then does not make
        the search incomplete. None: unknown.
    """

    reason: str
    size: float | None = None


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
    levels : callable or None
        Steps 1 to 3 at once, lazily, in the search's order (the module's docstring); the
        search uses it in place of ``sites`` and ``bound``, which give the same sites.
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
    sites: Callable[[Any, Hand], Iterable[Sites]]
    build: Callable[[Any, Any, Hand], Built]
    searched: str
    prune: Callable[[Any, Sites, Hand], NDArray[np.bool_] | Sequence[bool]] | None = None
    bound: Callable[[Any, Sites, Hand], NDArray[np.float64]] | None = None
    levels: Callable[[Any, Hand, Callable | None], Iterable[Any]] | None = None
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
