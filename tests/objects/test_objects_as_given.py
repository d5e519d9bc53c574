"""Objects read exactly as given: tessellated arcs, kinks, glyphs, far-away and scaled
objects; every region checked against the *input* geometry in the numbers printed.

The checks here are independent of the library's certificates: each printed
corner is matched to the input edge it lies on (by distance, in the test),
the normal is taken exactly from that input edge's two vertices, and
Theorem 1 is decided in rationals (``exact.py``) at the corners and at
interior samples.
"""

from __future__ import annotations

import json
import os
import re
from fractions import Fraction

import numpy as np
import pybullet_data
import pytest
import shapely
from matplotlib.font_manager import FontProperties
from matplotlib.textpath import TextPath
from test_outer_surface import distance_to_triangles, original_pieces, winding_number

from exact import planar_hard_wrenches, positively_spans
from forceclosure.analysis.batch import analyze_batch
from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.objects import POLYGONS, POLYHEDRA, Polygon, Polyhedron, bundled
from forceclosure.synthesis.best import synthesize


def input_edges(rings):
    """The input's edges as (start, end) float pairs, ring by ring, oriented by shapely
    (outer boundary counter-clockwise, holes clockwise: material on the left)."""
    shape = shapely.geometry.polygon.orient(shapely.Polygon(rings[0], rings[1:]), 1.0)
    oriented = [np.asarray(r.coords)[:-1] for r in (shape.exterior, *shape.interiors)]
    return [(r[k], r[(k + 1) % len(r)]) for r in oriented for k in range(len(r))]


def distance_to_edge(a, b, p):
    d = b - a
    s = np.clip((p - a) @ d / (d @ d), 0, 1)
    return float(np.linalg.norm(a + s * d - p))


def input_edges_under(edges, p0, p1, tol):
    """The input edges under the segment ``p0 p1``: its ends and 9 points inside it must
    each lie within ``tol`` of one; returns the edges found under the inside points (an edge
    that only meets an end is not under it)."""
    for p in (p0, p1):
        assert min(distance_to_edge(a, b, p) for a, b in edges) <= tol
    found = []
    for lam in np.linspace(0.05, 0.95, 9):
        p = p0 + lam * (p1 - p0)
        near = [(a, b) for a, b in edges if distance_to_edge(a, b, p) <= tol
                and (b - a) @ (p1 - p0) > 0]
        assert near, f"{p.tolist()} is on no input edge"
        found += near
    return found


def exact_outward(a, b):
    """(dy, -dx) of the input edge, in rationals (not unit: Theorem 1 does not care)."""
    dx, dy = (Fraction(float(y)) - Fraction(float(x)) for x, y in zip(a, b, strict=True))
    return [dy, -dx]


def check_regions_on_input(record, rings, mu, samples=3):
    """Every printed region of a two-finger ``--json`` record is force-closure on the input."""
    edges = input_edges(rings)
    size = float(np.linalg.norm(np.ptp(np.vstack(rings), axis=0)))
    # how far a printed float point may be from an input edge: its rounding
    tol = 1e-12 * size + 4 * float(np.spacing(np.abs(np.vstack(rings)).max()))
    for grasp in record["grasps"]:
        corners = np.array(grasp["points"], dtype=float)  # (2 fingers, 2 ends, 2)
        normals = []
        for seg in corners:
            # the region lies on input edges (to the rounding of its printed ends) that all
            # have exactly the same outward normal direction
            under = [exact_outward(a, b) for a, b in
                     input_edges_under(edges, seg[0], seg[1], tol)]
            n = under[0]
            assert all(m[0] * n[1] == m[1] * n[0] and m[0] * n[0] + m[1] * n[1] > 0
                       for m in under)
            normals.append(n)
        lam = np.linspace(0, 1, samples)
        for s in lam:
            for t in lam:
                p = corners[0, 0] + s * (corners[0, 1] - corners[0, 0])
                q = corners[1, 0] + t * (corners[1, 1] - corners[1, 0])
                W = planar_hard_wrenches([p, q], normals, [mu, mu])
                assert positively_spans(W), (grasp["edges"], s, t)


def synthesize_json(capsys, path, *options):
    assert main(["synthesize", str(path), "--json", *options]) == 0
    return json.loads(capsys.readouterr().out)


