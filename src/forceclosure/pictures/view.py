"""Interactive views: independent regions in a web page that works offline.

:func:`write_html` saves one self-contained HTML file (plotly.js embedded,
compressed, :mod:`forceclosure.pictures.page`; nothing is fetched; or, with
``shared_js``, a small page loading ``plotly.min.js`` written beside it) that a
browser can turn, zoom and hover: the object, each finger's region of contact in its
own colour, and at every region the cone of forces its finger can push with (the
friction cone, drawn on the finger's side of the surface; a frictionless finger's single
direction is a line).
On polyhedra several grasps share one page with a menu to switch between
them; on polygons they are drawn together, as in the PNG of
:func:`forceclosure.pictures.plot.plot_regions` (grasps with a soft finger on a convex
vertex among them), and each can be hidden from the legend. Like
:func:`forceclosure.pictures.plot.plot_found`, :func:`write_html` reads any region
sets and chooses by the object's dimension.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, cast

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..extras import require
from ..objects import Polygon, Polyhedron
from ..objects.polygon import axis_label
from ..synthesis.planar.vertex_grasps import VertexGrasp
from ..synthesis.regions import Regions, RegionSet
from ..synthesis.spatial.patches import SpatialRegions
from .grasp_scene import CONE_SIDES, cone_points
from .plot import corner_cone, dot_corners, on_vertex, one_object, planar_caption

if TYPE_CHECKING:
    import plotly.graph_objects as go
else:  # imported with this module, which the HTML view alone imports
    go = require("plotly.graph_objects", "the interactive HTML view", "view")

__all__ = ["COLOURS", "CONE_SIDES", "check_html_path", "grasps_figure", "planar_figure",
           "spatial_figure", "write_grasps_html", "write_html"]

#: matplotlib's tab10, so the page and the PNG colour the fingers alike.
COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
           "#7f7f7f", "#bcbd22", "#17becf")


def _lines(paths: Sequence[NDArray[np.float64]], closed: bool) -> NDArray[np.float64]:
    """Polylines joined into one array with NaN rows between them (one plotly trace)."""
    pieces = []
    for p in paths:
        pieces += [p, p[:1]] if closed else [p]
        pieces.append(np.full((1, p.shape[1]), np.nan))
    return np.concatenate(pieces) if pieces else np.empty((0, 3))


def _object_traces(poly: Polyhedron) -> list:
    """The object in grey; on polyhedra also the outlines of the planar faces, and their
    numbers on hover."""
    V, T = poly.vertices, poly.triangles
    traces = [go.Mesh3d(x=V[:, 0], y=V[:, 1], z=V[:, 2], i=T[:, 0], j=T[:, 1], k=T[:, 2],
                        color="#b8bcc4", opacity=0.55, flatshading=True, hoverinfo="skip",
                        lighting={"ambient": 0.55, "diffuse": 0.7, "specular": 0.05},
                        name=poly.name, showlegend=False)]
    merged = [f for f in poly.faces if len(f.triangles) > 1]
    if merged and len(merged) >= len(poly.faces) / 2:  # not on curved meshes: clutter
        edge = _lines([f.boundary for f in merged], closed=True)
        traces.append(go.Scatter3d(x=edge[:, 0], y=edge[:, 1], z=edge[:, 2], mode="lines",
                                   line={"color": "#30343b", "width": 2}, hoverinfo="skip",
                                   showlegend=False))
        centres = np.array([f.to_world(np.asarray(f.polygon.centroid)) for f in merged])
        traces.append(go.Scatter3d(x=centres[:, 0], y=centres[:, 1], z=centres[:, 2],
                                   mode="markers", marker={"size": 2, "color": "#30343b",
                                                           "opacity": 0.4},
                                   text=[f"face {f.index}, area {f.area:.4g}" for f in merged],
                                   hoverinfo="text", showlegend=False))
    return traces


def _cone(apex: NDArray, axis: NDArray, mu: float, height: float) -> go.Mesh3d:
    """The friction cone at ``apex`` around ``axis`` as a surface of triangles."""
    pts = cone_points(apex, axis, mu, height)
    ring = np.arange(1, CONE_SIDES + 1)
    return go.Mesh3d(x=pts[:, 0], y=pts[:, 1], z=pts[:, 2], i=np.zeros(CONE_SIDES, int),
                     j=ring, k=np.roll(ring, -1), opacity=0.3, hoverinfo="skip")


def _grasp_traces(regions: SpatialRegions) -> list:
    """Each finger's patches (lifted off the surface so they are not hidden) and its cone."""
    poly = regions.polyhedron
    lift, height = poly.size * 2e-3, poly.size * 0.18
    traces = []
    for k, region in enumerate(regions.regions):
        colour = COLOURS[k % len(COLOURS)]
        pts, tri, offset = [], [], 0
        for patch in region:
            m = len(patch.points)
            pts.append(patch.points + lift * poly.faces[patch.face].normal)
            tri += [(offset, offset + a, offset + a + 1) for a in range(1, m - 1)]
            offset += m
        P, F = np.vstack(pts), np.array(tri)
        faces = ", ".join(str(f) for f in sorted({p.face for p in region}))
        label = (f"finger {k + 1}: area {regions.areas[k]:.4g} on face"
                 f"{'s' if len(region) > 1 else ''} {faces}")
        traces.append(go.Mesh3d(x=P[:, 0], y=P[:, 1], z=P[:, 2], i=F[:, 0], j=F[:, 1],
                                k=F[:, 2], color=colour, opacity=1.0, flatshading=True,
                                name=f"finger {k + 1}", hovertext=label, hoverinfo="text",
                                showlegend=False))
        outline = _lines([p.points + lift * poly.faces[p.face].normal for p in region], True)
        traces.append(go.Scatter3d(x=outline[:, 0], y=outline[:, 1], z=outline[:, 2],
                                   mode="lines", line={"color": colour, "width": 4},
                                   hoverinfo="skip", showlegend=False))
        largest = max(region, key=lambda p: p.area)
        centre = largest.points.mean(axis=0)
        n = poly.faces[largest.face].normal
        if regions.mu > 0:
            cone = _cone(centre, n, regions.mu, height)
            cone.update(color=colour)
            traces.append(cone)
        else:
            ray = np.array([centre, centre + height * n])
            traces.append(go.Scatter3d(x=ray[:, 0], y=ray[:, 1], z=ray[:, 2], mode="lines",
                                       line={"color": colour, "width": 5}, hoverinfo="skip",
                                       showlegend=False))
    return traces


