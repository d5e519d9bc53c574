"""Candidate tuples of edges for the constructions on polygons, their prune (the
force-direction closure of the fingers' friction cones, Theorem 2, necessary) and their
bound (a region on an edge is no longer than the edge), the three at once in levels of one
bound (:func:`by_shortest_edge`), so that a search reaches its best tuples without listing
every tuple of a finely tessellated polygon.

Examples
--------
>>> from forceclosure.objects import bundled
>>> from forceclosure.synthesis.construction import Hand
>>> square, hand = bundled("square"), Hand(4, "frictionless", 0.0)
>>> [block] = edge_tuples(4)(square, hand)
>>> block.tolist(), force_direction_prune(square, block, hand).tolist()
([[0, 1, 2, 3]], [True])
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...objects.polygon import Polygon
from ..construction import Hand
from ..regions import narrowed, tie_rounded

__all__ = ["BLOCK", "Level", "by_shortest_edge", "edge_tuples", "force_direction_prune",
           "shortest_edge"]

#: Edge tuples generated and pruned at once.
BLOCK = 65_536


def _blocks(tuples: Iterator[tuple[int, ...]]) -> Iterator[NDArray[np.int64]]:
    """``tuples`` as integer arrays of :data:`BLOCK` rows (the last one shorter)."""
    while block := list(itertools.islice(tuples, BLOCK)):
        yield np.array(block, dtype=np.int64)


def _using(edges: Sequence[int], own: set[int], count: int) -> Iterator[tuple[int, ...]]:
    """Every ``count`` of ``edges`` (increasing) that uses an edge of ``own``, in
    lexicographic order, at a cost in proportion to their number: a prefix without an edge
    of ``own`` is followed only while one is left after it.

    Examples
    --------
    >>> list(_using([0, 1, 2, 3], {2}, 2))
    [(0, 2), (1, 2), (2, 3)]
    """
    n = len(edges)
    after = [n] * (n + 1)  # after[i]: the first place from i on that holds an edge of own
    for i in range(n - 1, -1, -1):
        after[i] = i if edges[i] in own else after[i + 1]

    def extend(start: int, left: int, prefix: tuple[int, ...]) -> Iterator[tuple[int, ...]]:
        if left == 1:  # the last edge: one of own
            i = after[start]
            while i < n:
                yield (*prefix, edges[i])
                i = after[i + 1]
            return
        for i in range(start, n - left + 1):
            if after[i] == n:  # no edge of own left
                return
            if edges[i] in own:  # used: any edges after it
                for rest in itertools.combinations(edges[i + 1:], left - 1):
                    yield (*prefix, edges[i], *rest)
            else:
                yield from extend(i + 1, left - 1, (*prefix, edges[i]))

    return extend(0, count, ())


def edge_tuples(count: int) -> Callable[[Polygon, Hand], Iterator[NDArray[np.int64]]]:
    """Step 1 of a construction on ``count`` edges: every ``count`` distinct edges in
    increasing order, as rows, in blocks of :data:`BLOCK`."""
    def sites(polygon: Polygon, hand: Hand) -> Iterator[NDArray[np.int64]]:
        return _blocks(itertools.combinations(range(len(polygon.edges)), count))
    return sites


def shortest_edge(polygon: Polygon, sites: NDArray, hand: Hand) -> NDArray[np.float64]:
    """Step 3: a tuple's smallest region is at most its shortest edge (over the size)."""
    return polygon.edge_arrays.length[sites].min(axis=1) / polygon.size


@dataclass(frozen=True)
class Level:
    """Sites of one bound, pruned, in site order (:func:`by_shortest_edge`).

    Attributes
    ----------
    bound : float
        Their bound, rounded as the search rounds bounds (:func:`tie_rounded`).
    sites : (m, count) int array
        The tuples of edges, increasing in each row, rows in lexicographic order.
    later : tuple of int, or ``(inf,)``
        No site of a later level precedes this tuple in site order (a lower bound: it
        ignores the prune, so a search may take up a few more sites than the full search
        would, never fewer, and finds the same region sets).
    """

    bound: float
    sites: NDArray[np.int64]
    later: tuple[float, ...]