def arc_square(segments=5000, turn=4e-3):
    """The square [-1, 1]^2 whose bottom is an arc of ``segments`` chords turning ``turn``."""
    radius = 1 / np.sin(turn / 2)
    theta = np.linspace(-turn / 2, turn / 2, segments + 1)
    bottom = np.stack([radius * np.sin(theta), -1 + radius * (np.cos(turn / 2)
                                                              - np.cos(theta))], 1)
    return np.vstack([bottom, [[1, 1], [-1, 1]]])


@pytest.mark.long  # 15 s; test_a_single_tiny_kink_is_kept keeps the case in the default run
def test_a_finely_tessellated_arc_is_not_straightened(tmp_path, capsys):
    """The 5000-chord arc turns 8e-7 rad a vertex: no merged edge with the chord's normal,
    and every printed region holds on the real boundary (it did not: 6e-4 rad outside)."""
    ring = arc_square()
    polygon = Polygon.from_points(ring)
    assert len(polygon.edges) == len(ring)
    geo = tmp_path / "fine-arc.geojson"
    coords = [*ring.tolist(), ring[0].tolist()]
    geo.write_text(json.dumps({"type": "Polygon", "coordinates": [coords]}))
    record = synthesize_json(capsys, geo, "--mu", "0.1", "--top", "4")
    assert len(record["grasps"]) == 4
    check_regions_on_input(record, [ring], 0.1)


def test_a_single_tiny_kink_is_kept(tmp_path, capsys):
    """A 5e-7 rad kink in the bottom edge: two edges, and regions sound at --margin 1e-9."""
    kink = 5e-7
    ring = np.array([[-1, -1], [0, -1 - np.tan(kink)], [1, -1], [1, 1], [-1, 1]])
    assert len(Polygon.from_points(ring).edges) == 5
    path = tmp_path / "kink.json"
    path.write_text(json.dumps({"outer": ring.tolist()}))
    record = synthesize_json(capsys, path, "--mu", "0.3", "--margin", "1e-9", "--top", "6")
    assert record["grasps"]
    check_regions_on_input(record, [ring], 0.3)


def test_exactly_collinear_vertices_still_merge():
    """Points on a line that floats represent exactly still make one physical edge."""
    ring = [[0, 0], [0.25, 0], [0.5, 0], [3, 0], [3, 1], [1.5, 1], [0, 1]]
    p = Polygon.from_points(ring)
    assert len(p.edges) == 4
    assert sorted(len(e.source) for e in p.edges) == [1, 1, 2, 3]


@pytest.mark.long  # 5 s; the glyph tests above stay in the default run
def test_a_high_resolution_glyph(tmp_path, capsys):
    """The letter O of matplotlib's DejaVu font, every edge of its outline cut into 40
    pieces: nearly straight runs in floating point; the printed regions hold on the input
    outline."""
    glyph = TextPath((0, 0), "O", size=10, prop=FontProperties(family="DejaVu Sans"))
    cut = np.linspace(0, 1, 40, endpoint=False)[:, None, None]
    rings = []
    for r in glyph.to_polygons():
        r = r[:-1]
        pieces = r[None] + cut * (np.roll(r, -1, axis=0) - r)[None]  # (40, n, 2)
        rings.append(pieces.transpose(1, 0, 2).reshape(-1, 2))
    outer = max(rings, key=lambda r: abs(shapely.Polygon(r).area))
    holes = [r for r in rings if r is not outer]
    file = tmp_path / "o.json"
    file.write_text(json.dumps({"outer": outer.tolist(), "holes": [h.tolist() for h in holes]}))
    record = synthesize_json(capsys, file, "--mu", "0.3", "--top", "3")
    assert record["grasps"]
    check_regions_on_input(record, [outer, *holes], 0.3)


@pytest.mark.parametrize("offset", [1e4, 1e5, 1e6])
def test_printed_regions_far_away_are_the_certified_ones(tmp_path, capsys, offset):
    """Near coordinates 1e4 to 1e6 with --margin 1e-13, the printed floats themselves hold
    (they failed exactly by 2e-13 to 1.2e-9 rad when rounded after certification)."""
    for name in ("square", "hexagon", "wrench-head", "star"):
        obj = bundled(name)
        rings = [r + offset for r in obj.rings]
        path = tmp_path / f"{name}.json"
        path.write_text(json.dumps({"outer": rings[0].tolist(),
                                    "holes": [h.tolist() for h in rings[1:]]}))
        record = synthesize_json(capsys, path, "--mu", "0.3", "--margin", "1e-13",
                                 "--top", "8")
        assert record["grasps"], name
        assert all(g["certificate"]["holds"] for g in record["grasps"])
        check_regions_on_input(record, rings, 0.3, samples=2)


