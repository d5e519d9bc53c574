"""Parallel-jaw grasps on meshes: contacts by ray casting, antipodal sampling, labels.

Every expectation is independent of the code under test: contacts on analytic
planes (a box, a cylinder's caps and facets) or from trimesh's own pure-numpy
ray queries; least friction from Corollary 3 in closed form (tan of the angle
between the jaws' line and the normals, exact when the normals are
antiparallel); the known fact that two hard fingers never close a spatial
grasp (rank 5).
"""

import json
import os

import numpy as np
import pybullet_data
import pytest
import trimesh
from trimesh.ray.ray_triangle import RayMeshIntersector

from forceclosure.app.cli import ANY_POSITIVE, main
from forceclosure.errors import InputError
from forceclosure.gripper.antipodal import sample_antipodal
from forceclosure.gripper.jaw import (
    INSIDE,
    MISSES,
    TOO_WIDE,
    JawPose,
    ParallelJaw,
    contacts_of,
    pose_from_contacts,
)
from forceclosure.gripper.labels import grasp_labels, label_grasps
from forceclosure.objects.io import load_object

BUNNY = os.path.join(pybullet_data.getDataPath(), "bunny.obj")
BOX = trimesh.creation.box(extents=(2.0, 4.0, 6.0))  # half-extents 1, 2, 3


def _angle(u, v):
    u, v = np.asarray(u, float), np.asarray(v, float)
    c = np.dot(u, v) / np.linalg.norm(u) / np.linalg.norm(v)
    return float(np.arccos(np.clip(c, -1, 1)))


def _labels(c, mu, contact="soft", torsion=None):
    code, mu_star, eps = label_grasps(c.points[None], c.normals[None], mu, contact, torsion)
    return int(code[0]), float(mu_star[0]), float(eps[0])


# --- the box ------------------------------------------------------------------------------


def test_box_pinch_across_opposite_faces():
    c = contacts_of(BOX, JawPose([0.0, 0.7, -1.2], [1, 0, 0], [0, 0, 1], 2.5))
    assert c.ok
    np.testing.assert_allclose(c.points, [[-1, 0.7, -1.2], [1, 0.7, -1.2]], atol=1e-12)
    np.testing.assert_allclose(c.normals, [[-1, 0, 0], [1, 0, 0]], atol=1e-12)
    code, mu_star, eps = _labels(c, 0.2)
    assert code == 2 and eps > 0
    assert mu_star < ANY_POSITIVE  # head-on: any positive friction closes it (within tolerance)
    # two hard fingers never close a spatial grasp: rotation about their line is free
    assert _labels(c, 0.2, "hard")[0] == 0
    assert np.isinf(_labels(c, 0.2, "hard")[1])


@pytest.mark.parametrize("theta", [0.1, 0.3, 0.5])
def test_box_tilted_pose_least_friction_is_tan_of_tilt(theta):
    axis = [np.cos(theta), np.sin(theta), 0.0]
    c = contacts_of(BOX, JawPose([0.0, 0.0, 0.5], axis, [0, 0, 1], 3.0))
    t = np.tan(theta)
    np.testing.assert_allclose(c.points, [[-1, -t, 0.5], [1, t, 0.5]], atol=1e-12)
    code, mu_star, _ = _labels(c, 1.2 * t)
    assert code == 2
    assert mu_star == pytest.approx(t, rel=1e-5)  # Corollary 3, antiparallel normals
    assert _labels(c, 0.8 * t)[0] == 0


def test_pads_with_torsion_still_close_a_head_on_pinch():
    gripper = ParallelJaw(3.0, pad_radius=0.1)
    assert gripper.torsion(0.3) == pytest.approx(2 / 3 * 0.3 * 0.1)
    c = contacts_of(BOX, JawPose([0.0, 0.5, 0.5], [1, 0, 0], [0, 0, 1], 2.5), gripper)
    assert _labels(c, 0.3, "soft", gripper.torsion(0.3))[0] == 2


