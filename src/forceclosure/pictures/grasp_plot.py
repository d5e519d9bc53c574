"""A picture of labelled jaw poses: the object and its best grasps drawn as grippers.

Each pose is drawn as a simple gripper outline in its jaw frame: the two
fingers, from their bases to their tips (``depth`` past the jaw centre),
standing on the contacts, the palm's bar joining the bases and a stem
behind it along the approach axis; the contacts as dots. Colours say the
label: closure and clear (green), closure but the hand collides (orange),
marginal (gold), none (red). The "best" poses are the clear closed grasps
by decreasing ε, then the colliding closed ones, then marginal, then none.
Drawn with a bare ``matplotlib.figure.Figure`` (no pyplot, no backend
switch), saved as PNG or SVG, atomically.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..gripper.jaw import ParallelJaw

__all__ = ["FORMATS", "best_grasps", "plot_grasps"]

#: The picture's formats, by file extension.
FORMATS = (".png", ".svg")

#: Label colours: closure and clear, closure but colliding, marginal, none.
COLOURS = {"closure": "#2e9e44", "closure, collides": "#e6862e", "marginal": "#d4b106",
           "none": "#c8303a"}


def _category(labels: Any) -> NDArray[np.int64]:
    """0 closure and clear, 1 closure but colliding, 2 marginal, 3 none."""
    code = np.asarray(labels.code)
    hit = (np.zeros(len(code), bool) if labels.collides is None
           else np.asarray(labels.collides, dtype=bool))
    return np.select([(code == 2) & ~hit, code == 2, code == 1], [0, 1, 2], 3)


def best_grasps(labels: Any, top: int) -> NDArray[np.int64]:
    """Indices of the ``top`` best grasps: by label (closure and clear, closure colliding,
    marginal, none), then by decreasing ε, then by index.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> labels = SimpleNamespace(code=np.array([2, 0, 2, 2]), collides=np.array(
    ...     [False, False, True, False]), epsilon=np.array([0.1, 0.0, 0.5, 0.3]))
    >>> best_grasps(labels, 3).tolist()
    [3, 0, 2]
    """
    eps = np.nan_to_num(np.asarray(labels.epsilon, dtype=float), nan=0.0)
    order = np.lexsort((np.arange(len(eps)), -eps, _category(labels)))
    return order[:max(0, int(top))]


def check_plot_path(path: str) -> None:
    """Refuse a picture file of an unsupported format, before any work."""
    if not str(path).lower().endswith(FORMATS):
        raise InputError(f"{path}: pictures of grasps are saved as "
                         f"{' or '.join(FORMATS)}")


def _outline(center, closing, approach, width, gripper: ParallelJaw) -> list[NDArray]:
    """Polylines of one gripper outline in the world: two fingers and the palm's U, and
    the stem."""
    base = gripper.depth - gripper.finger_length
    half = 0.5 * width
    in_frame = [
        np.array([[gripper.depth, -half], [base, -half], [base, half], [gripper.depth, half]]),
        np.array([[base, 0.0], [base - gripper.palm_thickness - 0.5 * gripper.finger_length,
                                0.0]]),
    ]
    return [center + xy[:, :1] * approach + xy[:, 1:] * closing for xy in in_frame]


def plot_grasps(obj: Any, labels: Any, path: str, top: int = 10,
                gripper: ParallelJaw | None = None, title: str | None = None, *,
                up: str = "z") -> list[int]:
    """Draw the object and its ``top`` best labelled poses; save to ``path`` (.png, .svg),
    with the ``up`` axis upright (:func:`forceclosure.plot.upright_axis`).

    Returns the indices of the grasps drawn (:func:`best_grasps`).

    Examples
    --------
    >>> import os, tempfile
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=8, least_friction=False)
    >>> path = os.path.join(tempfile.mkdtemp(), "grasps.png")
    >>> len(plot_grasps("cube", labels, path, top=3)), os.path.getsize(path) > 0
    (3, True)
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    from ..gripper.jaw import surface_mesh
    from ..io.atomic import atomic_write
    from ..io.export import labels_gripper

    check_plot_path(path)
    gripper = labels_gripper(labels) if gripper is None else gripper
    poly, mesh = surface_mesh(obj)
    chosen = best_grasps(labels, top)
    category = _category(labels)
    names = list(COLOURS)

    fig = Figure(figsize=(7.0, 6.0))
    ax = fig.add_subplot(projection="3d")
    V, T = mesh.vertices, mesh.faces
    light = np.array([0.4, 0.3, 0.85]) / np.linalg.norm([0.4, 0.3, 0.85])
    shade = 0.45 + 0.5 * np.clip(mesh.face_normals @ light, 0, 1)
    faces = np.column_stack([shade, shade, shade * 1.05, np.full(len(shade), 0.35)])
    ax.add_collection3d(Poly3DCollection(V[T], facecolors=np.clip(faces, 0, 1),
                                         edgecolors="none"))
    segments, colours, points = [], [], []
    for i in chosen:
        colour = COLOURS[names[category[i]]]
        for line in _outline(labels.center[i], labels.closing_axis[i],
                             labels.approach_axis[i], labels.width[i], gripper):
            segments += [line[k:k + 2] for k in range(len(line) - 1)]
            colours += [colour] * (len(line) - 1)
        points.append((labels.points[i], colour))
    if segments:
        ax.add_collection3d(Line3DCollection(segments, colors=colours, linewidths=1.6))
        for p, colour in points:
            ax.scatter(*np.asarray(p).T, color=colour, s=10, depthshade=False)
    everything = np.concatenate([V, *segments]) if segments else V
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    middle, radius = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo))
    ax.set_xlim(middle[0] - radius, middle[0] + radius)
    ax.set_ylim(middle[1] - radius, middle[1] + radius)
    ax.set_zlim(middle[2] - radius, middle[2] + radius)
    ax.set_box_aspect((1, 1, 1))
    if up not in ("x", "y", "z"):
        raise InputError(f"up must be 'x', 'y' or 'z', got {up!r}")
    ax.view_init(elev=30, azim=-60, vertical_axis=up)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    drawn = np.bincount(category[chosen], minlength=4) if len(chosen) else np.zeros(4, int)
    handles = [Line2D([], [], color=COLOURS[n], lw=2, label=f"{n} ({drawn[k]})")
               for k, n in enumerate(names) if drawn[k]]
    if handles:
        ax.legend(handles=handles, loc="upper left", fontsize=8)
    ax.set_title(title or f"{poly.name}: the {len(chosen)} best of {len(labels.code):,} "
                          "labelled jaw poses", fontsize=10)
    fmt = str(path).lower().rsplit(".", 1)[-1]
    try:
        with atomic_write(path) as f:
            fig.savefig(f, format=fmt, dpi=130, bbox_inches="tight")
    finally:
        fig.clear()
    return chosen.tolist()