def _moved_polygon(obj, offset, scale):
    return Polygon.from_points(obj.outer * scale + offset,
                               [h * scale + offset for h in obj.holes], name=obj.name)


@pytest.mark.parametrize("offset,scale", [(1e8, 1.0), (0.0, 1e-4), (-3e4, 1e4)])
def test_polygons_moved_far_or_scaled_keep_their_geometry_and_grasps(offset, scale):
    """Area, orientation and convexity from closed forms (a move keeps them, a scale
    multiplies the area by its square); the best region sizes, relative to the object's
    size, agree with the original to 1e-6 for two fingers on every bundled polygon, and for
    three and four on three of them."""
    for name in POLYGONS:
        obj = bundled(name)
        moved = _moved_polygon(obj, offset, scale)
        assert moved.area == pytest.approx(obj.area * scale**2, rel=1e-6)
        assert moved.convex == obj.convex
        for e, f in zip(obj.edges, moved.edges, strict=True):
            np.testing.assert_allclose(f.normal, e.normal, atol=1e-6)
        hands = [(2, "hard", 0.3)]
        if name in ("triangle", "hexagon", "l-shape"):
            hands += [(3, "hard", 0.5), (4, "frictionless", 0.0)]
        for fingers, contact, mu in hands:
            want = synthesize(obj, fingers, contact, mu, top=3).found
            got = synthesize(moved, fingers, contact, mu, top=3).found
            assert len(got) == len(want), (name, fingers)
            np.testing.assert_allclose([r.min_length / moved.size for r in got],
                                       [r.min_length / obj.size for r in want], rtol=1e-6,
                                       atol=1e-9, err_msg=f"{name}, {fingers} fingers")


def test_a_millimetre_cube_far_away_keeps_every_triangle():
    """A cube of side 2^-9 at 2^27 (about 1e8; every coordinate exact in floating point):
    the key that merges duplicate vertices overflowed there and every triangle was lost.
    Its volume and area are exact."""
    obj = bundled("cube")
    moved = Polyhedron.from_arrays(obj.vertices * 2.0**-10 + 2.0**27, obj.triangles)
    assert len(moved.triangles) == 12 and len(moved.faces) == 6
    assert moved.volume == 2.0**-27 and moved.area == 6 * 2.0**-18


@pytest.mark.parametrize("offset,scale", [(1.2e7, 1.0), (1e8, 1.0), (0.0, 1e-4),
                                          (0.0, 1e4)])
def test_polyhedra_moved_far_or_scaled_keep_their_geometry(offset, scale):
    """Volume, area, faces and centroid from closed forms under a move and a scale (a side-2
    cube near 1.2e7 had volume -128065)."""
    for name in POLYHEDRA:
        obj = bundled(name)
        moved = Polyhedron.from_arrays(obj.vertices * scale + offset, obj.triangles)
        assert moved.volume == pytest.approx(obj.volume * scale**3, rel=1e-6)
        assert moved.area == pytest.approx(obj.area * scale**2, rel=1e-6)
        assert len(moved.faces) == len(obj.faces)
        np.testing.assert_allclose(moved.centroid, obj.centroid * scale + offset,
                                   rtol=1e-12, atol=1e-6 * obj.size * scale)


@pytest.mark.parametrize("offset,scale", [(1e8, 1.0), (0.0, 1e-4), (0.0, 1e4)])
def test_two_soft_fingers_far_away_or_scaled(offset, scale):
    """§5.2 on faces (a deterministic LP): the best region sizes relative to the object's
    size do not change when the object moves by 1e8 or is scaled."""
    for name in ("cube", "l-prism", "hexagonal-prism"):
        obj = bundled(name)
        moved = Polyhedron.from_arrays(obj.vertices * scale + offset, obj.triangles)
        want = synthesize(obj, 2, "soft", 0.5, top=3).found
        got = synthesize(moved, 2, "soft", 0.5, top=3).found
        assert len(got) == len(want)
        np.testing.assert_allclose([r.min_area / moved.size**2 for r in got],
                                   [r.min_area / obj.size**2 for r in want], rtol=1e-5)
        assert all(r.certify().holds for r in got)


