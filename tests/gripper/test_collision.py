"""Gripper-object collision against independent truth.

Boxes placed by hand on the 2-unit cube (which of them reach into it is read
off the coordinates); fingers closing on a cylinder, whose contact with a
finger box is decided in closed form (a disc against a slab); the hand's
boxes against manifold3d's boolean intersection volume on the bunny (a
different library from FCL); parts wholly inside the object, or the object
wholly inside a part, which FCL's surface tests alone cannot see.
"""

import json
import os

import numpy as np
import pybullet_data
import pytest
import trimesh

from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.gripper.antipodal import sample_antipodal
from forceclosure.gripper.collision import collides, hand_boxes, jaw_frames
from forceclosure.gripper.jaw import JawPose, ParallelJaw
from forceclosure.gripper.labels import grasp_labels
from forceclosure.objects.io import load_object

CUBE = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
#: a hand whose boxes are easy to place by hand: fingers x in [-0.3, 0.2] of the jaw frame,
#: 0.2 thick, 0.4 high; palm x in [-0.5, -0.3], 3.4 wide
HAND = ParallelJaw(3.0, depth=0.2, finger_length=0.5, finger_thickness=0.2, finger_height=0.4,
                   palm_thickness=0.2)


def test_boxes_in_the_jaw_frame():
    boxes = {name: (ext, c) for name, ext, c in hand_boxes(HAND, 2.0, clearance=0.05)}
    ext, c = boxes["jaw2"]
    # the second finger's inner face at y = width/2 + clearance, tip at x = depth
    assert c[1] - ext[1] / 2 == pytest.approx(1.05)
    assert c[0] + ext[0] / 2 == pytest.approx(0.2)
    ext, c = boxes["palm"]
    assert c[0] + ext[0] / 2 == pytest.approx(-0.3) and ext[1] == pytest.approx(3.4)
    assert "palm" not in {n for n, _, _ in hand_boxes(ParallelJaw(1.0, palm_thickness=0), 0.5)}


def test_palm_in_the_cube_or_clear_of_it():
    # pinch across x at height 0.8; the palm sits 0.3 to 0.5 behind the centre along the
    # approach: from above (approach -z) at z in [1.1, 1.3], clear of the cube (z <= 1);
    # from below (approach +z) at z in [0.3, 0.5], inside the cube's slab, 3.4 wide: it
    # crosses the cube's x faces. The fingers stand 1.02 off the axis, clear, either way.
    above = JawPose([0, 0, 0.8], [1, 0, 0], [0, 0, -1], 2.0)
    below = JawPose([0, 0, 0.8], [1, 0, 0], [0, 0, 1], 2.0)
    assert collides(CUBE, [above, below], HAND, clearance=0.02).tolist() == [False, True]
    # without a palm, the centre at the cube's middle: the fingers stand beside the cube
    # (|x| >= 1.02), clear; an opening narrower than the cube and they cut its faces
    assert not collides(CUBE, JawPose([0, 0, 0.0], [1, 0, 0], [0, 0, -1], 2.0), ParallelJaw(
        3.0, depth=0.2, finger_length=0.5, palm_thickness=0.0), clearance=0.02)
    assert collides(CUBE, JawPose([0, 0, 0.0], [1, 0, 0], [0, 0, -1], 1.9), ParallelJaw(
        3.0, depth=0.2, finger_length=0.5, palm_thickness=0.0), clearance=0.02)


def test_clearance_decides_a_touching_finger():
    # opened to exactly the cube's width, the pads touch its faces; a clearance frees them
    pose = JawPose([0, 0, 0.0], [1, 0, 0], [0, 0, -1], 2.0)
    fingers = ParallelJaw(3.0, palm_thickness=0.0)
    assert not collides(CUBE, pose, fingers, clearance=1e-3)
    assert collides(CUBE, JawPose([0, 0, 0.0], [1, 0, 0], [0, 0, -1], 1.998), fingers,
                    clearance=0.0)


