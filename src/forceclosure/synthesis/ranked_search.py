"""One search for every construction: candidate sites, pruning, branch and bound, ranking.

Region sets are ranked by one rule: the larger smallest region relative to
the object (:attr:`~forceclosure.synthesis.regions.RegionSet.relative_min_size`,
a length on polygons, an area over size² on polyhedra) first, sizes within
:data:`TIE` of each other tied (:func:`ranked`), ties by the order of the sites.
Only certified region sets are returned.

Examples
--------
>>> from forceclosure.objects import bundled
>>> from forceclosure.synthesis.construction import Hand
>>> from forceclosure.synthesis.table import construction_for
>>> found = search(construction_for(2, 2, "hard"), bundled("hexagon"), Hand(2, "hard", 0.3, top=3))
>>> [r.edges for r in found]
[(0, 3), (1, 4), (2, 5)]
"""

from __future__ import annotations

import bisect
import dataclasses
import math
from collections.abc import Callable, Iterator
from typing import Any

import numpy as np

from ..errors import InputError
from ..objects.polygon import Polygon
from ..objects.polyhedron import Polyhedron
from .construction import Construction, Hand, Undecided
from .frame import UNPROVED, Frame
from .regions import TRIMS, RegionSet, first_proved, tie_rounded

__all__ = ["SPACINGS", "TIE", "Found", "candidate_sites", "ranked", "search"]

#: Relative sizes within this fraction of the largest of a run of them rank as ties, broken
#: by the order of the sites (edge indices: the object's own order), so that the rounding of
#: a moved or scaled copy (1e-8 of its size at 1e8, more where proofs cut regions at the
#: floats of far-away coordinates) does not reorder equal regions.
TIE = 1e-6
#: Sizes within this many spacings of the doubles where the object stands (relative to its
#: size: :attr:`~forceclosure.synthesis.construction.Hand.resolution`) tie too.
SPACINGS = 8


def _by_size(b: tuple[float, Any, Any]) -> tuple[float, Any]:
    return -b[0], b[1]


def _tied_floor(size: float, slack: float, areas: bool) -> float:
    """The least size that ties with ``size``: within :data:`TIE` of it, and within
    ``slack`` (times the square root of ``size`` for areas over size²: rounding by a length
    changes an area by that length times the region's extent)."""
    return size * (1 - TIE) - (slack * math.sqrt(max(size, 0.0)) if areas else slack)


def ranked(built: list[tuple[float, Any, Any]], slack: float = 0.0, limit: int | None = None,
           presorted: bool = False, areas: bool = False) -> list[tuple[float, Any, Any]]:
    """``(size, site, item)`` triples in rank order: by decreasing size, where every size
    within :data:`TIE` (relative) plus ``slack`` of the largest of its run ties with it, and
    ties go by site. ``limit``: the first that many only (the runs past them are not
    looked at); ``presorted``: ``built`` is already by decreasing size, then site;
    ``areas``: the sizes are areas over size² (:func:`_tied_floor`).

    Examples
    --------
    >>> [k for _, k, _ in ranked([(0.5, 3, None), (1.0, 2, None), (1.0 - 1e-9, 0, None)])]
    [0, 2, 3]
    """
    rest = built if presorted else sorted(built, key=_by_size)
    out: list[tuple[float, Any, Any]] = []
    start = 0
    while start < len(rest) and (limit is None or len(out) < limit):
        end = start + 1
        while end < len(rest) and rest[end][0] >= _tied_floor(rest[start][0], slack, areas):
            end += 1
        out += sorted(rest[start:end], key=lambda b: b[1])
        start = end
    return out if limit is None else out[:limit]


@dataclasses.dataclass(frozen=True)
class _Pending:
    """A region set built, on the object as given, with what proving it takes: ``cut(trim)``
    is it with each region cut by ``trim`` at each end, tried for ``trims`` in turn
    (:func:`~forceclosure.synthesis.regions.first_proved`); ``done`` once proved at
    ``cut(0.0)``."""

    cut: Callable[[float], RegionSet]
    trims: tuple[float, ...]
    reason: str
    done: bool = False

    @classmethod
    def of(cls, regions: RegionSet, mapped: tuple[Callable[[float], RegionSet],
                                                  tuple[float, ...]] | None) -> _Pending:
        """``regions`` as built (no frame: proved as they are) or mapped by a frame."""
        if mapped is None:
            return cls(lambda trim: regions, TRIMS[:1],
                       "a region set built on it failed its proof")
        cut, trims = mapped
        first = cut(0.0)  # the same object each time it is asked for: its proof is kept
        return cls(lambda trim: first if trim == 0.0 else cut(trim), trims, UNPROVED)

    @classmethod
    def proved(cls, regions: RegionSet) -> _Pending:
        return cls(lambda trim: regions, TRIMS[:1], "", done=True)


