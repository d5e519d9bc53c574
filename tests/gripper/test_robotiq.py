"""The built-in Robotiq 2F-85 against its sources, and a grasp with it on pybullet_data's duck.

The truths here are written down from the sources, not read from the library:

* Robotiq's 2F-85 & 2F-140 Instruction Manual, section 6.1 (Specifications): the
  stroke (the opening between the pads) is 85 mm.
* Robotiq's description as ROS-Industrial ships it
  (``robotiq_2f_85_gripper_visualization/urdf/robotiq_arg2f_85_model_macro.xacro``): the
  pad is a box 0.022 (across) × 0.00635 (thick) × 0.0375 (along the approach axis); the
  outer knuckle turns about x at (0, ±0.0306011, 0.054904) from the mounting face, the
  outer finger is fixed to it at (0, 0.0315, -0.0041), the inner finger turns at
  (0, 0.0061, 0.0471) on the outer finger by the opposite angle, the pad is fixed at
  (0, -0.0220203446692936, 0.03242) on it, and the knuckle's range is 0 (open) to 0.81.

The four-bar linkage is followed here in the (y, z) plane, y the closing axis and z the
approach axis out of the mounting face: the pads stay parallel, are about 85 mm apart at
full opening and meet at the closed end, and the built-in's fingertips, pad and
opening are those of the open linkage.
"""

from __future__ import annotations

import os

import numpy as np
import pybullet_data
import pytest

from forceclosure.app.cli import main
from forceclosure.gripper.grippers import gripper_named, make_gripper
from forceclosure.gripper.labels import GraspLabels
from forceclosure.verdicts import VerdictCode

STROKE = 0.085  # Instruction Manual, section 6.1
PAD = (0.022, 0.00635, 0.0375)  # across, thick, along the approach axis (the description's box)


def _pad(q: float) -> tuple[np.ndarray, float]:
    """The right pad's centre (y, z) from the mounting face at knuckle angle ``q``, and the
    pad's own turn (0: parallel to the approach axis)."""

    def turn(angle, v):
        c, s = np.cos(angle), np.sin(angle)
        return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])

    knuckle = np.array([0.0306011, 0.054904])
    outer_finger = knuckle + turn(q, [0.0315, -0.0041])
    inner_joint = outer_finger + turn(q, [0.0061, 0.0471])
    pad_turn = q - q  # the inner finger turns back by the knuckle's angle (mimic -1)
    return inner_joint + turn(pad_turn, [-0.0220203446692936, 0.03242]), pad_turn


def test_the_linkage_is_a_parallel_jaw_of_the_stroke():
    centre, turn = _pad(0.0)
    opening = 2 * (centre[0] - PAD[1] / 2)
    assert turn == 0.0  # the pads stay parallel: a parallel jaw at the fingertips
    assert opening == pytest.approx(STROKE, abs=0.0015)  # 86.0 mm at the open end
    closed, _ = _pad(0.81)
    assert 2 * (closed[0] - PAD[1] / 2) == pytest.approx(0.0, abs=0.002)  # they meet
    advance = closed[1] - centre[1]  # the pads move forward as they close
    assert 0.0 < advance < 0.015


def test_the_built_in_is_the_open_linkage():
    hand = gripper_named("robotiq-2f85")
    centre, _ = _pad(0.0)
    assert hand.width_max == STROKE
    assert (hand.pad_height, hand.pad_length) == PAD[0::2]
    assert hand.tip_offset == pytest.approx(centre[1] + PAD[2] / 2, abs=1e-4)  # the tips
    assert hand.tip_offset - hand.depth == pytest.approx(centre[1], abs=1e-4)  # pad centre
    assert hand.pad_length <= hand.finger_length and hand.pad_height <= hand.finger_height
    # the finger box holds the pad and the inner finger behind it, outside the opening
    assert hand.finger_thickness >= PAD[1] + 0.006
    assert make_gripper("robotiq-2f85") is hand


def test_a_grasp_with_it_on_the_duck(tmp_path, capsys):
    """``grasps duck_vhacd.urdf --gripper robotiq-2f85``: poses it can take, each no wider
    than its stroke, its contacts under the pads (between the tips and the pad's length
    behind them along the approach axis), some closed and clear."""
    out = tmp_path / "duck.npz"
    assert main(["grasps", os.path.join(pybullet_data.getDataPath(), "duck_vhacd.urdf"),
                 "--gripper", "robotiq-2f85", "--mu", "0.5", "--count", "60", "--seed", "3",
                 "--no-epsilon", "--out", str(out)]) == 0
    assert "robotiq-2f85 gripper" in capsys.readouterr().out
    labels = GraspLabels.load(str(out))
    hand = gripper_named("robotiq-2f85")
    assert len(labels) > 0
    assert np.all(labels.width <= STROKE + 1e-12)
    clear_closed = (labels.code == VerdictCode.CLOSURE) & ~labels.collides
    assert clear_closed.sum() >= 0.2 * len(labels)
    for i in range(len(labels)):
        along = (labels.points[i] - labels.center[i]) @ labels.approach_axis[i]
        assert np.all(along <= labels.depth[i] + 1e-9)
        assert np.all(along >= labels.depth[i] - hand.pad_length - 1e-9)
        gap = (labels.points[i][1] - labels.points[i][0]) @ labels.closing_axis[i]
        assert abs(gap) <= STROKE + 1e-9