def test_reasons_for_no_pair():
    gripper = ParallelJaw(2.4)
    assert contacts_of(BOX, JawPose([0, 0, 0], [1, 0, 0], [0, 0, 1], 2.5), gripper).reason \
        == TOO_WIDE
    # the box is 2 wide along x: jaws 1.5 apart start inside it
    assert contacts_of(BOX, JawPose([0, 0, 0], [1, 0, 0], [0, 0, 1], 1.5)).reason == INSIDE
    # a line beside the box meets nothing
    assert contacts_of(BOX, JawPose([0, 2.5, 0], [1, 0, 0], [0, 0, 1], 3)).reason == MISSES
    # the box lies beyond the second jaw: nothing between the jaws
    assert contacts_of(BOX, JawPose([-3, 0, 0], [1, 0, 0], [0, 0, 1], 1.5)).reason == MISSES
    with pytest.raises(InputError, match="parallel"):
        JawPose([0, 0, 0], [1, 0, 0], [2, 0, 0], 1.0)
    with pytest.raises(InputError, match="width"):
        JawPose([0, 0, 0], [1, 0, 0], [0, 1, 0], 0.0)
    with pytest.raises(InputError, match="width_max"):
        ParallelJaw(float("nan"))
    with pytest.raises(InputError, match="pad_radius"):
        ParallelJaw(1.0, pad_radius=-0.1)
    assert ParallelJaw(np.int64(2)).width_max == 2
    with pytest.raises(InputError, match="polygon"):
        contacts_of("wrench-head", JawPose([0, 0, 0], [1, 0, 0], [0, 1, 0], 1.0))


# --- the sphere and the cylinder -----------------------------------------------------------


SPHERE = trimesh.creation.icosphere(subdivisions=4)  # centrally symmetric, radius 1


def _reference_hit(mesh, origin, direction):
    """The first triangle and point by trimesh's pure-numpy ray queries."""
    ref = RayMeshIntersector(mesh)
    tri = ref.intersects_first([origin], [direction])[0]
    loc, _, tris = ref.intersects_location([origin], [direction], multiple_hits=True)
    k = np.argmin(np.linalg.norm(loc - origin, axis=1))
    assert tris[k] == tri
    a, b, c = mesh.vertices[mesh.faces[tri]]
    n = np.cross(b - a, c - a)
    return tri, loc[k], n / np.linalg.norm(n)


def test_sphere_pairs_through_the_centre_need_almost_no_friction():
    rng = np.random.default_rng(3)
    for d in rng.normal(size=(8, 3)):
        d /= np.linalg.norm(d)
        c = contacts_of(SPHERE, JawPose([0, 0, 0], d, np.cross(d, [0.6, 0.8, 0]), 2.5))
        _, _, n_p = _reference_hit(SPHERE, -1.25 * d, d)
        _, _, n_q = _reference_hit(SPHERE, 1.25 * d, -d)
        np.testing.assert_allclose(n_q, -n_p, atol=1e-12)  # antiparallel: Corollary 3 exact
        mu_star = _labels(c, 0.3)[1]
        assert mu_star == pytest.approx(np.tan(_angle(d, -n_p)), rel=1e-4, abs=ANY_POSITIVE)
        assert mu_star < 0.06  # facets of a 4-times subdivided icosahedron turn < 3.5 degrees


@pytest.mark.parametrize("h", [0.3, 0.6])
def test_sphere_off_centre_chord_least_friction(h):
    """On the round sphere, a chord at distance h from the centre closes two soft fingers iff
    mu > tan(asin h) (Corollaries 3 and 4: an internal force must run along the chord); the
    facets' normals turn by at most ``delta`` from the radius, which bounds the difference."""
    sphere = trimesh.creation.icosphere(subdivisions=5)
    rng = np.random.default_rng(int(h * 10))
    for _ in range(4):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        e = np.cross(d, rng.normal(size=3))
        e /= np.linalg.norm(e)
        c = contacts_of(sphere, JawPose(h * e, d, e, 2.5))
        deltas = [_angle(n, p) for n, p in zip(c.normals, c.points, strict=True)]
        mu_star = _labels(c, 1.0)[1]
        assert abs(np.arctan(mu_star) - np.arcsin(h)) <= 2 * max(deltas) + 1e-6


def test_cylinder_caps_and_sides():
    n = 64
    cyl = trimesh.creation.cylinder(radius=1.0, height=2.0, sections=n)
    theta = 0.25  # across the caps, tilted: mu* = tan(theta)
    c = contacts_of(cyl, JawPose([0, 0, 0], [np.sin(theta), 0, np.cos(theta)], [1, 0, 0], 3))
    np.testing.assert_allclose(c.normals, [[0, 0, -1], [0, 0, 1]], atol=1e-12)
    np.testing.assert_allclose(c.points[:, 2], [-1, 1], atol=1e-12)
    assert _labels(c, 0.5)[1] == pytest.approx(np.tan(theta), rel=1e-5)
    # across the side through the axis at azimuth psi: facet k spans [k, k+1] * 2 pi / n,
    # its normal at (k + 1/2) * 2 pi / n, the opposite facet's antiparallel
    for psi in (0.03, 0.51, 2.0):
        d = np.array([np.cos(psi), np.sin(psi), 0.0])
        c = contacts_of(cyl, JawPose([0, 0, 0.2], -d, [0, 0, 1], 3))
        step = 2 * np.pi / n
        normal_azimuth = (np.floor(psi / step) + 0.5) * step
        np.testing.assert_allclose(c.normals[0], [np.cos(normal_azimuth),
                                                  np.sin(normal_azimuth), 0], atol=1e-9)
        assert _labels(c, 0.5)[1] == pytest.approx(np.tan(abs(psi - normal_azimuth)),
                                                   rel=1e-4, abs=ANY_POSITIVE)


