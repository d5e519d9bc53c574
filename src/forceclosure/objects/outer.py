"""The outer surface of a mesh made of several shells, such as a convex decomposition.

A convex decomposition (V-HACD's ``*_vhacd.obj``, pybullet's
``random_urdfs``) stores an object as several closed shells that overlap or
touch. Their triangles inside another shell, or pressed against one, are
not on the object's surface: no finger can reach them. Only the **outer
surface** is kept:

* closed shells that enclose a volume are joined by their boolean union
  (manifold3d), group by group of shells whose bounding boxes meet; a group
  whose union leaves every shell apart (they do not overlap or touch) keeps
  its triangles as they are. The union's triangles lie on the original
  triangles' planes, so the planar faces are found again;
* shells the union cannot take — open ones, non-manifold ones (both only
  with ``allow_open``), closed ones without volume (a zero-thickness fin) —
  lose the triangles that lie inside a closed shell: the triangle's centroid
  strictly inside (generalised winding number above 3/4) and its corners
  inside or on it (above 1/4). A triangle that crosses a closed shell's
  surface is dropped too, and said so: cutting it would need the union, and
  kept whole it would let a region reach into the solid.

All of it is computed in object-centred, scaled coordinates
(:class:`~forceclosure.geometry.placement.Placement`): the union of a decomposition moved
by 1e8 or scaled by 1e-3 is the union at the origin, moved and scaled (manifold3d's own
tolerances and the winding numbers would otherwise see a different object), and the union's
new vertices are mapped back to the coordinates given.

Each change is said in a warning.

Examples
--------
Two unit cubes overlapping by half become one box of volume 1.5:

>>> import numpy as np
>>> from forceclosure.objects import Polyhedron, bundled
>>> cube = bundled("cube")
>>> V = np.vstack([cube.vertices, cube.vertices + [1, 0, 0]]) / 2
>>> T = np.vstack([cube.triangles, cube.triangles + len(cube.vertices)])
>>> box = Polyhedron.from_arrays(V, T)
>>> box.shells, len(box.faces), round(box.volume, 9), box.warnings
(1, 6, 1.5, ('merged 2 overlapping shells into their outer surface',))
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ..geometry.placement import Placement
from .orient import boundary_loops, edge_table, shell_labels, winding_numbers

__all__ = ["outer_surface"]

#: A closed shell encloses a volume when it is above this (relative to size^3).
VOLUME_RTOL = 1e-9


def _manifold(V: NDArray, T: NDArray):
    """A manifold3d solid of one closed shell, or None if manifold3d refuses it."""
    import manifold3d

    used, local = np.unique(T, return_inverse=True)
    mesh = manifold3d.Mesh64(vert_properties=np.ascontiguousarray(V[used], dtype=np.float64),
                             tri_verts=local.reshape(-1, 3).astype(np.uint64))
    solid = manifold3d.Manifold(mesh)
    return None if solid.is_empty() or solid.status() != manifold3d.Error.NoError else solid


def _union(solids: list):
    """The union's vertices and triangles (outward, counter-clockwise)."""
    import manifold3d

    mesh = manifold3d.Manifold.batch_boolean(solids, manifold3d.OpType.Add).to_mesh64()
    return (np.asarray(mesh.vert_properties, dtype=float)[:, :3].copy(),
            np.asarray(mesh.tri_verts).astype(np.int64))


def _cap(V: NDArray, T: NDArray, loops: list) -> tuple[NDArray, NDArray]:
    """The shell with each hole closed by a fan of triangles from the hole's centroid."""
    centres = np.array([V[loop].mean(axis=0) for loop in loops])
    fans = [np.column_stack([np.roll(loop, -1), loop, np.full(len(loop), len(V) + k)])
            for k, loop in enumerate(loops)]
    return np.vstack([V, centres]), np.vstack([T, *fans])


def _inside_any(V: NDArray, shells: list[NDArray], points: NDArray,
                strict: float) -> NDArray[np.bool_]:
    """Which points have a winding number above ``strict`` for one of the closed shells."""
    inside = np.zeros(len(points), dtype=bool)
    for own in shells:
        inside |= winding_numbers(V, own, points) > strict
    return inside