class Found(list):
    """What :func:`search` returns: the region sets, best first (a list), and the sites it
    could not decide (:attr:`undecided`).

    A site is undecided when its regions exist (by the construction's bound or linear
    program) but none could be proved in the coordinates given, or when a region set built
    on it failed its proof; such a site could have ranked among the best, so the search is
    not complete.

    Attributes
    ----------
    undecided_sites : tuple of (site, str)
        Each undecided site and why.
    """

    def __init__(self, found=(), undecided_sites=()):
        super().__init__(found)
        self.undecided_sites = tuple(undecided_sites)

    @property
    def undecided(self) -> int:
        """How many sites the search could not decide (0: every site it covered was)."""
        return len(self.undecided_sites)


def candidate_sites(construction: Construction, obj: Any, hand: Hand, prune: bool = True):
    """Steps 1 and 2: the construction's sites, block by block, each block pruned.

    Returns an array of rows when the sites are index tuples, else a list.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis.construction import Hand
    >>> from forceclosure.synthesis.table import construction_for
    >>> square, c, hand = bundled("square"), construction_for(2, 2, "hard"), Hand(2, "hard", 0.3)
    >>> len(candidate_sites(c, square, hand, prune=False)), candidate_sites(c, square, hand)
    (6, array([[0, 2, 0],
           [1, 3, 0]]))
    """
    kept = []
    for block in construction.sites(obj, hand):
        if prune and construction.prune is not None and len(block):
            keep = np.asarray(construction.prune(obj, block, hand), dtype=bool)
            block = block[keep] if isinstance(block, np.ndarray) else [
                s for s, k in zip(block, keep, strict=True) if k]
        kept.append(block)
    if kept and all(isinstance(b, np.ndarray) for b in kept):
        return np.concatenate(kept)
    return [s for block in kept for s in block]


def _in_order(construction: Construction, where: Any, hand: Hand) -> Iterator[
        tuple[float | None, Any, Any, Any]]:
    """Steps 1 to 3: ``(bound, key, site, least)`` for each site in the search's order — by
    decreasing bound (rounded: :func:`tie_rounded`; None without one), ties by site order —
    where ``key`` orders sites as the tie rule does and no site from here on has a key below
    ``least``. From the construction's ``levels`` when it has them (lazily; keys: the tuples
    of edges), else from all its sites at once (keys: their places in the list)."""
    if construction.levels is not None:
        for level in construction.levels(where, hand, construction.prune):
            for row in level.sites:
                key = tuple(int(e) for e in row)
                yield level.bound, key, row.copy(), min(key, level.later)  # not its block
        return
    sites = candidate_sites(construction, where, hand)
    bound = None
    if construction.bound is not None and len(sites):
        bound = np.array([tie_rounded(b) for b in construction.bound(where, sites, hand)])
    order = range(len(sites)) if bound is None else np.argsort(-bound, kind="stable")
    # the least site index from each place in the order on
    least = np.minimum.accumulate(np.asarray(order)[::-1])[::-1] if len(sites) else ()
    for at, k in enumerate(order):
        yield None if bound is None else bound[k], int(k), sites[k], int(least[at])


