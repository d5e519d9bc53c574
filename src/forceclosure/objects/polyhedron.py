"""Polyhedra: the spatial objects whose planar faces fingers touch (§5.2–§5.5).

A :class:`Polyhedron` is built from a triangle mesh. Construction checks
and cleans the mesh:

* **safe repairs, each with a warning**: duplicate vertices merged (OBJ
  files split vertices along texture seams), triangles that collapse
  when they are merged dropped, winding made consistent and each shell
  turned to face out (:mod:`~forceclosure.objects.orient`, open shells
  too), and a mesh of several overlapping shells (a convex decomposition)
  reduced to its outer surface (:mod:`~forceclosure.objects.outer`);
* **refusals, each in one line naming where**: non-finite vertices, indices
  out of range, degenerate triangles (distinct but collinear vertices),
  non-manifold edges, and open meshes (unless ``allow_open=True``, which
  accepts them with a warning and records them in ``defects``). Vertices
  and triangles are counted from 1 in the input's order, as in OBJ files;
  edges are named by their endpoints.

Coplanar adjacent triangles are merged into :class:`PlanarFace` objects.
Flatness is re-checked against the whole face, with a tolerance relative to
the object's size, so gently curved surfaces are not flattened. Each face is
a :class:`~forceclosure.objects.polygon.Polygon` (with holes) in a frame of
its own ``(origin, u, v)``, with outward normal ``n = u x v``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import cached_property
from itertools import pairwise

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..contacts import tangent_basis
from ..errors import InputError
from ..geometry.rings import signed_area
from .orient import (
    boundary_loops,
    edge_table,
    fix_winding,
    orient_outward,
    pieces,
    shell_labels,
    walk_loops,
)
from .outer import outer_surface
from .polygon import Polygon

__all__ = ["COORDINATE_LIMIT", "FACE_ANGLE", "FLAT_RTOL", "MERGE_RTOL", "OPEN_HINT", "PlanarFace",
           "Polyhedron"]

#: Relative tolerance (of the object's size) for merging vertices.
MERGE_RTOL = 1e-9
#: Coordinates beyond this magnitude, or objects smaller across than its inverse, are
#: refused: their areas and volumes (and the squares of both) would overflow or underflow.
COORDINATE_LIMIT = 1e50
#: Relative tolerance (of the object's size) for calling triangles coplanar.
FLAT_RTOL = 1e-6
#: Largest angle (radians) between a merged face's normal and any of its triangles' normals.
FACE_ANGLE = 1e-4
#: How an open mesh is accepted (the CLI says ``--allow-open``).
OPEN_HINT = "pass allow_open=True (--allow-open on the command line) to accept it"


@dataclass(frozen=True, eq=False)
class PlanarFace:
    """A planar face: coplanar triangles merged, as a polygon in its own frame.

    Attributes
    ----------
    index : int
    normal : (3,) array
        Outward unit normal.
    origin : (3,) array
        A point of the face; ``(u, v) = (0, 0)``.
    axes : (2, 3) array
        Unit in-plane axes ``u`` and ``v``, with ``u x v = normal``.
    loops : tuple of (k,) int arrays
        Vertex indices of the boundary loops, the outer one first.
    triangles : (t,) int array
        The mesh triangles making up the face.
    area : float
    spread : float
        The largest angle between ``normal`` and the normal of one of the
        face's triangles (at most ``FACE_ANGLE``; 0 for one triangle): the
        certificates narrow friction cones by it, so that nothing is proved
        on a normal the object does not have.
    """

    index: int
    normal: NDArray[np.float64]
    origin: NDArray[np.float64]
    axes: NDArray[np.float64]
    loops: tuple[NDArray[np.int64], ...]
    triangles: NDArray[np.int64]
    area: float
    _vertices: NDArray[np.float64] = field(repr=False)
    _mesh: NDArray[np.int64] = field(repr=False)  # the mesh's (m, 3) triangle array
    spread: float = 0.0

    def to_plane(self, points: ArrayLike) -> NDArray[np.float64]:
        """Coordinates ``(u, v)`` of points projected onto the face's plane."""
        return (np.asarray(points, dtype=float) - self.origin) @ self.axes.T

    def to_world(self, uv: ArrayLike) -> NDArray[np.float64]:
        """Object coordinates of plane coordinates ``(u, v)``."""
        return self.origin + np.asarray(uv, dtype=float) @ self.axes

    @cached_property
    def polygon(self) -> Polygon:
        """The face as a polygon in ``(u, v)``: outer boundary CCW seen from outside."""
        rings = [self.to_plane(self._vertices[loop]) for loop in self.loops]
        try:
            return Polygon.from_points(rings[0], rings[1:], name=f"face {self.index}")
        except InputError:
            # touching loops: let shapely resolve the union of the face's triangles
            tris = self._vertices[self._mesh[self.triangles]]
            union = shapely.union_all([shapely.Polygon(self.to_plane(t)) for t in tris])
            return Polygon.from_shapely(union, name=f"face {self.index}")

    @cached_property
    def triangle_outline(self) -> NDArray[np.float64] | None:
        """A one-triangle face's outline in ``(u, v)``, counter-clockwise: the outer ring
        :attr:`polygon` holds, without building and validating the polygon (a curved mesh
        has as many faces as triangles). ``None`` for a face of several triangles, and for
        a triangle with an angle whose sine is below 1e-6 (there the polygon's own checks
        decide).

        Examples
        --------
        >>> from forceclosure.objects import bundled
        >>> face = bundled("cube").faces[0]          # two triangles: no outline
        >>> face.triangle_outline is None
        True
        """
        if len(self.triangles) != 1:
            return None
        ring = self.to_plane(self._vertices[self.loops[0]])
        d = ring[[1, 2, 0]] - ring  # the edges, and each vertex's incoming one
        prev = d[[2, 0, 1]]
        turn = prev[:, 0] * d[:, 1] - prev[:, 1] * d[:, 0]
        lengths = np.linalg.norm(prev, axis=1) * np.linalg.norm(d, axis=1)
        # every turn left by an angle whose sine is over 1e-6: counter-clockwise, no edge
        # short or vertex straight for the polygon's checks, so it keeps the ring as it is
        if not np.all(turn > 1e-6 * lengths):
            return None
        ring.setflags(write=False)
        return ring

    @cached_property
    def plane_size(self) -> float:
        """The face's length scale: its polygon's bounding-box diagonal (``polygon.size``),
        from :attr:`triangle_outline` where there is one."""
        ring = self.triangle_outline
        if ring is None:
            return self.polygon.size
        return float(np.linalg.norm(np.ptp(ring, axis=0)))

    @property
    def boundary(self) -> NDArray[np.float64]:
        """The outer boundary in object coordinates (for plotting)."""
        return self._vertices[self.loops[0]]


