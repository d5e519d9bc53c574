"""A picture of labelled jaw poses: small multiples, one panel per pose.

The best poses drawn together are a tangle (which fingers belong to which
pose?), so each pose gets its own panel: the object, lit and translucent;
the hand's boxes as its collision check sees them, in the colour of the
pose's label; the two contacts, the friction cone at each pointing into the
object and the line between them (the pair closes where that line lies
inside both cones, Corollary 3); under it a caption: rank, verdict, hand
clear or colliding, μ*, ε. Each panel's camera keeps the file's up axis
upright (:func:`forceclosure.pictures.plot.upright_axis`) and turns about it
to show the closing axis across the picture. One legend above the panels
names the labels as they are ("closure and clear", "closure, hand
collides", "marginal", "none") with the poses drawn and in all. The scene
is :func:`forceclosure.pictures.grasp_scene.grasp_scene`'s, the same as the
interactive page's.

The "best" poses are the clear closed grasps by decreasing ε, then the
colliding closed ones, then marginal, then none. Drawn with a bare
``matplotlib.figure.Figure`` (no pyplot, no backend switch), saved as PNG
or SVG, atomically.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..gripper.jaw import ParallelJaw
from .grasp_scene import BOX_EDGES, BOX_TRIANGLES, CATEGORY_COLOURS, categories

__all__ = ["COLOURS", "FORMATS", "best_grasps", "check_plot_path", "grasps_picture",
           "plot_grasps"]

#: The picture's formats, by file extension.
FORMATS = (".png", ".svg")

#: Label colours: closure and clear, closure but colliding, marginal, none.
COLOURS = dict(zip(("closure", "closure, collides", "marginal", "none"), CATEGORY_COLOURS,
                   strict=True))

#: Panels per row of the small multiples.
COLUMNS = 5

#: The drawn mesh's triangle budget per panel
#: (:func:`~forceclosure.pictures.grasp_scene.drawn_mesh`).
PANEL_TRIANGLES = 1500

_ELEVATION = 22.0
_AZIMUTHS = tuple(-60.0 + 30.0 * k for k in range(12))


def _category(labels: Any) -> NDArray[np.int64]:
    """0 closure and clear, 1 closure but colliding, 2 marginal, 3 none."""
    return categories(labels)


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


def _view(pose: Any, up: str) -> tuple[float, float]:
    """The camera of a pose's panel: the elevation, and the azimuth showing the closing
    axis most across the picture, the hand towards the viewer on a tie."""
    from .plot import camera_eye

    def score(azimuth: float) -> float:
        eye = camera_eye((_ELEVATION, azimuth), up)
        across = float(np.linalg.norm(np.cross(pose.closing_axis, eye)))
        return round(across, 2) + 0.1 * float(-pose.approach_axis @ eye)

    return _ELEVATION, max(_AZIMUTHS, key=score)


def _panel(ax: Any, scene: Any, pose: Any, up: str) -> None:
    """One pose: the object, the cones, the hand, the contacts and the line between them,
    in layers (matplotlib's depth sort misorders crossing polygons)."""
    from matplotlib.colors import to_rgb
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    from .plot import camera_eye, camera_light

    view = _view(pose, up) if pose is not None else (_ELEVATION, _AZIMUTHS[0])
    eye = camera_eye(view, up)
    ax.computed_zorder = False
    V, T = scene.vertices, scene.triangles
    if len(T):
        n = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
        n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
        grey = 0.5 + 0.45 * np.clip(n @ camera_light(eye, up), 0, 1)
        ax.add_collection3d(Poly3DCollection(
            V[T], facecolors=np.column_stack([grey * 0.80, grey * 0.82, grey * 0.86,
                                              np.full(len(T), 0.35)]),
            edgecolors="none", zorder=1))
    drawn = [V]
    if pose is not None:
        colour = to_rgb(pose.colour)
        for cone in pose.cones:  # into the object: the forces this finger can push with
            apex, rim = cone[0], cone[1:]
            ax.add_collection3d(Poly3DCollection(
                [[apex, rim[k], rim[(k + 1) % len(rim)]] for k in range(len(rim))],
                facecolors=[(*colour, 0.25)], edgecolors="none", zorder=2))
            ax.plot(*np.vstack([rim, rim[:1]]).T, color=colour, linewidth=0.8, zorder=2)
        ax.add_collection3d(Poly3DCollection(
            [box[tri] for box in pose.boxes for tri in BOX_TRIANGLES],
            facecolors=[(*colour, 0.18)], edgecolors="none", zorder=3))
        ax.add_collection3d(Line3DCollection(
            [box[e] for box in pose.boxes for e in BOX_EDGES] + [pose.stem],
            colors=[colour], linewidths=1.1, zorder=3))
        ax.plot(*pose.points.T, color="#222222", linewidth=1.0, linestyle="--", zorder=4)
        ax.scatter(*pose.points.T, color=colour, edgecolors="#222222", s=22,
                   depthshade=False, zorder=5)
        drawn += [pose.boxes.reshape(-1, 3), pose.stem, pose.cones.reshape(-1, 3)]
    everything = np.concatenate(drawn)
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    mid, half = 0.5 * (lo + hi), 0.5 * float(np.max(hi - lo))
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=view[0], azim=view[1], vertical_axis=up)
    ax.set_axis_off()
    if pose is not None:
        ax.set_title(pose.caption, fontsize=8, color=pose.colour if pose.category else
                     "#1d6b2e", pad=0)