def search(construction: Construction, obj: Any, hand: Hand,
           progress: Callable[[int], object] | None = None) -> Found:
    """The ``hand.top`` best certified region sets a construction builds on ``obj``.

    Runs the construction's steps: its sites, pruned by its necessary
    condition; in decreasing order of its bound when it has one (branch and
    bound: the search stops at the first site whose bound cannot rank it
    ahead of the ``top``-th region set, once those ``top`` are proved, or
    when the bound falls to zero; with the construction's ``levels``, the
    sites are listed only as far as the search goes); each site built, and ranked by the one rule
    (the module's docstring). Region sets are proved in rank order, as they
    are needed (a proof can cost more than the construction), except with
    ``enough``, which counts proved region sets as they are built. On a polygon or
    polyhedron the steps run in object-centred, scaled coordinates
    (:class:`~forceclosure.synthesis.frame.Frame`), and the region sets are mapped
    back and proved on ``obj`` as given.

    Parameters
    ----------
    construction : Construction
    obj : Polygon or Polyhedron
    hand : Hand
        With the search's settings (``top``, ``samples``, ``seed``).
    progress : callable, optional
        Called with 1 for each site taken up, before it is built.

    Returns
    -------
    Found
        A list of region sets, best first; fewer than ``top`` when fewer exist (on the
        sites searched: ``construction.searched``), or when sites were undecided
        (:attr:`Found.undecided`: then the answer is not complete).
    """
    top = hand.top
    # sizes closer than the object's coordinates resolve (relative to its size: 6e-8 at 1e8
    # on an object 2 across) are ties too: a far-away copy is rounded by that much
    resolution = float(np.spacing(np.abs(obj.bounds).max())) / obj.size \
        if hasattr(obj, "bounds") else 0.0
    slack = SPACINGS * resolution
    # this search's own memory, for its steps, and the object's resolution
    hand = dataclasses.replace(hand, memo={}, resolution=resolution)
    if not isinstance(top, int | np.integer) or isinstance(top, bool) or top < 1:
        raise InputError(f"top must be a positive integer, got {top!r}")
    # on a polygon or polyhedron, every step but the proofs runs in object-centred, scaled
    # coordinates (frame.py); the regions are mapped back and proved on the object as given
    frame = Frame.of(obj) if isinstance(obj, Polygon | Polyhedron) else None
    where = obj if frame is None else frame.local(obj)
    areas = getattr(obj, "dim", 2) == 3
    # (size, site's key, pending region set), by decreasing size then site
    built: list[tuple[float, Any, _Pending]] = []
    site_of: dict[Any, Any] = {}  # each built site by its key
    # (site, why, the most its regions could measure or None)
    undecided: list[tuple[Any, str, float | None]] = []

    def settled(entry: tuple[float, Any, _Pending]) -> bool:
        """Prove ``entry``'s region set (cut as its proof needs): True when it holds at its
        size; otherwise it leaves ``built``, and comes back at its smaller size when a cut
        of it was proved, or is undecided when none was."""
        size, k, pending = entry
        proved = first_proved(pending.cut, pending.trims)
        built.remove(entry)
        if proved is None:
            undecided.append((site_of[k], pending.reason, None))
            return False
        now = float(proved.relative_min_size)
        bisect.insort(built, (now, k, _Pending.proved(proved)), key=_by_size)
        return now == size

    def proved_first() -> list[tuple[float, Any, _Pending]]:
        """The first ``top`` ranked region sets, each proved at the size it ranks by."""
        while True:
            first = ranked(built, slack, limit=top, presorted=True, areas=areas)
            if all(b[2].done or settled(b) for b in first):
                return first

    tie_check = [top]  # how many built before ties are next looked at (doubling)

    def beaten(size: float, site: Any) -> bool:
        """Whether ``top`` proved region sets rank ahead of any site whose regions are at
        most ``size`` and whose key is at least ``site``: the best the sites left can do
        (they come by decreasing bound)."""
        if len(built) < top:
            return False
        if size < _tied_floor(built[top - 1][0], slack, areas):
            first = proved_first()
            return len(first) == top and size < _tied_floor(min(b[0] for b in first),
                                                            slack, areas)
        # a size that ties with the top: beaten when a site as large as the bound allows
        # (its rounding included) with the least index left still ranks after the top;
        # looked at each time the number built doubles, so a run of ties stays linear
        if len(built) < tie_check[0]:
            return False
        tie_check[0] = 2 * len(built)
        if len(proved_first()) < top:
            return False
        trial: list[tuple[float, Any, _Pending | None]] = [*built]
        bisect.insort(trial, (size * (1 + 1e-7), site, None), key=_by_size)
        return all(b[2] is not None for b in ranked(trial, slack, limit=top, presorted=True,
                                                    areas=areas))

    for bound, key, site, least in _in_order(construction, where, hand):
        if bound is not None and (not bound > 0 or beaten(bound, least)):
            break
        if construction.enough is not None and len(built) >= construction.enough * top:
            break
        if progress is not None:
            progress(1)
        regions = construction.build(where, site, hand)
        if isinstance(regions, Undecided):
            undecided.append((site, regions.reason, regions.size))
            continue
        if regions is None:
            continue
        pending = _Pending.of(regions, None if frame is None else frame.cut_on(regions, obj))
        entry = (float(pending.cut(0.0).relative_min_size), key, pending)
        site_of[key] = site
        bisect.insort(built, entry, key=_by_size)
        if construction.enough is not None:  # counts proved region sets as they come
            settled(entry)
    first = proved_first()
    # a site whose regions could not have ranked among the best does not make it incomplete
    floor = _tied_floor(min(b[0] for b in first), slack, areas) if len(first) == top \
        else -math.inf
    return Found([b[2].cut(0.0) for b in first],
                 [(site, why) for site, why, size in undecided if size is None or size >= floor])
