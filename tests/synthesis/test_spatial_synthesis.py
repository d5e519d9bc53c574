"""Spatial synthesis (§5.2, §5.3, §5.5, and regions on meshes): every region set certified,
and the certificate checked again, independently, by sampling with the general analysis."""

from __future__ import annotations

import math
import os
from fractions import Fraction

import numpy as np
import pybullet_data
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from forceclosure.errors import InputError
from forceclosure.objects import Polyhedron, bundled
from forceclosure.objects.io import load_object
from forceclosure.synthesis import (
    FacePatch,
    SevenRegions,
    classify_three,
    counter_overlapping_cone,
    prototype_grasps,
    seven_frictionless_regions,
    soft_pair_regions,
    three_hard_regions,
    zone_regions,
)
from forceclosure.synthesis.best import synthesize
from forceclosure.synthesis.spatial.patches import sampling_check
from forceclosure.synthesis.spatial.seven_frictionless import cofactor_signs
from forceclosure.synthesis.spatial.three_hard import counter_overlap, three_hard_construction
from forceclosure.synthesis.spatial.two_soft import ANGLE_MARGIN, PYRAMID_EDGES
from forceclosure.synthesis.spatial.zones import surface_samples

TAN30 = math.tan(math.radians(30))


def _unit(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


def _angle(a, b):
    return math.acos(max(-1.0, min(1.0, float(_unit(a) @ _unit(b)))))


unit_vectors = st.tuples(*[st.floats(-1, 1)] * 3).filter(
    lambda v: np.linalg.norm(v) > 0.1).map(_unit)


# ---------------------------------------------------------------- §5.2 two soft fingers


@settings(max_examples=200, deadline=None)
@given(unit_vectors, unit_vectors, st.floats(0.05, 2.0), st.floats(0.05, 2.0),
       st.integers(0, 10**6))
def test_counter_overlapping_cone_is_inside_both_cones(n1, n2, mu1, mu2, seed):
    """The cone lies in C1 ∩ -C2 (checked on its rim), and exists iff the cones overlap."""
    k = counter_overlapping_cone(n1, mu1, n2, mu2)
    a1, a2 = math.atan(mu1), math.atan(mu2)
    overlap = _angle(-n1, n2) < a1 + a2
    assert (k is not None) == overlap
    if k is None:
        return
    rng = np.random.default_rng(seed)
    side = np.cross(k.axis, rng.normal(size=3))
    side /= np.linalg.norm(side)
    for t in np.linspace(0, 2 * np.pi, 16, endpoint=False):
        rot = side * math.cos(t) + np.cross(k.axis, side) * math.sin(t)
        rim = math.cos(k.half_angle) * k.axis + math.sin(k.half_angle) * rot
        assert _angle(rim, -n1) <= a1 + 1e-9 and _angle(rim, n2) <= a2 + 1e-9
    # and it is the largest: half of what is left of the two half-angles
    theta = _angle(-n1, n2)
    expected = min(a1, a2, (a1 + a2 - theta) / 2)
    assert k.half_angle == pytest.approx(expected, abs=1e-9)


def test_soft_pair_on_opposite_cube_faces_has_the_closed_form_size():
    """Cube of side 2, mu 0.5: centred regular polygons of circumradius r have opposite
    vertices 2r apart sideways over a height 2, so r <= tan(alpha'); the inscribed pyramids
    cost at most a factor cos(pi / edges)."""
    cube = bundled("cube")
    r = soft_pair_regions(cube, 0, 1, 0.5)
    assert r.certify().holds
    radius = np.linalg.norm(r.regions[0][0].uv - r.regions[0][0].uv.mean(axis=0), axis=1).max()
    top = math.tan(math.atan(0.5) - ANGLE_MARGIN)
    assert top * math.cos(math.pi / PYRAMID_EDGES) ** 2 - 1e-9 <= radius <= top + 1e-9
    assert sampling_check(r, samples=3000).holds


def test_nguyen_two_sided_cone_matches_the_disk_bound():
    """The paper's construction on the cube: the cone from the centre cuts disks of radius
    tan(alpha) out of both faces, so each region is at most pi tan^2(alpha)."""
    r = soft_pair_regions(bundled("cube"), 0, 1, 0.5, construction="nguyen")
    assert r.certify().holds and sampling_check(r, samples=2000).holds
    bound = math.pi * 0.5**2
    assert 0.95 * bound <= r.min_area <= bound
    assert np.allclose(r.apex, [0, 0, 0], atol=0.05)


@pytest.mark.parametrize("name,construction", [
    ("l-prism", "maximal"), ("holed-block", "maximal"), ("hexagonal-prism", "maximal"),
    ("triangular-prism", "maximal"), ("l-prism", "nguyen"), ("hexagonal-prism", "nguyen")])
def test_best_soft_pairs_on_bundled_polyhedra_survive_sampling(name, construction):
    found = synthesize(bundled(name), 2, "soft", 0.5, top=2, construction=construction,
                       method="faces").found
    assert found
    for r in found:
        assert r.certify().holds
        check = sampling_check(r, samples=1500)
        assert check.holds, check.detail


def test_regions_on_a_face_with_a_hole_stay_off_the_hole():
    block = bundled("holed-block")
    top = max(block.faces, key=lambda f: f.normal[2]).index
    bottom = min(block.faces, key=lambda f: f.normal[2]).index
    r = soft_pair_regions(block, top, bottom, 0.5)
    assert r.certify().holds
    face = block.faces[top].polygon.to_shapely()
    import shapely

    assert shapely.Polygon(r.regions[0][0].uv).difference(face.buffer(1e-9)).area == 0


def test_soft_pair_certificate_rejects_an_oversized_region():
    """The exact certificate can fail: a region grown past the cone is caught, and the
    sampling check agrees."""
    cube = bundled("cube")
    r = soft_pair_regions(cube, 0, 1, 0.5)
    big = FacePatch.on(cube.faces[0], r.regions[0][0].uv * 2.5)
    from dataclasses import replace

    bad = replace(r, regions=((big,), r.regions[1]))
    assert not bad.certify().holds
    assert not sampling_check(bad, samples=2000).holds


def test_soft_pair_exact_check_by_hand_in_rationals():
    """Independent of the certificate's code: every region vertex pair, in Fractions,
    makes an angle with each inward normal below atan(mu) (tan^2 < mu^2)."""
    cube = bundled("cube")
    r = soft_pair_regions(cube, 2, 4, 0.3)
    n1 = [Fraction(x) for x in cube.faces[2].normal]
    for a in r.regions[0][0].points:
        for b in r.regions[1][0].points:
            x = [Fraction(q) - Fraction(p) for p, q in zip(a, b, strict=True)]
            along = -sum(u * v for u, v in zip(x, n1, strict=True))
            across2 = sum(u * u for u in x) - along * along
            assert along > 0 and across2 < Fraction(0.3) ** 2 * along * along


@settings(max_examples=12, deadline=None)
@given(st.floats(0.2, 5.0), st.tuples(*[st.floats(-3, 3)] * 3), unit_vectors,
       st.floats(0, 2 * np.pi))
def test_soft_pair_invariance(scale, shift, axis, angle):
    """Rotating, translating and scaling the object moves the regions with it: the best
    region's area scales with the square of the scale. Up to discretisation: the 16-gons
    and the 32-edge pyramids are oriented in the faces' own frames, which turn with the
    object only up to a rotation, so the area may differ by the polygon's and the
    pyramid's factors cos^2(pi/16) cos^2(pi/32), about 5%."""
    cube = bundled("hexagonal-prism")
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R = np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K
    moved = Polyhedron.from_arrays(cube.vertices @ R.T * scale + shift, cube.triangles)
    base = synthesize(cube, 2, "soft", 0.4, top=1, method="faces").found[0].min_area
    found = synthesize(moved, 2, "soft", 0.4, top=1, method="faces").found[0]
    bound = (math.cos(math.pi / 16) * math.cos(math.pi / 32)) ** 2
    assert bound <= found.min_area / (base * scale**2) <= 1 / bound
    assert found.certify().holds


def test_soft_pair_bad_input():
    cube = bundled("cube")
    with pytest.raises(InputError, match="no face 9"):
        soft_pair_regions(cube, 0, 9, 0.5)
    with pytest.raises(InputError, match="two different faces"):
        soft_pair_regions(cube, 1, 1, 0.5)
    with pytest.raises(InputError, match="mu must be a positive"):
        soft_pair_regions(cube, 0, 1, -1)
    assert soft_pair_regions(cube, 0, 2, 0.5) is None  # at right angles: no closure


# ---------------------------------------------------------------- §5.3 three hard fingers


@settings(max_examples=300, deadline=None)
@given(unit_vectors, unit_vectors, unit_vectors, st.floats(0.01, TAN30))
def test_the_fourth_class_needs_mu_above_tan_30(n1, n2, n3, mu):
    assert classify_three([n1, n2, n3], mu).number < 4


@settings(max_examples=200, deadline=None)
@given(unit_vectors, unit_vectors, unit_vectors, st.floats(0.01, 3.0))
def test_classification_counts_counter_overlapping_pairs(n1, n2, n3, mu):
    """Independently: C_i ∩ -C_j has an interior iff some direction is within alpha of
    both -n_i and n_j, i.e. the axes are less than 2 alpha apart."""
    N = [n1, n2, n3]
    c = classify_three(N, mu)
    pairs = [(i, j) for i in range(3) for j in range(i + 1, 3)
             if _angle(-N[i], N[j]) < 2 * math.atan(mu)]
    assert list(c.pairs) == pairs and c.number == len(pairs) + 1


def test_fourth_class_just_above_tan_30():
    t = np.radians([90, 210, 330])
    ring = np.column_stack([np.cos(t), np.sin(t), np.zeros(3)])
    assert classify_three(ring, TAN30 * 1.001).number == 4
    assert classify_three(ring, TAN30 * 0.999).number == 1
    assert counter_overlap([0, 0, 1], [0, 0, -1], 0.01)


@pytest.mark.parametrize("faces,cls", [((0, 1, 1), 3), ((2, 4, 5), 2)])
def test_three_hard_regions_on_the_cube(faces, cls):
    r = three_hard_regions(bundled("cube"), faces, 0.5)
    assert r.grasp_class.number == cls
    assert r.certify().holds
    check = sampling_check(r, samples=3000)
    assert check.holds, check.detail
    assert r.to_dict()["class"]["number"] == cls


def test_best_three_hard_on_a_prism_survive_sampling():
    found = synthesize(bundled("triangular-prism"), 3, "hard", 0.6, top=2, method="faces",
                       construction=three_hard_construction(max_faces=5)).found
    assert found
    for r in found:
        assert r.certify().holds and sampling_check(r, samples=1500).holds


# ---------------------------------------------------------------- §5.5 seven frictionless


@pytest.mark.long  # 10 s; test_constructions builds and checks the seven on the cube
def test_seven_frictionless_regions_exact_and_sampled():
    found = synthesize(bundled("cube"), 7, "frictionless", top=2, samples=8000).found
    assert found
    for r in found:
        cert = r.certify()
        assert cert.holds and "multi-affine" in cert.method
        assert all(len(region[0].points) <= 6 for region in r.regions)
        check = sampling_check(r, samples=2000)
        assert check.holds, check.detail


@pytest.mark.long  # 8 s
def test_seven_certificate_fails_on_a_region_too_large():
    """Widen one region to its whole face: the minors change sign at some vertex tuple,
    and sampling finds grasps that are not force-closure too."""
    from dataclasses import replace

    cube = bundled("cube")
    r = synthesize(cube, 7, "frictionless", top=1, samples=8000).found[0]
    face = cube.faces[r.regions[0][0].face]
    whole = FacePatch.on(face, face.polygon.outer)
    bad = SevenRegions(**{**{f: getattr(r, f) for f in r.__dataclass_fields__},
                          "regions": ((whole,), *r.regions[1:])})
    assert not bad.certify().holds
    assert not sampling_check(replace(bad), samples=4000).holds


def test_cofactor_signs_are_exact_on_degenerate_grasps():
    """Seven contacts on the top and bottom faces have wrenches of rank 3: every minor is
    exactly zero, which floating point alone would not say."""
    cube = bundled("cube")
    rng = np.random.default_rng(3)
    regions, normals = [], []
    for k in range(7):
        z = 1.0 if k % 2 else -1.0
        corners = np.column_stack([rng.uniform(-0.9, 0.9, (3, 2)), np.full(3, z)])
        regions.append(corners)
        normals.append([0, 0, z])
    pos, neg, zero = cofactor_signs(tuple(regions), np.array(normals, dtype=float))
    assert pos == neg == 0 and zero == 7 * 3**6
    assert cube is not None


# ---------------------------------------------------------------- regions on meshes


@pytest.mark.parametrize("name,fingers,model,mu", [
    ("duck.obj", 3, "hard", 0.5), ("bunny.obj", 2, "soft", 0.5),
    ("teddy2_VHACD_CHs.obj", 4, "hard", 0.4)])
def test_mesh_regions_on_pybullet_objects(name, fingers, model, mu):
    obj = load_object(os.path.join(pybullet_data.getDataPath(), name))
    [p] = prototype_grasps(obj, fingers, model, mu, samples=3000)
    r = zone_regions(obj, p, model, mu)
    assert r.certify().holds
    assert all(a > 0 for a in r.areas)
    check = sampling_check(r, samples=2000)
    assert check.holds, check.detail


def _fin_beside_a_cube():
    """A unit cube and, against its +x face, a fin of zero thickness: a closed shell of
    two squares back to back (normals +y and -y) sticking out to x = 2."""
    cube = bundled("cube")
    lo = cube.vertices.min(axis=0)
    side = np.ptp(cube.vertices, axis=0)
    fin = np.array([[1, 0.5, 0.1], [2, 0.5, 0.1], [2, 0.5, 0.9], [1, 0.5, 0.9]]) * side + lo
    # one square split along 0-2, the other, turned over, along 1-3: every edge twice
    tris = np.array([[0, 1, 2], [0, 2, 3], [1, 0, 3], [2, 1, 3]]) + len(cube.vertices)
    return Polyhedron.from_arrays(np.vstack([cube.vertices, fin]),
                                  np.vstack([cube.triangles, tris]), name="finned")


@pytest.mark.parametrize("name", ["fin", "random_urdfs/002"])
def test_prototypes_keep_their_side_of_a_fin(name):
    """A fin of zero thickness has two faces back to back, normals +y and -y, so a point
    on it is on both: snapping to the nearest face picked the wrong side. The top
    prototypes keep the face they were drawn on, and their regions are certified.
    random_urdfs/002 had such faces too, between two of its pieces pressed together:
    they were inside the object, and its outer surface has none left."""
    obj = (_fin_beside_a_cube() if name == "fin" else
           load_object(os.path.join(pybullet_data.getDataPath(), name, "002.obj")))
    points, faces = surface_samples(obj, 3000, np.random.default_rng(0))
    snapped = np.array([obj.locate(p)[0] for p in points])
    normal = np.array([f.normal for f in obj.faces])
    agree = np.einsum("ij,ij->i", normal[snapped], normal[faces])
    if name == "fin":
        assert np.any(agree < -0.99)
    else:
        assert np.all(agree > 0.99)
    for p in prototype_grasps(obj, 3, "hard", 0.5, count=3, samples=3000):
        r = zone_regions(obj, p, "hard", 0.5)
        assert r.certify().holds and sampling_check(r, samples=1000).holds


def test_mesh_regions_grow_across_faces():
    """On a curved mesh a region spans many one-triangle faces, and stays connected."""
    obj = load_object(os.path.join(pybullet_data.getDataPath(), "duck.obj"))
    [p] = prototype_grasps(obj, 3, "soft", 0.8, samples=2000, seed=1)
    r = zone_regions(obj, p, "soft", 0.8)
    assert max(len(region) for region in r.regions) > 3


def test_zone_certificate_needs_a_closed_hull():
    """Drop one facet of the prototype's hull: the facets no longer close up around the
    origin, so the zones prove nothing, and the certificate says so."""
    from dataclasses import replace

    r = zone_regions(bundled("cube"), [[0, 0, 1], [0.3, 0.3, -1], [-0.3, -0.3, -1]], "hard",
                     0.5, grow=False)
    z = r.zones
    keep = np.arange(1, len(z.facets))
    renumber = np.full(len(z.facets), -1)
    renumber[keep] = np.arange(len(keep))
    open_hull = replace(z, facets=z.facets[keep], offsets=z.offsets[keep],
                        simplices=z.simplices[keep], neighbors=renumber[z.neighbors[keep]])
    cert = replace(r, zones=open_hull).certify()
    assert not cert.holds and "close up" in cert.detail


@settings(max_examples=200, deadline=None)
@given(st.tuples(*[st.floats(-3, 3)] * 3))
def test_locate_on_the_cube_matches_the_closed_form(p):
    """Distance to the surface of the cube [-1, 1]^3: outside, the length of the excess
    over the box; inside, the distance to the nearest face."""
    p = np.array(p)
    cube = bundled("cube")
    face, uv, dist = cube.locate(p)
    excess = np.maximum(np.abs(p) - 1, 0)
    expected = np.linalg.norm(excess) if excess.any() else 1 - np.abs(p).max()
    assert dist == pytest.approx(expected, abs=1e-12)
    n = cube.faces[face].normal
    assert np.allclose(cube.faces[face].to_world(uv), p - (p @ n - 1) * n)


def test_zone_regions_bad_input():
    cube = bundled("cube")
    with pytest.raises(InputError, match="away from the surface"):
        zone_regions(cube, [[0, 0, 3], [0, 0, -1], [1, 0, 0]], "hard", 0.5)
    with pytest.raises(InputError, match="not force-closure"):
        zone_regions(cube, [[0, 0, 1], [0, 0, -1], [0.5, 0, -1]], "frictionless")
    with pytest.raises(InputError, match="seven points"):
        seven_frictionless_regions(cube, [[0, 0, 1]])
    with pytest.raises(InputError, match="samples must be at least 1"):
        prototype_grasps(cube, 3, "hard", 0.5, samples=0)


# ---------------------------------------------------------------- the command


def test_synthesize_spatial_json(tmp_path, capsys):
    import json

    from forceclosure.app.cli import main

    png = tmp_path / "regions.png"
    assert main(["synthesize", "cube", "--fingers", "3", "--contact", "hard", "--mu", "0.5",
                 "--top", "2", "--json", "--plot", str(png)]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["method"] == "faces" and len(record["grasps"]) == 2
    grasp = record["grasps"][0]
    assert set(grasp) >= {"faces", "regions", "areas", "min_area", "construction",
                          "certificate", "class", "prototype"}
    assert grasp["certificate"]["holds"] is True
    patch = grasp["regions"][0][0]
    assert set(patch) == {"face", "polygon", "area"} and len(patch["polygon"][0]) == 3
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_synthesize_spatial_text_and_mesh(capsys):
    from forceclosure.app.cli import main

    assert main(["synthesize", "cube", "--fingers", "2", "--contact", "soft", "--mu", "0.5",
                 "--top", "1"]) == 0
    out = capsys.readouterr().out
    assert "regions on faces (§5.2)" in out and "certified: True (exact vertex pairs)" in out
    bunny = os.path.join(pybullet_data.getDataPath(), "bunny.obj")
    assert main(["synthesize", bunny, "--fingers", "3", "--contact", "hard", "--mu", "0.6",
                 "--top", "1", "--samples", "2000"]) == 0
    out = capsys.readouterr().out
    assert "grown on the mesh" in out and "certified: True (search zones)" in out


@pytest.mark.long  # 9 s; §5.5 keeps two default tests (exact and sampled, too large)
def test_seven_minors_count_only_what_no_turn_of_the_normals_can_reach():
    """cofactor_signs with ``turn``: where it proves one sign for normals that may turn by
    t, random normals within t of the faces' (Theorem 1 through analyze, independently)
    all close the grasp; as t grows the proof gives way before the grasp does."""
    from forceclosure import Verdict, analyze, point_contact

    r = synthesize(bundled("cube"), 7, "frictionless", top=1).found[0]
    points = np.array([region[0].points.mean(axis=0) for region in r.regions])
    normals = np.array([r.polyhedron.faces[region[0].face].normal for region in r.regions])
    rng = np.random.default_rng(5)
    proved = []
    for t in (1e-6, 1e-3, 1e-2, 0.05, 0.2, 1.0):
        pos, neg, zero = cofactor_signs(tuple(p[None] for p in points), normals, [t] * 7)
        proved.append(zero == 0 and (pos == 0 or neg == 0))
        if not proved[-1]:
            continue
        for _ in range(200):
            axis = rng.normal(size=(7, 3))
            axis -= np.einsum("ij,ij->i", axis, normals)[:, None] * normals
            axis /= np.linalg.norm(axis, axis=1, keepdims=True)
            angle = rng.uniform(0, t, 7)[:, None]
            turned = np.cos(angle) * normals + np.sin(angle) * axis
            grasp = [point_contact(p, n, "frictionless") for p, n in zip(points, turned,
                                                                          strict=True)]
            assert analyze(grasp).verdict is Verdict.CLOSURE
    assert proved[0] and not proved[-1]
    assert proved == sorted(proved, reverse=True)  # once refused, refused for larger turns


def _turned(normals: np.ndarray, angle: float, rng: np.random.Generator) -> np.ndarray:
    """Each normal turned by a random angle up to ``angle`` (a quarter exactly ``angle``)
    about a random axis across it."""
    axis = rng.normal(size=normals.shape)
    axis -= np.sum(axis * normals, axis=-1, keepdims=True) * normals
    axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
    t = rng.uniform(0, angle, (*normals.shape[:-1], 1))
    t[rng.random(t.shape) < 0.25] = angle
    return np.cos(t) * normals + np.sin(t) * axis


def _frictionless_closure(points: np.ndarray, normals: np.ndarray) -> bool:
    """Seven frictionless wrenches close iff they have rank 6 and the one null vector has
    all entries strictly of one sign (Theorem 1, by singular values, not by our code)."""
    W = np.column_stack([np.concatenate([-n, np.cross(p - points.mean(axis=0), -n)])
                         for p, n in zip(points, normals, strict=True)])
    _, s, vt = np.linalg.svd(W)
    null = vt[-1] * np.sign(vt[-1].sum())
    return bool(s[5] > 1e-9 * s[0] and null.min() > 1e-9)


@pytest.mark.long
@pytest.mark.parametrize("name", ["cube", "l-prism"])
def test_seven_frictionless_regions_hold_for_normals_turned_by_the_margin(name):
    """With --margin t, every tuple of points in the seven regions closes for normals
    turned by up to t in any direction (at the regions' corners too); a larger margin
    gives smaller regions; the certificate says what it covers."""
    obj = bundled(name)
    small = synthesize(obj, 7, "frictionless", top=1, margin=1e-3, samples=8000).found[0]
    large = synthesize(obj, 7, "frictionless", top=1, margin=0.01, samples=8000).found[0]
    assert large.min_area < small.min_area
    assert "turned by up to 0.01 rad" in large.certify().detail
    rng = np.random.default_rng(4)
    for r, t in ((small, 1e-3), (large, 0.01)):
        points, normals = r.sample(300, seed=1)
        corners = [np.vstack([p.points for p in region]) for region in r.regions]
        picks = np.stack([c[rng.integers(len(c), size=300)] for c in corners], axis=1)
        points = np.concatenate([points, picks])
        normals = np.concatenate([normals, normals[:300]])
        for P, N in zip(points, normals, strict=True):
            assert _frictionless_closure(P, _turned(N, t, rng))


@pytest.mark.long  # 9 s
def test_frictionless_fingers_grown_on_a_mesh_hold_for_turned_normals():
    """Search zones for frictionless fingers (regions grown on the mesh) with a margin: every
    generator of the pyramid around the forces within the margin must reach its zones, so
    sampled tuples close with normals turned by the margin."""
    r = synthesize(bundled("cube"), 7, "frictionless", top=1, method="mesh",
                   margin=0.02).found[0]
    assert r.certify().holds and r.margin == 0.02
    rng = np.random.default_rng(6)
    points, normals = r.sample(500, seed=2)
    for P, N in zip(points, normals, strict=True):
        assert _frictionless_closure(P, _turned(N, 0.02, rng))
    # the check can fail: turned by 0.3 rad, some of the same tuples do not close
    assert not all(_frictionless_closure(P, _turned(N, 0.3, rng))
                   for P, N in zip(points, normals, strict=True))