def grasps_picture(obj: Any, labels: Any, top: int = 10, gripper: ParallelJaw | None = None,
                   title: str | None = None, *, up: str = "z"):
    """The figure of the ``top`` best labelled poses, one panel each (best first, rows of
    :data:`COLUMNS`), the legend above them, with the ``up`` axis upright.

    Parameters
    ----------
    obj : file, bundled name, trimesh.Trimesh or Polyhedron
    labels : GraspLabels
    top : int
        How many of the best poses to draw (:func:`best_grasps`); with none, one panel
        shows the object alone.
    gripper : ParallelJaw, optional
        Default: the labels' gripper, from their ``meta``.
    title : str, optional
    up : {"x", "y", "z"}
        The axis drawn upright (:func:`forceclosure.pictures.plot.upright_axis`).

    Returns
    -------
    matplotlib.figure.Figure
        A bare figure (no pyplot): its axes are the panels, in rank order.

    Examples
    --------
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=8, least_friction=False)
    >>> fig = grasps_picture("cube", labels, top=3)
    >>> len(fig.axes), fig.axes[0].get_title().splitlines()[0]
    (3, '1. closure, clear')
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    from .grasp_scene import grasp_scene

    if up not in ("x", "y", "z"):
        raise InputError(f"up must be 'x', 'y' or 'z', got {up!r}")
    chosen = best_grasps(labels, top)
    scene = grasp_scene(obj, labels, chosen, gripper, title, most_triangles=PANEL_TRIANGLES)
    panels = max(1, len(scene.poses))
    columns = min(COLUMNS, panels)
    rows = -(-panels // columns)
    height = 2.6 * rows + 1.2  # inches: the panels, and above them the title and legend
    fig = Figure(figsize=(2.7 * columns, height))
    fig.subplots_adjust(left=0.01, right=0.99, bottom=0.01, top=1 - 1.2 / height,
                        wspace=0.02, hspace=0.18)
    for k in range(panels):
        ax = fig.add_subplot(rows, columns, k + 1, projection="3d")
        _panel(ax, scene, scene.poses[k] if scene.poses else None, up)
    fig.suptitle(scene.title, fontsize=11, y=1 - 0.08 / height, va="top")
    if scene.legend:
        handles = [Line2D([], [], color=e.colour, lw=3, label=e.text) for e in scene.legend]
        fig.legend(handles=handles, loc="upper center", ncol=min(4, len(handles)),
                   fontsize=8, frameon=False, bbox_to_anchor=(0.5, 1 - 0.38 / height))
    return fig


def plot_grasps(obj: Any, labels: Any, path: str, top: int = 10,
                gripper: ParallelJaw | None = None, title: str | None = None, *,
                up: str = "z") -> list[int]:
    """Draw the ``top`` best labelled poses, one panel each (:func:`grasps_picture`), and
    save to ``path`` (.png, .svg), atomically, with the ``up`` axis upright
    (:func:`forceclosure.pictures.plot.upright_axis`).

    Returns the indices of the grasps drawn (:func:`best_grasps`), in panel order.

    Examples
    --------
    >>> import os, tempfile
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=8, least_friction=False)
    >>> path = os.path.join(tempfile.mkdtemp(), "grasps.png")
    >>> len(plot_grasps("cube", labels, path, top=3)), os.path.getsize(path) > 0
    (3, True)
    """
    from ..files.atomic import atomic_write

    check_plot_path(path)
    fig = grasps_picture(obj, labels, top, gripper, title, up=up)
    fmt = str(path).lower().rsplit(".", 1)[-1]
    try:
        with atomic_write(path) as f:
            fig.savefig(f, format=fmt, dpi=110)
    finally:
        fig.clear()
    return best_grasps(labels, top).tolist()