def _camera(up: str) -> dict:
    """The page's camera: from the front, right and above, with ``up`` upright (as the
    PNG's :func:`forceclosure.pictures.plot.camera_eye` turns its camera)."""
    if up not in ("x", "y", "z"):
        raise InputError(f"up must be 'x', 'y' or 'z', got {up!r}")
    turn = "xyz".index(up) - 2
    eye = np.roll([1.5, -1.6, 1.0], turn)
    return {"eye": dict(zip("xyz", eye.tolist(), strict=True)),
            "up": dict(zip("xyz", np.roll([0.0, 0.0, 1.0], turn).tolist(), strict=True))}


def spatial_figure(found: Sequence[SpatialRegions], title: str | None = None, *,
                   up: str = "z") -> go.Figure:
    """The interactive figure of region sets on one polyhedron (§5.2–§5.5, or mesh regions).

    Parameters
    ----------
    found : sequence of SpatialRegions
        Region sets on the same polyhedron, best first (``synthesize(...).found``).
        The first is shown; a menu switches to the others.
    title : str, optional
    up : {"x", "y", "z"}
        The axis the camera holds upright (:func:`forceclosure.pictures.plot.upright_axis`).

    Returns
    -------
    plotly.graph_objects.Figure

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import soft_pair_regions
    >>> fig = spatial_figure([soft_pair_regions(bundled("cube"), 0, 1, 0.5)])
    >>> sum(t.type == "mesh3d" for t in fig.data)  # object, two regions, two cones
    5
    """
    poly = one_object(found)
    if not isinstance(poly, Polyhedron):
        raise InputError("spatial_figure draws grasps on a polyhedron; on a polygon, "
                         "planar_figure (or write_html)")
    fig = go.Figure(_object_traces(poly))
    always = len(fig.data)
    groups = []
    for rank, regions in enumerate(found):
        traces = _grasp_traces(regions)
        for t in traces:
            t.visible = rank == 0
        groups.append(range(len(fig.data), len(fig.data) + len(traces)))
        fig.add_traces(traces)
    first = found[0]
    friction = (f"{first.model} fingers, mu {first.mu:g}" if first.mu > 0
                else "frictionless fingers")
    heading = title or (f"{poly.name}: independent regions for {len(first.regions)} "
                        f"{friction}")

    def caption(r: SpatialRegions, rank: int) -> str:
        cert = r.certify()
        return (f"{heading}<br><sub>grasp {rank + 1} of {len(found)}: {r.construction}; "
                f"smallest region {r.min_area:.4g}; certified {cert.holds} "
                f"({cert.method})</sub>")

    buttons = []
    for rank, r in enumerate(found):
        visible = [True] * always + [False] * (len(fig.data) - always)
        for i in groups[rank]:
            visible[i] = True
        buttons.append({"label": f"grasp {rank + 1}: smallest region {r.min_area:.3g}",
                        "method": "update",
                        "args": [{"visible": visible}, {"title.text": caption(r, rank)}]})
    fig.update_layout(
        title={"text": caption(first, 0), "x": 0.02, "font": {"size": 15}},
        scene={"aspectmode": "data", "xaxis_title": "x", "yaxis_title": "y",
               "zaxis_title": "z", "camera": _camera(up)},
        margin={"l": 0, "r": 0, "t": 60, "b": 0}, paper_bgcolor="white",
        updatemenus=[{"buttons": buttons, "x": 0.02, "y": 0.93, "xanchor": "left",
                      "yanchor": "top"}] if len(found) > 1 else [])
    return fig


