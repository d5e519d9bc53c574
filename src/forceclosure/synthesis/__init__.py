"""The reverse problem: where to put the fingers (Nguyen 1988, §4, §5)."""

from .frictionless import (
    FrictionlessRegions,
    best_frictionless_regions,
    maximal_frictionless_regions,
    nguyen_frictionless_regions,
)
from .nguyen import nguyen_regions
from .planar import (
    IndependentRegions,
    PairGrasps,
    Sector,
    best_regions,
    counter_overlapping_sector,
    maximal_regions,
    pair_grasps,
)
from .regions import Certificate, Regions
from .three_fingers import ThreeFingerRegions, best_three_finger_regions, three_finger_regions
from .vertices import VertexGrasp, convex_vertices, vertex_grasps

__all__ = [
    "Certificate",
    "FrictionlessRegions",
    "IndependentRegions",
    "PairGrasps",
    "Regions",
    "Sector",
    "ThreeFingerRegions",
    "VertexGrasp",
    "best_frictionless_regions",
    "best_regions",
    "best_three_finger_regions",
    "convex_vertices",
    "counter_overlapping_sector",
    "maximal_frictionless_regions",
    "maximal_regions",
    "nguyen_frictionless_regions",
    "nguyen_regions",
    "pair_grasps",
    "three_finger_regions",
    "vertex_grasps",
]
