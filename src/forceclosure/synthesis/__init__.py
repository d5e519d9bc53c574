"""The reverse problem: where to put the fingers (Nguyen 1988, §4, §5)."""

from .planar import (
    Certificate,
    IndependentRegions,
    PairGrasps,
    Sector,
    best_regions,
    counter_overlapping_sector,
    maximal_regions,
    nguyen_regions,
    pair_grasps,
)

__all__ = ["Certificate", "IndependentRegions", "PairGrasps", "Sector", "best_regions",
           "counter_overlapping_sector", "maximal_regions", "nguyen_regions", "pair_grasps"]
