"""Orientation of a triangle mesh: consistent winding, and normals that face out.

A finger pushes along ``-n`` where ``n`` is the surface's **outward**
normal, so every triangle must be wound counter-clockwise seen from
outside. Two steps do this, one shell (connected piece) at a time:

1. **consistent winding** (:func:`fix_winding`): two triangles that share an
   edge must run through it in opposite directions; a 2-colouring of the
   triangles' adjacency graph (over edges shared by exactly two triangles)
   flips the triangles that disagree with their neighbours. A surface with
   no consistent colouring (a Moebius strip) is refused.
2. **outward** (:func:`orient_outward`): a *closed* shell faces out when
   its signed volume is positive. An *open* shell (a scanned mesh with
   holes, a tube) has no volume; it faces out when the generalised winding
   number (Jacobson et al. 2013), averaged over the shell's own surface, is
   positive. On a closed outward shell that average is exactly 1/2 (every
   surface point is half inside); holes lower it in proportion to the solid
   angle they take, so the rule holds as long as the holes are smaller than
   the surface around them (a cup, a tube, a scan with gaps). A nearly flat
   sheet has no inside (the average is near 0 for either winding): its
   winding is kept as the file gives it, with a warning, since a finger may
   touch either side.

Examples
--------
A cube with its top removed, given inside out, is turned to face out:

>>> import numpy as np
>>> from forceclosure.objects import bundled
>>> cube = bundled("cube")
>>> top = cube.faces[[tuple(f.normal.round(6)) for f in cube.faces].index((0.0, 0.0, 1.0))]
>>> T = np.delete(cube.triangles, top.triangles, axis=0)[:, ::-1]
>>> notes = []
>>> T2 = orient_outward(cube.vertices, T, shell_labels(T, len(cube.vertices)),
...                     np.array([False]), notes)
>>> bool(np.all(T2 == T[:, ::-1])), notes
(True, ['the triangles faced inward; flipped them to face outward'])
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import breadth_first_order, connected_components

from ..errors import InputError

__all__ = [
    "OPEN_SHEET",
    "boundary_loops",
    "edge_table",
    "fix_winding",
    "orient_outward",
    "pieces",
    "shell_labels",
    "walk_loops",
    "winding_numbers",
]

#: An open shell whose mean winding number is within this of 0 is a sheet with no inside.
OPEN_SHEET = 0.05
#: Triangles of an open shell sampled (area-weighted) for its mean winding number.
WINDING_SAMPLES = 256


def edge_table(triangles: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """Directed edges ``(3m, 2)``, their undirected ids ``(3m,)``, and the count of each id.

    Examples
    --------
    >>> directed, ids, counts = edge_table(np.array([[0, 1, 2], [0, 2, 3]]))
    >>> len(directed), counts.tolist()
    (6, [1, 2, 1, 1, 1])
    """
    directed = triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    n = int(triangles.max()) + 1
    key = np.minimum(directed[:, 0], directed[:, 1]) * n + np.maximum(directed[:, 0],
                                                                      directed[:, 1])
    _, ids, counts = np.unique(key, return_inverse=True, return_counts=True)
    return directed, ids.reshape(-1), counts


def boundary_loops(triangles: NDArray) -> list[NDArray[np.int64]]:
    """The holes of a surface: its boundary edges (those of one triangle) walked into closed
    loops of vertex indices, each in the direction its triangles run along it.

    Examples
    --------
    >>> [loop.tolist() for loop in boundary_loops(np.array([[0, 1, 2], [0, 2, 3]]))]
    [[0, 1, 2, 3]]
    """
    directed, ids, counts = edge_table(triangles)
    return walk_loops(directed[counts[ids] == 1].tolist())


def walk_loops(edges: list) -> list[NDArray[np.int64]]:
    """Directed edges ``(a, b)`` that form closed paths, walked into loops of vertex indices.

    Examples
    --------
    >>> [loop.tolist() for loop in walk_loops([(2, 0), (0, 1), (1, 2)])]
    [[2, 0, 1]]
    """
    nxt: dict[int, list[int]] = {}
    for a, b in edges:
        nxt.setdefault(a, []).append(b)
    loops = []
    while nxt:
        start = next(iter(nxt))
        loop, cur = [start], start
        while cur in nxt:
            outs = nxt[cur]
            step = outs.pop()
            if not outs:
                del nxt[cur]
            if step == start:
                break
            loop.append(step)
            cur = step
        loops.append(np.array(loop, dtype=np.int64))
    return loops


def shell_labels(triangles: NDArray, n_vertices: int) -> NDArray[np.int64]:
    """Which shell (connected piece; sharing a vertex connects) each triangle belongs to.

    Examples
    --------
    >>> shell_labels(np.array([[0, 1, 2], [2, 3, 4], [5, 6, 7]]), 8).tolist()
    [0, 0, 1]
    """
    m = len(triangles)
    rows = np.repeat(np.arange(m), 3)
    incidence = coo_matrix((np.ones(3 * m), (rows, m + triangles.reshape(-1))),
                           shape=(m + n_vertices, m + n_vertices))
    labels = connected_components(incidence, directed=False)[1][:m]
    return np.unique(labels, return_inverse=True)[1].reshape(-1)


def pieces(T: NDArray) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
    """The pieces orientation works on: triangles connected through edges of exactly two
    triangles (so two solids glued along a non-manifold edge are two pieces), and whether
    each piece is closed (each of its edges twice among its own triangles).

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> label, closed = pieces(bundled("cube").triangles)
    >>> int(label.max()) + 1, closed.tolist()
    (1, [True])
    """
    _, ids, counts = edge_table(T)
    m = len(T)
    order = np.argsort(ids, kind="stable")
    same = np.flatnonzero((ids[order][1:] == ids[order][:-1]) & (counts[ids[order][1:]] == 2))
    a, b = order[same] // 3, order[same + 1] // 3
    graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(m, m))
    label = connected_components(graph, directed=False)[1]
    label = np.unique(label, return_inverse=True)[1].reshape(-1)
    n = int(label.max()) + 1
    key = label[np.arange(3 * m) // 3] * (int(ids.max()) + 1) + ids
    _, inverse, times = np.unique(key, return_inverse=True, return_counts=True)
    closed = np.ones(n, dtype=bool)
    closed[label[np.flatnonzero(times[inverse.reshape(-1)] != 2) // 3]] = False
    return label, closed


def _consistent(directed: NDArray, ids: NDArray, counts: NDArray, n: int) -> bool:
    """Every edge shared by two triangles is run through in opposite directions."""
    two = counts[ids] == 2
    d = directed[two]
    key = np.sort(d[:, 0] * n + d[:, 1])  # no directed edge twice (a sort: np.unique hashes,
    return not np.any(key[1:] == key[:-1])  # slower on 300k distinct keys)


def fix_winding(T: NDArray, name: str, warnings: list[str]) -> NDArray:
    """Orient every triangle like its neighbours across the edges that two triangles share.

    Edges of one triangle (a hole's rim) and of three or more (non-manifold,
    accepted only with ``allow_open``) put no constraint.

    Examples
    --------
    >>> T = np.array([[0, 1, 2], [0, 3, 2]])  # both run through edge 0-2 from 2 to 0
    >>> notes = []
    >>> fix_winding(T, "sheet", notes).tolist(), notes
    ([[0, 1, 2], [2, 3, 0]], ['re-oriented 1 triangles for consistent winding'])
    """
    directed, ids, counts = edge_table(T)
    n = int(T.max()) + 1
    if _consistent(directed, ids, counts, n):
        return T
    m = len(T)
    order = np.argsort(ids, kind="stable")
    same = np.flatnonzero((ids[order][1:] == ids[order][:-1]) & (counts[ids[order][1:]] == 2))
    first, second = order[same], order[same + 1]
    a, b = first // 3, second // 3
    parity = directed[first, 0] == directed[second, 0]  # same direction: one must flip
    graph = coo_matrix((np.ones(len(a)), (a, b)), shape=(m, m)).tocsr()
    lookup = dict(zip(zip(np.minimum(a, b).tolist(), np.maximum(a, b).tolist(), strict=True),
                      parity.tolist(), strict=True))
    flip = np.zeros(m, dtype=bool)
    seen = np.zeros(m, dtype=bool)
    for root in range(m):
        if seen[root]:
            continue
        nodes, parent = breadth_first_order(graph, root, directed=False,
                                            return_predecessors=True)
        seen[nodes] = True
        for node in nodes[1:].tolist():
            up = int(parent[node])
            flip[node] = flip[up] ^ lookup[(min(node, up), max(node, up))]
    fixed = np.where(flip[:, None], T[:, ::-1], T)
    if not _consistent(*edge_table(fixed), n):
        raise InputError(f"{name}: the surface is not orientable (it has no consistent "
                         "outside, like a Moebius strip)")
    warnings.append(f"re-oriented {int(min(flip.sum(), m - flip.sum()))} triangles for "
                    "consistent winding")
    return fixed


def winding_numbers(V: NDArray, T: NDArray, points: NDArray,
                    skip: NDArray | None = None) -> NDArray[np.float64]:
    """Generalised winding number of each point with respect to the triangles ``T``.

    The sum of the triangles' signed solid angles over ``4 pi``
    (Van Oosterom and Strackee's formula): 1 inside a closed outward
    surface, 0 outside, 1/2 on it (a triangle in whose plane the point lies
    counts 0, its principal value). ``skip[i]`` is a triangle left out for
    point ``i`` (e.g. the one it was sampled on), or -1.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> cube = bundled("cube")
    >>> winding_numbers(cube.vertices, cube.triangles, [[0, 0, 0], [2, 0, 0], [1, 0.5, 0]])
    array([1. , 0. , 0.5])
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.empty(len(points))
    chunk = max(1, 2_000_000 // max(len(T), 1))
    A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    for s in range(0, len(points), chunk):
        p = points[s:s + chunk, None, :]
        a, b, c = A[None] - p, B[None] - p, C[None] - p
        la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
        num = np.einsum("kij,kij->ki", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("kij,kij->ki", a, b) * lc
               + np.einsum("kij,kij->ki", b, c) * la + np.einsum("kij,kij->ki", c, a) * lb)
        angle = 2 * np.arctan2(num, den)
        angle[np.abs(num) <= 1e-12 * la * lb * lc] = 0.0  # in the triangle's plane
        if skip is not None:
            rows = np.flatnonzero(skip[s:s + chunk] >= 0)
            angle[rows, skip[s:s + chunk][rows]] = 0.0
        out[s:s + chunk] = angle.sum(axis=1) / (4 * np.pi)
    return out


def orient_outward(V: NDArray, T: NDArray, labels: NDArray, closed: NDArray,
                   warnings: list[str]) -> NDArray:
    """Flip each piece whose consistently wound triangles face inward.

    Parameters
    ----------
    V, T : arrays
        The mesh, its winding consistent within each piece (:func:`fix_winding`).
    labels : (m,) int array
        Each triangle's piece (:func:`pieces`).
    closed : (pieces,) bool array
        Which pieces are closed.
    warnings : list
        Gets a line for what was flipped, and for open sheets with no inside.

    Returns
    -------
    (m, 3) int array
    """
    areas2 = np.linalg.norm(np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]]), axis=1)
    n_shells = int(labels.max()) + 1
    # about the bounding box's centre: far from the origin the products would cancel
    C = V - (V.min(axis=0) + V.max(axis=0)) / 2
    signed = np.bincount(labels, np.einsum("ij,ij->i", C[T[:, 0]],
                                           np.cross(C[T[:, 1]], C[T[:, 2]])), n_shells)
    flip = np.asarray(closed, dtype=bool) & (signed < 0)
    sheets = 0
    rng = np.random.default_rng(0)
    for s in np.flatnonzero(~np.asarray(closed, dtype=bool)).tolist():
        tris = np.flatnonzero(labels == s)
        weights = areas2[tris] / areas2[tris].sum()
        pick = (tris if len(tris) <= WINDING_SAMPLES
                else rng.choice(tris, WINDING_SAMPLES, replace=False, p=weights))
        local = np.searchsorted(tris, pick)
        w = winding_numbers(V, T[tris], V[T[pick]].mean(axis=1), skip=local)
        mean = float(np.average(w, weights=areas2[pick]))
        if abs(mean) <= OPEN_SHEET:
            sheets += 1
        flip[s] = mean < -OPEN_SHEET
    flipped = flip[labels]
    if flipped.all():
        warnings.append("the triangles faced inward; flipped them to face outward")
    elif flipped.any():
        warnings.append(f"{int(flip.sum())} of {len(flip)} pieces faced inward; flipped them "
                        "to face outward")
    if sheets:
        warnings.append(f"{sheets} open shell{'s' if sheets > 1 else ''} with no inside (a "
                        "nearly flat sheet): kept the file's winding; a finger may touch "
                        "either side")
    return np.where(flipped[:, None], T[:, ::-1], T)
