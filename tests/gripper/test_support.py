"""A support plane the hand must not cross (forceclosure.gripper.support).

Truths used: a box rests on one of its largest faces (its most stable pose, by the
quasi-static argument: the largest face holds the centre of mass lowest); the hand's boxes
are rebuilt here from the gripper's documented sizes (the jaw frame: x the approach, y the
closing axis; fingers from ``depth - finger_length`` to ``depth`` along x, their inner faces
at ``±(width / 2 + clearance)``, the palm behind them) and every vertex of every box, moved
to each returned pose, is tested against the plane here.
"""

import json

import numpy as np
import pytest
import trimesh

from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.gripper.collision import CLEARANCE
from forceclosure.gripper.grippers import gripper_named
from forceclosure.gripper.labels import grasp_labels
from forceclosure.gripper.support import SupportPlane, support_plane

BOX = trimesh.creation.box(extents=[0.05, 0.03, 0.02])  # rests on a 5 x 3 face: z = +-0.01
PANDA = gripper_named("panda")


def _hand_vertices(g, center, closing, approach, width, depth):
    """Every box vertex of the hand at one pose, rebuilt from the gripper's sizes."""
    c = CLEARANCE * g.width_max
    shift = depth - g.depth  # the fingertips at this depth, the hand moved along the approach
    x_tip = g.depth + shift
    x_base = x_tip - g.finger_length
    boxes = []
    for side in (-1, 1):
        y_in = side * (width / 2 + c)
        y_out = side * (width / 2 + c + g.finger_thickness)
        boxes.append(((x_base, x_tip), tuple(sorted((y_in, y_out))),
                      (-g.finger_height / 2, g.finger_height / 2)))
    boxes.append(((x_base - g.palm_thickness, x_base), (-g.palm_width / 2, g.palm_width / 2),
                  (-g.palm_height / 2, g.palm_height / 2)))
    a = approach - (approach @ closing) * closing
    a /= np.linalg.norm(a)
    R = np.column_stack([a, closing, np.cross(a, closing)])
    corners = np.array([[x, y, z] for (xs, ys, zs) in boxes for x in xs for y in ys for z in zs])
    return corners @ R.T + center


def _lowest(labels, plane):
    """Each pose's lowest hand vertex above the plane (negative: through the table)."""
    return np.array([min(_hand_vertices(PANDA, labels.center[i], labels.closing_axis[i],
                                        labels.approach_axis[i], labels.width[i],
                                        labels.depth[i]) @ plane.normal) - plane.offset
                     for i in range(len(labels))])


def test_a_box_rests_on_its_largest_face():
    plane = support_plane(BOX)
    assert np.allclose(np.abs(plane.normal), [0, 0, 1])
    assert plane.offset == pytest.approx(-0.01)
    # the normal points from the table into the box: the box's centre is above the plane
    assert plane.normal @ BOX.center_mass - plane.offset == pytest.approx(0.01)


def test_no_pose_crosses_the_plane():
    plane = support_plane(BOX)
    free = grasp_labels(BOX, PANDA, 0.5, 40, seed=3, epsilon=False)
    held = grasp_labels(BOX, PANDA, 0.5, 40, seed=3, epsilon=False, support=plane)
    # without the table, hands do reach through it: the check below can fail
    assert np.sum(_lowest(free, plane) < -1e-9) > 0
    assert len(held) > 0
    assert np.all(_lowest(held, plane) >= -1e-9)
    assert held.meta["support_plane"]["offset"] == pytest.approx(-0.01)
    # the contacts are on the box's surface
    half = np.array([0.025, 0.015, 0.01])
    assert np.allclose(np.max(np.abs(held.points) / half, axis=-1), 1.0, atol=1e-6)


def test_support_plane_refusals_and_cli(tmp_path, capsys):
    with pytest.raises(InputError, match="no use without it"):
        grasp_labels(BOX, PANDA, 0.5, 5, support=SupportPlane([0, 0, 1], -0.01),
                     collision=False)
    with pytest.raises(InputError, match="finite"):
        SupportPlane([0, 0, 0], 0.0)
    mesh = tmp_path / "box.stl"
    BOX.export(mesh)
    assert main(["grasps", str(mesh), "--gripper", "panda", "--count", "10", "--mu", "0.5",
                 "--support-plane", "--no-epsilon", "--approaches", "4", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert np.allclose(np.abs(summary["support_plane"]["normal"]), [0, 0, 1])
    assert main(["grasps", str(mesh), "--gripper", "panda", "--support-plane",
                 "--no-collision"]) == 2
    assert "--support-plane is part of the collision check" in capsys.readouterr().err
