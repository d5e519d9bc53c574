"""The scene of a picture of labelled jaw poses: what both renderers draw, computed once.

A person looking at the best poses of ``forceclosure grasps`` asks, for
each: which two contacts, does the pair close and by how much, and can the
hand take it. :func:`grasp_scene` answers in geometry and words, and the
two renderers draw the same answer: :func:`forceclosure.pictures.grasp_plot.plot_grasps`
(small multiples, one panel per pose) and
:func:`forceclosure.pictures.view.grasps_figure` (one pose highlighted at a time).

Per pose (:class:`PoseScene`): the hand's boxes as its collision check
sees them (:func:`forceclosure.gripper.collision.hand_boxes`, opened to the
grasp's width plus the check's clearance, moved along the approach axis by
the pose's own ``depth`` where the labels have one), a stem back to the
hand's base frame (``tip_offset`` behind the fingertips, where the gripper
states it), the two contacts, the friction cone at each pointing into the
object (the forces the finger can push with, half-angle ``atan μ``) and
the line between the contacts: where that line lies inside both cones the
pair closes (Corollary 3). A caption in words: rank, verdict, hand clear
or colliding, μ*, ε.

The legend (:class:`LegendEntry`) names each label as it is ("closure and
clear", "closure, hand collides", "marginal", "none") with how many poses
of it are drawn and how many the labels hold in all. The object's mesh is
drawn decimated (:func:`drawn_mesh`) so that a scanned mesh keeps a page
small.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..gripper.collision import CLEARANCE, hand_boxes, jaw_frames
from ..gripper.jaw import ParallelJaw
from ..verdicts import VERDICT_WORDS, VerdictCode

__all__ = [
    "CONE_SIDES",
    "GraspScene",
    "LegendEntry",
    "PoseScene",
    "cone_points",
    "drawn_mesh",
    "grasp_scene",
    "legend_entries",
]

#: Segments of a drawn friction cone's rim.
CONE_SIDES = 24

#: Label colours by category: closure and clear, closure but colliding, marginal, none.
CATEGORY_COLOURS = ("#2e9e44", "#e6862e", "#d4b106", "#c8303a")

#: The corners of a unit box centred on the origin, and its 12 triangles (for meshes) and
#: 12 edges (for outlines), by corner index.
_CORNERS = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
BOX_TRIANGLES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                          [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
BOX_EDGES = np.array([[0, 1], [1, 3], [3, 2], [2, 0], [4, 5], [5, 7], [7, 6], [6, 4],
                      [0, 4], [1, 5], [2, 6], [3, 7]])


def category_words(collides: Any) -> tuple[str, str, str, str]:
    """The legend's words for the four categories, as the labels say them: with the
    collision check, "closure and clear" and "closure, hand collides"; without it,
    "closure (hand not checked)" and (never used) "closure, hand collides".

    Examples
    --------
    >>> category_words(None)[0], category_words([False])[0]
    ('closure (hand not checked)', 'closure and clear')
    """
    first = "closure (hand not checked)" if collides is None else "closure and clear"
    return first, "closure, hand collides", "marginal", "none"


def categories(labels: Any) -> NDArray[np.int64]:
    """Per pose: 0 closure and clear (or closure, where collision was not checked),
    1 closure but the hand collides, 2 marginal, 3 none.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> categories(SimpleNamespace(code=np.array([2, 2, 1, 0]),
    ...                            collides=np.array([False, True, True, False]))).tolist()
    [0, 1, 2, 3]
    """
    code = np.asarray(labels.code)
    hit = (np.zeros(len(code), bool) if labels.collides is None
           else np.asarray(labels.collides, dtype=bool))
    return np.select([(code == VerdictCode.CLOSURE) & ~hit, code == VerdictCode.CLOSURE,
                      code == VerdictCode.MARGINAL], [0, 1, 2], 3)


@dataclass(frozen=True)
class LegendEntry:
    """One label of the legend: its ``words``, ``colour``, how many poses of it are
    ``drawn`` and how many the labels hold in ``total``."""

    words: str
    colour: str
    drawn: int
    total: int

    @property
    def text(self) -> str:
        """``"closure and clear: 9 drawn of 12"``."""
        return f"{self.words}: {self.drawn:,} drawn of {self.total:,}"


def legend_entries(labels: Any, chosen: NDArray[np.int64]) -> list[LegendEntry]:
    """The legend of a picture drawing the poses ``chosen``: one entry per category that
    has a pose drawn, with the counts drawn and in all.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> labels = SimpleNamespace(code=np.array([2, 2, 0, 2]),
    ...                          collides=np.array([False, True, False, False]))
    >>> [e.text for e in legend_entries(labels, np.array([0, 1]))]
    ['closure and clear: 1 drawn of 2', 'closure, hand collides: 1 drawn of 1']
    """
    kind = categories(labels)
    total = np.bincount(kind, minlength=4)
    drawn = np.bincount(kind[np.asarray(chosen, dtype=int)], minlength=4)
    words = category_words(labels.collides)
    return [LegendEntry(words[k], CATEGORY_COLOURS[k], int(drawn[k]), int(total[k]))
            for k in range(4) if drawn[k]]


@dataclass(frozen=True)
class PoseScene:
    """One pose as drawn.

    Attributes
    ----------
    rank : int
        1 for the best.
    index : int
        The pose's index in the labels.
    category : int
        0 closure and clear, 1 closure but the hand collides, 2 marginal, 3 none.
    colour : str
    caption : str
        Two lines: ``"1. closure, clear"`` and ``"μ* 0.31   ε 0.054"``.
    boxes : (B, 8, 3) array
        The corners of the hand's boxes in the world (corner order of
        :data:`BOX_TRIANGLES` and :data:`BOX_EDGES`): the two fingers, then the palm.
    stem : (2, 3) array
        From the back of the palm to the hand's base frame along the approach axis.
    points, normals : (2, 3) arrays
        The contacts and their outward normals.
    cones : (2, CONE_SIDES + 1, 3) array
        Per contact, the apex (the contact) and the rim of its friction cone,
        pointing into the object (none, ``(0, CONE_SIDES + 1, 3)``, where the labels
        have no normals).
    closing_axis, approach_axis : (3,) arrays
    """

    rank: int
    index: int
    category: int
    colour: str
    caption: str
    boxes: NDArray[np.float64]
    stem: NDArray[np.float64]
    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    cones: NDArray[np.float64]
    closing_axis: NDArray[np.float64]
    approach_axis: NDArray[np.float64]


@dataclass(frozen=True)
class GraspScene:
    """What a picture of labelled poses draws (:func:`grasp_scene`).

    Attributes
    ----------
    name : str
        The object's name.
    vertices, triangles : arrays
        The object's mesh as drawn (decimated, :func:`drawn_mesh`).
    size : float
        The object's size (its bounding box's largest side).
    poses : tuple of PoseScene
        Best first.
    legend : tuple of LegendEntry
    title : str
    mu : float
        The friction coefficient the labels are at (the cones' half-angle is ``atan mu``).
    """

    name: str
    vertices: NDArray[np.float64]
    triangles: NDArray[np.int64]
    size: float
    poses: tuple[PoseScene, ...]
    legend: tuple[LegendEntry, ...]
    title: str
    mu: float


def drawn_mesh(vertices: NDArray, triangles: NDArray, most: int
               ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """At most ``most`` triangles that look like the mesh: vertex clustering (Rossignac and
    Borrel, 1993) on the coarsest of a few grids that is fine enough; the mesh itself when
    it is small.

    Vertices in one cell of a cubic grid merge into their mean; triangles whose corners
    merge are dropped, and so are repeated ones. For drawing only: the result need not be
    closed or manifold.

    Examples
    --------
    >>> import trimesh
    >>> sphere = trimesh.creation.icosphere(subdivisions=5)
    >>> V, T = drawn_mesh(sphere.vertices, sphere.faces, 2000)
    >>> radius = np.linalg.norm(V, axis=1)
    >>> len(sphere.faces), len(T) <= 2000, bool(np.allclose(radius, 1, atol=0.05))
    (20480, True, True)
    """
    V = np.asarray(vertices, dtype=float)
    T = np.asarray(triangles, dtype=np.int64)
    if len(T) <= most:
        return V, T
    lo = V.min(axis=0)
    size = float(np.ptp(V, axis=0).max()) or 1.0
    # the triangle count scales about as cells ** 2 on a surface: start there, then coarsen
    cells = max(4, int(np.sqrt(most / 2.0)))
    while True:
        key = np.floor((V - lo) / (size / cells)).astype(np.int64)
        _, group = np.unique(key, axis=0, return_inverse=True)
        group = group.reshape(-1)
        count = np.bincount(group)
        merged = np.zeros((len(count), 3))
        np.add.at(merged, group, V)
        merged /= count[:, None]
        tri = group[T]
        tri = tri[(tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2])]
        if len(tri):
            tri = np.unique(tri, axis=0)
            _, first = np.unique(np.sort(tri, axis=1), axis=0, return_index=True)
            tri = tri[np.sort(first)]
        if len(tri) <= most or cells <= 4:
            return merged, tri
        cells = max(4, int(cells * 0.8))


def _number(x: float, missing: str) -> str:
    x = float(x)
    return missing if np.isnan(x) else "none closes" if np.isinf(x) else f"{x:.3g}"


def _value(labels: Any, name: str, i: int) -> float:
    """A label's value at pose ``i``; NaN where the labels do not have it."""
    values = getattr(labels, name, None)
    return float("nan") if values is None else float(values[i])


def _caption(rank: int, labels: Any, i: int) -> str:
    verdict = VERDICT_WORDS[int(labels.code[i])]
    hand = ("hand not checked" if labels.collides is None
            else "collides" if labels.collides[i] else "clear")
    return (f"{rank}. {verdict}, {hand}\n"
            f"μ* {_number(_value(labels, 'least_friction', i), '–')}   "
            f"ε {_number(_value(labels, 'epsilon', i), '–')}")


def cone_points(apex: NDArray, axis: NDArray, mu: float, height: float,
                sides: int = CONE_SIDES) -> NDArray[np.float64]:
    """The apex and the ``sides`` rim points of a friction cone of half-angle ``atan mu``
    along the unit ``axis``, ``height`` long: every picture's cone (jaw poses, regions).

    Examples
    --------
    >>> cone_points(np.zeros(3), np.array([0.0, 0.0, 1.0]), 0.5, 2.0, sides=4)[:, 2].tolist()
    [0.0, 2.0, 2.0, 2.0, 2.0]
    """
    from ..contacts import tangent_basis

    t1, t2 = tangent_basis(np.asarray(axis, float)[None])
    angles = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    rim = apex + height * (axis + mu * (np.cos(angles)[:, None] * t1[0] +
                                        np.sin(angles)[:, None] * t2[0]))
    return np.vstack([apex, rim])


def grasp_scene(obj: Any, labels: Any, chosen: NDArray[np.int64],
                gripper: ParallelJaw | None = None, title: str | None = None,
                most_triangles: int = 4000) -> GraspScene:
    """The scene of the poses ``chosen`` (indices into ``labels``, best first).

    Parameters
    ----------
    obj : file, bundled name, trimesh.Trimesh or Polyhedron
    labels : GraspLabels
        Also read, where present: ``meta["mu"]``, ``meta["collision"]["clearance"]``
        (the opening the check used), ``meta["tip_offset"]`` and a per-pose ``depth``.
    chosen : array of int
    gripper : ParallelJaw, optional
        Default: the labels' gripper, from their ``meta``.
    title : str, optional
    most_triangles : int
        The drawn mesh's budget (:func:`drawn_mesh`).

    Examples
    --------
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), 0.3, 6, least_friction=False)
    >>> scene = grasp_scene("cube", labels, np.array([0, 1]))
    >>> [p.rank for p in scene.poses], scene.poses[0].boxes.shape
    ([1, 2], (3, 8, 3))
    """
    from ..gripper.jaw import surface_mesh
    from ..io.export import labels_gripper

    gripper = labels_gripper(labels) if gripper is None else gripper
    poly, mesh = surface_mesh(obj)
    chosen = np.asarray(chosen, dtype=np.int64).reshape(-1)
    meta = getattr(labels, "meta", None) or {}
    mu = float(meta.get("mu", 0.5))
    check = meta.get("collision") or {}
    clearance = check.get("clearance") if isinstance(check, dict) else None
    if clearance is None:
        clearance = CLEARANCE * gripper.width_max
    depth_of = getattr(labels, "depth", None)
    tip_offset = meta.get("tip_offset", getattr(gripper, "tip_offset", None))
    kind = categories(labels)
    V, T = drawn_mesh(mesh.vertices, mesh.faces, most_triangles)
    size = float(np.ptp(mesh.vertices, axis=0).max())
    frames = (jaw_frames(np.asarray(labels.center)[chosen],
                         np.asarray(labels.closing_axis)[chosen],
                         np.asarray(labels.approach_axis)[chosen])
              if len(chosen) else np.zeros((0, 4, 4)))
    poses = []
    for rank, (index, frame) in enumerate(zip(chosen, frames, strict=True), start=1):
        i = int(index)
        depth = gripper.depth if depth_of is None else float(np.asarray(depth_of)[i])
        shift = np.array([depth - gripper.depth, 0.0, 0.0])
        boxes = np.array([centre + shift + extents * _CORNERS for _, extents, centre in
                          hand_boxes(gripper, float(labels.width[i]), clearance)])
        R, t = frame[:3, :3], frame[:3, 3]
        boxes = boxes @ R.T + t
        back = depth - gripper.finger_length - gripper.palm_thickness
        base = back - 0.5 * gripper.finger_length
        if tip_offset is not None and depth - float(tip_offset) < back:
            base = depth - float(tip_offset)
        stem = np.array([[back, 0.0, 0.0], [base, 0.0, 0.0]]) @ R.T + t
        points = np.asarray(labels.points[i], dtype=float)
        if getattr(labels, "normals", None) is None:  # no normals, no cones
            normals, cones = np.full((2, 3), np.nan), np.zeros((0, CONE_SIDES + 1, 3))
        else:
            normals = np.asarray(labels.normals[i], dtype=float)
            reach = 0.35 * float(np.linalg.norm(points[1] - points[0])) or 0.1 * size
            cones = np.array([cone_points(p, -n / np.linalg.norm(n), mu, reach)
                              for p, n in zip(points, normals, strict=True)])
        poses.append(PoseScene(rank, i, int(kind[i]), CATEGORY_COLOURS[kind[i]],
                               _caption(rank, labels, i), boxes, stem, points, normals, cones,
                               R[:, 1].copy(), R[:, 0].copy()))
    heading = title or (f"{poly.name}: the {len(chosen)} best of {len(labels.code):,} "
                        f"labelled jaw poses (μ {mu:g})")
    return GraspScene(poly.name, V, T, size, tuple(poses),
                      tuple(legend_entries(labels, chosen)), heading, mu)