@pytest.mark.parametrize("obj,fingers,contact,mu", [
    ("square", 2, "hard", 0.3), ("triangle", 3, "hard", 0.5),
    ("hexagon", 4, "frictionless", 0.0), ("cube", 2, "soft", 0.5),
    pytest.param("cube", 3, "hard", 0.5, marks=pytest.mark.long),  # 7 s
    pytest.param("l-prism", 3, "hard", 0.6, marks=pytest.mark.long)])
def test_one_margin_reaches_every_construction(obj, fingers, contact, mu):
    """--margin has one meaning (radians off every cone; frictionless: turned normals) and
    every construction feels it: the best regions shrink from 1e-3 to 0.2. With friction,
    the regions built with margin 0.2 hold (sampled, exact cones, independently of the
    certificate) with the cones narrowed by 0.2 rad."""
    obj = bundled(obj)
    small = synthesize(obj, fingers, contact, mu, top=1, margin=1e-3).found
    large = synthesize(obj, fingers, contact, mu, top=1, margin=0.2).found
    assert small
    size = (lambda r: r.min_length) if obj.dim == 2 else (lambda r: r.min_area)
    assert large and size(large[0]) < 0.99 * size(small[0])
    if large and contact != "frictionless" and obj.dim == 3:
        narrow = np.tan(np.arctan(mu) - 0.2)
        points, normals = large[0].sample(2000, seed=3)
        result = analyze_batch(points, normals, mu=narrow, model=contact, cone="exact")
        assert np.all(result.code == 2)


@pytest.mark.parametrize("name,fingers,contact,offset,scale", [
    ("random_urdfs/000/000.obj", 2, "soft", 1e8, 1.0),   # a convex decomposition, far away
    ("random_urdfs/000/000.obj", 2, "soft", 0.0, 1e-3),
    ("duck_vhacd.obj", 3, "hard", -2e7, 1e4),
    ("objects/mug.obj", 3, "hard", 1e8, 1.0),          # open, with a handle
])
def test_real_meshes_moved_and_scaled_hold_on_the_original_geometry(name, fingers, contact,
                                                                   offset, scale):
    """pybullet's meshes moved by up to 1e8 and scaled: every sampled tuple of the regions,
    mapped back to the file's coordinates, lies on a triangle of the file that no other
    piece encloses, and is force-closure (exact cones) with that triangle's own normal."""
    path = os.path.join(pybullet_data.getDataPath(), name)
    mesh, pieces = original_pieces(path)
    size = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0)))
    moved = Polyhedron.from_arrays(mesh.vertices * scale + offset, mesh.faces,
                                   allow_open=True)
    found = synthesize(moved, fingers, contact, 0.5, top=2, samples=3000, seed=1).found
    assert found
    tri = mesh.triangles
    own = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    own /= np.linalg.norm(own, axis=1, keepdims=True)
    for r in found:
        points, normals = r.sample(300, seed=2)
        q = ((points - offset) / scale).reshape(-1, 3)
        n = normals.reshape(-1, 3)
        best = np.array([np.argmin(distance_to_triangles(p, tri)) for p in q])
        gap = np.array([distance_to_triangles(p, tri[[k]])[0] for p, k in zip(q, best,
                                                                              strict=True)])
        assert gap.max() <= 1e-6 * size  # the rounding of coordinates near 1e8
        t = own[best] * np.sign(np.einsum("ij,ij->i", own[best], n))[:, None]
        assert np.min(np.einsum("ij,ij->i", t, n)) >= np.cos(2e-4)  # within FACE_ANGLE
        for piece in pieces:  # on the outer surface: a step out is outside every piece
            assert np.all(winding_number(piece.vertices, piece.faces, q + 1e-6 * size * t)
                          < 0.5)
        result = analyze_batch(q.reshape(points.shape), t.reshape(points.shape), mu=0.5,
                               model=contact, cone="exact")
        assert np.all(result.code == 2)


@pytest.mark.parametrize("name,fingers,contact,offset,scale", [
    pytest.param("cube", 3, "hard", 1e8, 1.0, marks=pytest.mark.long),  # 7 s
    ("triangular-prism", 3, "hard", -3e5, 2.0**-12),
    pytest.param("l-prism", 3, "hard", 1e8, 1e4, marks=pytest.mark.long),
    pytest.param("hexagonal-prism", 3, "hard", 0.0, 1e-4, marks=pytest.mark.long),  # 12 s
    pytest.param("hexagonal-prism", 3, "hard", 2e7, 3.0, marks=pytest.mark.long),
    pytest.param("cube", 7, "frictionless", 1e3, 1e-4, marks=pytest.mark.long),
    pytest.param("l-prism", 7, "frictionless", 0.0, 1e4, marks=pytest.mark.long)])
