"""The interactive HTML view: what the figure holds, that the page is self-contained, and,
in headless Chromium, that the object is really drawn."""

from __future__ import annotations

import gzip
import json
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import matplotlib.image
import numpy as np
import pybullet_data
import pytest
import trimesh

from forceclosure import ParallelJaw, load_object
from forceclosure.app.cli import main
from forceclosure.errors import InputError, OutputError
from forceclosure.gripper.labels import grasp_labels
from forceclosure.objects import bundled
from forceclosure.pictures.page import PLOTLY_JS, _packed, small_page, write_plotly_js
from forceclosure.pictures.view import (
    PAGE_TRIANGLES,
    grasps_figure,
    planar_figure,
    spatial_figure,
    write_grasps_html,
    write_html,
)
from forceclosure.synthesis import synthesize


@pytest.fixture(scope="module")
def cube_pairs():
    return synthesize(bundled("cube"), 2, "soft", 0.5, top=3).found


def _xyz(trace) -> np.ndarray:
    return np.column_stack([trace.x, trace.y, trace.z]).astype(float)


def test_regions_drawn_where_they_are(cube_pairs):
    """Each finger's region mesh has the patch's corners (lifted off the face by a hair),
    and its friction cone opens by atan(mu) around the face normal, apex on the region."""
    regions = cube_pairs[0]
    poly = regions.polyhedron
    fig = spatial_figure([regions])
    meshes = [t for t in fig.data if t.type == "mesh3d"]
    assert len(meshes) == 1 + 2 * len(regions.regions)  # object, then (region, cone) each
    for k, region in enumerate(regions.regions):
        (patch,) = region
        n = poly.faces[patch.face].normal
        drawn, cone = _xyz(meshes[1 + 2 * k]), _xyz(meshes[2 + 2 * k])
        lift = (drawn - patch.points) @ n
        assert np.allclose(drawn - lift[:, None] * n, patch.points)
        assert np.all((lift > 0) & (lift < 0.01 * poly.size))
        apex, rim = cone[0], cone[1:]
        assert abs((apex - patch.points.mean(axis=0)) @ n) < 1e-12  # on the face
        axis = rim - apex
        angle = np.arccos(axis @ n / np.linalg.norm(axis, axis=1))
        assert np.allclose(angle, np.arctan(regions.mu))


def test_menu_shows_one_grasp_at_a_time(cube_pairs):
    fig = spatial_figure(cube_pairs)
    (menu,) = fig.layout.updatemenus
    assert len(menu.buttons) == len(cube_pairs)
    object_traces = sum(t.visible is None for t in fig.data)  # the rest belong to grasps
    assert object_traces == 3  # object, face outlines, face numbers
    shown = []
    for button in menu.buttons:
        visible = np.array(button.args[0]["visible"])
        assert visible[:object_traces].all()  # the object is always there
        shown.append(frozenset(np.flatnonzero(visible[object_traces:])))
    assert all(shown) and len(set().union(*shown)) == sum(map(len, shown))  # disjoint groups
    assert np.array_equal(np.array(menu.buttons[0].args[0]["visible"]),
                          np.array([t.visible is not False for t in fig.data]))


def test_planar_view_segments_and_cones():
    """The bold lines are the regions' segments; every cone ray leaves a segment end at
    atan(mu) from the inward normal."""
    polygon = bundled("hexagon")
    found = synthesize(polygon, 2, "hard", 0.3, top=2).found
    fig = planar_figure(found)
    lines = [t for t in fig.data if t.showlegend is not False]
    assert [t.name for t in lines] == ["grasp 1", "grasp 2"]
    for r, t in zip(found, lines, strict=True):
        xy = np.column_stack([t.x, t.y]).astype(float)
        xy = xy[~np.isnan(xy).any(axis=1)]
        assert np.allclose(xy, r.points.reshape(-1, 2))
        ends = {tuple(np.round(p, 12)) for p in r.points.reshape(-1, 2)}
        for start, end in r.cone_rays(1.0):
            assert tuple(np.round(start, 12)) in ends
            inward = [-polygon.edges[e].normal for e in r.edges]
            cos = max(float((end - start) @ d) for d in inward)
            assert cos == pytest.approx(np.cos(np.arctan(0.3)))


