"""Object-centred, scaled coordinates: where the searches on polygons compute.

The rule is :class:`~forceclosure.geometry.placement.Placement`'s (polyhedra follow it too). A
polygon far from the origin (1e8) or very small or large (1e-4, 1e3) is searched in a
copy centred on its bounding box and divided by a power of two near its size, so that the
constructions' tolerances and linear programs see an object about 1 across at the origin,
wherever and however large the user's is. Its edges keep their indices and their unit
normals (the very floats of the user's polygon), so a moved or scaled copy is searched on
the same numbers up to the rounding of the move. Each region set found is mapped back
(edge parameters times the scale, points moved back, :meth:`Frame.cut_on`) and, when the
search ranks it among the best, proved again on the user's polygon, at the floats that are
printed and returned; where those round off a proof, the regions are cut a little
(:data:`~forceclosure.synthesis.regions.TRIMS`), and a site whose regions cannot be proved
at all is reported undecided.

A polyhedron is searched the same way: its faces keep their indices, unit normals and in-plane
axes (the user's floats), their origins and vertices are moved and scaled; a region set's
patches are mapped back (plane coordinates times the scale, then onto the user's face), points
such as a prototype grasp or an apex moved back, search zones given the user's reference point
and length scale (the same wrenches), and each region set is proved again on the polyhedron as
given, its patches cut towards their centres by the same trims where the printed floats need it.

Examples
--------
>>> from forceclosure.objects import Polygon
>>> far = Polygon.from_points([[1e8, 0], [1e8 + 2, 0], [1e8 + 2, 2], [1e8, 2]])
>>> frame = Frame.of(far)
>>> frame.scale, frame.local(far).outer.tolist()
(4.0, [[-0.25, -0.25], [0.25, -0.25], [0.25, 0.25], [-0.25, 0.25]])

A polyhedron keeps its faces (indices, normals), moved and scaled:

>>> from forceclosure.objects import Polyhedron, bundled
>>> cube = bundled("cube")
>>> moved = Polyhedron.from_arrays(cube.vertices + 1e8, cube.triangles)
>>> local = Frame.of(moved).local(moved)
>>> local.bounds.tolist(), local.faces[0].normal.tolist() == moved.faces[0].normal.tolist()
([[-0.25, -0.25, -0.25], [0.25, 0.25, 0.25]], True)
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..geometry.placement import Placement
from ..objects.polygon import Edge, Polygon
from ..objects.polyhedron import Polyhedron
from .regions import TRIMS, RegionSet
from .spatial.patches import FacePatch, SpatialRegions

__all__ = ["UNPROVED", "Frame"]

#: Why a site is undecided when its region set, found in the frame, fails every cut on the
#: user's object.
UNPROVED = ("regions found in object-centred coordinates could not be proved at the floats "
            "of the coordinates given")

#: Region set fields that are points in the object's coordinates (moved back, scaled).
_POINTS = ("apex", "centre")
#: The same on polyhedra: arrays of points (a prototype grasp's contacts, a cone's apex).
_POINTS_3D = ("apex", "prototype")


@dataclass(frozen=True)
class Frame(Placement):
    """The map from the user's coordinates to the search's: ``local = (x - centre) / scale``
    (:class:`~forceclosure.geometry.placement.Placement`), with a polygon's edges and region
    sets mapped by it.

    Attributes
    ----------
    centre : (2,) array
        The centre of the object's bounding box.
    scale : float
        A power of two within a factor of 1.5 of the object's size (so that edge parameters
        map back exactly: times the scale).
    """

    @classmethod
    def of(cls, obj: Polygon | Polyhedron) -> Frame:  # type: ignore[override]
        """The frame of a polygon or polyhedron: its bounding box's centre, a power of two
        near its size."""
        return super().of(obj.bounds, obj.size)

    def local(self, polygon: Polygon | Polyhedron) -> Polygon | Polyhedron:
        """``polygon`` in this frame: the same edges (indices, sources, unit normals), moved
        and scaled; no new validation (a move and a scale keep the polygon valid). A
        polyhedron keeps its triangles and faces (indices, normals, axes, loops), its
        vertices and face origins moved and scaled."""
        if isinstance(polygon, Polyhedron):
            return self._local_polyhedron(polygon)
        def to(x):
            out = (np.asarray(x, float) - self.centre) / self.scale
            out.setflags(write=False)
            return out

        edges = tuple(Edge(e.index, e.ring, to(e.start), to(e.end), e.normal,
                           e.length / self.scale, e.source) for e in polygon.edges)
        return Polygon(to(polygon.outer), tuple(to(h) for h in polygon.holes), edges,
                       polygon.name, polygon.warnings, polygon.spread)

    def cut_on(self, regions: Any, polygon: Polygon | Polyhedron
               ) -> tuple[Callable[[float], RegionSet], tuple[float, ...]] | None:
        """The region set found in this frame, mapped onto the user's ``polygon`` (or
        polyhedron) unproved: a function of the fraction by which each region is cut at each
        end (``cut(0.0)``: not cut), and the cuts to try in turn
        (:func:`~forceclosure.synthesis.regions.first_proved`); ``None`` for anything but a
        region set. :func:`~forceclosure.synthesis.ranked_search.search` proves only the
        region sets it ranks among the best."""
        if not (isinstance(regions, RegionSet) and dataclasses.is_dataclass(regions)):
            return None
        if isinstance(regions, SpatialRegions):
            assert isinstance(polygon, Polyhedron)
            return self._spatial_cut(regions, polygon), TRIMS
        assert isinstance(polygon, Polygon)
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

        def mapped(trim: float) -> Any:
            cut = []
            for e, (u, v) in pieces:
                u, v = u * self.scale, v * self.scale
                cut.append((min(max(u + trim * (v - u), 0.0), e.length) + 0.0,
                            min(max(v - trim * (v - u), 0.0), e.length) + 0.0))
            if "segments" in names:
                fixed["segments"] = tuple(cut)
            elif cut:
                fixed["segment"] = cut[0]
            return dataclasses.replace(regions, **fixed)

        return mapped, TRIMS if pieces else TRIMS[:1]  # no piece: no cut

    def _local_polyhedron(self, polyhedron: Polyhedron) -> Polyhedron:
        V = self.to_local_points(polyhedron.vertices)
        V.setflags(write=False)
        area = self.scale * self.scale

        def origin(face):
            out = self.to_local_points(face.origin)
            out.setflags(write=False)
            return out

        faces = tuple(dataclasses.replace(f, origin=origin(f), area=f.area / area, _vertices=V)
                      for f in polyhedron.faces)
        return dataclasses.replace(polyhedron, vertices=V, faces=faces)

    def _spatial_cut(self, regions: SpatialRegions, polyhedron: Polyhedron
                     ) -> Callable[[float], SpatialRegions]:
        names = {f.name for f in dataclasses.fields(regions)}
        fixed: dict[str, Any] = {"polyhedron": polyhedron}
        for name in _POINTS_3D:
            point = getattr(regions, name, None)
            if name in names and point is not None:
                fixed[name] = self.to_user_points(point)
                fixed[name].setflags(write=False)
        zones = getattr(regions, "zones", None)
        if "zones" in names and zones is not None:  # the same wrenches, about the same point
            fixed["zones"] = dataclasses.replace(
                zones, reference=self.to_user_points(zones.reference),
                length_scale=zones.length_scale * self.scale)
        faces = polyhedron.faces

        def moved(trim: float) -> SpatialRegions:
            patches = []
            for region in regions.regions:
                mapped = []
                for p in region:
                    middle = p.uv.mean(axis=0)
                    uv = (middle + (1 - 2 * trim) * (p.uv - middle)) * self.scale + 0.0
                    mapped.append(FacePatch(p.face, uv, faces[p.face].to_world(uv)))
                patches.append(tuple(mapped))
            fixed["regions"] = tuple(patches)
            return dataclasses.replace(regions, **fixed)

        return moved