def _vertex_traces(g, colour: str, group: str, reach: float, sizes: list[int]) -> list:
    """A grasp with a soft finger on a convex vertex: the vertex (and the other one, for two
    vertices) as dots of ``sizes``, each with its cone shaded (the hull of its two edges'
    friction cones, :func:`forceclosure.pictures.plot.corner_cone`); the other finger's segment in
    bold."""
    polygon, traces = g.object, []
    kind, k = g.other
    ends = dot_corners(g)
    dots = np.array([polygon.edges[a].end for a, _ in ends])
    where = [f"vertex {g.vertex}" if i == 0 else f"vertex {k}" for i in range(len(dots))]
    text = f"{group}: " + "; ".join(g.describe())
    traces.append(go.Scatter(x=dots[:, 0], y=dots[:, 1], mode="markers", name=group,
                             legendgroup=group, hovertext=[f"{text} ({w})" for w in where],
                             hoverinfo="text", marker={"color": colour, "size": sizes,
                                                       "line": {"color": "white",
                                                                "width": 1.5}}))
    rays = []
    for a, b in ends:
        _, edge_rays, fan = corner_cone(polygon, a, b, g.mu, reach)
        rays += edge_rays
        if fan is not None:
            traces.append(go.Scatter(x=fan[:, 0], y=fan[:, 1], mode="lines", fill="toself",
                                     fillcolor=colour, opacity=0.25, legendgroup=group,
                                     line={"width": 0}, hoverinfo="skip", showlegend=False))
    if kind == "edge":
        e = polygon.edges[k]
        seg = np.array([e.point(t) for t in g.segment])
        traces.append(go.Scatter(x=seg[:, 0], y=seg[:, 1], mode="lines", legendgroup=group,
                                 line={"color": colour, "width": 7}, hovertext=text,
                                 hoverinfo="text", showlegend=False))
        for s in (-1, 1):
            c, d = np.cos(s * np.arctan(g.mu)), np.sin(s * np.arctan(g.mu))
            push = -e.normal
            ray = reach * np.array([c * push[0] - d * push[1], d * push[0] + c * push[1]])
            rays += [np.array([q, q + ray]) for q in seg]
    cone = _lines(rays, closed=False)
    traces.append(go.Scatter(x=cone[:, 0], y=cone[:, 1], mode="lines", legendgroup=group,
                             line={"color": colour, "width": 1}, opacity=0.7,
                             hoverinfo="skip", showlegend=False))
    return traces