def test_page_is_self_contained(tmp_path, cube_pairs):
    out = write_html(cube_pairs, tmp_path / "cube.html")
    page = out.read_text(encoding="utf-8")
    assert "<script src=" not in page  # plotly.js embedded, nothing fetched
    # plotly.js, packed, and a figure of a few kB
    assert "Plotly.newPlot" in page and len(_packed()) < len(page) < len(_packed()) + 100_000
    with pytest.raises(InputError, match=r"saved as \.html"):
        write_html(cube_pairs, tmp_path / "cube.png")
    with pytest.raises(InputError, match="no regions"):
        write_html([], tmp_path / "none.html")
    other = synthesize(bundled("hexagonal-prism"), 2, "soft", 0.5, top=1).found[0]
    with pytest.raises(InputError, match="same object"):
        spatial_figure([cube_pairs[0], other])


def test_cli_html(tmp_path, capsys):
    out = tmp_path / "cube.html"
    assert main(["synthesize", "cube", "--fingers", "2", "--contact", "soft", "--mu", "0.5",
                 "--top", "2", "--html", str(out)]) == 0
    assert f"interactive view: {out}" in capsys.readouterr().out
    assert len(_packed()) < out.stat().st_size < len(_packed()) + 100_000
    planar = tmp_path / "hexagon.html"
    assert main(["synthesize", "hexagon", "--json", "--html", str(planar)]) == 0
    assert planar.exists() and capsys.readouterr().err.startswith("  interactive view")
    # a wrong extension is refused before any work, in one line
    assert main(["synthesize", "cube", "--contact", "soft", "--html",
                 str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err
    assert "--html" in err and err.count("\n") == 1


# -- headless Chromium --------------------------------------------------------------------

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def _screenshot(page: Path, png: Path) -> np.ndarray:
    """The page as a (700, 900, 3) array of 0–255, rendered by headless Chromium (software
    WebGL, no network)."""
    with tempfile.TemporaryDirectory() as profile:
        subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                        "--enable-unsafe-swiftshader", "--disable-quic", "--no-first-run",
                        "--disable-background-networking", "--disable-component-update",
                        "--disable-sync", f"--user-data-dir={profile}", "--hide-scrollbars",
                        "--window-size=900,700", "--virtual-time-budget=10000",
                        f"--screenshot={png}", page.resolve().as_uri()],
                       check=True, capture_output=True)
    return (matplotlib.image.imread(png)[..., :3] * 255).round().astype(int)


def _object_pixels(image: np.ndarray) -> float:
    """Share of the screenshot in the object's shaded grey."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return float(((abs(r - g) < 14) & (abs(g - b) < 18) & (r > 60) & (r < 200)).mean())


def _blue_pixels(image: np.ndarray) -> float:
    """Share of the screenshot in the first finger's blue."""
    r, g, b = image[..., 0], image[..., 1], image[..., 2]
    return float(((b > r + 60) & (b > g + 25)).mean())


@pytest.mark.skipif(CHROMIUM is None and not os.environ.get("FORCECLOSURE_REQUIRE_BROWSER"),
                    reason="Debian's chromium is not installed (.ci/run installs it)")
def test_chromium_draws_the_object(tmp_path, cube_pairs):
    """The page, opened in a real browser, shows the cube and the first finger's region;
    the same page with the object hidden does not pass for it (the check can fail)."""
    assert CHROMIUM is not None, "FORCECLOSURE_REQUIRE_BROWSER is set but chromium is missing"
    page = write_html(cube_pairs, tmp_path / "cube.html")
    shot = _screenshot(page, tmp_path / "cube.png")
    fig = spatial_figure(cube_pairs)
    fig.update_traces(visible=False, selector={"name": "cube"})
    fig.write_html(tmp_path / "hidden.html", include_plotlyjs=True)
    control = _screenshot(tmp_path / "hidden.html", tmp_path / "hidden.png")
    assert _object_pixels(shot) > 0.04, "the object is not drawn"
    assert _object_pixels(control) < 0.01
    assert _blue_pixels(shot) > 0.002, "the first finger's region is not drawn"