def test_sampled_constructions_far_away_or_scaled(name, fingers, contact, offset, scale):
    """§5.3 and §5.5 through sampled prototypes and search zones: moved by up to 1e8 and
    scaled by 1e-4, 3 or 1e4, the best regions' sizes relative to the object are the same
    to six digits. The samples are drawn in each face's own frame, so they differ only by
    rounding; ties (between symmetric generators, the hexagonal prism's equal faces, equal
    regions) are broken by index on values rounded to 12 digits, not by that rounding."""
    obj = bundled(name)
    moved = Polyhedron.from_arrays(obj.vertices * scale + offset, obj.triangles)
    want = synthesize(obj, fingers, contact, 0.5, top=2, samples=8000).found
    got = synthesize(moved, fingers, contact, 0.5, top=2, samples=8000).found
    assert len(got) == len(want) == 2
    np.testing.assert_allclose([r.min_area / moved.size**2 for r in got],
                               [r.min_area / obj.size**2 for r in want], rtol=1e-6)
    assert all(r.certify().holds for r in got)


@pytest.mark.parametrize("offset,scale", [(0.0, 1e-4), (5e6, 1e4)])
def test_regions_grown_on_a_real_mesh_far_away_or_scaled(offset, scale):
    """Regions grown on pybullet's bunny (search zones around sampled prototypes): scaled by
    1e-4 or moved and scaled by 1e4, the same regions relative to the object's size."""
    import trimesh

    mesh = trimesh.load(os.path.join(pybullet_data.getDataPath(), "bunny.obj"),
                        force="mesh", process=False)
    obj = Polyhedron.from_arrays(mesh.vertices, mesh.faces, allow_open=True)
    moved = Polyhedron.from_arrays(mesh.vertices * scale + offset, mesh.faces, allow_open=True)
    want = synthesize(obj, 3, "hard", 0.6, top=2, samples=2000, seed=1)
    got = synthesize(moved, 3, "hard", 0.6, top=2, samples=2000, seed=1)
    assert got.method == want.method == "mesh" and len(got.found) == len(want.found) == 2
    np.testing.assert_allclose([r.min_area / moved.size**2 for r in got.found],
                               [r.min_area / obj.size**2 for r in want.found], rtol=1e-6)


@pytest.mark.parametrize("shape,mu", [('<circle r="1"/>', 0.3), ('<ellipse rx="2" ry="1"/>', 0.3),
                                      ('<circle r="1"/>', 0.05)])
def test_regions_on_tessellated_curves_hold_on_the_true_curve(tmp_path, capsys, shape, mu):
    """An SVG circle or ellipse is read as chords whose normals are up to 0.07 rad off the
    curve's; the proofs narrow every cone by that turn. Every sampled pair in the printed
    regions, moved onto the true curve and given its true normal, is force-closure (exact,
    in rationals); where the friction cannot cover the turn (mu 0.05 < 0.07 rad) the command
    refuses in one line saying so."""
    from forceclosure import point_contact
    from forceclosure.analysis.closure import Verdict, decide

    path = tmp_path / "curve.svg"
    path.write_text(f'<svg xmlns="http://www.w3.org/2000/svg">{shape}</svg>')
    if mu < 0.07:
        assert main(["synthesize", str(path), "--json", "--mu", str(mu)]) == 2
        assert "as far as the object's normals turn" in capsys.readouterr().err
        return
    record = synthesize_json(capsys, path, "--mu", str(mu), "--top", "5")
    assert record["grasps"]
    a, b = (2.0, 1.0) if "ellipse" in shape else (1.0, 1.0)
    theta = np.linspace(0, 2 * np.pi, 200_001)
    curve = np.stack([a * np.cos(theta), b * np.sin(theta)], 1)
    rng = np.random.default_rng(4)
    for grasp in record["grasps"]:
        ends = np.array(grasp["points"])
        for _ in range(40):
            contacts = []
            for (p, q) in ends:
                x = p + rng.uniform() * (q - p)
                k = int(np.argmin(np.linalg.norm(curve - x, axis=1)))  # onto the true curve
                on = curve[k]
                normal = np.array([on[0] / a**2, on[1] / b**2])
                contacts.append(point_contact(on, normal / np.linalg.norm(normal), "hard",
                                              mu=mu))
            assert decide(contacts, "exact")[0].verdict is Verdict.CLOSURE


