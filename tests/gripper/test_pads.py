"""Where the pads touch, checked without the library's clipping: dense rays and closed forms.

The truth here is independent of :mod:`forceclosure.gripper.pads` and its
kernels: a grid of rays cast along the closing axis from behind each pad
(trimesh's ray queries) finds how far the surface under the pad reaches;
the first touch is the ray grid's extreme up to the surface's rise between
rays; a contact lies on the mesh (closest-point distance), under the pad,
within the pressed layer, with the normal of a face it lies on. The Panda's
poses on pybullet_data's duck are checked collision-free by manifold3d's
intersection volume of boxes built here from the built-in's sizes.
"""

from __future__ import annotations

import os

import numpy as np
import pybullet_data
import pytest
import trimesh

from forceclosure.errors import InputError
from forceclosure.gripper.grippers import GRIPPERS, gripper_named, make_gripper
from forceclosure.gripper.jaw import ParallelJaw, rectangle_mean_radius
from forceclosure.gripper.labels import grasp_labels
from forceclosure.gripper.pads import line_candidates, pad_contacts
from forceclosure.objects.io import load_object

D = pybullet_data.getDataPath()


@pytest.fixture(scope="module")
def duck():
    obj = load_object(os.path.join(D, "duck_vhacd.urdf"))
    return obj, grasp_labels(obj, gripper_named("panda"), 0.5, 60, seed=5, least_friction=False,
                             epsilon=False)


def _frame(labels, i):
    a, c = labels.approach_axis[i], labels.closing_axis[i]
    return a, c, np.cross(a, c)


def test_contacts_are_on_the_surface_under_the_pads_and_first_by_dense_rays(duck):
    obj, labels = duck
    mesh = obj.to_trimesh()
    hand = gripper_named("panda")
    size = obj.size
    # on the surface, and on a face whose normal is the contact's
    _, distance, tri = trimesh.proximity.closest_point(mesh, labels.points.reshape(-1, 3))
    assert distance.max() < 1e-9 * size
    normals = labels.normals.reshape(-1, 3)
    on_face = np.abs(np.einsum("ij,ij->i", mesh.face_normals[tri], normals))
    assert np.mean(on_face > 1 - 1e-9) > 0.9  # a vertex or edge may show one face of several
    for i in range(len(labels)):
        a, c, b = _frame(labels, i)
        rel = labels.points[i] - labels.center[i]
        x, y, z = rel @ a, rel @ c, rel @ b
        # under the pad: from the tips back by the pad's length, across by its height
        assert np.all(x <= labels.depth[i] + 1e-12)
        assert np.all(x >= labels.depth[i] - hand.pad_length - 1e-12)
        assert np.all(np.abs(z) <= 0.5 * hand.pad_height + 1e-12)
        # pressed at most the compliance past the pads' faces, which stand at -+ width/2
        assert -0.5 * labels.width[i] - 1e-12 <= y[0] <= -0.5 * labels.width[i] + \
            hand.pad_compliance + 1e-12
        assert 0.5 * labels.width[i] - hand.pad_compliance - 1e-12 <= y[1] <= \
            0.5 * labels.width[i] + 1e-12
        # dense rays over the pad from outside each jaw: nothing of the surface stands
        # beyond the pads' faces, and the surface reaches them (to the rise between rays)
        k = 41
        xs = np.linspace(labels.depth[i] - hand.pad_length, labels.depth[i], k)
        zs = np.linspace(-0.5 * hand.pad_height, 0.5 * hand.pad_height, k)
        X, Z = (g.ravel() for g in np.meshgrid(xs, zs))
        grid = labels.center[i] + X[:, None] * a + Z[:, None] * b
        for sign in (-1.0, 1.0):
            start = grid + sign * size * c
            hit, ray, _ = mesh.ray.intersects_location(start, np.repeat(-sign * c[None], k * k, 0),
                                                       multiple_hits=True)
            reach = sign * (hit - labels.center[i]) @ c  # how far out each hit stands
            first = np.full(k * k, -np.inf)
            np.maximum.at(first, ray, reach)
            assert first.max() <= 0.5 * labels.width[i] + 1e-9 * size
            step = hand.pad_length / (k - 1)
            assert first.max() >= 0.5 * labels.width[i] - 2 * step  # a slope of at most 2