# -- vertex grasps on the planar page; any region sets through one front door ---------------

def _page_figure(page: Path) -> tuple[list, dict]:
    """The traces and layout a saved page hands to ``Plotly.newPlot``, read back from the
    HTML (numeric arrays decoded from plotly's base64 typed arrays)."""
    import base64
    import json

    def decode(value):
        if isinstance(value, dict) and set(value) >= {"dtype", "bdata"}:
            return np.frombuffer(base64.b64decode(value["bdata"]), dtype=value["dtype"])
        if isinstance(value, dict):
            return {k: decode(v) for k, v in value.items()}
        if isinstance(value, list):
            return [decode(v) for v in value]
        return value

    text = page.read_text(encoding="utf-8")
    at = text.index("Plotly.newPlot(") + len("Plotly.newPlot(")
    reader = json.JSONDecoder()
    parsed = []
    for _ in range(3):  # the element id, the traces, the layout
        while text[at] in " \n,":
            at += 1
        value, at = reader.raw_decode(text, at)
        parsed.append(value)
    return decode(parsed[1]), decode(parsed[2])


def test_planar_view_draws_each_vertex_grasp_at_its_vertex():
    """The square (corners (+-1, +-1)) at mu 0.3: each vertex grasp is a legend entry v1, v2,
    ... whose dot is on a corner, with its bold segment on the opposite or a neighbouring
    edge: with the vertex fixed, a finger at q on the edge across holds iff the line from q
    to the vertex stays within the edge's cone narrowed by the margin, a segment
    2 tan(atan 0.3 - 1e-3) long from the corner above (or beside) the vertex."""
    square = bundled("square")
    corners = synthesize(square, 2, "soft", 0.3, top=5, construction="vertices").found
    fig = planar_figure([*synthesize(square, 2, "hard", 0.3, top=2).found, *corners])
    length = 2 * np.tan(np.arctan(0.3) - 1e-3)
    for rank, g in enumerate(corners, start=1):
        (dot,) = [t for t in fig.data if t.name == f"v{rank}"]
        vertex = np.array([dot.x[0], dot.y[0]], dtype=float)
        assert np.array_equal(np.abs(vertex), [1.0, 1.0]) and np.array_equal(vertex, g.point)
        bold = [t for t in fig.data if t.legendgroup == dot.name and t.line.width == 7]
        (segment,) = bold
        ends = np.column_stack([segment.x, segment.y]).astype(float)
        assert np.linalg.norm(ends[1] - ends[0]) == pytest.approx(length, rel=1e-9)
        fixed = np.flatnonzero(np.isclose(ends[0], ends[1]))  # the edge's line: x or y = +-1
        assert len(fixed) == 1 and np.allclose(np.abs(ends[:, fixed]), 1.0)
        # one end of the segment is the corner sharing the vertex's other coordinate
        shares = [np.isclose(np.abs(e), 1).all() and np.sum(np.isclose(e, vertex)) == 1
                  for e in ends]
        assert any(shares), (vertex, ends)
    assert [t.name for t in fig.data if t.showlegend is not False] == [
        "grasp 1", "grasp 2", "v1", "v2", "v3", "v4", "v5"]


