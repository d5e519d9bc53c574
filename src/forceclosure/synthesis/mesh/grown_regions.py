"""Regions grown on any mesh around sampled prototype grasps: the construction for a
hand or an object the paper's constructions do not serve (beyond Nguyen 1988, §5.3's
search zones on a mesh).

Random grasps are analysed in a batch; the best by epsilon become
prototypes, and each grows its search-zone regions over the mesh's faces
(:func:`~forceclosure.synthesis.spatial.zones.zone_regions`).

Examples
--------
>>> from forceclosure.objects import bundled
>>> from forceclosure.synthesis.construction import Hand
>>> from forceclosure.synthesis.ranked_search import search
>>> found = search(MESH, bundled("cube"), Hand(4, "hard", 0.5, samples=2000, top=1))
>>> len(found), found[0].certify().holds
(1, True)
"""

from __future__ import annotations

from ...errors import InputError
from ...objects.polyhedron import Polyhedron
from ..construction import Construction, Hand
from ..regions import narrowed
from ..spatial.zones import Prototype, ZoneRegions, prototype_grasps, zone_regions

__all__ = ["MESH"]


def _prototypes(polyhedron: Polyhedron, hand: Hand):
    """Step 1: the ``top`` best of ``samples`` random grasps by epsilon (with the cones
    narrowed by the margin)."""
    yield prototype_grasps(polyhedron, hand.fingers, hand.contact,
                           narrowed(hand.mu, hand.margin), count=hand.top,
                           samples=hand.samples, seed=hand.seed)


def _grow(polyhedron: Polyhedron, prototype: Prototype, hand: Hand) -> ZoneRegions | None:
    try:
        return zone_regions(polyhedron, prototype, hand.contact, hand.mu, grow=True,
                            margin=hand.margin, resolution=hand.resolution)
    except InputError:  # a prototype on the boundary of closure: skip it
        return None


MESH = Construction(
    dim=3, fingers=None, contact="any", name="mesh", paper="§5.3's search zones, on a mesh",
    method="mesh", sites=_prototypes, build=_grow,
    searched="around the best sampled grasps by epsilon")