@pytest.mark.parametrize("mu", [0.6, 0.04])
def test_regions_on_a_tessellated_urdf_cylinder_hold_on_the_true_cylinder(tmp_path, mu):
    """A URDF <cylinder> is read as 72 facets whose normals are up to pi/72 (0.044 rad) off
    the cylinder's; the proofs narrow every cone by that. Sampled pairs of two soft fingers,
    moved onto the true cylinder (radially on the side, onto the plane on a cap) with its
    true normal, are force-closure with exact cones; at mu 0.04 (below the turn) it is
    refused in one line."""
    from forceclosure.objects.io import load_object

    urdf = tmp_path / "rod.urdf"
    urdf.write_text('<robot name="rod"><link name="rod"><collision><geometry>'
                    '<cylinder radius="0.5" length="2"/></geometry></collision></link></robot>')
    rod = load_object(urdf)
    assert min(f.spread for f in rod.faces) >= np.pi / 72
    if mu < np.pi / 72:
        with pytest.raises(InputError, match="normals turn from its chords or facets"):
            synthesize(rod, 2, "soft", mu, top=2)
        return
    found = synthesize(rod, 2, "soft", mu, top=2).found
    assert found
    for r in found:
        points, _ = r.sample(500, seed=6)
        p = points.reshape(-1, 3)
        side = np.abs(p[:, 2]) < 1 - 1e-9
        radial = np.column_stack([p[:, :2], np.zeros(len(p))])
        radial /= np.maximum(np.linalg.norm(radial, axis=1, keepdims=True), 1e-300)
        true_p = np.where(side[:, None], 0.5 * radial + [0, 0, 1] * p[:, 2:3], p)
        true_n = np.where(side[:, None], radial, np.sign(p[:, 2:3]) * [0, 0, 1])
        result = analyze_batch(true_p.reshape(points.shape), true_n.reshape(points.shape),
                               mu=mu, model="soft", cone="exact")
        assert np.all(result.code == 2)


@pytest.mark.parametrize("name,fingers,contact,mu", [
    pytest.param("cube", 3, "hard", 0.5, marks=pytest.mark.long),  # 7 s
    ("cube", 2, "soft", 0.5),
    pytest.param("cube", 7, "frictionless", 0.0, marks=pytest.mark.long),
    ("square", 2, "hard", 0.3), ("triangle", 3, "hard", 0.5),
    ("hexagon", 4, "frictionless", 0.0)])
def test_synthesis_serves_sizes_from_a_micrometre_to_a_megametre(name, fingers, contact, mu):
    """At the ends of synthesize's size range (1e-6 and 1e6 across) the regions, relative to
    the object, are those of the unit object; beyond it the object is refused in one line
    that says why, not answered with "no grasp" (which absolute tolerances gave at 1e-12
    and 1e12)."""
    obj = bundled(name)

    def scaled(s):
        if obj.dim == 3:
            return Polyhedron.from_arrays(obj.vertices * s, obj.triangles)
        return Polygon.from_points(np.asarray(obj.outer) * s)

    def sizes(o):
        found = synthesize(o, fingers, contact, mu, top=2, samples=8000).found
        return [r.min_area / o.size**2 if o.dim == 3 else r.min_length / o.size for r in found]

    want = sizes(obj)
    assert want
    for s in (1.001e-6 / obj.size, 0.999e6 / obj.size):
        np.testing.assert_allclose(sizes(scaled(s)), want, rtol=1e-5)
    for s in (1e-8, 1e8):
        with pytest.raises(InputError, match="across; synthesis is made and tested for "
                                             "objects 1e-06 to 1e"):
            synthesize(scaled(s), fingers, contact, mu, top=1)


@pytest.mark.parametrize("scale,message", [(1e60, "beyond 1e+50 in magnitude"),
                                           (1e-60, "across, below 1e-50")])
def test_polyhedra_too_large_or_small_for_floating_point_are_refused(scale, message):
    """Beyond 1e50 areas and volumes overflow (1e150 was an OverflowError, 1e200 "0 triangles
    cannot enclose a volume", 1e-200 "all vertices coincide"): one line that says so."""
    obj = bundled("cube")
    with pytest.raises(InputError, match=re.escape(message)):
        Polyhedron.from_arrays(obj.vertices * scale, obj.triangles)
    assert Polyhedron.from_arrays(obj.vertices * 1e49, obj.triangles).volume == pytest.approx(
        8e147)
