"""The reverse problem: where to put the fingers (Nguyen 1988, §4, §5).

:func:`synthesize` picks the paper's construction for a hand on an object
and returns the best region sets; the constructions are also here one by one.
"""

from typing import Any

from .._moved import moved_attribute
from .best import Synthesis, synthesize
from .construction import Construction, Hand, construction_for, register, registered
from .planar.four_frictionless import (
    FrictionlessRegions,
    best_frictionless_regions,
    maximal_frictionless_regions,
    nguyen_frictionless_regions,
)
from .planar.three_fingers import (
    ThreeFingerRegions,
    best_three_finger_regions,
    three_finger_regions,
)
from .planar.two_fingers import (
    IndependentRegions,
    PairGrasps,
    Sector,
    best_regions,
    counter_overlapping_sector,
    maximal_regions,
    pair_grasps,
)
from .planar.two_sided_cone import nguyen_regions
from .planar.vertex_grasps import VertexGrasp, convex_vertices, vertex_grasps
from .ranked_search import candidate_sites, search
from .regions import Certificate, Regions, RegionSet
from .spatial.patches import FacePatch, SpatialRegions, convex_pieces, sampling_check
from .spatial.seven_frictionless import (
    SevenRegions,
    best_seven_frictionless_regions,
    seven_frictionless_regions,
)
from .spatial.three_hard import (
    GraspClass,
    ThreeHardRegions,
    best_three_hard_regions,
    classify_three,
    counter_overlap,
    three_hard_regions,
)
from .spatial.two_soft import (
    CircularCone,
    SoftPairRegions,
    best_soft_pair_regions,
    counter_overlapping_cone,
    soft_pair_regions,
)
from .spatial.zones import (
    Prototype,
    SearchZones,
    ZoneRegions,
    prototype_grasps,
    search_zones,
    zone_regions,
)

__all__ = [
    "Certificate",
    "CircularCone",
    "Construction",
    "FacePatch",
    "FrictionlessRegions",
    "GraspClass",
    "Hand",
    "IndependentRegions",
    "PairGrasps",
    "Prototype",
    "RegionSet",
    "Regions",
    "SearchZones",
    "Sector",
    "SevenRegions",
    "SoftPairRegions",
    "SpatialRegions",
    "Synthesis",
    "ThreeFingerRegions",
    "ThreeHardRegions",
    "VertexGrasp",
    "ZoneRegions",
    "best_frictionless_regions",
    "best_regions",
    "best_seven_frictionless_regions",
    "best_soft_pair_regions",
    "best_three_finger_regions",
    "best_three_hard_regions",
    "candidate_sites",
    "classify_three",
    "construction_for",
    "convex_pieces",
    "convex_vertices",
    "counter_overlap",
    "counter_overlapping_cone",
    "counter_overlapping_sector",
    "maximal_frictionless_regions",
    "maximal_regions",
    "nguyen_frictionless_regions",
    "nguyen_regions",
    "pair_grasps",
    "prototype_grasps",
    "register",
    "registered",
    "sampling_check",
    "search",
    "search_zones",
    "seven_frictionless_regions",
    "soft_pair_regions",
    "synthesize",
    "three_finger_regions",
    "three_hard_regions",
    "vertex_grasps",
    "zone_regions",
]


def __getattr__(name: str) -> Any:
    # the modules that moved into planar/, spatial/, mesh/ (forceclosure.synthesis.nguyen, ...)
    return moved_attribute(__name__, name)
