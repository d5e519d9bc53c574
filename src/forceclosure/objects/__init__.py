"""Objects to grasp: polygons (edges) and polyhedra (planar faces)."""

from .examples import POLYGONS, POLYHEDRA, bundled, glyph, prism
from .polygon import Edge, Polygon
from .polyhedron import PlanarFace, Polyhedron

__all__ = ["POLYGONS", "POLYHEDRA", "Edge", "PlanarFace", "Polygon", "Polyhedron", "bundled",
           "glyph", "prism"]