def _rounding_hint(vertices: ArrayLike) -> str:
    """Where the doubles at the object's coordinates are more than :data:`FLAT_RTOL` of its
    size apart (so that rounding may have made a defect): how far apart, in words; else
    ``""``."""
    try:
        V = np.asarray(vertices, dtype=float)
        far = float(np.abs(V).max())
        size = float(np.linalg.norm(np.ptp(V, axis=0)))
    except (TypeError, ValueError):
        return ""
    if not (np.isfinite(far) and np.isfinite(size)):
        return ""
    spacing = float(np.spacing(far))
    if not spacing > FLAT_RTOL * size:
        return ""
    within = f", {spacing / size:.2g} of the object's size" if size > 0 else ""
    return f"coordinates near {far:.3g} are {spacing:.3g} apart{within}: move it nearer the origin"


def _point(p: NDArray) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in p) + ")"


def _fail(name: str, message: str, defect: str, allow: bool, warnings: list[str],
          defects: list[str]) -> None:
    """Refuse a mesh defect, or with ``allow_open`` accept it with a warning."""
    if not allow:
        raise InputError(f"{name}: {message}; {OPEN_HINT}")
    warnings.append(f"{message} (accepted: allow_open)")
    defects.append(defect)


def _unique_rows(key: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """First index of each distinct row, and each row's group (like ``np.unique(axis=0)``)."""
    order = np.lexsort(key.T[::-1])
    step = np.any(np.diff(key[order], axis=0) != 0, axis=1)
    group_sorted = np.concatenate([[0], np.cumsum(step)])
    inverse = np.empty(len(key), dtype=np.int64)
    inverse[order] = group_sorted
    first = order[np.concatenate([[0], np.flatnonzero(step) + 1])]
    return first, inverse


def _merge_vertices(vertices: NDArray[np.float64], triangles: NDArray[np.int64], size: float,
                    warnings: list[str],
                    ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.intp]]:
    """Vertices rounding to one point of the grid of step ``MERGE_RTOL * size`` merged and
    unused ones dropped: the kept vertices, the triangles renumbered (those with a repeated
    vertex dropped), and the input index of each kept triangle."""
    # from the bounding box's corner, so that far-away coordinates cannot overflow the key
    key = np.round((vertices - vertices.min(axis=0)) / (MERGE_RTOL * size)).astype(np.int64)
    first, inverse = _unique_rows(key)
    merged = len(vertices) - len(first)
    if merged:
        warnings.append(f"merged {merged} duplicate vertices")
    triangles = inverse[triangles]
    collapsed = ((triangles[:, 0] == triangles[:, 1]) | (triangles[:, 1] == triangles[:, 2])
                 | (triangles[:, 0] == triangles[:, 2]))
    if collapsed.any():
        warnings.append(f"dropped {int(collapsed.sum())} triangles with a repeated vertex")
    source = np.flatnonzero(~collapsed)
    triangles = triangles[source]
    used = np.unique(triangles)
    remap = np.full(len(first), -1)
    remap[used] = np.arange(len(used))
    return vertices[first][used], remap[triangles], source