@pytest.mark.parametrize("opening_share", [0.5, 0.8, 0.95])
def test_finger_tips_against_a_cylinder_in_closed_form(opening_share):
    # a cylinder of radius r along z (256 sides: its section lies within r(1 - 8e-5) and r);
    # the hand comes along +y from y < -r, fingers' inner faces at x = +-o/2. The finger box
    # (x in [o/2, o/2 + t], y up to the tip, |z| small) meets the disc x^2 + y^2 <= r^2 iff
    # the tip passes y = -sqrt(r^2 - (o/2)^2), the disc's lowest point at x = o/2.
    r = 1.0
    cyl = trimesh.creation.cylinder(radius=r, height=4.0, sections=256)
    o = 2 * r * opening_share
    gripper = ParallelJaw(3.0, depth=0.3, finger_length=0.6, finger_thickness=0.1,
                          finger_height=0.2, palm_thickness=0.0)  # the fingers alone
    threshold = -np.sqrt(r ** 2 - (o / 2) ** 2)
    for gap in (-0.02, 0.02):
        tip = threshold + gap  # the tips' y
        pose = JawPose([0, tip - gripper.depth, 0], [1, 0, 0], [0, 1, 0], o)
        assert collides(cyl, pose, gripper, clearance=0.0) == (gap > 0), (opening_share, gap)


def test_boxes_agree_with_manifold_boolean_volume_on_the_bunny():
    bunny = load_object(os.path.join(pybullet_data.getDataPath(), "bunny.obj"))
    mesh = bunny.to_trimesh()
    # small fingers (the bunny's antipodal pairs are mostly across its ears and face)
    gripper = ParallelJaw(0.6, depth=0.01, finger_length=0.03, finger_thickness=0.01,
                          finger_height=0.02, palm_thickness=0.01)
    s = sample_antipodal(bunny, 0.5, 40, 3, 0.6)
    # approach from outside: towards the centroid, made perpendicular to the closing axis
    # (the sampler's own approach axes nearly always put the palm into the bunny)
    inward = mesh.centroid - s.center
    approach = inward - np.einsum("ij,ij->i", inward, s.closing_axis)[:, None] * s.closing_axis
    poses = [JawPose(c, k, a, w) for c, k, a, w in zip(s.center, s.closing_axis, approach,
                                                        s.width, strict=True)]
    hit = collides(bunny, poses, gripper, clearance=0.03)
    frames = jaw_frames(s.center, s.closing_axis, approach)
    truth = []
    for i in range(len(hit)):
        volume = 0.0
        for _, ext, c in hand_boxes(gripper, s.width[i], clearance=0.03):
            T = frames[i].copy()
            T[:3, 3] += frames[i, :3, :3] @ c
            box = trimesh.creation.box(extents=ext, transform=T)
            common = trimesh.boolean.intersection([mesh, box], engine="manifold")
            volume += 0.0 if common.is_empty else common.volume
        truth.append(volume > 1e-12)
    assert hit.tolist() == truth
    assert 0 < sum(truth) < len(truth)  # both outcomes occur


def test_parts_wholly_inside_and_object_wholly_inside():
    big = trimesh.creation.box(extents=(20.0, 20.0, 20.0))
    pose = JawPose([0, 0, 0], [1, 0, 0], [0, 0, 1], 1.0)
    gripper = ParallelJaw(2.0)
    assert collides(big, pose, gripper)  # every box inside: no surface meets another
    # a small cube inside the palm box (palm x in [-0.8, -0.6] of the jaw frame: z here)
    tiny = trimesh.creation.box(extents=(0.05, 0.05, 0.05))
    tiny.apply_translation([0, 0, -0.7])
    assert collides(tiny, pose, gripper)
    tiny.apply_translation([0, 0, -1.0])
    assert not collides(tiny, pose, gripper)


