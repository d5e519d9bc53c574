"""Figures: objects and independent regions as a person would sketch them (matplotlib).

:func:`plot_found` is the one front door for the region sets a synthesis
finds, whatever made them: it reads the object's dimension from the data
(``found[0].object.dim``) and draws the planar ones with
:func:`plot_regions`, the spatial ones with :func:`plot_spatial_regions`.
:func:`upright_axis` is the one rule for which axis a file's object stands
along.

``plot_object`` draws a polygon with numbered edges and outward normals, or a
polyhedron with each planar face of several triangles in its own colour and
the faces turned towards the viewer numbered (one-triangle faces, the curved
parts, in grey). ``plot_regions`` draws the independent segments of planar
grasps (and grasps with a soft finger on a convex vertex);
``plot_spatial_regions`` the regions of contact on a polyhedron: the object
lit and translucent, every finger's region on top of it and labelled, its
friction cone outside the object, as the HTML view
(:mod:`forceclosure.pictures.view`) draws it.

The figures are bare ``matplotlib.figure.Figure`` objects: nothing here
imports pyplot or switches matplotlib's backend (a Jupyter session keeps its
own), and no figure is left registered anywhere. Every function takes
``ax=`` to draw into a user's own axes. Pictures save as PNG or SVG by the
file's extension (:data:`FORMATS`), atomically.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..objects import Polygon, Polyhedron
from ..objects.polygon import axis_label

__all__ = ["FORMATS", "UP_AXIS", "check_plot_path", "corner_cone", "dot_corners", "on_vertex",
           "planar_caption", "plot_found", "plot_object", "plot_regions", "plot_spatial_regions",
           "standing", "upright_axis"]

#: The pictures' formats, by file extension.
FORMATS = (".png", ".svg")

#: The default camera (degrees): elevation, and the azimuths tried in turn by
#: :func:`plot_spatial_regions` for the one showing most regions from the front.
ELEVATION = 24.0
AZIMUTHS = tuple(-58.0 + 45.0 * k for k in range(8))

_GREY = np.array([0.80, 0.82, 0.86])

#: The axis a mesh file's object stands along, by the file's extension, where the format
#: says: glTF's specification makes +Y up ("glTF uses a right-handed coordinate system ...
#: +Y is up"), and OBJ, which states none, is written y-up by the tools that make most
#: of them (Blender's and Maya's exporters by default; pybullet_data's duck and teddy sit
#: on y = 0). Every other source (STL and PLY, with no convention; bundled objects; objects
#: made in Python) is drawn z-up; a URDF (z-up by ROS REP 103) as its meshes' format says
#: when every mesh it places is of a y-up format and unturned (pybullet_data's duck and
#: teddy: OBJs placed as they are), else z-up.
UP_AXIS = {".obj": "y", ".glb": "y", ".gltf": "y"}

#: How far (degrees) an object standing on an axis must be tipped before it falls over for
#: :func:`upright_axis` to call that axis "it stands on it".
STANDS = 10.0


def _urdf_axis(path: Path) -> str:
    """A URDF's up axis: its meshes' format's, when every ``<mesh>`` it places is of a y-up
    format with no turn in its ``<origin>``; else z (REP 103)."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.fromstring(path.read_bytes().lstrip(b" \t\r\n"))
    except (OSError, ET.ParseError):
        return "z"
    axes = set()
    for element in root.iter():
        if element.tag not in ("collision", "visual"):
            continue
        mesh = element.find("geometry/mesh")
        origin = element.find("origin")
        turned = origin is not None and any(
            float(v) != 0.0 for v in (origin.get("rpy") or "0 0 0").split())
        if mesh is None:
            if element.find("geometry") is not None:
                axes.add("z")  # a box, cylinder or sphere of the URDF itself
            continue
        axes.add("z" if turned else UP_AXIS.get(Path(mesh.get("filename", "")).suffix.lower(),
                                                  "z"))
    return axes.pop() if len(axes) == 1 else "z"


def _convention(source: Any) -> str:
    if not isinstance(source, str | Path):
        return "z"
    path = Path(source)
    if path.suffix.lower() == ".urdf":
        return _urdf_axis(path) if path.is_file() else "z"
    return UP_AXIS.get(path.suffix.lower(), "z")