# --- ray casting against trimesh's own queries ---------------------------------------------


def test_jaw_contacts_agree_with_trimesh_ray_queries_on_the_bunny():
    bunny = load_object(BUNNY)
    mesh = bunny.to_trimesh()
    centre = bunny.vertices.mean(axis=0)
    rng = np.random.default_rng(7)
    hits = 0
    for _ in range(25):
        d = rng.normal(size=3)
        d /= np.linalg.norm(d)
        pose = JawPose(centre + rng.normal(scale=0.2, size=3), d, np.cross(d, [0, 0, 1]), 3.0)
        c = contacts_of(bunny, pose)
        jaws = pose.jaws
        tri = RayMeshIntersector(mesh).intersects_first(jaws, [d, -d])
        if c.reason == MISSES:
            continue  # (misses are checked on the box)
        assert (tri >= 0).all()
        for k in range(2):
            ref_tri, ref_point, ref_normal = _reference_hit(mesh, jaws[k], (d, -d)[k])
            np.testing.assert_allclose(c.points[k], ref_point, atol=1e-6 * bunny.size)
            if c.triangles[k] == ref_tri:
                np.testing.assert_allclose(c.normals[k], ref_normal, atol=1e-9)
        if c.ok:
            hits += 1
            # outward normals face their jaws
            assert np.dot(c.normals[0], d) < 0 < np.dot(c.normals[1], d)
    assert hits >= 10


def test_round_trip_pose_contacts_pose():
    s = sample_antipodal(BUNNY, 0.5, 40, seed=2, width_max=1.5)
    for i in range(len(s)):
        p, q = s.points[i]
        pose = pose_from_contacts(p, q, approach=s.approach_axis[i])
        np.testing.assert_allclose(pose.approach_axis @ pose.closing_axis, 0, atol=1e-12)
        back = contacts_of(BUNNY, pose, ParallelJaw(1.5))
        assert back.ok, back.reason
        np.testing.assert_allclose(back.points, s.points[i], atol=1e-9)
        np.testing.assert_allclose(back.normals, s.normals[i], atol=1e-12)
    # and the other way: a box pose, its contacts, the pose again
    pose = JawPose([0.0, 0.3, 0.4], [1, 0.2, 0], [0, 0, 1], 2.5)
    again = pose_from_contacts(*contacts_of(BOX, pose).points, approach=[0, 0, 1])
    np.testing.assert_allclose(again.center, pose.center, atol=1e-12)
    np.testing.assert_allclose(again.closing_axis, pose.closing_axis, atol=1e-12)
    np.testing.assert_allclose(again.approach_axis, [0, 0, 1], atol=1e-12)


# --- the sampler ---------------------------------------------------------------------------


