"""Figures: objects as a person would sketch them (matplotlib, no screen needed).

``plot_object`` draws a polygon with numbered edges and outward normals, or a
polyhedron with each planar face of several triangles in its own colour and
numbered (one-triangle faces, the curved parts, in grey). Figures save as PNG or
SVG by the file's extension.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.patches import PathPatch
from matplotlib.path import Path as MplPath
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from .errors import InputError
from .objects import Polygon, Polyhedron


def _polygon_axes(ax, polygon: Polygon, label_edges: bool = True) -> None:
    verts, codes = [], []
    for ring in polygon.rings:
        verts += [*ring.tolist(), ring[0].tolist()]
        codes += [MplPath.MOVETO] + [MplPath.LINETO] * (len(ring) - 1) + [MplPath.CLOSEPOLY]
    ax.add_patch(PathPatch(MplPath(verts, codes), facecolor="#dfe7f2", edgecolor="#1f3b63",
                           linewidth=1.5))
    scale = polygon.size * 0.06
    for e in polygon.edges:
        mid = (e.start + e.end) / 2
        if label_edges:
            ax.annotate("", mid + e.normal * scale, mid,
                        arrowprops={"arrowstyle": "->", "color": "#b5533c", "lw": 1})
            ax.text(*(mid + e.normal * scale * 1.8), str(e.index), ha="center", va="center",
                    fontsize=8, color="#b5533c")
    lo, hi = polygon.bounds
    pad = polygon.size * 0.12
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")


def _polyhedron_axes(ax, poly: Polyhedron, label_faces: bool) -> None:
    cmap = plt.get_cmap("tab20")
    merged = np.array([len(f.triangles) > 1 for f in poly.faces])
    palette = np.array([cmap(i % 20) if merged[i] else (0.72, 0.72, 0.72, 1.0)
                        for i in range(len(poly.faces))])
    colours = palette[poly.face_of_triangle]  # one-triangle faces (curved parts) in grey
    light = np.array([0.4, 0.3, 0.85]) / np.linalg.norm([0.4, 0.3, 0.85])
    V, T = poly.vertices, poly.triangles
    normals = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    shade = 0.55 + 0.45 * np.clip(normals @ light, 0, 1)
    colours[:, :3] *= shade[:, None]
    ax.add_collection3d(Poly3DCollection(V[T], facecolors=colours, edgecolors="none",
                                         linewidths=0))
    outline = [f.boundary for f in poly.faces if len(f.triangles) > 1]
    if outline:
        ax.add_collection3d(Poly3DCollection(outline, facecolors="none",
                                             edgecolors="#1b1b1b", linewidths=0.6))
    if label_faces:
        for f in poly.faces:
            centre = f.to_world(np.asarray(f.polygon.centroid))
            ax.text(*(centre + f.normal * poly.size * 0.04), str(f.index), fontsize=7)
    lo, hi = poly.bounds
    centre, half = (lo + hi) / 2, (hi - lo).max() / 2
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), centre, strict=True):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")


def _save(fig, path: str | Path | None) -> None:
    """Save as PNG or SVG by the extension; a bad path is one InputError line."""
    if path is None:
        return
    path = Path(path)
    if path.suffix.lower() not in (".png", ".svg"):
        plt.close(fig)
        raise InputError(f"{path}: plots are saved as .png or .svg")
    try:
        fig.savefig(path, dpi=130, bbox_inches="tight")
    except OSError as e:
        plt.close(fig)
        raise InputError(f"{path}: cannot write the plot: {e.strerror}") from None


def plot_object(obj: Polygon | Polyhedron, path: str | Path | None = None,
                title: str | None = None):
    """Draw an object; save it to ``path`` (``.png`` or ``.svg``) when given.

    Returns the matplotlib figure.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> fig = plot_object(bundled("frame"))
    >>> len(fig.axes)
    1
    """
    if isinstance(obj, Polygon):
        fig, ax = plt.subplots(figsize=(5.5, 5.5))
        _polygon_axes(ax, obj)
    else:
        fig = plt.figure(figsize=(6, 6))
        ax = fig.add_subplot(projection="3d")
        ax.view_init(elev=24, azim=-58)
        _polyhedron_axes(ax, obj, label_faces=len(obj.faces) <= 60)
    summary = obj.summary()
    counts = (f"{summary['edges']} edges" if obj.dim == 2
              else f"{summary['faces']} planar faces from {summary['triangles']} triangles")
    ax.set_title(title or f"{obj.name}: {counts}", fontsize=10)
    _save(fig, path)
    return fig


def plot_regions(regions: list, path: str | Path | None = None, title: str | None = None):
    """Independent regions on a polygon, in the spirit of the paper's Fig. 7 and 10.

    The polygon, each grasp's segments in bold (one colour per grasp,
    numbered by rank), and at the segments' ends the friction cones (two
    fingers with friction) or the pushing directions (frictionless fingers).
    """
    if not regions:
        raise InputError("no regions to draw")
    polygon = regions[0].polygon
    fig, ax = plt.subplots(figsize=(6, 6))
    _polygon_axes(ax, polygon, label_edges=False)
    cmap = plt.get_cmap("tab10")
    reach = polygon.size * 0.18
    for rank, r in enumerate(regions):
        colour = cmap(rank % 10)
        mus = r.friction()
        for (a, b), e in zip(r.points, (polygon.edges[k] for k in r.edges), strict=True):
            ax.plot(*np.array([a, b]).T, color=colour, linewidth=4.5, solid_capstyle="butt",
                    zorder=3)
            mid = (a + b) / 2 + e.normal * polygon.size * 0.05
            ax.text(*mid, str(rank + 1), color=colour, fontsize=10, fontweight="bold",
                    ha="center", va="center")
        for ray in r.cone_rays(reach):  # the cones of forces the fingers can push with
            ax.plot(*ray.T, color=colour, linewidth=0.8, alpha=0.7, zorder=2)
        apex = getattr(r, "apex", None)  # Nguyen's two-sided cone (Fig. 7)
        if apex is not None:
            from .synthesis import counter_overlapping_sector

            e1, e2 = (polygon.edges[k] for k in r.edges)
            sector = counter_overlapping_sector(e1.normal, mus[0], e2.normal, mus[1])
            if sector is not None:
                rays = [np.array([np.cos(t), np.sin(t)]) for t in (sector.low, sector.high)]
                for side in (1, -1):
                    wedge = [apex, apex + side * polygon.size * rays[0],
                             apex + side * polygon.size * rays[1]]
                    ax.fill(*np.array(wedge).T, color=colour, alpha=0.12, zorder=1)
                ax.plot(*apex, marker="o", color=colour, markersize=4, zorder=4)
        centre = getattr(r, "centre", None)  # three fingers: where the lines of force meet
        if centre is not None:
            ax.plot(*centre, marker="x", color=colour, markersize=8, zorder=4)
    fingers = len(regions[0].edges)
    friction = f", mu {mus[0]:g}" if mus[0] > 0 else ", frictionless"
    ax.set_title(title or f"{polygon.name}: {len(regions)} best {fingers}-finger grasps"
                 f"{friction} (bold: independent regions)", fontsize=10)
    _save(fig, path)
    return fig


def plot_spatial_regions(regions, path: str | Path | None = None, title: str | None = None,
                         cones: bool = True):
    """Independent regions on a polyhedron, as in the paper's Fig. 1 and 8.

    The object in light grey, each finger's region in its own colour, and
    (with friction) the friction cone at the middle of each region, drawn as
    a ring of rays into the object. ``regions`` is one region set (e.g. the
    best of :func:`forceclosure.synthesis.best_soft_pair_regions`).

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import soft_pair_regions
    >>> fig = plot_spatial_regions(soft_pair_regions(bundled("cube"), 0, 1, 0.5))
    >>> len(fig.axes)
    1
    """
    poly = regions.polyhedron
    fig = plt.figure(figsize=(6.5, 6.5))
    ax = fig.add_subplot(projection="3d")
    ax.view_init(elev=24, azim=-58)
    V, T = poly.vertices, poly.triangles
    normals = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    light = np.array([0.4, 0.3, 0.85]) / np.linalg.norm([0.4, 0.3, 0.85])
    grey = 0.55 + 0.4 * np.clip(normals @ light, 0, 1)
    ax.add_collection3d(Poly3DCollection(V[T], facecolors=np.column_stack(
        [grey, grey, grey, np.full(len(T), 0.35)]), edgecolors="none", linewidths=0))
    cmap = plt.get_cmap("tab10")
    lift = poly.size * 2e-3
    reach = poly.size * 0.2
    for k, region in enumerate(regions.regions):
        colour = cmap(k % 10)
        for patch in region:
            n = poly.faces[patch.face].normal
            ax.add_collection3d(Poly3DCollection([patch.points + lift * n], facecolors=[colour],
                                                 edgecolors=[colour], linewidths=1.2,
                                                 alpha=0.9))
        centre = np.mean([p.points.mean(axis=0) for p in region], axis=0)
        n = poly.faces[region[0].face].normal
        ax.text(*(centre + n * poly.size * 0.06), str(k + 1), color=colour, fontsize=11,
                fontweight="bold")
        if cones and regions.mu > 0:
            from .contacts import tangent_basis

            t1, t2 = tangent_basis(n[None])
            for a in np.linspace(0, 2 * np.pi, 12, endpoint=False):
                ray = -n + regions.mu * (np.cos(a) * t1[0] + np.sin(a) * t2[0])
                ray *= reach / np.linalg.norm(ray)
                ax.plot(*np.array([centre, centre + ray]).T, color=colour, linewidth=0.7,
                        alpha=0.8)
        elif cones:
            ax.plot(*np.array([centre, centre - n * reach]).T, color=colour, linewidth=1.2)
    lo, hi = poly.bounds
    mid, half = (lo + hi) / 2, (hi - lo).max() / 2
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, strict=True):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    friction = f"{regions.model} fingers, mu {regions.mu:g}" if regions.mu > 0 else \
        "frictionless fingers"
    ax.set_title(title or f"{poly.name}: independent regions for {len(regions.regions)} "
                 f"{friction}\n{regions.construction}; smallest region "
                 f"{regions.min_area:.3g}", fontsize=9)
    _save(fig, path)
    return fig