def by_shortest_edge(count: int) -> Callable[[Polygon, Hand, Callable | None], Iterator[Level]]:
    """Steps 1 to 3 at once for a construction on ``count`` edges bounded by
    :func:`shortest_edge`: the tuples in the order of a search by decreasing bound, ties in
    site order, generated lazily a bound at a time.

    The edges are classed by their rounded bound, largest first; level ``j`` holds the
    tuples of edges of the first ``j`` classes that use an edge of class ``j`` (their
    shortest), in lexicographic order, pruned block by block. Each level also names the
    least tuple any later one could hold (the first ``count - 1`` edges of the later
    classes and the first edge of its own class, or the first ``count``), which a search
    needs to break ties by site order before it has seen those levels.

    Examples
    --------
    >>> from forceclosure.objects import Polygon
    >>> from forceclosure.synthesis.construction import Hand
    >>> # edges of lengths 4, 1, 1.41, 3, 2: the third is the shortest of the first level
    >>> kite = Polygon.from_points([[0, 0], [4, 0], [4, 1], [3, 2], [0, 2]])
    >>> levels = by_shortest_edge(4)(kite, Hand(4, "frictionless", 0.0), force_direction_prune)
    >>> [(level.sites.tolist(), level.later) for level in levels]
    [([[0, 2, 3, 4]], (0, 1, 2, 3)), ([[0, 1, 2, 4], [0, 1, 3, 4]], (inf,))]
    """
    def levels(polygon: Polygon, hand: Hand, prune: Callable | None) -> Iterator[Level]:
        lengths = shortest_edge(polygon, np.arange(len(polygon.edges))[:, None], hand)
        rounded = np.array([tie_rounded(float(x)) for x in lengths])
        classes = sorted(set(rounded.tolist()), reverse=True)
        # the least tuple of each level, and from each level on
        least: list[tuple] = []
        first = np.empty(0, dtype=np.int64)
        owns = [np.flatnonzero(rounded == value) for value in classes]
        for own in owns:
            first = np.sort(np.concatenate([first, own[:count]]))[:count]
            if len(first) < count:  # no tuple yet
                least.append((math.inf,))
            else:
                least.append(tuple(int(e) for e in first) if np.isin(first, own).any()
                             else (*map(int, first[:count - 1]), int(own[0])))
        after: list[tuple] = [(math.inf,)] * len(classes)  # the least of the levels after
        for j in range(len(classes) - 2, -1, -1):
            after[j] = min(after[j + 1], least[j + 1])
        for value, own, later in zip(classes, owns, after, strict=True):
            usable = np.flatnonzero(rounded >= value)
            if len(usable) < count:
                continue
            for block in _blocks(_using(usable.tolist(), set(own.tolist()), count)):
                if prune is not None:
                    block = block[np.asarray(prune(polygon, block, hand), dtype=bool)]
                if len(block):
                    yield Level(value, block, later)
    return levels


def force_direction_prune(polygon: Polygon, sites: NDArray, hand: Hand) -> NDArray[np.bool_]:
    """Step 2: the friction cones of the fingers on each tuple of edges, narrowed by the
    margin (the pushing directions ``-n`` for frictionless fingers), positively span the
    plane: their edges leave no gap of ``pi`` or more around the circle. Force-direction
    closure is necessary for force closure (Theorem 2)."""
    normals = polygon.edge_arrays.normal
    push = np.arctan2(-normals[sites, 1], -normals[sites, 0])
    half = math.atan(narrowed(hand.mu, hand.margin)) if hand.mu > 0 else 0.0
    angles = np.sort(np.concatenate([push - half, push + half], axis=1) % (2 * np.pi), axis=1)
    gaps = np.diff(np.concatenate([angles, angles[:, :1] + 2 * np.pi], axis=1), axis=1)
    return gaps.max(axis=1) < np.pi - 1e-12
