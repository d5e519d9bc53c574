"""Four hard fingers on a polygon: two force-closure pairs, each holding the object alone.

A grasp that contains a force-closure grasp is force-closure (its wrench cone only grows,
Theorem 1). So four hard fingers whose edges split into two pairs, each pair with two-finger
independent regions (Corollary 3, Lemma 1: :mod:`.two_fingers`), have independent regions:
the four segments. Such a grasp is redundant on purpose, as a fixture's locators are: any
one finger may slip or lift and the other pair still holds. The regions of a quadruple of
edges are those of its best pairing (the larger shorter segment of the two pairs); the bound
is the same from the two-finger linear program of every pair, solved at once, so the search
is exact over every quadruple and pairing. It does not find grasps that need all four
fingers (none of its pairs force-closure): those need a common equilibrium, which this
construction does not search.

Examples
--------
>>> from forceclosure.objects import bundled
>>> r = two_pair_regions(bundled("square"), (0, 1, 2, 3), mu=0.4)
>>> r.pairs, round(r.min_length, 3), r.certify().holds
(((0, 2), (1, 3)), 0.798, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...errors import InputError
from ...objects.polygon import Polygon
from ..construction import Construction, Hand
from ..regions import MARGIN, Certificate, Regions, check_edges, check_margin, narrowed, proved_once
from .edge_pair import IndependentRegions
from .edge_sites import edge_tuples
from .two_fingers import edge_pair_sites, maximal_regions, solve_sites

__all__ = ["PairedRegions", "two_pair_regions"]

#: The three ways to split four fingers (positions in the quadruple) into two pairs.
PAIRINGS = (((0, 1), (2, 3)), ((0, 2), (1, 3)), ((0, 3), (1, 2)))


@dataclass(frozen=True, eq=False)
class PairedRegions(Regions):
    """Four segments in two pairs, each pair's every choice of two points force-closure.

    Attributes (beyond :class:`Regions`)
    ------------------------------------
    mu : float
    pairs : ((int, int), (int, int))
        The edges of each pair.
    spreading : (bool, bool)
        Whether each pair's fingers push apart (from inside a slot or a hole).
    """

    mu: float = 0.0
    pairs: tuple[tuple[int, int], tuple[int, int]] = ((0, 1), (2, 3))
    spreading: tuple[bool, bool] = (False, False)

    def friction(self) -> tuple[float, ...]:
        """The friction coefficient at each finger."""
        return (self.mu,) * len(self.edges)

    def notes(self) -> list[str]:
        """Which pairs hold alone."""
        (a, b), (c, d) = self.pairs
        return [f"edges {a} + {b} and edges {c} + {d} each hold the object alone (any one "
                "finger may slip)"]

    def to_dict(self) -> dict[str, object]:
        """The JSON record (see :meth:`Regions.to_dict`), with ``mu``, ``pairs`` and
        ``pair_spreading`` (each pair's)."""
        return {**super().to_dict(), "mu": self.mu, "pairs": [list(p) for p in self.pairs],
                "pair_spreading": list(self.spreading)}

    def _pair(self, k: int) -> IndependentRegions:
        where = {e: s for e, s in zip(self.edges, self.segments, strict=True)}
        a, b = self.pairs[k]
        return IndependentRegions(self.polygon, (a, b), (where[a], where[b]),
                                  "maximal (linear program)", (self.mu, self.mu),
                                  spreading=self.spreading[k])

    @proved_once
    def certify(self) -> Certificate:
        """Prove each pair's regions (the exact corner check of
        :meth:`IndependentRegions.certify`): a grasp containing a force-closure grasp is
        force-closure."""
        if sorted(e for p in self.pairs for e in p) != sorted(self.edges):
            return Certificate(False, "corner check of each pair (exact rationals)",
                               "the pairs are not the four edges")
        for k in (0, 1):
            proof = self._pair(k).certify()
            if not proof.holds:
                return Certificate(False, "corner check of each pair (exact rationals)",
                                   f"the pair on edges {self.pairs[k]}: {proof.detail}")
        return Certificate(True, "corner check of each pair (exact rationals)",
                           "each pair's segments are two-finger independent regions "
                           "(Corollary 3 at their corners); a grasp containing a "
                           "force-closure grasp is force-closure")


def _build(polygon: Polygon, edges: tuple[int, ...], mu: float,
           margin: float) -> PairedRegions | None:
    best = None
    for (p, q), (r, s) in PAIRINGS:
        first = maximal_regions(polygon, edges[p], edges[q], mu, margin=margin)
        second = maximal_regions(polygon, edges[r], edges[s], mu, margin=margin)
        if not (isinstance(first, IndependentRegions) and isinstance(second, IndependentRegions)):
            continue  # an undecided pair is left out: this construction is not complete
        where: dict[int, tuple[float, float]] = {}
        for pair in (first, second):
            where.update(zip(pair.edges, pair.segments, strict=True))
        regions = PairedRegions(polygon, tuple(edges), tuple(where[e] for e in edges),
                                "two force-closure pairs (maximal)", float(mu),
                                ((edges[p], edges[q]), (edges[r], edges[s])),
                                (first.spreading, second.spreading))
        # a later pairing only when larger beyond rounding: ties go by pairing order
        if regions.certify().holds and (best is None or regions.min_length
                                        > best.min_length * (1 + 1e-6)):
            best = regions
    return best


def two_pair_regions(polygon: Polygon, edges: tuple[int, int, int, int], mu: float,
                     margin: float = MARGIN) -> PairedRegions | None:
    """The largest regions for four hard fingers on four edges made of two force-closure
    pairs (the best of the three pairings), or None when no pairing has two.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> two_pair_regions(bundled("triangle"), (0, 1, 2, 0), mu=0.4)
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: four fingers need four different edges, got (0, 1, 2, 0)
    """
    edges = check_edges(polygon, edges, 4)
    if not (isinstance(mu, int | float) and np.isfinite(mu) and mu > 0):
        raise InputError(f"friction coefficient must be a positive number, got {mu!r}")
    check_margin(margin)
    return _build(polygon, edges, float(mu), margin)


#: The key of a search's memo (:attr:`~forceclosure.synthesis.construction.Hand.memo`)
#: under which the polygon's table is kept: the best two-finger segment of each pair of
#: edges (either orientation), over the size, as an (n, n) array.
_TABLE = "two_pairs.table"


def _pair_table(polygon: Polygon, hand: Hand) -> NDArray[np.float64]:
    mu = narrowed(hand.mu, hand.margin)
    kept = hand.memo.get(_TABLE)
    if kept is not None and kept[0] is polygon and kept[1] == mu:
        return kept[2]
    n = len(polygon.edges)
    table = np.zeros((n, n))
    sites = np.concatenate(list(edge_pair_sites(polygon, Hand(2, "hard", hand.mu, hand.margin))))
    if len(sites) and mu > 0:
        z = solve_sites(polygon, sites, mu)[0] / polygon.size
        z = np.where(np.isfinite(z), np.maximum(z, 0.0), 0.0)
        i, j = sites[:, 0], sites[:, 1]
        np.maximum.at(table, (i, j), z)
        table = np.maximum(table, table.T)
    hand.memo[_TABLE] = (polygon, mu, table)
    return table


def _bound(polygon: Polygon, sites: NDArray, hand: Hand) -> NDArray[np.float64]:
    """Step 3: the best pairing's smaller two-finger segment (exact: the linear program of
    every pair), over the size."""
    table = _pair_table(polygon, hand)
    best = np.zeros(len(sites))
    for (p, q), (r, s) in PAIRINGS:
        both = np.minimum(table[sites[:, p], sites[:, q]], table[sites[:, r], sites[:, s]])
        best = np.maximum(best, both)
    return best


def _prune(polygon: Polygon, sites: NDArray, hand: Hand) -> NDArray[np.bool_]:
    """Step 2: some pairing has two pairs with two-finger regions (necessary)."""
    return _bound(polygon, sites, hand) > 0


def _build_site(polygon: Polygon, site: NDArray, hand: Hand) -> PairedRegions | None:
    return _build(polygon, tuple(int(e) for e in site), hand.mu, hand.margin)


TWO_PAIRS = Construction(
    dim=2, fingers=4, contact="hard", name="maximal", paper="§5.1, Corollary 3 (two pairs)",
    method="edges", sites=edge_tuples(4), prune=_prune, bound=_bound, build=_build_site,
    searched="every four edges split into two pairs that each hold the object alone (two "
             "force-closure pairs; grasps that need all four fingers are not searched)")