def test_sampler_is_deterministic_and_its_lines_lie_in_the_cones():
    mu = 0.4
    a = sample_antipodal(BOX, mu, 300, seed=11, width_max=5.0)
    b = sample_antipodal(BOX, mu, 300, seed=11, width_max=5.0)
    c = sample_antipodal(BOX, mu, 300, seed=12, width_max=5.0)
    assert len(a) == 300
    for name in ("center", "closing_axis", "approach_axis", "width", "points", "normals"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.allclose(a.points, c.points)
    half = np.array([1.0, 2.0, 3.0])
    for (p, q), (n_p, n_q) in zip(a.points, a.normals, strict=True):
        for x, n in ((p, n_p), (q, n_q)):  # on a face of the box, with that face's normal
            axis = int(np.argmax(np.abs(x) / half))
            assert abs(x[axis]) == pytest.approx(half[axis], abs=1e-12)
            np.testing.assert_allclose(n, np.sign(x[axis]) * np.eye(3)[axis], atol=1e-12)
        assert _angle(q - p, -n_p) < np.arctan(mu)  # inside the first contact's cone
        assert np.linalg.norm(q - p) <= 5.0
    np.testing.assert_allclose(np.einsum("ij,ij->i", a.approach_axis, a.closing_axis), 0,
                               atol=1e-12)


def test_sampler_refuses_lines_wider_than_the_opening():
    s = sample_antipodal(BOX, 0.3, 200, seed=0, width_max=2.5)
    assert len(s) == 200 and np.all(s.width <= 2.5)
    # opposite faces 4 and 6 apart (y, z) are out of reach; only x faces may be opposed
    opposed = np.einsum("ij,ij->i", s.normals[:, 0], s.normals[:, 1]) < -0.5
    assert opposed.any()
    np.testing.assert_allclose(np.abs(s.normals[opposed][:, :, 0]), 1, atol=1e-12)
    assert s.rejected[INSIDE] > 0  # jaw 2, width_max from the first contact, is inside
    # narrower than the box everywhere: only chords across a corner, between adjacent faces
    corner = sample_antipodal(BOX, 0.3, 50, seed=0, width_max=1.5)
    assert np.all(corner.width <= 1.5)
    np.testing.assert_allclose(np.einsum("ij,ij->i", *corner.normals.transpose(1, 0, 2)), 0,
                               atol=1e-12)
    with pytest.raises(InputError, match="mu"):
        sample_antipodal(BOX, 0.0, 10)


def test_labels_of_sampled_box_grasps_follow_corollary_3():
    mu = 0.4
    labels = grasp_labels(BOX, ParallelJaw(5.0, pad_radius=0), mu, 150, seed=4)  # paper's pads
    p, q = labels.points[:, 0], labels.points[:, 1]
    n_p, n_q = labels.normals[:, 0], labels.normals[:, 1]
    opposite = np.einsum("ij,ij->i", n_p, n_q) < -0.5
    # opposite faces: antiparallel normals, mu* = tan(max angle) exactly
    for i in np.flatnonzero(opposite):
        expected = np.tan(max(_angle(q[i] - p[i], -n_p[i]), _angle(p[i] - q[i], -n_q[i])))
        assert labels.least_friction[i] == pytest.approx(expected, rel=1e-5, abs=ANY_POSITIVE)
        assert labels.code[i] == (2 if expected < mu - 1e-6 else 0)
        # epsilon is of 8-edge inscribed pyramids, as closed as cones of friction mu cos(pi/8)
        if expected < mu * np.cos(np.pi / 8) - 1e-6:
            assert labels.epsilon[i] > 0
    assert np.all(labels.epsilon[labels.code != 2] == 0)
    record = labels.to_dict()
    assert len(record["verdict"]) == 150 and record["meta"]["mu"] == mu


# --- the command ---------------------------------------------------------------------------


def test_cli_grasps(tmp_path, capsys):
    out = tmp_path / "labels.npz"
    assert main(["grasps", "cube", "--width", "3", "--count", "60", "--mu", "0.3",
                 "--seed", "5", "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    with np.load(out) as saved:
        code = saved["code"]
        assert saved["points"].shape == (60, 2, 3)
        assert json.loads(str(saved["meta"]))["seed"] == 5
    assert summary["candidates"] == 60
    assert [summary[v] for v in ("none", "marginal", "closure")] == np.bincount(
        code, minlength=3).tolist()
    assert main(["grasps", "cube", "--width", "3", "--count", "10"]) == 0
    assert "closure" in capsys.readouterr().out
    for bad in (["--width", "0"], ["--width", "3", "--mu", "-1"],
                ["--width", "3", "--out", str(tmp_path / "x.json")],
                ["--width", "3", "--out", str(tmp_path / "no" / "x.npz")]):
        assert main(["grasps", "cube", "--count", "5", *bad]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "error" in err
    assert main(["grasps", "wrench-head", "--width", "3"]) == 2
    capsys.readouterr()
    assert main(["grasps", "cube", "--width", "3", "--count", "30", "--no-least-friction",
                 "--out", str(out)]) == 0
    assert "least friction: not computed" in capsys.readouterr().out
    with np.load(out) as saved:
        assert np.isnan(saved["least_friction"]).all() and len(saved["code"]) == 30


def test_cli_grasps_open_mesh_refused_unless_allowed(tmp_path, capsys):
    box = trimesh.creation.box()
    box.update_faces(np.arange(1, len(box.faces)))  # one triangle missing: open
    path = tmp_path / "open.stl"
    box.export(path)
    assert main(["grasps", str(path), "--width", "3", "--count", "20"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "open mesh" in err and "--allow-open" in err
    assert main(["grasps", str(path), "--width", "3", "--count", "20", "--allow-open",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["candidates"] == 20