def test_cli_html_draws_vertex_grasps(tmp_path, capsys):
    """``synthesize triangle --vertices --html``: no two fingers on edges hold the triangle
    at mu 0.3, yet the page comes, with the vertex grasps; every dot is a vertex of the
    bundled triangle (circumradius 1, a vertex at (-1, 0), the others 120 degrees apart),
    the pairs of vertices with two dots."""
    page = tmp_path / "t.html"
    assert main(["synthesize", "triangle", "--mu", "0.3", "--vertices", "--html",
                 str(page)]) == 0
    assert f"interactive view: {page}" in capsys.readouterr().out
    data, _ = _page_figure(page)
    dots = {t["name"]: np.column_stack([t["x"], t["y"]]) for t in data
            if t.get("mode") == "markers"}
    assert sorted(dots) == ["v1", "v2", "v3", "v4", "v5"]
    corners = np.array([[np.cos(a), np.sin(a)] for a in np.radians([60, 180, 300])])
    for name, xy in dots.items():
        for p in xy:
            assert np.min(np.linalg.norm(corners - p, axis=1)) < 1e-12, (name, p)
    assert sorted(len(xy) for xy in dots.values()) == [1, 1, 1, 2, 2]


def test_page_of_a_y_up_obj_holds_y_up(tmp_path):
    """``--html`` of an OBJ (y-up by convention, :func:`forceclosure.pictures.plot.upright_axis`):
    the page's camera holds +y up and looks from above along it; from an STL, +z."""
    import trimesh

    box = trimesh.creation.box((1.0, 3.0, 1.0))
    for suffix, up in ((".obj", [0, 1, 0]), (".stl", [0, 0, 1])):
        path = tmp_path / f"tall{suffix}"
        box.export(path)
        page = tmp_path / f"tall{suffix}.html"
        assert main(["synthesize", str(path), "--fingers", "2", "--contact", "soft", "--mu",
                     "0.5", "--top", "1", "--html", str(page)]) == 0
        _, layout = _page_figure(page)
        camera = layout["scene"]["camera"]
        assert [camera["up"][k] for k in "xyz"] == up
        eye = np.array([camera["eye"][k] for k in "xyz"])
        assert eye @ up == pytest.approx(1.0)  # above the object, along its up axis
    with pytest.raises(InputError, match="up must be"):
        write_html(synthesize(bundled("cube"), 2, "soft", 0.5, top=1).found,
                   tmp_path / "c.html", up="w")


# -- the page of labelled jaw poses (forceclosure grasps --html) -----------------------------
# a figure under 150 kB on a real mesh, offline, one trace per label with the counts counted here,
# one pose highlighted at a time; a dense mesh drawn decimated; in headless Chromium, the
# compressed plotly.js unpacks and draws. The real mesh is pybullet_data's teddy (a convex
# decomposition, its outer surface 3,546 triangles).

TEDDY = Path(pybullet_data.getDataPath()) / "teddy_vhacd.urdf"


@pytest.fixture(scope="module")
def teddy():
    """pybullet_data's teddy and 12 labelled poses on it (a 0.15 opening for a bear about
    0.1 across)."""
    teddy = load_object(str(TEDDY))
    return teddy, grasp_labels(teddy, ParallelJaw(0.15), 0.5, 12, seed=1, least_friction=False)


def test_page_of_a_real_mesh_is_small_and_reads_right(tmp_path, teddy):
    obj, labels = teddy
    page = tmp_path / "teddy.html"
    drawn = write_grasps_html(obj, labels, page, top=10)
    text = page.read_text(encoding="utf-8")
    assert page.stat().st_size < len(_packed()) + 150_000  # the figure: under 150 kB
    assert "<script src=" not in text and "DecompressionStream" in text  # nothing fetched
    data, layout = _page_figure(page)
    assert data[0]["type"] == "mesh3d" and len(data[0]["i"]) == len(obj.triangles)
    # the best 10, computed here, and the counts of each label drawn and in all
    code, hit, eps = labels.code, labels.collides, labels.epsilon
    category = np.where((code == 2) & ~hit, 0, np.where(code == 2, 1, np.where(code == 1, 2, 3)))
    order = sorted(range(len(code)), key=lambda i: (category[i], -eps[i], i))[:10]
    assert drawn == order
    words = ["closure and clear", "closure, hand collides", "marginal", "none"]
    named = [t["name"] for t in data if t.get("showlegend") is not False and "name" in t
             and t["type"] == "scatter3d"]
    total = np.bincount(category, minlength=4)
    shown = np.bincount(category[order], minlength=4)
    assert named == [f"{words[k]}: {shown[k]} drawn of {total[k]}" for k in range(4)
                     if shown[k]]
    # one pose highlighted at a time: a slider step per pose, each moving the contacts'
    # line onto that pose's contacts
    steps = layout["sliders"][0]["steps"]
    assert [s["label"] for s in steps] == [str(k) for k in range(1, 11)]
    for step, i in zip(steps, order, strict=True):
        line = np.column_stack([step["args"][0][c][2] for c in "xyz"])
        assert np.allclose(line, labels.points[i], atol=1e-6)
        assert step["args"][1]["title.text"].count(f"grasp {order.index(i) + 1}. ") == 1


