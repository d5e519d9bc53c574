"""Object-centred, scaled coordinates: where the searches on polygons compute.

A polygon far from the origin (1e8) or very small or large (1e-4, 1e3) is searched in a
copy centred on its bounding box and divided by a power of two near its size, so that the
constructions' tolerances and linear programs see an object about 1 across at the origin,
wherever and however large the user's is. Its edges keep their indices and their unit
normals (the very floats of the user's polygon), so a moved or scaled copy is searched on
the same numbers up to the rounding of the move. Each region set found is mapped back
(edge parameters times the scale, points moved back) and proved again on the user's
polygon, at the floats that are printed and returned; where those round off a proof, the
regions are cut a little (:data:`~forceclosure.synthesis.regions.TRIMS`), and a site whose
regions cannot be proved at all is reported undecided.

Examples
--------
>>> from forceclosure.objects import Polygon
>>> far = Polygon.from_points([[1e8, 0], [1e8 + 2, 0], [1e8 + 2, 2], [1e8, 2]])
>>> frame = Frame.of(far)
>>> frame.scale, frame.local(far).outer.tolist()
(4.0, [[-0.25, -0.25], [0.25, -0.25], [0.25, 0.25], [-0.25, 0.25]])
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..objects.polygon import Edge, Polygon
from .construction import Undecided
from .regions import TRIMS, RegionSet

__all__ = ["Frame"]

#: Region set fields that are points in the object's coordinates (moved back, scaled).
_POINTS = ("apex", "centre")


@dataclass(frozen=True)
class Frame:
    """The map from the user's coordinates to the search's: ``local = (x - centre) / scale``.

    Attributes
    ----------
    centre : (2,) array
        The centre of the object's bounding box.
    scale : float
        A power of two within a factor of 1.5 of the object's size (so that edge parameters
        map back exactly: times the scale).
    """

    centre: NDArray[np.float64]
    scale: float

    @classmethod
    def of(cls, polygon: Polygon) -> Frame:
        """The frame of ``polygon``: its bounding box's centre, a power of two near its size."""
        lo, hi = polygon.bounds
        centre = 0.5 * lo + 0.5 * hi
        return cls(centre, math.ldexp(1.0, round(math.log2(polygon.size))))

    def local(self, polygon: Polygon) -> Polygon:
        """``polygon`` in this frame: the same edges (indices, sources, unit normals), moved
        and scaled; no new validation (a move and a scale keep the polygon valid)."""
        def to(x):
            out = (np.asarray(x, float) - self.centre) / self.scale
            out.setflags(write=False)
            return out

        edges = tuple(Edge(e.index, e.ring, to(e.start), to(e.end), e.normal,
                           e.length / self.scale, e.source) for e in polygon.edges)
        return Polygon(to(polygon.outer), tuple(to(h) for h in polygon.holes), edges,
                       polygon.name, polygon.warnings, polygon.spread)

    def to_user(self, regions: Any, polygon: Polygon) -> Any:
        """A region set found in this frame, on the user's ``polygon``, proved there; cut by
        :data:`~forceclosure.synthesis.regions.TRIMS` until its proof holds, or
        :class:`~forceclosure.synthesis.construction.Undecided` when no cut does. Anything
        but a region set (``None``, an Undecided) is returned as it is."""
        if not (isinstance(regions, RegionSet) and dataclasses.is_dataclass(regions)):
            return regions
        names = {f.name for f in dataclasses.fields(regions)}
        fixed: dict[str, Any] = {"polygon": polygon}
        for name in _POINTS:
            point = getattr(regions, name, None)
            if name in names and point is not None:
                fixed[name] = tuple(float(v) + 0.0 for v in
                                    np.asarray(point, float) * self.scale + self.centre)
        if "segments" in names:
            edges = [polygon.edges[k] for k in regions.edges]
            pieces = list(zip(edges, regions.segments, strict=True))
        elif "segment" in names and regions.segment is not None:  # a vertex grasp's edge
            pieces = [(polygon.edges[regions.other[1]], regions.segment)]
        else:
            pieces = []
        for trim in TRIMS:
            cut = []
            for e, (u, v) in pieces:
                u, v = u * self.scale, v * self.scale
                cut.append((min(max(u + trim * (v - u), 0.0), e.length) + 0.0,
                            min(max(v - trim * (v - u), 0.0), e.length) + 0.0))
            if "segments" in names:
                fixed["segments"] = tuple(cut)
            elif cut:
                fixed["segment"] = cut[0]
            mapped = dataclasses.replace(regions, **fixed)
            if mapped.certify().holds:
                return mapped
            if not pieces:
                break
        return Undecided("regions found in object-centred coordinates could not be proved "
                         "at the floats of the coordinates given")
