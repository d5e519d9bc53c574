"""The paper's constructions on a polygon's edges (Nguyen 1988, §5.1, §5.4).

* :mod:`.two_fingers` — two hard fingers: the maximal regions (Corollary 3,
  Lemma 1), and the table's ``(2, 2, hard)`` construction;
* :mod:`.two_sided_cone` — Nguyen's Algorithm 1, the two-sided cone;
* :mod:`.three_fingers` — three hard fingers;
* :mod:`.four_frictionless` — four frictionless fingers (§5.4);
* :mod:`.two_pairs` — four hard fingers as two force-closure pairs;
* :mod:`.vertex_grasps` — fingers on convex vertices;
* :mod:`.grown_segments` — any other hand: segments grown around sampled prototypes, the
  table's planar fallback;
* :mod:`.edge_pair`, :mod:`.edge_sites` — the candidate edge tuples.

Part of :mod:`forceclosure.synthesis` (it imports the analysis, objects,
geometry and the core, never the gripper, pictures, io or the app). It was the
module :mod:`.two_fingers` before (issue 16), whose names it still gives:
``from forceclosure.synthesis.planar import best_regions`` works.

Examples
--------
>>> from forceclosure.synthesis.planar import best_regions, two_fingers
>>> best_regions is two_fingers.best_regions
True
"""

from typing import Any

from ..._moved import forward

__all__ = ["ANGLE_MARGIN", "CHUNK", "MAX_EDGE_PAIRS", "IndependentRegions", "PairGrasps", "Sector",
           "best_regions", "counter_overlapping_sector", "max_min_segments", "maximal_regions",
           "pair_grasps"]


def __getattr__(name: str) -> Any:
    return forward(__name__, f"{__name__}.two_fingers", name)