def test_a_dense_mesh_is_drawn_decimated(tmp_path):
    """A sphere of 20,480 triangles (a page drawing them all would pass a megabyte): the page
    draws at most PAGE_TRIANGLES of them, on the sphere (every drawn vertex within 2 % of its
    radius), and its figure stays under 150 kB."""
    sphere = trimesh.creation.icosphere(subdivisions=5, radius=0.05)
    labels = grasp_labels(sphere, ParallelJaw(0.15), 0.5, 3, seed=1, least_friction=False,
                          collision=False)
    page = tmp_path / "sphere.html"
    write_grasps_html(sphere, labels, page, top=3)
    assert page.stat().st_size < len(_packed()) + 150_000
    data, _ = _page_figure(page)
    mesh = data[0]
    assert 1000 < len(mesh["i"]) <= PAGE_TRIANGLES
    radius = np.linalg.norm(np.column_stack([mesh[c] for c in "xyz"]).astype(float), axis=1)
    assert np.allclose(radius, 0.05, rtol=0.02)


def test_the_inlined_bundle_is_plotly_js_of_the_installed_plotly():
    """The page's plotly.js is the installed plotly's, packed: nothing of it is ours."""
    import base64

    import plotly.offline

    unpacked = gzip.decompress(base64.b64decode(_packed())).decode("utf-8")
    assert unpacked == plotly.offline.get_plotlyjs()


@pytest.mark.long  # two browser runs, a few CPU-seconds: in the long profile
@pytest.mark.skipif(CHROMIUM is None and not os.environ.get("FORCECLOSURE_REQUIRE_BROWSER"),
                    reason="Debian's chromium is not installed (.ci/run installs it)")
def test_chromium_unpacks_the_page_and_draws_the_object(tmp_path):
    """The small page, opened in a real browser, unpacks plotly.js and draws the cube; the
    same page with the object hidden does not pass for it (the check can fail)."""
    assert CHROMIUM is not None, "FORCECLOSURE_REQUIRE_BROWSER is set but chromium is missing"
    labels = grasp_labels("cube", ParallelJaw(3.0), 0.3, 4, least_friction=False)
    fig = grasps_figure("cube", labels, top=2)
    shown = tmp_path / "shown.html"
    shown.write_text(small_page(fig), encoding="utf-8")
    fig.update_traces(visible=False, selector={"type": "mesh3d"})
    hidden = tmp_path / "hidden.html"
    hidden.write_text(small_page(fig), encoding="utf-8")
    drawn = _object_pixels(_screenshot(shown, tmp_path / "shown.png"))
    assert drawn > 0.015, "the page draws no object"
    assert _object_pixels(_screenshot(hidden, tmp_path / "hidden.png")) < drawn / 3


