"""Polygons: normalisation, edges, loaders, real glyph outlines, bad input."""

import json

import numpy as np
import pytest
import shapely
from hypothesis import example, given
from hypothesis import strategies as st
from matplotlib.font_manager import FontProperties
from matplotlib.textpath import TextPath

from forceclosure import InputError
from forceclosure.objects import POLYGONS, Polygon, bundled
from forceclosure.objects.io import (
    load_object,
    polygon_from_csv,
    polygon_from_json,
    polygon_from_svg,
)


def assert_outward(polygon: Polygon, reference: shapely.Polygon):
    """Every edge's normal points out of the material (checked with shapely)."""
    eps = polygon.size * 1e-6
    for e in polygon.edges:
        mid = (e.start + e.end) / 2
        assert not reference.contains(shapely.Point(mid + eps * e.normal)), e
        assert reference.contains(shapely.Point(mid - eps * e.normal)), e
        np.testing.assert_allclose(e.normal @ (e.end - e.start), 0, atol=1e-9 * e.length)


@pytest.mark.parametrize("name", list(POLYGONS))
def test_bundled_polygons_are_oriented_with_outward_normals(name):
    p = bundled(name)
    assert_outward(p, p.to_shapely())
    assert p.area == pytest.approx(p.to_shapely().area) and p.area > 0
    assert sum(e.length for e in p.edges) == pytest.approx(p.to_shapely().length)


def test_clockwise_input_and_hole_orientation():
    outer_cw = [[0, 0], [0, 4], [4, 4], [4, 0]]
    hole_ccw = [[1, 1], [3, 1], [3, 3], [1, 3]]
    p = Polygon.from_points(outer_cw, [hole_ccw])
    ref = shapely.Polygon(outer_cw, [hole_ccw])
    assert p.area == pytest.approx(12.0)
    assert shapely.Polygon(p.outer).exterior.is_ccw
    assert not shapely.LinearRing(p.holes[0]).is_ccw
    assert_outward(p, ref)
    assert [e.ring for e in p.edges] == [0] * 4 + [1] * 4


def test_collinear_edges_merge_and_keep_their_sources():
    pts = [[0, 0], [1, 0], [2, 0], [3, 0], [3, 1], [0, 1]]
    p = Polygon.from_points(pts)
    assert len(p.edges) == 4
    bottom = next(e for e in p.edges if e.normal[1] < -0.5)
    assert bottom.source == (0, 1, 2) and bottom.length == pytest.approx(3.0)
    for t in np.linspace(0, bottom.length, 7):
        assert bottom.parameter(bottom.point(t)) == pytest.approx(t)
    edge, t, dist = p.locate([2.5, -0.2])
    assert edge == bottom.index and t == pytest.approx(2.5) and dist == pytest.approx(0.2)


def test_loaders_agree():
    ring = [[0, 0], [4, 0], [4, 3], [0, 3]]
    hole = [[1, 1], [2, 1], [2, 2], [1, 2]]
    want = shapely.Polygon(ring, [hole]).area
    from_json = polygon_from_json({"outer": ring, "holes": [hole]})
    geo = {"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},
           "geometry": {"type": "Polygon", "coordinates": [[*ring, ring[0]], hole]}}]}
    svg = ('<svg xmlns="http://www.w3.org/2000/svg"><path fill-rule="evenodd" d="M0 0 h4 v3 '
           'h-4 z m1 1 l1 0 l0 1 l-1 0 z"/></svg>')  # both rings wind one way: evenodd holes
    csv = "x,y\n" + "\n".join(f"{x},{y}" for x, y in ring) + "\n\n" + "\n".join(
        f"{x} {y}" for x, y in hole)
    shapely_obj = Polygon.from_shapely(shapely.Polygon(ring, [hole]))
    for p in (from_json, polygon_from_json(geo), polygon_from_svg(svg), polygon_from_csv(csv),
              shapely_obj):
        assert p.area == pytest.approx(want) and len(p.holes) == 1 and len(p.edges) == 8
    tri = polygon_from_svg('<svg><polygon points="0,0 3,0 0,3"/></svg>')
    assert tri.area == pytest.approx(4.5)