def planar_figure(found: Sequence[RegionSet], title: str | None = None) -> go.Figure:
    """The interactive figure of region sets on one polygon (§5.1, §5.4).

    Every grasp's segments in its own colour, with the cones of forces its
    fingers can push with at the segments' ends; grasps with a soft finger on
    a convex vertex (:func:`forceclosure.pictures.plot.on_vertex`), anywhere in the
    list, as the PNG draws them: the vertex a dot with its cone shaded,
    named ``v1``, ``v2``, ... Every grasp's colour is that of its place in
    the list; clicking a grasp in the legend hides it.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import synthesize
    >>> square = bundled("square")
    >>> fig = planar_figure([*synthesize(square, 2, "hard", 0.3, top=2).found,
    ...                      *synthesize(square, 2, "soft", 0.3, top=1,
    ...                                  construction="vertices").found])
    >>> sorted({t.legendgroup for t in fig.data if t.legendgroup})
    ['grasp 1', 'grasp 2', 'v1']
    """
    polygon = one_object(found)
    if not isinstance(polygon, Polygon):
        raise InputError("planar_figure draws grasps on a polygon; on a polyhedron, "
                         "spatial_figure (or write_html)")
    outline = _lines(list(polygon.rings), closed=True)
    fig = go.Figure(go.Scatter(x=outline[:, 0], y=outline[:, 1], mode="lines", fill="toself",
                               fillcolor="#dfe7f2", line={"color": "#1f3b63", "width": 2},
                               hoverinfo="skip", showlegend=False))
    reach = polygon.size * 0.18
    # fingers on segments of edges; a soft finger on a vertex
    sets = [cast(Regions, r) for r in found if not on_vertex(r)]
    corners = [cast(VertexGrasp, r) for r in found if on_vertex(r)]
    colours = {id(r): COLOURS[place % len(COLOURS)] for place, r in enumerate(found)}
    for rank, r in enumerate(sets):
        colour, group = colours[id(r)], f"grasp {rank + 1}"
        segs = _lines(list(r.points), closed=False)
        cone = _lines(list(r.cone_rays(reach)), closed=False)
        fig.add_trace(go.Scatter(x=segs[:, 0], y=segs[:, 1], mode="lines", name=group,
                                 legendgroup=group, line={"color": colour, "width": 7},
                                 hovertext=f"{group}: edges {list(r.edges)}, shortest "
                                           f"segment {r.min_length:.4g}", hoverinfo="text"))
        fig.add_trace(go.Scatter(x=cone[:, 0], y=cone[:, 1], mode="lines", legendgroup=group,
                                 line={"color": colour, "width": 1}, opacity=0.7,
                                 hoverinfo="skip", showlegend=False))
    # grasps sharing a vertex: rings, the first (best) outermost, so every one shows
    total = Counter(a for g in corners for a, _ in dot_corners(g))
    seen: Counter = Counter()
    for rank, g in enumerate(corners):
        sizes = []
        for a, _ in dot_corners(g):
            seen[a] += 1
            sizes.append(13 + 8 * (total[a] - seen[a]))
        fig.add_traces(_vertex_traces(g, colours[id(g)], f"v{rank + 1}", reach, sizes))
    words = planar_caption(sets, corners)
    fig.update_layout(
        title={"text": title or f"{polygon.name}: " + ";<br>".join(words), "x": 0.02},
        xaxis={"scaleanchor": "y", "scaleratio": 1,
               "title": axis_label("x", polygon.units)},
        yaxis={"title": axis_label("y", polygon.units)},
        plot_bgcolor="white", paper_bgcolor="white", margin={"l": 40, "r": 20, "t": 80,
                                                             "b": 40})
    return fig