def test_a_flat_face_pressed_flat_touches_at_the_pads_middle_and_a_tilt_by_the_rim():
    # a 4 x 4 x 1 slab: pads 1 x 1 close along z; head-on the whole pad presses, evenly: the
    # centre of pressure is the pad's middle; tilted by t about the approach axis, the face
    # rises by tan(t) per unit across the pad: pressed 0.05 deep over a rise of 0.1, the
    # pressure falls linearly from the rim first touched (across = +0.5) to nothing halfway:
    # its centre is a third of that half, a sixth of the pad, in from the rim
    slab = trimesh.creation.box(extents=[4, 4, 1])
    tris = np.arange(len(slab.faces))
    for t, across in ((0.0, 0.0), (np.arctan(0.1), 0.5 - 1 / 6)):
        c = np.array([[0.0, np.sin(t), np.cos(t)]])  # closing, tilted about x
        a = np.array([[1.0, 0.0, 0.0]])
        pc = pad_contacts(slab, np.zeros((1, 3)), c, a, np.array([0.5]), 1.0, 1.0,
                          np.zeros(len(tris), int), tris, 5.75, 0.05)
        b = np.cross(a[0], c[0])
        rel = pc.points[0, 0]
        assert rel[2] == pytest.approx(-0.5)  # on the bottom face
        assert rel @ a[0] == pytest.approx(0.0, abs=1e-12)  # the pad's middle along x
        assert rel @ b == pytest.approx(across, abs=1e-9)
        np.testing.assert_allclose(pc.normals[0, 0], [0, 0, -1])
        if t == 0:  # pressed evenly: the torsional lever is the square's mean radius, from
            # below (the closed form of rectangle_mean_radius, itself checked below)
            truth = rectangle_mean_radius(1.0, 1.0)
            assert 0.97 * truth <= pc.lever[0, 0] <= truth


def test_candidates_never_miss_a_triangle_that_reaches_the_line():
    rng = np.random.default_rng(3)
    mesh = trimesh.creation.icosphere(subdivisions=2)
    origins = rng.normal(size=(30, 3)) * 0.5
    directions = rng.normal(size=(30, 3))
    directions /= np.linalg.norm(directions, axis=1)[:, None]
    line, tri = line_candidates(mesh, origins, directions, 0.2)
    kept = set(zip(line.tolist(), tri.tolist(), strict=True))
    # a triangle's points within 0.2 of a line (dense samples of the triangle) must be kept
    w = rng.dirichlet(np.ones(3), size=200)
    for t, face in enumerate(mesh.faces):
        pts = w @ mesh.vertices[face]
        for i in range(30):
            d = pts - origins[i]
            perp = d - np.outer(d @ directions[i], directions[i])
            if np.linalg.norm(perp, axis=1).min() <= 0.2:
                assert (i, t) in kept


def _panda_parts(width, clearance):
    """The real Panda hand's collision meshes (pybullet_data's hand.obj and finger.obj, as
    panda.urdf mounts them) in the hand's frame, fingers opened to ``width/2 + clearance``
    each: their convex hulls (which hold the meshes), for manifold3d."""
    folder = os.path.join(D, "franka_panda", "meshes", "collision")
    hand = trimesh.load(os.path.join(folder, "hand.obj"), force="mesh").convex_hull
    finger = trimesh.load(os.path.join(folder, "finger.obj"), force="mesh").convex_hull
    q = 0.5 * width + clearance
    left = finger.copy().apply_translation([0, q, 0.0584])  # panda_finger_joint1: +y
    right = finger.copy().apply_transform(trimesh.transformations.rotation_matrix(
        np.pi, [0, 0, 1])).apply_translation([0, -q, 0.0584])  # joint2: -y, turned about z
    return [hand, left, right]


def test_panda_poses_on_the_duck_are_clear_for_the_real_hand(duck):
    """Each clear pose, with the Panda's own meshes placed at it (its base frame behind the
    fingertips by the tip offset less the pose's depth; z the approach, y the closing axis),
    meets the duck in no volume (manifold3d)."""
    obj, labels = duck
    mesh = obj.to_trimesh()
    hand = gripper_named("panda")
    clear = np.flatnonzero(~labels.collides)
    assert len(clear) >= 0.9 * len(labels)  # the search finds clear poses
    for i in clear[:8]:
        a, c = labels.approach_axis[i], labels.closing_axis[i]
        T = np.eye(4)
        T[:3, :3] = np.column_stack([np.cross(c, a), c, a])  # x = y × z
        T[:3, 3] = labels.center[i] - (hand.tip_offset - labels.depth[i]) * a
        for part in _panda_parts(labels.width[i], 0.01 * hand.width_max):
            common = trimesh.boolean.intersection([mesh, part.copy().apply_transform(T)],
                                                  engine="manifold")
            assert common.is_empty or common.volume < 1e-12
        # and the fingertips' pads reach the contacts: each contact lies between the
        # finger's base and its tip along the approach axis
        along = (labels.points[i] - T[:3, 3]) @ a
        assert np.all((along >= 0.0584) & (along <= hand.tip_offset + 1e-12))