def test_files_on_disk(tmp_path):
    path = tmp_path / "l.json"
    path.write_text(json.dumps({"outer": [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]]}))
    obj = load_object(path)
    assert obj.name == "l" and obj.area == pytest.approx(5.0) and not obj.convex


def _glyph_polygons(text):
    path = TextPath((0, 0), text, size=10, prop=FontProperties(family="DejaVu Sans"))
    geometry = shapely.Polygon()
    for ring in path.to_polygons():
        if len(ring) >= 4:
            geometry = geometry.symmetric_difference(shapely.Polygon(ring))  # even-odd fill
    return [g for g in getattr(geometry, "geoms", [geometry]) if g.area > 1e-6]


@pytest.mark.parametrize("letters", ["ABDOPQR", "abdegopq", "0689&%@"])
def test_real_glyph_outlines_with_holes(letters):
    """Outlines from matplotlib's bundled DejaVu font: non-convex, with holes."""
    holes = 0
    for letter in letters:
        for part in _glyph_polygons(letter):
            part = shapely.make_valid(part)
            if part.geom_type != "Polygon":
                continue
            p = Polygon.from_shapely(part, name=f"glyph {letter}")
            assert p.area == pytest.approx(part.area, rel=1e-9)
            assert len(p.edges) <= sum(len(r.coords) - 1 for r in [part.exterior,
                                                                   *part.interiors])
            assert_outward(p, part)
            holes += len(p.holes)
    assert holes >= 3


@pytest.mark.parametrize("points,message", [
    ([[0, 0], [2, 2], [2, 0], [0, 2]], "self-intersection at (1, 1)"),
    ([[0, 0], [1, 0], [1, 0], [0, 1]], "vertex 3 repeats vertex 2"),
    ([[0, 0], [1, 1], [0, 0]], "fewer than 3 distinct vertices"),
    ([[0, 0], [1, 0], [2, 0]], "zero area"),
    ([[0, 0], [1, 0], [np.inf, 1]], "vertex 3 is not finite"),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], "must be (x, y) pairs"),
])
def test_bad_polygons(points, message):
    with pytest.raises(InputError, match=message.replace("(", r"\(").replace(")", r"\)")):
        Polygon.from_points(points)


def test_numbers_after_close_path_are_refused():
    with pytest.raises(InputError, match="'Z' takes no numbers"):
        polygon_from_svg('<svg><path d="M0 0 L1 0 L1 1 Z 5"/></svg>')


def test_collinear_points_are_not_a_polygon():
    with pytest.raises(InputError):
        Polygon.from_points([[0, 0], [1, 0], [2, 0], [3, 0]])


coordinate = st.one_of(st.floats(-1e6, 1e6), st.sampled_from([0.0, 1.0, np.nan, np.inf]))
ring_points = st.lists(st.tuples(coordinate, coordinate), min_size=0, max_size=12)


@given(ring_points, st.lists(ring_points, max_size=2))
def test_random_geometry_only_raises_input_error(outer, holes):
    try:
        p = Polygon.from_points(outer, holes)
    except InputError:
        return
    assert p.area > 0
    assert p.to_shapely().is_valid


json_values = st.recursive(
    st.none() | st.booleans() | st.floats(allow_nan=True) | st.integers() | st.text(max_size=5),
    lambda children: st.lists(children, max_size=5)
    | st.dictionaries(st.sampled_from(["outer", "holes", "type", "coordinates", "features",
                                       "geometry", "name"]), children, max_size=4),
    max_leaves=25)


@given(json_values)
@example({"type": "\n"})  # a name with a line break is escaped in the one-line error
def test_random_json_only_raises_input_error(data):
    try:
        polygon_from_json(data)
    except InputError as e:
        assert "\n" not in str(e)


@given(st.text(alphabet="MmLlHhVvZzCc0123456789.-, e", max_size=60),
       st.sampled_from(["path", "polygon", "polyline"]))
def test_random_svg_only_raises_input_error(d, tag):
    attribute = "d" if tag == "path" else "points"
    try:
        polygon_from_svg(f'<svg><{tag} {attribute}="{d}"/></svg>')
    except InputError as e:
        assert "\n" not in str(e)


@given(st.text(alphabet="0123456789.,-e \nxy", max_size=80))
def test_random_csv_only_raises_input_error(text):
    try:
        polygon_from_csv(text)
    except InputError as e:
        assert "\n" not in str(e)
