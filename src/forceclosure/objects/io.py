"""Loading objects from what users have: files, shapely, trimesh, arrays.

:func:`load_object` dispatches on the file's extension:

* polygons: ``.json`` / ``.geojson`` (``{"outer": [...], "holes": [...]}``,
  a list of points, or a GeoJSON Polygon, Feature or FeatureCollection of
  one polygon), ``.svg`` (read as a browser draws it, y up: transforms,
  ``<use>``, viewBox and units applied, ``<defs>`` ignored, curves and
  basic shapes tessellated within a stated tolerance; the largest drawn
  shape, or the one ``part`` names by id; see :mod:`forceclosure.objects.svg`),
  ``.csv`` (``x,y`` per line; an empty line starts a hole);
* polyhedra: ``.stl``, ``.obj``, ``.ply``, ``.off``, ``.glb``, ``.gltf``
  (through trimesh, scenes flattened into one mesh), and ``.urdf``: every
  ``<collision>`` geometry of one link (meshes with their scale, boxes,
  cylinders and spheres, the curved ones tessellated), each placed by its
  ``<origin xyz rpy>``, as robot simulators see it; the ``<visual>`` ones,
  with a warning, if the link has no collision geometry. A robot with
  several such links needs ``part=`` naming one (see
  :mod:`forceclosure.objects.urdf`).

A bundled example's name (``forceclosure objects``) works in place of a
path. Every failure is an :class:`~forceclosure.errors.InputError` with one
line naming the file and the problem.
"""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

import numpy as np
import shapely
from numpy.typing import NDArray

from ..errors import InputError, parse_json
from ..errors import first_line as _first_line
from ..files.read import regular_file
from .examples import POLYGONS, POLYHEDRA, bundled
from .meshfile import MESH_SUFFIXES, read_mesh_arrays
from .polygon import Polygon
from .polyhedron import Polyhedron
from .svg import polygon_from_svg
from .urdf import polyhedron_from_urdf

__all__ = ["load_object", "polygon_from_csv", "polygon_from_json", "polygon_from_svg",
           "polyhedron_from_mesh_file"]

POLYGON_SUFFIXES = (".json", ".geojson", ".svg", ".csv")
ROBOT_SUFFIXES = (".urdf",)


def polygon_from_json(data: Any, name: str = "polygon") -> Polygon:
    """A polygon from parsed JSON: our format, a point list, or GeoJSON.

    Examples
    --------
    >>> gj = {"type": "Polygon", "coordinates": [[[0, 0], [2, 0], [2, 2], [0, 2], [0, 0]]]}
    >>> polygon_from_json(gj).area
    4.0
    """
    if isinstance(data, list):
        return Polygon.from_points(data, name=name)
    if not isinstance(data, dict):
        raise InputError(f"{name}: expected an object or a list of points")
    kind = data.get("type")
    if kind == "FeatureCollection":
        features = data.get("features") or []
        if not isinstance(features, list):
            raise InputError(f"{name}: the FeatureCollection's 'features' must be a list of "
                             f"features, got {type(features).__name__}")
        polys = [f for f in features if isinstance(f, dict) and isinstance(f.get("geometry"), dict)
                 and f["geometry"].get("type") in ("Polygon", "MultiPolygon")]
        if len(polys) != 1:
            raise InputError(f"{name}: the FeatureCollection has {len(polys)} polygon features; "
                             "give exactly one")
        return polygon_from_json(polys[0]["geometry"], name)
    if kind == "Feature":
        return polygon_from_json(data.get("geometry"), name)
    if kind in ("Polygon", "MultiPolygon"):
        try:
            with np.errstate(all="ignore"):  # NaN coordinates are refused below, in one line
                geometry = shapely.geometry.shape(data)
        except Exception as e:  # shapely raises several types for bad GeoJSON
            raise InputError(f"{name}: bad GeoJSON {kind}: {_first_line(e)}") from None
        return Polygon.from_shapely(geometry, name)
    if kind is not None:
        raise InputError(f"{name}: GeoJSON type {kind!r} is not a polygon")
    if "outer" not in data:
        raise InputError(f"{name}: missing field 'outer' (or a GeoJSON 'type')")
    holes = data.get("holes", [])
    if not isinstance(holes, list):
        raise InputError(f"{name}: field 'holes' must be a list of rings")
    return Polygon.from_points(data["outer"], holes, name=data.get("name", name)
                               if isinstance(data.get("name"), str) else name)