@dataclass(frozen=True, eq=False)
class Polyhedron:
    """A triangle mesh with its planar faces, validated and oriented outward.

    Build one with :meth:`from_arrays`, :meth:`from_trimesh`, or
    :func:`forceclosure.objects.io.load_object`.

    Attributes
    ----------
    vertices : (n, 3) array
    triangles : (m, 3) int array
        Counter-clockwise seen from outside.
    faces : tuple of PlanarFace
    face_of_triangle : (m,) int array
    name : str
    watertight : bool
    warnings : tuple of str
        What the safe repairs changed.
    defects : tuple of str
        What ``allow_open`` accepted in the input (``"open"``,
        ``"non-manifold"``); empty for a closed 2-manifold input. An open input
        may still give a watertight object, when its holes lie inside a closed
        shell (:mod:`forceclosure.objects.outer`).
    """

    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    faces: tuple[PlanarFace, ...]
    face_of_triangle: NDArray[np.int64]
    name: str
    watertight: bool
    warnings: tuple[str, ...]
    defects: tuple[str, ...] = ()

    @classmethod
    def from_arrays(cls, vertices: ArrayLike, triangles: ArrayLike, name: str = "polyhedron",
                    allow_open: bool = False, spread: float = 0.0) -> Polyhedron:
        """Validate, repair and face-merge a triangle mesh.

        ``spread`` (radians) is how far the normal of the surface the mesh
        stands for may turn from its triangles' (a tessellated cylinder or
        sphere); every face's ``spread`` is at least that, so that the proofs
        narrow their cones by it.

        Examples
        --------
        >>> v = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]
        >>> t = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]
        >>> tet = Polyhedron.from_arrays(v, t, name="tetrahedron")
        >>> len(tet.faces), round(tet.volume, 6)
        (4, 0.166667)

        A defect that rounding may have made (vertices of a small object far from the origin
        fallen onto the same doubles) is refused with the doubles' spacing there:

        >>> Polyhedron.from_arrays(np.add(v, 1e16), t)
        Traceback (most recent call last):
        ...
        forceclosure.errors.InputError: polyhedron: all vertices coincide (coordinates near \
1e+16 are 2 apart: move it nearer the origin)
        """
        try:
            return cls._from_arrays(vertices, triangles, name, allow_open, spread)
        except InputError as e:
            hint = _rounding_hint(vertices)
            if not hint:
                raise
            raise InputError(f"{e} ({hint})") from None

    @classmethod
    def _from_arrays(cls, vertices: ArrayLike, triangles: ArrayLike, name: str,
                     allow_open: bool, spread: float) -> Polyhedron:
        warnings: list[str] = []
        defects: list[str] = []
        try:
            V = np.asarray(vertices, dtype=float)
            T = np.asarray(triangles)
        except (TypeError, ValueError):
            raise InputError(f"{name}: vertices and triangles must be numeric arrays") from None
        if V.ndim != 2 or V.shape[1] != 3 or len(V) == 0:
            raise InputError(f"{name}: vertices must be (n, 3), got shape {V.shape}")
        if T.ndim != 2 or T.shape[1] != 3 or len(T) == 0:
            raise InputError(f"{name}: triangles must be (m, 3), got shape {T.shape}")
        if not np.issubdtype(T.dtype, np.integer):
            if not np.all(np.isfinite(T)) or np.any(np.round(T) != T):
                raise InputError(f"{name}: triangle vertex indices must be integers")
            T = T.astype(np.int64)
        bad = np.flatnonzero(~np.all(np.isfinite(V), axis=1))
        if len(bad):
            raise InputError(f"{name}: vertex {bad[0] + 1} is not finite: {V[bad[0]].tolist()}")
        out = np.argwhere((T < 0) | (len(V) <= T))
        if len(out):
            i, j = out[0]
            raise InputError(f"{name}: triangle {i + 1} refers to vertex {T[i, j] + 1}, but "
                             f"there are {len(V)} vertices")
        huge = np.flatnonzero(np.any(np.abs(V) > COORDINATE_LIMIT, axis=1))
        if len(huge):  # beyond it, areas and volumes overflow
            raise InputError(f"{name}: vertex {huge[0] + 1} is beyond {COORDINATE_LIMIT:g} in "
                             "magnitude: rescale the object")
        used = np.zeros(len(V), dtype=bool)
        used[T] = True  # the vertices of some triangle
        extent = np.ptp(V[used], axis=0)
        if not extent.any():
            raise InputError(f"{name}: all vertices coincide")
        size = float(np.linalg.norm(extent))
        if size < 1 / COORDINATE_LIMIT:  # below it, areas and volumes underflow
            raise InputError(f"{name}: the object is {size:.3g} across, below "
                             f"{1 / COORDINATE_LIMIT:g}: rescale it")
        V, T, source = _merge_vertices(V, T.astype(np.int64), size, warnings)
        if len(T) < 4:
            raise InputError(f"{name}: {len(T)} triangles cannot enclose a volume")
        cross = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
        double_area = np.linalg.norm(cross, axis=1)
        flat = np.flatnonzero(double_area <= 1e-12 * size * size)
        if len(flat):
            i = flat[0]
            corners = ", ".join(_point(V[k]) for k in T[i])
            raise InputError(f"{name}: triangle {source[i] + 1} is degenerate: its vertices "
                             f"{corners} are collinear")
        directed, ids, counts = edge_table(T)
        many = np.flatnonzero(counts > 2)
        if len(many):
            a, b = directed[np.flatnonzero(ids == many[0])[0]]
            _fail(name, f"non-manifold edge from {_point(V[a])} to {_point(V[b])} (shared by "
                  f"{counts[many[0]]} triangles)", "non-manifold", allow_open, warnings, defects)
        open_edges = np.flatnonzero(counts == 1)
        if len(open_edges):
            a, b = directed[np.flatnonzero(ids == open_edges[0])[0]]
            _fail(name, f"open mesh, {len(open_edges)} boundary edges (e.g. from {_point(V[a])} "
                  f"to {_point(V[b])})", "open", allow_open, warnings, defects)
        T = fix_winding(T, name, warnings)
        T = orient_outward(V, T, *pieces(T), warnings)
        labels = shell_labels(T, len(V))
        closed = np.ones(int(labels.max()) + 1, dtype=bool)
        closed[labels[np.repeat(np.arange(len(T)), 3)[counts[ids] != 2]]] = False
        V2, T, notes = outer_surface(V, T, labels, closed, size)
        warnings.extend(notes)
        if V2 is not V:
            V = V2
            if len(T) < 4:
                raise InputError(f"{name}: nothing is left of the mesh outside its closed shells")
        cross = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
        directed, ids, counts = edge_table(T)
        watertight = bool(np.all(counts == 2))
        if watertight:
            volume = _signed_volume(V, T)
            if abs(volume) <= 1e-12 * size**3:
                raise InputError(f"{name}: the mesh encloses no volume")
        double_area = np.linalg.norm(cross, axis=1)
        sliver = double_area <= 1e-12 * size * size
        normals, glued = _sliver_normals(V, T, cross, sliver, directed, ids)
        faces, face_of = _planar_faces(V, T, normals, double_area / 2, directed, ids, counts,
                                       size, glued, _rounding(V, T, double_area, sliver))
        for arr in (V, T, face_of):
            arr.setflags(write=False)
        if spread > 0:
            faces = tuple(replace(f, spread=max(f.spread, float(spread))) for f in faces)
        return cls(V, T, faces, face_of, name, watertight, tuple(warnings), tuple(defects))

    @classmethod
    def from_trimesh(cls, mesh, name: str | None = None, allow_open: bool = False) -> Polyhedron:
        """A polyhedron from a ``trimesh.Trimesh`` (its vertices and faces as given)."""
        return cls.from_arrays(mesh.vertices, mesh.faces,
                               name or mesh.metadata.get("name") or "mesh", allow_open)

    @property
    def dim(self) -> int:
        """3: polyhedra are spatial objects."""
        return 3

    @cached_property
    def shell_of_triangle(self) -> NDArray[np.int64]:
        """Which connected shell each triangle belongs to (sharing vertices connects)."""
        return shell_labels(self.triangles, len(self.vertices))

    @property
    def shells(self) -> int:
        """Number of separate closed surfaces (e.g. the parts of a convex decomposition)."""
        return len(np.unique(self.shell_of_triangle))

    @cached_property
    def area(self) -> float:
        """Surface area."""
        return float(sum(f.area for f in self.faces))

    @property
    def volume(self) -> float:
        """Enclosed volume (positive: triangles face outward)."""
        return _signed_volume(self.vertices, self.triangles)

    @property
    def bounds(self) -> NDArray[np.float64]:
        """``[[xmin, ymin, zmin], [xmax, ymax, zmax]]``."""
        return np.array([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    @cached_property
    def size(self) -> float:
        """Length of the bounding box's diagonal: the object's length scale."""
        return float(np.linalg.norm(np.ptp(self.vertices, axis=0)))

    @property
    def centroid(self) -> NDArray[np.float64]:
        """Centre of volume (of the surface's vertices for an open mesh)."""
        V, T = self.vertices, self.triangles
        if not self.watertight:
            return V.mean(axis=0)
        centre = self.bounds.mean(axis=0)
        a, b, c = (V[T[:, k]] - centre for k in range(3))
        w = np.einsum("ij,ij->i", a, np.cross(b, c))
        return centre + ((a + b + c) * w[:, None]).sum(axis=0) / (4 * w.sum())

    def locate(self, p: ArrayLike) -> tuple[int, NDArray[np.float64], float]:
        """The face nearest to point ``p``: ``(face index, (u, v), distance)``.

        Examples
        --------
        >>> from forceclosure.objects import bundled
        >>> cube = bundled("cube")
        >>> face, uv, dist = cube.locate([1.1, 0.2, 0.3])
        >>> cube.faces[face].normal.round(6).tolist(), round(dist, 6)
        ([1.0, 0.0, 0.0], 0.1)
        """
        p = np.asarray(p, dtype=float)
        dist = _triangle_distances(p, *(self.vertices[self.triangles[:, k]] for k in range(3)))
        t = int(np.argmin(dist))
        face = self.faces[int(self.face_of_triangle[t])]
        return face.index, face.to_plane(p), float(dist[t])

    @cached_property
    def face_neighbors(self) -> dict[int, set[int]]:
        """The faces sharing an edge with each face (faces with no neighbour left out).
        Computed once; do not modify.

        Examples
        --------
        >>> from forceclosure.objects import bundled
        >>> sorted(len(n) for n in bundled("cube").face_neighbors.values())
        [4, 4, 4, 4, 4, 4]
        """
        T, label = self.triangles, self.face_of_triangle
        edges = np.sort(T[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        owner = np.repeat(label, 3)
        order = np.lexsort((edges[:, 1], edges[:, 0]))
        e, o = edges[order], owner[order]
        same = np.flatnonzero(np.all(e[1:] == e[:-1], axis=1))
        graph: dict[int, set[int]] = {}
        for a, b in zip(o[same].tolist(), o[same + 1].tolist(), strict=True):
            if a != b:
                graph.setdefault(a, set()).add(b)
                graph.setdefault(b, set()).add(a)
        return graph

    @cached_property
    def holes(self) -> int:
        """Number of holes: loops of boundary edges (edges of one triangle); 0 if watertight."""
        return len(boundary_loops(self.triangles))

    @property
    def boundary_edges(self) -> int:
        """Number of edges of only one triangle (a hole's rim)."""
        return int(np.sum(edge_table(self.triangles)[2] == 1))

    @property
    def non_manifold_edges(self) -> int:
        """Number of edges of three or more triangles."""
        return int(np.sum(edge_table(self.triangles)[2] > 2))

    def to_trimesh(self):
        """The surface as a ``trimesh.Trimesh`` (triangles facing outward, not re-processed).

        Examples
        --------
        >>> from forceclosure.objects import bundled
        >>> mesh = bundled("cube").to_trimesh()
        >>> mesh.is_watertight, round(float(mesh.volume), 9)
        (True, 8.0)
        """
        import trimesh

        return trimesh.Trimesh(self.vertices.copy(), self.triangles.copy(), process=False,
                               metadata={"name": self.name})

    def summary(self) -> dict[str, object]:
        """Counts and sizes, for people and JSON."""
        merged = sum(len(f.triangles) > 1 for f in self.faces)
        notes = list(self.warnings)
        if self.shells > 1:
            notes.append(f"{self.shells} separate shells (pieces that share no vertex)")
        return {"name": self.name, "kind": "polyhedron", "vertices": len(self.vertices),
                "triangles": len(self.triangles), "faces": len(self.faces),
                "merged_faces": merged, "shells": self.shells, "watertight": self.watertight,
                "volume": self.volume if self.watertight else None, "area": self.area,
                "size": self.size, "bounds": self.bounds.tolist(), "warnings": notes,
                "boundary_edges": self.boundary_edges, "holes": self.holes,
                "non_manifold_edges": self.non_manifold_edges,
                "defects": list(self.defects),
                "units": None}  # mesh files are read without units: the file's own


def _signed_volume(V: NDArray, T: NDArray) -> float:
    """Volume enclosed by outward triangles, summed about the bounding box's centre (about the
    origin, products of far-away coordinates would cancel)."""
    centre = (V.min(axis=0) + V.max(axis=0)) / 2
    a, b, c = (V[T[:, k]] - centre for k in range(3))
    return float(np.einsum("ij,ij->", a, np.cross(b, c))) / 6


def _triangle_distances(p: NDArray, a: NDArray, b: NDArray, c: NDArray) -> NDArray:
    """Distance from point ``p`` to each triangle ``(a, b, c)``: to its plane where ``p``
    projects inside it, else to the nearest of its three edges."""
    n = np.cross(b - a, c - a)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    height = np.einsum("ij,ij->i", p - a, n)
    foot = p - height[:, None] * n
    inside = np.ones(len(a), dtype=bool)
    edge = np.full(len(a), np.inf)
    for x, y in ((a, b), (b, c), (c, a)):
        d = y - x
        inside &= np.einsum("ij,ij->i", np.cross(d, foot - x), n) >= 0
        s = np.clip(np.einsum("ij,ij->i", p - x, d) / np.einsum("ij,ij->i", d, d), 0, 1)
        edge = np.minimum(edge, np.linalg.norm(x + s[:, None] * d - p, axis=1))
    return np.where(inside, np.abs(height), edge)


def _sliver_normals(V, T, cross, sliver, directed, ids):
    """Unit normals; a sliver (a boolean union's near-zero-area triangle, its corners
    almost on a line) takes the normal of the triangle across its longest edge, and is
    glued to that triangle's face: its third corner is within its tiny height of that edge,
    so of that triangle's plane. Returns the normals and the ``(sliver, neighbour)`` pairs."""
    normals = cross.copy()
    good = ~sliver
    normals[good] /= np.linalg.norm(cross[good], axis=1, keepdims=True)
    if not sliver.any():
        return normals, np.zeros((0, 2), dtype=np.int64)
    tri_of_edge = np.repeat(np.arange(len(T)), 3)
    across = {}
    for t in np.flatnonzero(sliver).tolist():
        d = V[T[t, [1, 2, 0]]] - V[T[t]]
        k = int(np.argmax(np.einsum("ij,ij->i", d, d)))
        across[t] = tri_of_edge[(ids == ids[3 * t + k]) & (tri_of_edge != t)].tolist()
    pairs = []
    while across:  # slivers next to slivers wait for their neighbour's normal
        done = [t for t, nb in across.items() if any(good[u] for u in nb)]
        if not done:  # only slivers around: glue them to each other, any unit normal
            for t, nb in across.items():
                normals[t] = [0.0, 0.0, 1.0]
                pairs.extend((t, u) for u in nb[:1])
            break
        for t in done:
            u = next(u for u in across.pop(t) if good[u])
            normals[t] = normals[u]
            good[t] = True
            pairs.append((t, u))
    return normals, np.array(pairs, dtype=np.int64).reshape(-1, 2)


def _rounding(V, T, double_area, sliver) -> tuple[NDArray, float]:
    """What the doubles where the mesh stands leave unresolved: each triangle's normal to
    within the returned angles (radians: its corners rounded by two spacings each turn it
    by up to 6 spacings over its least height; 0 for a sliver, which takes its
    neighbour's normal), and its points to within the returned length (two spacings).

    Negligible at the origin (1e-12 rad for a triangle 1e-3 of a unit object high); at 1e8,
    the small triangles of a union (1e-6 of a decomposition 0.15 across high) turn by up to
    1e-2 rad, a hundred times :data:`FACE_ANGLE`. The faces are then merged as at the
    origin wherever the rounding can explain the difference, and the spread of a face does
    not count the turn of such a triangle that it explains (the surface the copy stands
    for is the original's, moved)."""
    spacing = float(np.spacing(np.abs(V).max()))
    d = V[T[:, [1, 2, 0]]] - V[T]
    longest = np.sqrt(np.einsum("ijk,ijk->ij", d, d).max(axis=1))
    height = np.where(sliver, np.inf, double_area / np.where(sliver, 1.0, longest))
    return 6 * spacing / height, 2 * spacing


def _planar_faces(V, T, normals, areas, directed, ids, counts, size, glued=None,
                  rounding=None):
    """Group coplanar adjacent triangles (and each sliver with the triangle it is glued
    to); return the faces and each triangle's face. ``rounding``: each triangle's normal
    and every point are known to within these (:func:`_rounding`), and the tests of
    flatness allow for it."""
    m = len(T)
    tri_of_edge = np.repeat(np.arange(m), 3)
    turned, off = rounding if rounding is not None else (np.zeros(m), 0.0)
    tol = FLAT_RTOL * size + off
    # pairs of triangles sharing an (undirected) edge
    order = np.argsort(ids, kind="stable")
    sid = ids[order]
    same = np.flatnonzero(sid[1:] == sid[:-1])
    a, b = tri_of_edge[order[same]], tri_of_edge[order[same + 1]]
    # each triangle's vertices against the other's plane, which its normal's rounding tilts
    # by up to that angle times the distance
    coplanar = np.einsum("ij,ij->i", normals[a], normals[b]) > 0.999
    for x, y in ((a, b), (b, a)):
        arm = V[T[y]] - V[T[x, 0]][:, None, :]
        dist = np.max(np.abs(np.einsum("ikj,ij->ik", arm, normals[x]))
                      - turned[x][:, None] * np.linalg.norm(arm, axis=2), axis=1)
        coplanar &= dist <= tol
    a, b = a[coplanar], b[coplanar]
    if glued is not None and len(glued):
        a, b = np.concatenate([a, glued[:, 0]]), np.concatenate([b, glued[:, 1]])
    graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(m, m))
    _, label = connected_components(graph, directed=False)
    label = _split_curved(V, T, normals, areas, label, a, b, tol, turned)
    n_faces = int(label.max()) + 1
    face_normal = np.zeros((n_faces, 3))
    np.add.at(face_normal, label, normals * areas[:, None])
    face_normal /= np.linalg.norm(face_normal, axis=1, keepdims=True)
    u, v = tangent_basis(face_normal)
    face_area = np.bincount(label, weights=areas, minlength=n_faces)
    # each triangle's angle from its face's normal (|cross| is accurate for tiny angles),
    # padded for the rounding of the normals
    turn = np.arcsin(np.clip(np.linalg.norm(np.cross(normals, face_normal[label]), axis=1),
                             0.0, 1.0))
    # a normal the doubles do not resolve turns by what the rounding of its corners explains
    turn = np.where(turned > np.sin(FACE_ANGLE) / 2, np.maximum(turn - turned, 0.0), turn)
    spread = np.zeros(n_faces)
    np.maximum.at(spread, label, turn)
    sizes = np.bincount(label, minlength=n_faces)
    spread = np.where(sizes > 1, spread + 1e-12, 0.0)
    order = np.argsort(label, kind="stable")
    cut = np.concatenate([[0], np.flatnonzero(np.diff(label[order])) + 1, [m]]).tolist()
    groups = [order[a:b] for a, b in pairwise(cut)]
    # a face's boundary edges: those whose reverse is not an edge of the same face
    face_of_edge = label[tri_of_edge]
    forward = (directed[:, 0] < directed[:, 1]).astype(np.int64)
    key = (face_of_edge * (int(ids.max()) + 1) + ids) * 2
    rim = np.flatnonzero(~_member(key + 1 - forward, key + forward))
    rim = rim[np.argsort(face_of_edge[rim], kind="stable")]
    cut = np.searchsorted(face_of_edge[rim], np.arange(n_faces + 1)).tolist()
    rims = [rim[a:b] for a, b in pairwise(cut)]
    faces = []
    all_axes = np.stack([u, v], axis=1)
    rows = zip(groups, face_normal, all_axes, face_area.tolist(), spread.tolist(), strict=True)
    for k, (tris, normal, axes, area, turned) in enumerate(rows):
        loops = (T[tris[0]],) if len(tris) == 1 else _loops(V, directed[rims[k]], axes)
        faces.append(PlanarFace(k, normal, V[loops[0][0]], axes, loops, tris, area, V, T,
                                turned))
    return tuple(faces), label


def _member(x: NDArray[np.int64], of: NDArray[np.int64]) -> NDArray[np.bool_]:
    """``np.isin(x, of)`` by one sort and a binary search (``np.isin`` hashes, slower on
    hundreds of thousands of distinct keys)."""
    table = np.sort(of)
    at = np.minimum(np.searchsorted(table, x), len(table) - 1)
    return table[at] == x


def _split_curved(V, T, normals, areas, label, a, b, tol, turned):
    """Re-check flatness per group; regrow groups that drift off one plane from a seed
    (a triangle's normal allowed to turn by ``turned``, its rounding, beyond
    :data:`FACE_ANGLE`).

    The groups' centres are averaged about the bounding box's centre: averaged in far-away
    coordinates (1e12) they would be rounded by more than ``tol``, and a flat group regrown
    under another label (the same faces, numbered otherwise than at the origin)."""
    n_groups = label.max() + 1
    w = normals * areas[:, None]
    n_sum = np.zeros((n_groups, 3))
    np.add.at(n_sum, label, w)
    n_mean = n_sum / np.linalg.norm(n_sum, axis=1, keepdims=True)
    X = V[T] - 0.5 * (V.min(axis=0) + V.max(axis=0))
    centre = np.zeros((n_groups, 3))
    np.add.at(centre, label, X.mean(axis=1) * areas[:, None])
    area_sum = np.bincount(label, weights=areas, minlength=n_groups)
    centre /= area_sum[:, None]
    dev = np.abs(np.einsum("ikj,ij->ik", X - centre[label][:, None, :], n_mean[label]))
    turn = np.linalg.norm(np.cross(normals, n_mean[label]), axis=1) - turned
    bad_groups = np.unique(label[(dev.max(axis=1) > tol) | (turn > np.sin(FACE_ANGLE) / 2)])
    if len(bad_groups) == 0:
        return label
    neighbours: dict[int, list[int]] = {}
    for i, j in zip(a.tolist(), b.tolist(), strict=True):
        neighbours.setdefault(i, []).append(j)
        neighbours.setdefault(j, []).append(i)
    label = label.copy()
    next_label = n_groups
    resolved = turned <= np.sin(FACE_ANGLE) / 2
    for g in bad_groups:
        todo = set(np.flatnonzero(label == g).tolist())
        sure = iter(np.flatnonzero((label == g) & resolved).tolist())
        while todo:
            seed = todo.pop()
            if not resolved[seed]:  # a normal the doubles do not resolve would take in both
                # faces it lies between: grow from the first resolved triangle left, if any
                first = next((t for t in sure if t in todo), None)
                if first is not None:
                    todo.add(seed)
                    seed = first
                    todo.discard(seed)
            n0, p0 = normals[seed], V[T[seed, 0]]
            label[seed] = next_label
            stack = [seed]
            while stack:
                t = stack.pop()
                for u in neighbours.get(t, ()):
                    arm = V[T[u]] - p0
                    if u in todo and np.max(np.abs(arm @ n0) - turned[seed] * np.linalg.norm(
                            arm, axis=1)) <= tol and np.linalg.norm(np.cross(
                            normals[u], n0)) <= np.sin(FACE_ANGLE) / 2 + turned[seed] + turned[u]:
                        todo.discard(u)
                        label[u] = next_label
                        stack.append(u)
            next_label += 1
    return np.unique(label, return_inverse=True)[1].reshape(-1)


def _loops(V, boundary, axes):
    """A face's boundary edges walked into loops, the counter-clockwise outer one first."""
    loops = tuple(walk_loops(boundary.tolist()))
    if len(loops) == 1:
        return loops
    signed = [signed_area((V[loop] - V[loop[0]]) @ axes.T) for loop in loops]
    first = int(np.argmax(signed))
    return (loops[first], *(lp for i, lp in enumerate(loops) if i != first))
