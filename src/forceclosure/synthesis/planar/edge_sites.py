"""Candidate tuples of edges for the constructions on polygons, and their prune: the
force-direction closure of the fingers' friction cones (Theorem 2, necessary).

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
from collections.abc import Callable, Iterator

import numpy as np
from numpy.typing import NDArray

from ...objects.polygon import Polygon
from ..construction import Hand
from ..regions import narrowed

__all__ = ["BLOCK", "edge_tuples", "force_direction_prune"]

#: Edge tuples generated and pruned at once.
BLOCK = 65_536


def edge_tuples(count: int) -> Callable[[Polygon, Hand], Iterator[NDArray[np.int64]]]:
    """Step 1 of a construction on ``count`` edges: every ``count`` distinct edges in
    increasing order, as rows, in blocks of :data:`BLOCK`."""
    def sites(polygon: Polygon, hand: Hand) -> Iterator[NDArray[np.int64]]:
        tuples = itertools.combinations(range(len(polygon.edges)), count)
        while block := list(itertools.islice(tuples, BLOCK)):
            yield np.array(block, dtype=np.int64)
    return sites


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