def standing(vertices: NDArray) -> dict[str, float]:
    """How steadily the object of ``vertices`` stands on each axis: per axis, the larger
    over its two ends of the angle (degrees) it must be tipped to fall over, resting on a
    table with that end down; negative where it falls by itself.

    The object is taken as its convex hull, solid and uniform. Resting on the end ``-a``
    of axis ``a``, it touches the table with the hull's points within 0.5 % of its size of
    the lowest; it stands when its centre of mass is above their convex hull, and the
    angle is ``atan(margin / height)`` (the centre's distance inside that hull's edge,
    over its height above the table).

    Examples
    --------
    A box 1 wide, 3 long along y and 1 high stands on x or z by 45° and on its
    ends by atan(0.5 / 1.5):

    >>> import trimesh
    >>> {a: round(v, 1) for a, v in standing(trimesh.creation.box((1, 3, 1)).vertices).items()}
    {'x': 45.0, 'y': 18.4, 'z': 45.0}
    """
    import shapely
    import trimesh

    hull = trimesh.convex.convex_hull(np.asarray(vertices, dtype=float))
    V, centre = hull.vertices, hull.center_mass
    size = float(np.ptp(V, axis=0).max())
    found = {}
    for k, axis in enumerate("xyz"):
        plane = [j for j in range(3) if j != k]
        best = -90.0
        for sign in (1.0, -1.0):
            height = sign * V[:, k]
            low = height.min()
            base = shapely.MultiPoint(V[height <= low + 0.005 * size][:, plane]).convex_hull
            above = shapely.Point(centre[plane])
            margin = (base.exterior.distance(above)
                      if base.geom_type == "Polygon" and base.contains(above)
                      else -base.distance(above))
            best = max(best, float(np.degrees(np.arctan2(margin, sign * centre[k] - low))))
        found[axis] = best
    return found


def upright_axis(source: Any, obj: Any = None) -> str:
    """The axis to draw ``source``'s object upright along.

    First the file format's convention (:data:`UP_AXIS`): ``"y"`` for
    ``.obj``, ``.glb``, ``.gltf`` and for a URDF whose meshes are all of these
    and placed unturned, ``"z"`` for anything else. Then, given the loaded
    object ``obj``, its shape: where the object does not stand on the
    convention's axis (tipped by less than :data:`STANDS` degrees it falls,
    :func:`standing`) but does on another, the one it stands on most steadily
    (pybullet_data's mug, an OBJ written z-up).

    Parameters
    ----------
    source : path, str or anything else given to :func:`forceclosure.objects.io.load_object`
    obj : Polyhedron, trimesh.Trimesh or Polygon, optional
        The object loaded from ``source`` (a polygon lies in its plane: ``"z"``).

    Examples
    --------
    >>> upright_axis("duck_vhacd.obj"), upright_axis("part.STL"), upright_axis("cube")
    ('y', 'z', 'z')
    >>> import trimesh
    >>> upright_axis("lying.obj", trimesh.creation.cylinder(radius=1, height=0.5))  # a puck
    'z'
    """
    convention = _convention(source)
    vertices = getattr(obj, "vertices", None)
    if obj is None or isinstance(obj, Polygon) or vertices is None or len(vertices) < 4:
        return convention
    stands = standing(vertices)
    best = max("xyz", key=lambda a: (stands[a], a == convention))
    return convention if stands[convention] >= STANDS or stands[best] < STANDS else best


def on_vertex(regions: Any) -> bool:
    """Whether a planar region set has a finger on a vertex
    (:attr:`~forceclosure.synthesis.regions.RegionSet.kinds`).

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import synthesize
    >>> square = bundled("square")
    >>> pair = synthesize(square, 2, "hard", 0.3, top=1).found[0]
    >>> corner = synthesize(square, 2, "soft", 0.3, construction="vertices").found[0]
    >>> on_vertex(pair), on_vertex(corner)
    (False, True)
    """
    return "vertex" in regions.kinds


def dot_corners(g: Any) -> tuple[tuple[int, int], ...]:
    """The (incoming, outgoing) edges of the vertices a vertex grasp puts a dot on: both
    of a grasp on two vertices, the first of one with its other finger on an edge."""
    return g.corners if g.other[0] == "vertex" else g.corners[:1]


def planar_caption(sets: Sequence[Any], corners: Sequence[Any]) -> list[str]:
    """The phrases of a planar region picture's title (its renderer joins them): the
    segment grasps and the grasps with a finger on a vertex.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import synthesize
    >>> planar_caption(synthesize(bundled("square"), 2, "hard", 0.3, top=2).found, [])
    ['2 best 2-finger grasps, mu 0.3 (bold: independent regions)']
    """
    words = []
    if sets:
        mu = sets[0].friction()[0]
        friction = f"mu {mu:g}" if mu > 0 else "frictionless"
        words.append(f"{len(sets)} best {len(sets[0].edges)}-finger grasps, {friction} "
                     "(bold: independent regions)")
    if corners:
        words.append(f"{len(corners)} with a soft finger on a convex vertex (v), "
                     f"mu {corners[0].mu:g}")
    return words


def check_plot_path(path: str | Path) -> None:
    """Refuse a picture file of an unsupported format (one line), before any work.

    Examples
    --------
    >>> check_plot_path("regions.svg")
    >>> check_plot_path("regions.jpg")
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: regions.jpg: plots are saved as .png or .svg
    """
    if Path(path).suffix.lower() not in FORMATS:
        raise InputError(f"{path}: plots are saved as {' or '.join(FORMATS)}")