def write_html(found: Sequence[RegionSet], path: str | Path, title: str | None = None, *,
               up: str = "z", shared_js: bool = False) -> Path:
    """Save region sets as one offline HTML page, self-contained unless ``shared_js``.

    Chooses by the data, the dimension of the object the regions are on
    (``found[0].object.dim``), as :func:`forceclosure.pictures.plot.plot_found`.

    Parameters
    ----------
    found : sequence of RegionSet
        Region sets on one polyhedron (:func:`spatial_figure`) or on one
        polygon, vertex grasps among them anywhere (:func:`planar_figure`),
        best first.
    path : str or Path
        Where to write the page, atomically (plotly.js is inlined, compressed:
        :func:`forceclosure.pictures.page.small_page`, about 2 MB).
    title : str, optional
    up : {"x", "y", "z"}
        The axis held upright on a polyhedron (:func:`forceclosure.pictures.plot.upright_axis`).
    shared_js : bool
        Write the installed plotly's plotly.js beside the page as ``plotly.min.js`` (once:
        :func:`forceclosure.pictures.page.write_plotly_js`) and a small page that loads it
        (its figure only, tens of kB); the two must stay together.

    Returns
    -------
    Path
        ``path``.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import soft_pair_regions
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "cube.html"
    >>> write_html([soft_pair_regions(bundled("cube"), 0, 1, 0.5)], out).stat().st_size < 3e6
    True
    """
    path = Path(path)
    if path.suffix.lower() not in (".html", ".htm"):
        raise InputError(f"{path}: an interactive view is saved as .html")
    obj = one_object(found)
    fig = (spatial_figure([r for r in found if isinstance(r, SpatialRegions)], title, up=up)
           if isinstance(obj, Polyhedron)  # every region set on a polyhedron is spatial
           else planar_figure(found, title))
    from ..files.atomic import atomic_write

    page = _page(fig, fig.layout.title.text or obj.name, path, shared_js)
    try:
        with atomic_write(str(path)) as f:
            f.write(page.encode("utf-8"))
    except OSError as exc:
        raise InputError(f"{path}: cannot write ({exc.strerror})") from None
    return path


# --- labelled parallel-jaw poses (``forceclosure grasps --html``) ---------------------------

#: The drawn mesh's triangle budget on a page
#: (:func:`~forceclosure.pictures.grasp_scene.drawn_mesh`).
PAGE_TRIANGLES = 4000


def _segments(boxes: NDArray, stem: NDArray) -> NDArray[np.float64]:
    """A pose's hand as line segments joined with NaN rows: its boxes' edges and the stem."""
    from .grasp_scene import BOX_EDGES

    pieces = [box[e] for box in boxes for e in BOX_EDGES] + [stem]
    return _lines(pieces, closed=False)


def _pose_mesh(pose) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """The highlighted pose's hand boxes and its cones as two triangle meshes."""
    from .grasp_scene import BOX_TRIANGLES

    hand = pose.boxes.reshape(-1, 3)
    hand_tri = np.concatenate([BOX_TRIANGLES + 8 * b for b in range(len(pose.boxes))])
    sides = pose.cones.shape[1] - 1
    ring = np.arange(1, sides + 1)
    one = np.column_stack([np.zeros(sides, int), ring, np.roll(ring, -1)])
    cones = pose.cones.reshape(-1, 3)
    cone_tri = np.concatenate([one + (sides + 1) * c for c in range(len(pose.cones))]
                              or [np.zeros((0, 3), int)])
    return hand, hand_tri, cones, cone_tri


def _caption_html(scene, pose) -> str:
    """The page's title with the highlighted pose's caption."""
    line1, line2 = pose.caption.split("\n")
    return (f"{scene.title}<br><sub><b style='color:{pose.colour}'>grasp {line1}</b>"
            f"   {line2}</sub>")


