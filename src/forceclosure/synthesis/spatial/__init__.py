"""The paper's constructions on a polyhedron's faces (Nguyen 1988, §5.2, §5.3, §5.5).

* :mod:`.two_soft` — two soft fingers, the counter-overlapping cone (§5.2);
* :mod:`.three_hard` — three hard fingers, classified by counter-overlapping pairs (§5.3);
* :mod:`.seven_frictionless` — seven frictionless fingers, multi-affine minors (§5.5);
* :mod:`.patches` — face patches, convex pieces, the sampling check;
* :mod:`.zones` — prototype grasps and search zones (Roa & Suárez 2009).

Part of :mod:`forceclosure.synthesis` (it imports the analysis, objects,
geometry and the core, never the gripper, pictures, io or the app).
"""

__all__: list[str] = []