def _palette() -> tuple:
    """matplotlib's tab10 (the HTML view uses the same colours)."""
    import matplotlib

    return tuple(matplotlib.color_sequences["tab10"])


def _axes(ax: Any, three_d: bool, figsize: tuple[float, float], who: str):
    """The figure and axes to draw into: ``ax``, or a new bare Figure (no pyplot)."""
    if ax is None:
        from matplotlib.figure import Figure

        fig = Figure(figsize=figsize)
        return fig, fig.add_subplot(projection="3d" if three_d else None)
    if (getattr(ax, "name", "") == "3d") != three_d:
        kind = "3-D axes (projection='3d')" if three_d else "2-D axes"
        raise InputError(f"{who}: ax must be {kind} for this object")
    return ax.get_figure(root=True) if hasattr(ax, "get_figure") else ax.figure, ax


def _save(fig: Any, path: str | Path | None) -> None:
    """Save as PNG or SVG by the extension, atomically; a bad path is one InputError line."""
    if path is None:
        return
    from ..files.atomic import atomic_write

    check_plot_path(path)
    with atomic_write(str(path)) as f:
        fig.savefig(f, format=Path(path).suffix.lower()[1:], dpi=130, bbox_inches="tight")


# --- the plane --------------------------------------------------------------------------


def one_object(found: Sequence[Any]) -> Polygon | Polyhedron:
    """The object all the region sets are on, or one InputError line."""
    if not found:
        raise InputError("no regions to draw")
    obj = found[0].object
    if any(r.object is not obj for r in found):
        raise InputError("all grasps of one picture must be on the same object")
    return obj


def _polygon_axes(ax: Any, polygon: Polygon, label_edges: bool = True) -> None:
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath

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
    if polygon.units:  # what the coordinates measure, when the file says (an SVG's mm)
        ax.set_xlabel(axis_label("x", polygon.units), fontsize=8)
        ax.set_ylabel(axis_label("y", polygon.units), fontsize=8)


def _turn(v: NDArray, angle: float) -> NDArray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def corner_cone(polygon: Polygon, a: int, b: int, mu: float, reach: float
                ) -> tuple[NDArray, list[NDArray], NDArray | None]:
    """A soft finger's cone at the convex vertex where edge ``a`` ends and edge ``b`` starts,
    for drawing (here and in :mod:`forceclosure.pictures.view`): the vertex, the four rays of
    length ``reach`` bounding the friction cones of the two edges (each ``(2, 2)``, from the
    vertex), and the wedge they span into the object (their hull, the finger's cone) as a
    fan of points, or None when it is a half-plane or more."""
    edges = polygon.edges
    p = edges[a].end
    push = -(edges[a].normal + edges[b].normal)
    push /= np.linalg.norm(push)
    rays = [_turn(-edges[k].normal, s * np.arctan(mu)) for k in (a, b) for s in (-1, 1)]
    turns = [np.arctan2(push[0] * r[1] - push[1] * r[0], push @ r) for r in rays]
    lo, hi = min(turns), max(turns)
    fan = None
    if hi - lo < np.pi:
        fan = np.array([p, *(p + reach * _turn(push, t) for t in np.linspace(lo, hi, 16))])
    return p, [np.array([p, p + reach * r]) for r in rays], fan