@pytest.mark.long  # 2,000 poses labelled on the duck: about 15 s
def test_grasps_page_of_the_duck_reads_right(tmp_path, capsys):
    """``grasps duck_vhacd.urdf --gripper panda --count 2000 --html``: the page's figure
    (parsed from the HTML) is small, one trace of outlines per label named with the counts
    computed here from the saved labels, the best pose highlighted (the contacts' line on its
    contacts, its caption in the title), and the duck upright: the camera holds +y up, the
    side the duck's largest flat area (its base) faces away from."""
    duck = str(Path(pybullet_data.getDataPath()) / "duck_vhacd.urdf")
    page, out = tmp_path / "duck.html", tmp_path / "duck.npz"
    assert main(["grasps", duck, "--gripper", "panda", "--mu", "0.5", "--count", "2000",
                 "--seed", "1", "--html", str(page), "--out", str(out)]) == 0
    capsys.readouterr()
    size = page.stat().st_size
    # plotly.js packed (about 1.96 MB, :mod:`forceclosure.pictures.page`) and a figure of
    # at most 150 kB: a page drawing every pose or the whole mesh would pass that
    assert size < len(_packed()) + 150_000
    data, layout = _page_figure(page)
    labels = np.load(out, allow_pickle=False)
    code, hit, eps = labels["code"], labels["collides"], labels["epsilon"]
    category = np.where((code == 2) & ~hit, 0, np.where(code == 2, 1,
                                                        np.where(code == 1, 2, 3)))
    order = sorted(range(len(code)), key=lambda i: (category[i], -np.nan_to_num(eps[i]), i))
    best = order[:10]
    words = ["closure and clear", "closure, hand collides", "marginal", "none"]
    total = np.bincount(category, minlength=4)
    shown = np.bincount(category[best], minlength=4)
    named = [t["name"] for t in data if t["type"] == "scatter3d"
             and t.get("showlegend") is not False and t.get("name") != "contacts"]
    assert named == [f"{words[k]}: {shown[k]:,} drawn of {total[k]:,}" for k in range(4)
                     if shown[k]]
    assert total[0] >= 100  # the search finds clear closed poses on the duck
    # every label's outlines are one trace: as many line traces as legend entries
    lines = [t for t in data if t["type"] == "scatter3d" and t.get("mode") == "lines"]
    assert len(lines) == len(named)
    # the best pose highlighted: the contacts' line on its contacts, its rank in the title
    (contacts,) = [t for t in data if t.get("name") == "contacts"]
    drawn = np.column_stack([np.asarray(contacts[c], float) for c in "xyz"])
    assert np.allclose(drawn, labels["points"][best[0]], atol=1e-6)
    assert "grasp 1. closure, clear" in layout["title"]["text"]
    # upright: the duck's base (the largest flat area) faces -y, and the camera holds +y up
    mesh = load_object(duck).to_trimesh()
    flat = {(axis, sign): float(mesh.area_faces[mesh.face_normals[:, axis] * sign > 0.95].sum())
            for axis in range(3) for sign in (1, -1)}
    assert max(flat, key=flat.get) == (1, -1)
    camera = layout["scene"]["camera"]
    assert [camera["up"][k] for k in "xyz"] == [0, 1, 0]


# -- pages sharing one plotly.js beside them (issue 24: pages under 1 MB) ------------------

def _installed_plotly_js() -> bytes:
    import plotly.offline

    return plotly.offline.get_plotlyjs().encode("utf-8")


def test_a_shared_page_loads_plotly_js_beside_it_and_draws_the_same_figure(tmp_path):
    """The shared page names plotly.min.js in one ``<script src>``, inlines nothing of
    plotly.js, and hands ``Plotly.newPlot`` the very traces and layout of the self-contained
    page; names that are no relative file are refused in one line."""
    labels = grasp_labels("cube", ParallelJaw(3.0), 0.3, 4, least_friction=False)
    fig = grasps_figure("cube", labels, top=2)
    whole, shared = tmp_path / "whole.html", tmp_path / "shared.html"
    whole.write_text(small_page(fig, "cube"), encoding="utf-8")
    shared.write_text(small_page(fig, "cube", plotly_js=PLOTLY_JS), encoding="utf-8")
    text = shared.read_text(encoding="utf-8")
    assert text.count("<script src=") == 1 and '<script src="plotly.min.js"></script>' in text
    assert "fc-plotly" not in text and "DecompressionStream" not in text
    assert shared.stat().st_size < 100_000 < 1_000_000 < whole.stat().st_size
    # the figure, read back from both pages, is the same
    (data_w, layout_w), (data_s, layout_s) = _page_figure(whole), _page_figure(shared)
    assert repr(data_w) == repr(data_s) and repr(layout_w) == repr(layout_s)
    assert "<script src=" not in whole.read_text(encoding="utf-8")  # the default: one file
    for bad in ("/tmp/plotly.min.js", "https://cdn.plot.ly/plotly.min.js", "", "C:plotly.js",
                "js\\plotly.min.js", "js/"):
        with pytest.raises(InputError, match="relative to the page"):
            small_page(fig, plotly_js=bad)


