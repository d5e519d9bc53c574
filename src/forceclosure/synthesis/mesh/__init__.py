"""Regions grown over any triangle mesh around prototype grasps (:mod:`.grown_regions`).

The mesh method beyond the paper (Roa & Suárez 2009; Krug et al. 2010), the
table's construction for curved objects and for hands no construction on faces
serves. Part of :mod:`forceclosure.synthesis` (it imports the analysis, objects,
geometry and the core, never the gripper, pictures, io or the app).
"""

__all__: list[str] = []