def _vertex_grasp(ax: Any, g: Any, colour: Any, label: str, reach: float,
                  labels_at: dict) -> None:
    """A soft finger on a convex vertex: a dot, and its cone (the hull of the friction cones
    of the two edges meeting there, shaded); the other finger's segment or vertex alike.
    ``labels_at`` counts the labels already written at each vertex (they stack outward),
    collects where they are (``"places"``), and holds how many grasps have a dot at each
    vertex (``"dots"``, by incoming edge) and how many are drawn."""
    polygon = g.polygon
    edges = polygon.edges

    def corner(a: int, b: int) -> None:
        p, rays, fan = corner_cone(polygon, a, b, g.mu, reach)
        if fan is not None:  # the cone: a wedge from the vertex into the object
            ax.fill(*fan.T, color=colour, alpha=0.22, zorder=2, linewidth=0)
        for ray in rays:
            ax.plot(*ray.T, color=colour, linewidth=0.8, alpha=0.8, zorder=2)
        # grasps sharing a vertex: rings, the first (best) outermost, so every one shows
        behind = labels_at["dots"][a] - labels_at.setdefault(("dot", a), 0) - 1
        labels_at[("dot", a)] += 1
        ax.plot(*p, marker="o", markersize=9 + 6 * behind, color=colour,
                markeredgecolor="white", zorder=4 + 0.01 * labels_at[("dot", a)])

    corner(*g.corners[0])
    kind, k = g.other
    if kind == "edge":
        e = edges[k]
        a, b = e.point(g.segment[0]), e.point(g.segment[1])
        ax.plot(*np.array([a, b]).T, color=colour, linewidth=4.5, solid_capstyle="butt",
                zorder=3)
        for s in (-1, 1):
            ray = reach * _turn(-e.normal, s * np.arctan(g.mu))
            for q in (a, b):
                ax.plot(*np.array([q, q + ray]).T, color=colour, linewidth=0.8, alpha=0.7,
                        zorder=2)
        n = labels_at[("edge", k)] = labels_at.get(("edge", k), 0) + 1  # after the sets'
        other = (a + b) / 2 + e.normal * polygon.size * 0.05 * (n + 1)
        other_normal = e.normal
    else:
        corner(*g.corners[1])
        other = None
    for a, b in g.corners if other is None else g.corners[:1]:
        k = labels_at[a] = labels_at.get(a, 0) + 1
        where = edges[a].end + polygon.size * (0.01 + 0.06 * k) * _outward(edges, a, b)
        text = ax.text(*where, label, color=colour, fontsize=LABEL_SIZE, fontweight="bold",
                       ha="center", va="center", zorder=5)
        labels_at.setdefault("places", []).append(where)
        labels_at.setdefault("texts", []).append((text, _outward(edges, a, b)))
    if other is not None:
        text = ax.text(*other, label, color=colour, fontsize=LABEL_SIZE, fontweight="bold",
                       ha="center", va="center", zorder=5)
        labels_at.setdefault("places", []).append(other)
        labels_at.setdefault("texts", []).append((text, other_normal))


#: The grasps' labels' font size (points).
LABEL_SIZE = 10.0


def place_labels(ax: Any, labels: Sequence[tuple[Any, NDArray]], gap: float = 1.0) -> None:
    """Move labels so that no two overprint: each from where it was written, outward along
    its direction in steps of half its font size, at each step also tried sideways (one
    and two font sizes either way), until its box clears every label placed before it.

    The offsets are in points from each label's anchor (``offset_copy`` of the data
    transform), so they hold when the picture is saved at another size; place the labels
    after the axes' limits are final (the anchors' places on the screen depend on them).

    Parameters
    ----------
    ax : matplotlib Axes
        2-D axes with the labels in data coordinates.
    labels : sequence of (Text, (2,) array)
        The labels, first placed first (keep the best grasp's nearest its region), each
        with the direction it may move in (the outward normal of its edge or vertex).
    gap : float
        Least room between two labels' boxes, in pixels.
    """
    from matplotlib.transforms import offset_copy

    if not labels:
        return
    fig = ax.get_figure(root=True) if hasattr(ax, "get_figure") else ax.figure
    fig.draw_without_rendering()  # the aspect applied: the anchors where they will be drawn
    placed: list[Any] = []

    def clear(box) -> bool:
        return all(box.x1 + gap <= b.x0 or b.x1 + gap <= box.x0 or box.y1 + gap <= b.y0
                   or b.y1 + gap <= box.y0 for b in placed)

    for text, direction in labels:
        n = np.asarray(direction, dtype=float)
        n = n / (np.linalg.norm(n) or 1.0)
        t = np.array([-n[1], n[0]])
        size = float(text.get_fontsize())
        base = text.get_transform()
        box = text.get_window_extent()
        for k in range(400):  # far enough out, every box clears the finitely many placed
            for j in (0, 1, -1, 2, -2):
                dx, dy = 0.5 * size * k * n + size * j * t
                text.set_transform(offset_copy(base, fig=fig, x=dx, y=dy, units="points"))
                box = text.get_window_extent()
                if clear(box):
                    break
            else:
                continue
            break
        placed.append(box)


def _outward(edges: Any, a: int, b: int) -> NDArray:
    n = edges[a].normal + edges[b].normal
    return n / np.linalg.norm(n)


def plot_object(obj: Polygon | Polyhedron, path: str | Path | None = None,
                title: str | None = None, *, ax: Any = None, label: bool = True,
                view: tuple[float, float] | None = None, up: str = "z"):
    """Draw an object; save it to ``path`` (``.png`` or ``.svg``) when given.

    Parameters
    ----------
    obj : Polygon or Polyhedron
    path : str or Path, optional
    title : str, optional
    ax : matplotlib Axes, optional
        Draw into these axes (3-D axes, ``projection="3d"``, for a
        polyhedron) instead of a new figure.
    label : bool
        Number the edges (polygon) or the planar faces that face the viewer
        (polyhedron of at most 60 faces).
    view : (elevation, azimuth) in degrees, optional
        The camera of a polyhedron (default ``(24, -58)``).
    up : {"x", "y", "z"}
        The axis drawn upright ("y" for the y-up convention of OBJ and glTF).

    Returns
    -------
    matplotlib.figure.Figure
        The new figure, or the figure of ``ax``.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> fig = plot_object(bundled("frame"))
    >>> len(fig.axes)
    1
    """
    if isinstance(obj, Polygon):
        fig, ax = _axes(ax, False, (5.5, 5.5), "plot_object")
        _polygon_axes(ax, obj, label_edges=label)
    else:
        fig, ax = _axes(ax, True, (6, 6), "plot_object")
        _polyhedron_axes(ax, obj, label, view or (ELEVATION, AZIMUTHS[0]), up)
    summary = obj.summary()
    counts = (f"{summary['edges']} edges" if obj.dim == 2
              else f"{summary['faces']} planar faces from {summary['triangles']} triangles")
    ax.set_title(title or f"{obj.name}: {counts}", fontsize=10)
    _save(fig, path)
    return fig


