"""The reverse problem: where to put the fingers (Nguyen 1988, §4, §5).

:func:`synthesize` is the one door: it takes the table's construction for a hand on an
object (:data:`TABLE`, ``construction=`` a name in it or a :class:`Construction`) and
returns the best region sets. The regions on one given site (edges, faces) are here too,
construction by construction.
"""

from __future__ import annotations

from ..lazy import lazy_names

#: Where each public name lives: imported on first use, so that the table's names
#: (``forceclosure synthesize --help``) are read without loading numpy.
_HOME = {
    **dict.fromkeys(["Synthesis", "synthesize"], "best"),
    **dict.fromkeys(["Construction", "Hand", "Undecided"], "construction"),
    **dict.fromkeys(["FrictionlessRegions", "maximal_frictionless_regions",
                     "nguyen_frictionless_regions"], "planar.four_frictionless"),
    **dict.fromkeys(["ThreeFingerRegions", "three_finger_regions"], "planar.three_fingers"),
    **dict.fromkeys(["IndependentRegions", "PairGrasps", "Sector", "counter_overlapping_sector",
                     "maximal_regions", "pair_grasps"], "planar.two_fingers"),
    **dict.fromkeys(["nguyen_regions"], "planar.two_sided_cone"),
    **dict.fromkeys(["VertexGrasp"], "planar.vertex_grasps"),
    **dict.fromkeys(["search"], "ranked_search"),
    **dict.fromkeys(["Certificate", "RegionSet", "Regions"], "regions"),
    **dict.fromkeys(["FacePatch", "SpatialRegions"], "spatial.patches"),
    **dict.fromkeys(["SevenRegions", "seven_frictionless_regions"], "spatial.seven_frictionless"),
    **dict.fromkeys(["GraspClass", "ThreeHardRegions", "classify_three", "three_hard_regions"],
                    "spatial.three_hard"),
    **dict.fromkeys(["CircularCone", "SoftPairRegions", "counter_overlapping_cone",
                     "soft_pair_regions"], "spatial.two_soft"),
    **dict.fromkeys(["Prototype", "SearchZones", "ZoneRegions", "prototype_grasps", "search_zones",
                     "zone_regions"], "spatial.zones"),
    **dict.fromkeys(["TABLE", "construction_for", "constructions", "served"], "table"),
}

__all__ = sorted(_HOME)


__getattr__, __dir__ = lazy_names(__name__, _HOME)
