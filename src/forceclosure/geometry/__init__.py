"""Plane and cone geometry shared by the analysis, the kernels and the constructions.

A leaf package: it imports nothing from :mod:`forceclosure` but
:mod:`forceclosure.errors` and :mod:`forceclosure.tolerance`, so every layer
above may use it.

* :mod:`.clip` — a convex polygon cut by half-planes.
* :mod:`.rings` — the signed area of a polygon ring.
* :mod:`.cones` — friction cones: the angle between two axes, whether two
  cones counter-overlap, tangent bases (from the coordinate axes, or from
  the grasp itself), and the friction pyramid.
"""

from __future__ import annotations

from .clip import clip
from .cones import (
    angle_between,
    counter_overlap,
    counter_overlap_angle,
    friction_forces,
    grasp_tangents,
    pyramid_radius,
    pyramid_rim,
    tangent_basis,
)
from .rings import signed_area

__all__ = ["angle_between", "clip", "counter_overlap", "counter_overlap_angle",
           "friction_forces", "grasp_tangents", "pyramid_radius", "pyramid_rim",
           "signed_area", "tangent_basis"]