def plot_regions(regions: Sequence[Any], path: str | Path | None = None,
                 title: str | None = None, *, ax: Any = None):
    """Independent regions on a polygon, in the spirit of the paper's Fig. 7 and 10.

    The polygon, each grasp's segments in bold (one colour per grasp,
    numbered by rank), and at the segments' ends the friction cones (two
    fingers with friction) or the pushing directions (frictionless fingers).
    Grasps with a soft finger on a convex vertex
    (:class:`~forceclosure.synthesis.planar.vertex_grasps.VertexGrasp`, told apart by
    :func:`on_vertex`) may be given too, anywhere in the list: the vertex as
    a dot with its wider cone shaded, labelled ``v1``, ``v2``, ... by their
    own rank. Every grasp's colour is that of its place in the list (tab10).

    Parameters
    ----------
    regions : sequence of RegionSet
        Grasps on one polygon (any planar construction's, and vertex grasps),
        best first.
    path : str or Path, optional
        Save the picture there (``.png`` or ``.svg``).
    title : str, optional
    ax : matplotlib Axes, optional
        Draw into these (2-D) axes instead of a new figure.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import synthesize
    >>> square = bundled("square")
    >>> fig = plot_regions([*synthesize(square, 2, "hard", 0.3, top=2).found,
    ...                     *synthesize(square, 2, "soft", 0.3, top=1,
    ...                                 construction="vertices").found])
    >>> len(fig.axes[0].lines) > 0
    True
    """
    polygon = one_object(regions)
    if not isinstance(polygon, Polygon):
        raise InputError("plot_regions draws grasps on a polygon; on a polyhedron, "
                         "plot_spatial_regions (or plot_found)")
    fig, ax = _axes(ax, False, (6, 6), "plot_regions")
    _polygon_axes(ax, polygon, label_edges=False)
    palette = _palette()
    reach = polygon.size * 0.18
    colours = {id(r): palette[place % 10] for place, r in enumerate(regions)}
    sets = [r for r in regions if not on_vertex(r)]
    corners = [r for r in regions if on_vertex(r)]
    labels: list[tuple[Any, NDArray]] = []  # each grasp's numbers, and where they may move
    for rank, r in enumerate(sets):
        colour = colours[id(r)]
        mus = r.friction()
        for (a, b), e in zip(r.points, (polygon.edges[k] for k in r.edges), strict=True):
            ax.plot(*np.array([a, b]).T, color=colour, linewidth=4.5, solid_capstyle="butt",
                    zorder=3)
            mid = (a + b) / 2 + e.normal * polygon.size * 0.05
            labels.append((ax.text(*mid, str(rank + 1), color=colour, fontsize=LABEL_SIZE,
                                   fontweight="bold", ha="center", va="center"), e.normal))
        for ray in r.cone_rays(reach):  # the cones of forces the fingers can push with
            ax.plot(*ray.T, color=colour, linewidth=0.8, alpha=0.7, zorder=2)
        apex = getattr(r, "apex", None)  # Nguyen's two-sided cone (Fig. 7)
        if apex is not None:
            from ..synthesis import counter_overlapping_sector

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
    labels_at: dict = {"dots": Counter(a for g in corners for a, _ in dot_corners(g))}
    for rank, g in enumerate(corners):
        _vertex_grasp(ax, g, colours[id(g)], f"v{rank + 1}", reach, labels_at)
    if "places" in labels_at:  # room for the labels
        places, pad = np.array(labels_at["places"]), polygon.size * 0.05
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        ax.set_xlim(min(x0, places[:, 0].min() - pad), max(x1, places[:, 0].max() + pad))
        ax.set_ylim(min(y0, places[:, 1].min() - pad), max(y1, places[:, 1].max() + pad))
    place_labels(ax, [*labels, *labels_at.get("texts", [])])  # none overprints another
    words = planar_caption(sets, corners)
    ax.set_title(title or f"{polygon.name}: " + ";\n".join(words), fontsize=10)
    _save(fig, path)
    return fig


# --- space ------------------------------------------------------------------------------