def test_plotly_js_is_written_once_and_is_the_installed_plotlys(tmp_path):
    installed = _installed_plotly_js()
    path = write_plotly_js(tmp_path)
    assert path == tmp_path / PLOTLY_JS and path.read_bytes() == installed
    before = path.stat()
    assert write_plotly_js(tmp_path) == path  # the same content: left as it is
    after = path.stat()
    assert (after.st_ino, after.st_mtime_ns) == (before.st_ino, before.st_mtime_ns)
    path.write_bytes(installed[:-1] + b" ")  # another plotly.js of the same size: replaced
    write_plotly_js(tmp_path)
    assert path.read_bytes() == installed
    assert sorted(p.name for p in tmp_path.iterdir()) == [PLOTLY_JS]  # no temporary left
    with pytest.raises(OutputError, match="cannot write"):
        write_plotly_js(tmp_path / "missing")


def test_cli_grasps_html_shared(tmp_path, capsys):
    """``grasps --html P --html-shared``: a page under 1 MB and plotly.min.js beside it,
    the installed plotly's; without the flag one self-contained page and nothing beside it;
    the flag alone is refused in one line."""
    shared, whole = tmp_path / "shared", tmp_path / "whole"
    shared.mkdir()
    whole.mkdir()
    base = ["grasps", "cube", "--width", "3", "--mu", "0.5", "--count", "4", "--seed", "1"]
    assert main([*base, "--html", str(shared / "cube.html"), "--html-shared", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["html_plotly_js"] == str(shared / PLOTLY_JS)
    assert sorted(p.name for p in shared.iterdir()) == ["cube.html", PLOTLY_JS]
    assert (shared / PLOTLY_JS).read_bytes() == _installed_plotly_js()
    page = (shared / "cube.html").read_text(encoding="utf-8")
    assert '<script src="plotly.min.js"></script>' in page and len(page) < 1_000_000
    assert main([*base, "--html", str(whole / "cube.html")]) == 0
    assert "loads" not in capsys.readouterr().out
    assert [p.name for p in whole.iterdir()] == ["cube.html"]
    assert (whole / "cube.html").stat().st_size > len(_packed())
    assert main([*base, "--html-shared"]) == 2
    err = capsys.readouterr().err
    assert "--html-shared" in err and err.count("\n") == 1


@pytest.mark.long  # two browser runs, about 4 s of wall time each: in the long profile
@pytest.mark.skipif(CHROMIUM is None and not os.environ.get("FORCECLOSURE_REQUIRE_BROWSER"),
                    reason="Debian's chromium is not installed (.ci/run installs it)")
def test_chromium_draws_a_shared_page(tmp_path):
    """A ``shared_js`` page opened from file:// in a real browser loads plotly.min.js beside
    it and draws the cube; the same page with plotly.min.js gone draws nothing (the check can
    fail)."""
    assert CHROMIUM is not None, "FORCECLOSURE_REQUIRE_BROWSER is set but chromium is missing"
    labels = grasp_labels("cube", ParallelJaw(3.0), 0.3, 4, least_friction=False)
    page = tmp_path / "cube.html"
    write_grasps_html("cube", labels, page, top=2, shared_js=True)
    assert page.stat().st_size < 1_000_000
    drawn = _object_pixels(_screenshot(page, tmp_path / "shown.png"))
    assert drawn > 0.015, "the shared page draws no object"
    (tmp_path / PLOTLY_JS).unlink()
    assert _object_pixels(_screenshot(page, tmp_path / "gone.png")) < drawn / 3