def grasps_figure(obj, labels, top: int = 10, gripper=None, title: str | None = None, *,
                  up: str = "z") -> go.Figure:
    """The interactive figure of an object and its ``top`` best labelled jaw poses.

    The same scene as :func:`forceclosure.pictures.grasp_plot.plot_grasps`
    (:func:`forceclosure.pictures.grasp_scene.grasp_scene`): every pose's hand as a thin
    outline in the colour of its label and its contacts as dots (hovering one names its
    pose), one trace per label
    (named in the legend with the poses drawn and in all, e.g.
    ``closure and clear: 9 drawn of 9``; clicking it hides them); and one pose
    highlighted at a time, chosen with the slider under the figure: its hand's
    boxes, the friction cone at each contact pointing into the object, the line
    between the contacts, and its caption (rank, verdict, hand clear or colliding,
    μ*, ε) in the title. The object's mesh is
    drawn decimated to at most :data:`PAGE_TRIANGLES` triangles, in single precision.

    Parameters
    ----------
    obj : file, bundled name, trimesh.Trimesh or Polyhedron
    labels : GraspLabels
    top : int
        How many of the best poses to draw.
    gripper : ParallelJaw, optional
        Default: the labels' gripper, from their ``meta``.
    title : str, optional
    up : {"x", "y", "z"}
        The axis the camera holds upright (:func:`forceclosure.pictures.plot.upright_axis`).

    Examples
    --------
    >>> from forceclosure.gripper.jaw import ParallelJaw
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), 0.3, 6, least_friction=False)
    >>> fig = grasps_figure("cube", labels, top=4)
    >>> [t.name for t in fig.data if t.showlegend is not False]
    ['closure and clear: 4 drawn of 6']
    >>> len(fig.layout.sliders[0].steps)
    4
    """
    from .grasp_plot import best_grasps
    from .grasp_scene import grasp_scene

    chosen = best_grasps(labels, top)
    scene = grasp_scene(obj, labels, chosen, gripper, title, most_triangles=PAGE_TRIANGLES)
    V, T = scene.vertices.astype(np.float32), scene.triangles.astype(np.int32)
    fig = go.Figure(go.Mesh3d(x=V[:, 0], y=V[:, 1], z=V[:, 2], i=T[:, 0], j=T[:, 1],
                              k=T[:, 2], color="#b8bcc4", opacity=0.55, flatshading=True,
                              hoverinfo="skip", name=scene.name, showlegend=False,
                              lighting={"ambient": 0.55, "diffuse": 0.7, "specular": 0.05}))
    for entry in scene.legend:  # one trace of outlines and one of contacts per label
        poses = [p for p in scene.poses if p.colour == entry.colour]
        line = np.concatenate([_segments(p.boxes, p.stem) for p in poses]).astype(np.float32)
        fig.add_trace(go.Scatter3d(x=line[:, 0], y=line[:, 1], z=line[:, 2], mode="lines",
                                   name=entry.text, legendgroup=entry.words,
                                   line={"color": entry.colour, "width": 2}, opacity=0.3,
                                   hoverinfo="skip"))
        dots = np.concatenate([p.points for p in poses]).astype(np.float32)
        fig.add_trace(go.Scatter3d(x=dots[:, 0], y=dots[:, 1], z=dots[:, 2], mode="markers",
                                   legendgroup=entry.words, showlegend=False,
                                   marker={"size": 3, "color": entry.colour},
                                   hovertext=[p.caption.replace("\n", "<br>") for p in poses
                                              for _ in range(2)], hoverinfo="text"))
    layout = {"scene": {"aspectmode": "data", "xaxis_title": "x", "yaxis_title": "y",
                        "zaxis_title": "z", "camera": _camera(up)},
              "margin": {"l": 0, "r": 0, "t": 70, "b": 0}, "paper_bgcolor": "white",
              "legend": {"x": 0.01, "y": 0.98, "bgcolor": "rgba(255,255,255,0.7)"}}
    if scene.poses:
        first = scene.poses[0]
        hand, hand_tri, cones, cone_tri = _pose_mesh(first)
        at = len(fig.data)
        fig.add_trace(go.Mesh3d(x=hand[:, 0], y=hand[:, 1], z=hand[:, 2], i=hand_tri[:, 0],
                                j=hand_tri[:, 1], k=hand_tri[:, 2], color=first.colour,
                                opacity=0.35, flatshading=True, hoverinfo="skip",
                                name="highlighted hand", showlegend=False))
        fig.add_trace(go.Mesh3d(x=cones[:, 0], y=cones[:, 1], z=cones[:, 2], i=cone_tri[:, 0],
                                j=cone_tri[:, 1], k=cone_tri[:, 2], color=first.colour,
                                opacity=0.4, hoverinfo="skip", name="friction cones",
                                showlegend=False))
        fig.add_trace(go.Scatter3d(x=first.points[:, 0], y=first.points[:, 1],
                                   z=first.points[:, 2], mode="lines+markers",
                                   line={"color": "#222222", "width": 4, "dash": "dash"},
                                   marker={"size": 5, "color": "#222222"}, hoverinfo="skip",
                                   name="contacts", showlegend=False))
        steps = []
        for pose in scene.poses:
            hand, _, cones, _ = _pose_mesh(pose)
            xyz = [hand, cones, pose.points]
            steps.append({"label": str(pose.rank), "method": "update",
                          "args": [{"x": [a[:, 0].round(7).tolist() for a in xyz],
                                    "y": [a[:, 1].round(7).tolist() for a in xyz],
                                    "z": [a[:, 2].round(7).tolist() for a in xyz],
                                    # the meshes' colour; the contacts' line keeps its own
                                    "color": [pose.colour, pose.colour, None]},
                                   {"title.text": _caption_html(scene, pose)},
                                   [at, at + 1, at + 2]]})
        layout["sliders"] = [{"steps": steps, "active": 0, "x": 0.05, "len": 0.9,
                              "y": 0.02, "currentvalue": {"prefix": "grasp "},
                              "pad": {"t": 0, "b": 10}}]
        layout["title"] = {"text": _caption_html(scene, first), "x": 0.02,
                           "font": {"size": 15}}
    else:
        layout["title"] = {"text": scene.title, "x": 0.02, "font": {"size": 15}}
    fig.update_layout(**layout)
    return fig