def camera_eye(view: tuple[float, float], up: str) -> NDArray[np.float64]:
    """The unit vector from the object towards the camera (matplotlib's convention)."""
    if up not in ("x", "y", "z"):
        raise InputError(f"up must be 'x', 'y' or 'z', got {up!r}")
    e, a = np.radians(view)
    toward = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])
    return np.roll(toward, "xyz".index(up) - 2)


def camera_light(eye: NDArray, up: str) -> NDArray[np.float64]:
    """A light from above the camera and to its left."""
    vertical = np.eye(3)["xyz".index(up)]
    right = np.cross(-eye, vertical)
    right /= np.linalg.norm(right)
    light = eye + 0.7 * vertical - 0.4 * right
    return light / np.linalg.norm(light)


def _normals(poly: Polyhedron) -> NDArray[np.float64]:
    V, T = poly.vertices, poly.triangles
    n = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    return n / np.linalg.norm(n, axis=1, keepdims=True)


def _frame(ax: Any, points: NDArray, view: tuple[float, float], up: str) -> None:
    """Equal scales on the three axes around ``points``; the camera."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    mid, half = (lo + hi) / 2, 0.52 * float((hi - lo).max())
    for setter, c in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, strict=True):
        setter(c - half, c + half)
    ax.set_box_aspect((1, 1, 1))
    ax.view_init(elev=view[0], azim=view[1], vertical_axis=up)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")


def _refined(triangles: NDArray, values: NDArray, longest: float
             ) -> tuple[NDArray, NDArray]:
    """Triangles longer than ``longest`` split in four (three rounds at most), each piece
    keeping its triangle's value (colour): matplotlib paints triangles back to front by
    their centres, which misorders long thin ones."""
    for _ in range(3):
        edges = np.linalg.norm(triangles - np.roll(triangles, -1, axis=1), axis=2)
        big = edges.max(axis=1) > longest
        if not big.any():
            break
        a, b, c = triangles[big, 0], triangles[big, 1], triangles[big, 2]
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        pieces = [np.stack(t, axis=1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c),
                                                (ab, bc, ca))]
        triangles = np.concatenate([triangles[~big], *pieces])
        values = np.concatenate([values[~big], *[values[big]] * 4])
    return triangles, values


def _unseen(poly: Polyhedron, points: NDArray, eye: NDArray) -> NDArray[np.bool_]:
    """Which points the object hides from a camera far along ``eye`` (a ray from each
    point towards the camera meets a triangle: Moller-Trumbore)."""
    tri = poly.vertices[poly.triangles]
    o, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    h = np.cross(eye, e2)
    det = np.einsum("ij,ij->i", e1, h)
    ok = np.abs(det) > 1e-14 * poly.size ** 2
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    start = points + 1e-6 * poly.size * eye
    hidden = np.zeros(len(points), bool)
    for lo in range(0, len(points), 64):
        s = start[lo:lo + 64, None, :] - o[None]
        u = np.einsum("kmj,mj->km", s, h) * inv
        q = np.cross(s, e1[None])
        v = (q @ eye) * inv
        t = np.einsum("kmj,mj->km", q, e2) * inv
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9 * poly.size)
        hidden[lo:lo + 64] = hit.any(axis=1)
    return hidden


def _inside(polygon: Polygon) -> NDArray[np.float64]:
    """Where to write a face's number: its centroid, or a point inside when the centroid
    is not (a face with a hole, an L)."""
    shape = polygon.to_shapely()
    point = shape.centroid if shape.contains(shape.centroid) else shape.representative_point()
    return np.array(point.coords[0])


def _polyhedron_axes(ax: Any, poly: Polyhedron, label_faces: bool,
                     view: tuple[float, float], up: str) -> None:
    from matplotlib import colormaps
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    eye = camera_eye(view, up)
    cmap = colormaps["tab20"]
    merged = np.array([len(f.triangles) > 1 for f in poly.faces])
    palette = np.array([cmap(i % 20) if merged[i] else (0.72, 0.72, 0.72, 1.0)
                        for i in range(len(poly.faces))])
    colours = palette[poly.face_of_triangle]  # one-triangle faces (curved parts) in grey
    normals = _normals(poly)
    shade = 0.5 + 0.5 * np.clip(normals @ camera_light(eye, up), 0, 1)
    colours[:, :3] *= shade[:, None]
    # explicit layers: the object, then the outlines and numbers of what is in sight
    ax.computed_zorder = False
    V, T = poly.vertices, poly.triangles
    # a closed surface hides its far side: leave it out (nothing of it to misorder)
    near = normals @ eye > 0 if poly.watertight else np.ones(len(T), bool)
    pieces, colours = _refined(V[T[near]], colours[near], poly.size / 8)
    ax.add_collection3d(Poly3DCollection(pieces, facecolors=colours, edgecolors=colours,
                                         linewidths=0.3, zorder=1))  # edges: no seams
    front = [f for f in poly.faces if f.normal @ eye > 0.05]
    loops = [f.boundary for f in front if len(f.triangles) > 1]
    if loops:  # the outlines of the merged faces, cut where the object hides them
        steps = np.linspace(0, 1, 9)[:-1, None]
        samples = [np.concatenate([a + steps * (b - a) for a, b in
                                   zip(loop, np.roll(loop, -1, axis=0), strict=True)])
                   for loop in loops]
        hidden = _unseen(poly, np.concatenate(samples), eye)
        segments, at = [], 0
        for pts in samples:
            shown = ~hidden[at:at + len(pts)]
            at += len(pts)
            nxt = np.roll(np.arange(len(pts)), -1)
            segments += [pts[[i, int(j)]] for i, j in enumerate(nxt) if shown[i] and shown[j]]
        ax.add_collection3d(Line3DCollection(segments, colors="#1b1b1b", linewidths=0.6,
                                             zorder=2))
    if label_faces and len(poly.faces) <= 60 and front:
        centres = np.array([f.to_world(_inside(f.polygon)) for f in front])
        for f, c, hidden in zip(front, centres, _unseen(poly, centres, eye), strict=True):
            if not hidden:
                ax.text(*(c + f.normal * poly.size * 0.02), str(f.index), fontsize=7,
                        ha="center", va="center", zorder=3)
    _frame(ax, V, view, up)


def _choose_view(normals: list[NDArray], centres: list[NDArray], size: float,
                 up: str) -> tuple[float, float]:
    """The default elevation and the azimuth (of :data:`AZIMUTHS`) that shows the most
    regions clearly from the front, then keeps them furthest apart on the picture (two
    opposed fingers are not drawn over each other), then the first (an oblique view)."""
    def score(k: int) -> tuple:
        eye = camera_eye((ELEVATION, AZIMUTHS[k]), up)
        facing = np.array([n @ eye for n in normals])
        flat = [c - (c @ eye) * eye for c in centres]
        apart = min(np.linalg.norm(a - b) for i, a in enumerate(flat) for b in flat[i + 1:]) \
            if len(flat) > 1 else 0.0
        return int(np.sum(facing > 0.35)), round(apart / size, 1), -k

    return ELEVATION, AZIMUTHS[max(range(len(AZIMUTHS)), key=score)]


def plot_spatial_regions(regions: Any, path: str | Path | None = None,
                         title: str | None = None, cones: bool = True, *, ax: Any = None,
                         view: tuple[float, float] | None = None, up: str = "z"):
    """Independent regions on a polyhedron, as in the paper's Fig. 1 and 8.

    The object lit and translucent; each finger's region in its own colour
    (tab10, as the HTML view), drawn over the object so that none is hidden,
    and labelled ``finger 1``, ``finger 2``, ...; a region on the far side of
    the object is seen through it (dashed outline, labelled "behind"). With
    ``cones``, the cone of forces each finger can push with (the friction
    cone, or a frictionless finger's line) stands outside the object on the
    region's largest patch, as in :func:`forceclosure.pictures.view.spatial_figure`.
    No face numbers are drawn.

    Parameters
    ----------
    regions : SpatialRegions
        One region set (e.g. the best that
        :func:`~forceclosure.synthesis.best.synthesize` finds on a polyhedron).
    path : str or Path, optional
        Save the picture there (``.png`` or ``.svg``).
    title : str, optional
    cones : bool
    ax : matplotlib 3-D Axes, optional
        Draw into these axes (``projection="3d"``) instead of a new figure;
        their ``computed_zorder`` is turned off (the layers are drawn in order).
    view : (elevation, azimuth) in degrees, optional
        The camera; by default elevation 24 and the azimuth that shows most
        regions from the front.
    up : {"x", "y", "z"}
        The axis drawn upright ("y" for the y-up convention of OBJ and glTF).

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import soft_pair_regions
    >>> fig = plot_spatial_regions(soft_pair_regions(bundled("cube"), 0, 1, 0.5))
    >>> [t.get_text() for t in fig.axes[0].texts]
    ['finger 1', 'finger 2 (behind)']
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from .grasp_scene import cone_points

    poly = regions.polyhedron
    fig, ax = _axes(ax, True, (6.5, 6.5), "plot_spatial_regions")
    faces = poly.faces
    lift, height = poly.size * 2e-3, poly.size * 0.18

    def facing(region) -> NDArray:  # the area-weighted normal of a region
        n = sum(p.area * faces[p.face].normal for p in region)
        return n / max(np.linalg.norm(n), 1e-300)

    anchors = [max(region, key=lambda p: p.area) for region in regions.regions]
    view = view or _choose_view([facing(r) for r in regions.regions],
                                [p.points.mean(axis=0) for p in anchors], poly.size, up)
    eye = camera_eye(view, up)
    ax.computed_zorder = False  # layers: far regions, object, near regions, cones, labels
    V, T = poly.vertices, poly.triangles
    grey = 0.55 + 0.45 * np.clip(_normals(poly) @ camera_light(eye, up), 0, 1)
    pieces, rgba = _refined(V[T], np.column_stack([grey[:, None] * _GREY,
                                                   np.full(len(T), 0.32)]), poly.size / 8)
    ax.add_collection3d(Poly3DCollection(pieces, facecolors=rgba, edgecolors="none",
                                         linewidths=0, zorder=2))
    merged = [f for f in faces if len(f.triangles) > 1]
    if merged and len(merged) >= len(faces) / 2:  # not on curved meshes: clutter
        ax.add_collection3d(Poly3DCollection([f.boundary for f in merged], facecolors="none",
                                             edgecolors="#30343b", linewidths=0.5,
                                             alpha=0.55, zorder=2))
    colours = _palette()
    drawn = [V]
    for k, region in enumerate(regions.regions):
        colour = colours[k % 10]
        near = facing(region) @ eye > 0
        layer = 3 if near else 1
        patches = [p.points + lift * faces[p.face].normal for p in region]
        ax.add_collection3d(Poly3DCollection(
            patches, facecolors=[(*colour, 0.95 if near else 0.6)], edgecolors=[colour],
            linewidths=1.4, linestyles="solid" if near else "dashed", zorder=layer))
        largest = anchors[k]
        n = faces[largest.face].normal
        apex = largest.points.mean(axis=0) + lift * n
        tip = apex + height * n
        if cones and regions.mu > 0:
            ring = cone_points(apex, n, regions.mu, height, sides=24)[1:]
            rim = np.vstack([ring, ring[:1]])  # closed
            ax.add_collection3d(Poly3DCollection(
                [[apex, rim[i], rim[i + 1]] for i in range(24)], facecolors=[(*colour, 0.2)],
                edgecolors="none", zorder=layer + 1))
            ax.plot(*rim.T, color=colour, linewidth=1.0, alpha=0.9, zorder=layer + 1)
            for i in range(0, 24, 6):
                ax.plot(*np.array([apex, rim[i]]).T, color=colour, linewidth=0.8, alpha=0.9,
                        zorder=layer + 1)
            drawn.append(rim)
        elif cones:
            ax.plot(*np.array([apex, tip]).T, color=colour, linewidth=2.0, zorder=layer + 1)
        where = apex + 1.3 * height * n
        drawn.append(where[None])
        ax.text(*where, f"finger {k + 1}" + ("" if near else " (behind)"), color=colour,
                fontsize=9, fontweight="bold", ha="center", va="center", zorder=6,
                bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "alpha": 0.75,
                      "edgecolor": "none"})
    _frame(ax, np.concatenate(drawn), view, up)
    friction = f"{regions.model} fingers, mu {regions.mu:g}" if regions.mu > 0 else \
        "frictionless fingers"
    ax.set_title(title or f"{poly.name}: independent regions for {len(regions.regions)} "
                 f"{friction}\n{regions.construction}; smallest region "
                 f"{regions.min_area:.3g}", fontsize=9)
    _save(fig, path)
    return fig


