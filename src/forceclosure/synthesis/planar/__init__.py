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
geometry and the core, never the gripper, pictures, io or the app). Its names are
in its modules (``from forceclosure.synthesis.planar.two_fingers import
maximal_regions``).
"""

__all__: list[str] = []