def _page(fig, title: str, path: Path, shared_js: bool) -> str:
    """The page's HTML: self-contained, or (``shared_js``) loading ``plotly.min.js``, written
    beside ``path`` first, so that no page names a file that is not there."""
    from .page import PLOTLY_JS, small_page, write_plotly_js

    if not shared_js:
        return small_page(fig, title=title)
    write_plotly_js(Path(path).parent)
    return small_page(fig, title=title, plotly_js=PLOTLY_JS)


def check_html_path(path: str | Path) -> None:
    """Refuse a page file that is not ``.html`` (or ``.htm``), before any work."""
    if Path(path).suffix.lower() not in (".html", ".htm"):
        raise InputError(f"{path}: an interactive view is saved as .html")


def write_grasps_html(obj, labels, path: str | Path, top: int = 10, gripper=None,
                      title: str | None = None, *, up: str = "z",
                      shared_js: bool = False) -> list[int]:
    """Save the object and its ``top`` best labelled jaw poses (:func:`grasps_figure`) as one
    self-contained, offline HTML page (:func:`forceclosure.pictures.page.small_page`:
    plotly.js inlined, compressed; about 2 MB), atomically, with ``up``
    upright (:func:`forceclosure.pictures.plot.upright_axis`). Returns the indices of the
    poses drawn.

    With ``shared_js``, the installed plotly's plotly.js is written beside the page as
    ``plotly.min.js`` (once: :func:`forceclosure.pictures.page.write_plotly_js`) and the page
    loads it: a page of the figure only (tens of kB), for folders of many pages.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from forceclosure.gripper.jaw import ParallelJaw
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), 0.3, 6, least_friction=False)
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "grasps.html"
    >>> len(write_grasps_html("cube", labels, out, top=3)), out.stat().st_size < 3 * 10**6
    (3, True)
    """
    from ..files.atomic import atomic_write
    from .grasp_plot import best_grasps

    check_html_path(path)
    fig = grasps_figure(obj, labels, top, gripper, title, up=up)
    page = _page(fig, fig.layout.title.text or "grasps", Path(path), shared_js)
    with atomic_write(str(path)) as f:
        f.write(page.encode("utf-8"))
    return best_grasps(labels, top).tolist()