# --- any region sets --------------------------------------------------------------------


def plot_found(found: Sequence[Any], path: str | Path | None = None, title: str | None = None,
               *, ax: Any = None, up: str = "z"):
    """The picture of the region sets a synthesis found, whatever construction made them.

    Chooses by the data, the dimension of the object the regions are on
    (``found[0].object.dim``): on a polygon every grasp together, vertex
    grasps among them wherever they are in the list (:func:`plot_regions`);
    on a polyhedron the best, the first, lit and with every finger's region
    labelled (:func:`plot_spatial_regions`; the HTML view of
    :func:`forceclosure.pictures.view.write_html` has a menu for the others).

    Parameters
    ----------
    found : sequence of RegionSet
        Region sets on one object, best first (``synthesize(...).found``,
        with any found by ``construction="vertices"`` added).
    path : str or Path, optional
        Save the picture there (``.png`` or ``.svg``).
    title : str, optional
    ax : matplotlib Axes, optional
        2-D axes for a polygon, 3-D axes for a polyhedron.
    up : {"x", "y", "z"}
        The axis drawn upright on a polyhedron (``upright_axis(file)`` gives the file
        format's); a polygon lies in its plane.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis.best import synthesize
    >>> fig = plot_found(synthesize(bundled("cube"), 2, "soft", 0.5, top=2).found)
    >>> [t.get_text() for t in fig.axes[0].texts]
    ['finger 1', 'finger 2 (behind)']
    """
    obj = one_object(found)
    if obj.dim == 2:
        return plot_regions(found, path, title, ax=ax)
    return plot_spatial_regions(found[0], path, title, ax=ax, up=up)