def polygon_from_csv(text: str, name: str = "polygon") -> Polygon:
    """A polygon from CSV: ``x,y`` per line, an empty line before each hole.

    Examples
    --------
    >>> polygon_from_csv("x,y\\n0,0\\n3,0\\n0,3\\n").area
    4.5
    """
    rings: list[list[list[float]]] = [[]]
    reader = csv.reader(io.StringIO(text))
    try:
        rows = list(reader)
    except csv.Error as e:  # a field over csv's limit (131,072 characters), a NUL byte
        raise InputError(f"{name}: line {reader.line_num}: not CSV coordinates: "
                         f"{_first_line(e)}") from None
    for lineno, row in enumerate(rows, start=1):
        cells = [c.strip() for c in row if c.strip()]
        if len(cells) == 1:
            cells = cells[0].split()
        if not cells:
            if rings[-1]:
                rings.append([])
            continue
        try:
            values = [float(c) for c in cells]
        except ValueError:
            if lineno == 1:
                continue  # a header
            raise InputError(f"{name}: line {lineno}: expected two numbers, got "
                             f"{','.join(cells)[:60]!r}") from None
        if len(values) != 2:
            raise InputError(f"{name}: line {lineno}: expected two numbers, got {len(values)}")
        rings[-1].append(values)
    rings = [r for r in rings if r]
    if not rings:
        raise InputError(f"{name}: no coordinates")
    return Polygon.from_points(rings[0], rings[1:], name=name)


def polyhedron_from_mesh_file(path: Path, allow_open: bool = False,
                              scale: NDArray[np.float64] | None = None,
                              name: str | None = None) -> Polyhedron:
    """A polyhedron from a mesh file, read by trimesh without its own processing, its
    vertices multiplied by ``scale`` (per axis) if given."""
    vertices, triangles = read_mesh_arrays(path)
    if scale is not None:
        vertices = vertices * scale
    return Polyhedron.from_arrays(vertices, triangles, name or path.stem, allow_open)


def load_object(source: str | Path | Any, allow_open: bool = False,
                part: str | None = None, *,
                allow_outside_meshes: bool = False) -> Polygon | Polyhedron:
    """Load a polygon or polyhedron from a file, a bundled name, or a library object.

    Parameters
    ----------
    source : path, str, shapely geometry, trimesh.Trimesh, Polygon or Polyhedron
    allow_open : bool
        Accept open and non-manifold meshes (with a warning) instead of
        refusing them.
    part : str, optional
        The URDF link to read (a URDF with several links carrying geometry is
        refused without it), or the SVG element id.
    allow_outside_meshes : bool
        A URDF may name meshes outside its folder (or its package's);
        refused by default.

    Examples
    --------
    >>> load_object("l-prism").summary()["faces"]
    8
    >>> import os, pybullet_data
    >>> r2d2 = os.path.join(pybullet_data.getDataPath(), "r2d2.urdf")
    >>> load_object(r2d2, part="right_leg").bounds.round(4).tolist()
    [[-0.05, -0.1, -0.6], [0.05, 0.1, 0.0]]
    """
    if part is not None and not isinstance(source, str | Path):
        raise InputError(f"{type(source).__name__}: part={part!r} names a URDF link or an SVG "
                         "element id; give the file")
    if isinstance(source, Polygon | Polyhedron):
        return source
    if isinstance(source, shapely.Polygon | shapely.MultiPolygon):
        return Polygon.from_shapely(source)
    if type(source).__name__ == "Trimesh":
        return Polyhedron.from_trimesh(source, allow_open=allow_open)
    if not isinstance(source, str | Path):
        raise InputError(f"cannot make an object from a {type(source).__name__}")
    path = Path(source)
    if not path.exists():
        if str(source) in POLYGONS or str(source) in POLYHEDRA:
            if part is not None:
                raise InputError(f"{source}: part={part!r} names a URDF link or an SVG element "
                                 "id; a bundled object has no parts")
            return bundled(str(source))
        raise InputError(f"{source}: no such file, and no bundled object of that name "
                         "(see 'forceclosure objects')")
    if path.is_dir():
        raise InputError(f"{source}: is a directory")
    regular_file(str(path))  # a FIFO or a device would block or never end
    suffix = path.suffix.lower()
    if part is not None and suffix not in (".svg", *ROBOT_SUFFIXES):
        raise InputError(f"{path.name}: part '{part}' given, but only SVG files (element ids) "
                         "and URDF files (links) have parts")
    if suffix in ROBOT_SUFFIXES:
        return polyhedron_from_urdf(path, allow_open, part,
                                    allow_outside_meshes=allow_outside_meshes)
    if suffix in MESH_SUFFIXES:
        return polyhedron_from_mesh_file(path, allow_open)
    if suffix not in POLYGON_SUFFIXES:
        raise InputError(f"{path.name}: unknown file type '{suffix}'; expected one of "
                         f"{', '.join(POLYGON_SUFFIXES + MESH_SUFFIXES + ROBOT_SUFFIXES)}")
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{path.name}: not a text file") from None
    if not text.strip():
        raise InputError(f"{path.name}: the file is empty")
    name = path.stem
    if suffix == ".svg":
        return polygon_from_svg(text, name, part=part)
    if suffix == ".csv":
        return polygon_from_csv(text, name)
    return polygon_from_json(parse_json(text, path.name), name)