def test_a_hand_mesh_instead_of_boxes():
    # a hand mesh given as is: one box of the palm's place; the object inside it, then clear
    hand = trimesh.creation.box(extents=(0.2, 3.4, 0.4))
    hand.apply_translation([-0.4, 0, 0])
    pose = JawPose([0, 0, 0.8], [1, 0, 0], [0, 0, 1], 2.0)
    assert collides(CUBE, pose, HAND, hand=hand)
    assert not collides(CUBE, JawPose([0, 0, 0.8], [1, 0, 0], [0, 0, -1], 2.0), HAND, hand=hand)
    with pytest.raises(InputError, match="hand must be a trimesh"):
        collides(CUBE, pose, HAND, hand="hand.stl")


# --- labels and the command ----------------------------------------------------------------


def _manifold_truth(mesh, gripper, centers, closing, approach, widths, clearance, depths):
    frames = jaw_frames(centers, closing, approach)
    truth = []
    for i in range(len(widths)):
        volume = 0.0
        for _, ext, c in hand_boxes(gripper, widths[i], clearance=clearance):
            c = c + np.array([depths[i] - gripper.depth, 0.0, 0.0])  # the pose's depth
            T = frames[i].copy()
            T[:3, 3] += frames[i, :3, :3] @ c
            box = trimesh.creation.box(extents=ext, transform=T)
            common = trimesh.boolean.intersection([mesh, box], engine="manifold")
            volume += 0.0 if common.is_empty else common.volume
        truth.append(volume > 1e-12)
    return truth


def test_labels_carry_collides_and_save_it(tmp_path):
    # on the 2-unit cube, one approach each: the palm, 1.1 to 1.2 behind the jaws' line, is
    # in the cube unless the line runs within 1.1 of the face's edge it comes from
    gripper = ParallelJaw(2.5, depth=0.1, finger_length=1.2, finger_thickness=0.05,
                          finger_height=0.1, palm_thickness=0.1, pad_length=0.2)
    labels = grasp_labels("cube", gripper, mu=0.1, count=40, seed=2, least_friction=False,
                          clearance=0.01, approaches=1, depths=1, tilt=1.0)
    truth = _manifold_truth(CUBE, gripper, labels.center, labels.closing_axis,
                            labels.approach_axis, labels.width, 0.01, labels.depth)
    assert labels.collides.tolist() == truth
    assert 0 < sum(truth) < len(truth)
    assert labels.meta["collision"]["clearance"] == 0.01
    labels.save(str(tmp_path / "l.npz"))
    with np.load(tmp_path / "l.npz") as saved:
        assert saved["collides"].tolist() == truth
    skipped = grasp_labels("cube", gripper, mu=0.3, count=5, least_friction=False,
                           collision=False)
    assert skipped.collides is None and skipped.meta["collision"] is None
    skipped.save(str(tmp_path / "s.npz"))
    with np.load(tmp_path / "s.npz") as saved:
        assert "collides" not in saved.files and "code" in saved.files


def test_cli_grasps_counts_colliding_grasps(tmp_path, capsys):
    out = tmp_path / "l.npz"
    assert main(["grasps", "cube", "--width", "3", "--count", "40", "--no-least-friction",
                 "--seed", "1", "--out", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    with np.load(out) as saved:
        hit, code = saved["collides"], saved["code"]
        truth = _manifold_truth(CUBE, ParallelJaw(3.0), saved["center"],
                                saved["closing_axis"], saved["approach_axis"], saved["width"],
                                0.03, saved["depth"])
    assert hit.tolist() == truth  # default clearance 0.01 x width, boxes from width_max
    assert summary["collides"] == sum(truth)
    assert summary["collides_closure"] == int(np.sum(hit & (code == 2)))
    assert summary["closure_clear"] == int(np.sum(~hit & (code == 2)))
    assert summary["closure"] == int(np.sum(code == 2))  # colliding grasps keep their verdict
    assert main(["grasps", "cube", "--width", "3", "--count", "10", "--no-least-friction",
                 "--no-collision"]) == 0
    assert "collision: not checked" in capsys.readouterr().out
    assert main(["grasps", "cube", "--width", "3", "--count", "5", "--clearance", "-1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--clearance" in err
