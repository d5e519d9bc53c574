"""Regions grown over any triangle mesh around prototype grasps (:mod:`.grown_regions`).

The mesh method beyond the paper (Roa & Suárez 2009; Krug et al. 2010), the
table's construction for curved objects. Part of :mod:`forceclosure.synthesis`
(it imports the analysis, objects, geometry and the core, never the gripper,
pictures, io or the app). It was the module :mod:`.grown_regions` before
(issue 16), whose names it still gives.
"""

from typing import Any

from ..._moved import forward

__all__ = ["MESH"]


def __getattr__(name: str) -> Any:
    return forward(__name__, f"{__name__}.grown_regions", name)