def outer_surface(V: NDArray, T: NDArray, labels: NDArray, closed: NDArray,
                  size: float) -> tuple[NDArray, NDArray, list[str]]:
    """The triangles of the outer surface of a mesh of several shells.

    Parameters
    ----------
    V, T : arrays
        The mesh, every shell facing outward
        (:func:`~forceclosure.objects.orient.orient_outward`).
    labels : (m,) int array
        Each triangle's shell.
    closed : (shells,) bool array
        Which shells are closed.
    size : float
        The object's length scale.

    Returns
    -------
    V, T : arrays
        The outer surface (the input arrays themselves if nothing changed).
    warnings : list of str
        What was merged, capped and dropped.
    """
    n_shells = int(labels.max()) + 1
    if n_shells < 2:
        return V, T, []
    given = V
    placement = Placement.of(V[np.unique(T)], size)
    V = placement.to_local_points(V)  # everything below in object-centred, scaled coordinates
    size = size / placement.scale
    A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    volume = np.bincount(labels, np.einsum("ij,ij->i", A, np.cross(B, C)) / 6, n_shells)
    lo = np.full((n_shells, 3), np.inf)
    hi = np.full((n_shells, 3), -np.inf)
    np.minimum.at(lo, labels, np.minimum(np.minimum(A, B), C))
    np.maximum.at(hi, labels, np.maximum(np.maximum(A, B), C))
    tol = 1e-9 * size
    tiny = VOLUME_RTOL * size**3
    solids = {}  # shell -> manifold3d solid
    for s in np.flatnonzero(np.asarray(closed, dtype=bool) & (volume > tiny)).tolist():
        solid = _manifold(V, T[labels == s])
        if solid is not None:
            solids[s] = solid
    closed_tris = [T[labels == s] for s in solids]
    capped = holes = 0
    for s in range(n_shells):  # open shells whose every hole lies inside a closed shell
        if s in solids or closed[s] or not closed_tris:
            continue
        own = T[labels == s]
        if edge_table(own)[2].max() > 2:
            continue  # non-manifold
        loops = boundary_loops(own)
        Vc, Tc = _cap(V, own, loops)
        caps = Tc[len(own):]
        points = np.vstack([Vc[caps].mean(axis=1), Vc[len(V):]])
        rims = np.concatenate(loops)
        spokes = (Vc[caps[:, 1]] + Vc[caps[:, 2]]) / 2  # from each rim vertex to the centre
        # the caps must lie in a closed shell: well inside at their middles, and their rims
        # inside or on its surface (a cap whose rim leaves the solid would invent a surface)
        if not (_inside_any(V, closed_tris, points, 0.75).all()
                and _inside_any(V, closed_tris, np.vstack([V[rims], spokes]), 0.25).all()):
            continue
        solid = _manifold(Vc, Tc)
        if solid is not None and solid.volume() > tiny:
            solids[s] = solid
            capped += 1
            holes += len(loops)
    keep = np.ones(len(T), dtype=bool)
    parts: list[tuple[NDArray, NDArray]] = []
    notes: list[str] = []
    idx = np.array(sorted(solids), dtype=np.int64)
    merged = 0
    if len(idx) > 1:
        meet = np.all((lo[idx, None] <= hi[None, idx] + tol)
                      & (lo[None, idx] <= hi[idx, None] + tol), axis=2)
        i, j = np.nonzero(np.triu(meet, 1))
        graph = coo_matrix((np.ones(len(i)), (i, j)), shape=(len(idx), len(idx)))
        _, group = connected_components(graph, directed=False)
        for g in np.unique(group):
            members = idx[group == g]
            if len(members) < 2:
                continue
            Vu, Tu = _union([solids[s] for s in members.tolist()])
            if len(Tu) and shell_labels(Tu, len(Vu)).max() + 1 == len(members):
                continue  # no two overlap or touch: left as they are
            keep[np.isin(labels, members)] = False
            parts.append((Vu, Tu))
            merged += len(members)
    if capped:
        notes.append(f"capped {holes} holes of {capped} open shells where they lie inside a "
                     "closed shell (like a handle's ends in a mug's wall)")
    if merged:
        notes.append(f"merged {merged} overlapping shells into their outer surface")
    dropped = crossing = 0
    for s in range(n_shells):  # what the union could not take: drop what lies inside
        if s in solids or not closed_tris:
            continue
        tris = np.flatnonzero(labels == s)
        near = [own for t, own in zip(solids, closed_tris, strict=True)
                if not (np.any(lo[s] > hi[t] + tol) or np.any(lo[t] > hi[s] + tol))]
        corners = np.zeros((len(tris), 3), dtype=bool)
        centre = np.zeros(len(tris), dtype=bool)
        deep = np.zeros((len(tris), 3), dtype=bool)
        for own in near:
            w = winding_numbers(V, own, V[T[tris]].reshape(-1, 3)).reshape(-1, 3)
            corners |= w > 0.25
            deep |= w > 0.75
            centre |= winding_numbers(V, own, V[T[tris]].mean(axis=1)) > 0.75
        inside = centre & corners.all(axis=1)
        crosses = (centre | deep.any(axis=1)) & ~inside
        # a triangle partly inside would let a region reach into the solid: it goes too (cutting
        # it would need the union, which an open shell cannot join)
        keep[tris[inside | crosses]] = False
        dropped += int(inside.sum())
        crossing += int(crosses.sum())
    if dropped:
        notes.append(f"dropped {dropped} triangles of open or non-manifold shells that lie "
                     "inside a closed shell")
    if crossing:
        notes.append(f"dropped {crossing} triangles of open or non-manifold shells that cross "
                     "into a closed shell (no union with an open shell cuts them)")
    if keep.all():
        return given, T, notes
    vertices, triangles = [given], [T[keep]]
    offset = len(V)
    for Vu, Tu in parts:
        vertices.append(placement.to_user_points(Vu))
        triangles.append(Tu + offset)
        offset += len(Vu)
    Vn, Tn = np.vstack(vertices), np.vstack(triangles)
    used, Tn = np.unique(Tn, return_inverse=True)
    return Vn[used], Tn.reshape(-1, 3), notes