def test_built_in_hands_match_their_sources():
    panda = gripper_named("panda")
    # pybullet_data's panda.urdf: fingers slide 0 to 0.04 each, mounted 0.0584 ahead of the
    # hand frame; finger.obj is 0.0538 long; hand.obj reaches 0.066 ahead and 0.0259 behind
    assert panda.width_max == pytest.approx(2 * 0.04)
    assert panda.tip_offset == pytest.approx(0.0584 + 0.0538)
    assert panda.tip_offset - panda.finger_length == pytest.approx(0.066)
    assert panda.tip_offset - panda.finger_length - panda.palm_thickness == \
        pytest.approx(-0.0259)
    finger = trimesh.load(os.path.join(D, "franka_panda", "meshes", "collision", "finger.obj"),
                          force="mesh")
    hand = trimesh.load(os.path.join(D, "franka_panda", "meshes", "collision", "hand.obj"),
                        force="mesh")
    lo, hi = finger.bounds
    assert hi[2] - lo[2] == pytest.approx(0.0538, abs=1e-4)
    assert panda.finger_height >= hi[0] - lo[0] - 1e-4  # the box encloses the finger
    assert panda.finger_thickness >= hi[1] - lo[1] - 1e-4
    lo, hi = hand.bounds
    assert panda.palm_width >= hi[1] - lo[1] - 1e-4 and panda.palm_height >= hi[0] - lo[0] - 1e-4
    # graspnetAPI's collision model: height 0.02, depth_base 0.02, finger_width 0.01
    g = gripper_named("graspnet")
    assert (g.finger_height, g.finger_thickness, g.palm_thickness) == (0.02, 0.01, 0.01)
    assert g.finger_length - g.depth == pytest.approx(0.02 + 0.02)  # palm 0.02 behind, depth 0.02
    assert sorted(GRIPPERS) == ["graspnet", "panda", "robotiq-2f85"]
    assert make_gripper(width=0.1) == ParallelJaw(0.1)


def test_pad_torsion_is_the_rectangles_mean_radius():
    # the mean distance from a rectangle's centre, by a fine midpoint rule
    for length, height in ((2.0, 2.0), (0.0175, 0.0175), (1.0, 0.2)):
        n = 1000
        u = (np.arange(n) + 0.5) / n - 0.5
        X, Y = np.meshgrid(u * length, u * height)
        assert rectangle_mean_radius(length, height) == pytest.approx(
            float(np.hypot(X, Y).mean()), rel=1e-5)
    hand = gripper_named("panda")
    assert hand.torsion(0.5) == pytest.approx(0.5 * rectangle_mean_radius(0.0175, 0.0175))
    assert make_gripper("panda", pad_radius=0).torsion(0.5) is None


def test_contacts_on_a_convex_decomposition_are_on_its_outer_surface(duck):
    # the duck's URDF is overlapping convex pieces (V-HACD): read here from the OBJ with
    # trimesh, scaled as the URDF says (0.05), no contact lies inside any piece
    _, labels = duck
    pieces = trimesh.load(os.path.join(D, "duck_vhacd.obj"), force="mesh").split(
        only_watertight=False)
    assert len(pieces) >= 4
    points = labels.points.reshape(-1, 3)
    for piece in pieces:
        piece.apply_scale(0.05)
        inside = trimesh.proximity.signed_distance(piece, points)  # positive inside
        assert inside.max() < 1e-9


def test_the_fused_pass_is_the_batched_kernels_to_the_bit(duck):
    """pad_contacts' one compiled pass over the poses against its kernel-per-step path, on
    the duck's labelled poses perturbed as robust_labels perturbs them (a fixed seed): the
    same contacts, first touches, levers and verdicts, bit for bit."""
    from forceclosure.analysis.two_finger import pair_codes
    from forceclosure.gripper.pads import pad_reach

    obj, labels = duck
    mesh = obj.to_trimesh()
    hand = gripper_named("panda")
    rng = np.random.default_rng(7)
    k = 40
    origin = np.repeat(labels.center, k, axis=0) + 0.002 * rng.standard_normal(
        (len(labels) * k, 3))
    closing = np.repeat(labels.closing_axis, k, axis=0) + 0.05 * rng.standard_normal(
        (len(origin), 3))
    closing /= np.linalg.norm(closing, axis=1)[:, None]
    approach = np.repeat(labels.approach_axis, k, axis=0)
    approach -= np.einsum("ij,ij->i", approach, closing)[:, None] * closing
    approach /= np.linalg.norm(approach, axis=1)[:, None]
    depth = np.repeat(labels.depth, k)
    line, tri = line_candidates(mesh, origin, closing,
                                pad_reach(depth, hand.pad_length, hand.pad_height))
    run = [pad_contacts(mesh, origin, closing, approach, depth, hand.pad_length,
                        hand.pad_height, line, tri, obj.size, hand.pad_compliance, engine=e)
           for e in ("fused", "batched")]
    for name in ("points", "normals", "triangles", "touched", "first", "lever"):
        assert np.array_equal(getattr(run[0], name), getattr(run[1], name)), name
    held = run[0].holds(hand.width_max, obj.size)
    assert held.mean() > 0.5
    codes = [pair_codes(r.points[held], r.normals[held], 0.5, "soft", 0.5 * r.lever[held])
             for r in run]
    assert np.array_equal(*codes) and 0 < (codes[0] == 2).mean() < 1
    with pytest.raises(InputError, match="engine"):
        pad_contacts(mesh, origin[:1], closing[:1], approach[:1], depth[:1], 0.01, 0.01,
                     line[:1] * 0, tri[:1], obj.size, engine="gpu")
