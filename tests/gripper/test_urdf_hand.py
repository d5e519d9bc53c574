"""A user's hand from its URDF (forceclosure.gripper.urdf_hand).

Truths used, none from the code under test: the Panda's description as pybullet_data ships
it (panda.urdf's joint origins and limits, its collision meshes' bounds read with trimesh
directly here), the built-in ``panda`` measured by hand from the same files, a box hand
written here whose every size follows from its boxes, and the real files that are not
parallel-jaw hands (pybullet_data's PR2 gripper turns its fingers; its WSG-50 finger files
hold one link each).
"""

import json
from pathlib import Path

import numpy as np
import pybullet_data
import pytest
import trimesh

from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.gripper.grippers import gripper_named, make_gripper
from forceclosure.gripper.urdf_hand import gripper_from_urdf

DATA = Path(pybullet_data.getDataPath())
PANDA = DATA / "franka_panda" / "panda.urdf"
MESHES = DATA / "franka_panda" / "meshes" / "collision"

#: panda.urdf: the fingers' joints sit 0.0584 in front of panda_hand (z) and slide 0 to 0.04
#: along +y (left) and -y (right, its mesh turned half a turn about z).
FINGER_MOUNT, TRAVEL = 0.0584, 0.04


@pytest.fixture(scope="module")
def panda():
    return gripper_from_urdf(PANDA)


@pytest.fixture(scope="module")
def meshes():
    load = lambda name: trimesh.load(str(MESHES / name), force="mesh", process=False)  # noqa: E731
    return load("finger.obj"), load("hand.obj")


def test_panda_sizes_are_its_meshes_bounds(panda, meshes):
    finger, hand = meshes
    (fx0, fy0, fz0), (fx1, fy1, fz1) = finger.bounds
    (hx0, hy0, hz0), (hx1, hy1, hz1) = hand.bounds
    tip = FINGER_MOUNT + fz1
    assert panda.tip_offset == pytest.approx(tip, abs=1e-9)
    # the pads' planes at the open limit: each finger's innermost side (y = fy0) moved 0.04 out
    assert panda.width_max == pytest.approx(2 * TRAVEL + 2 * fy0, abs=1e-9)
    assert panda.finger_thickness == pytest.approx(fy1 - fy0, abs=1e-9)
    assert panda.finger_height == pytest.approx(2 * max(-fx0, fx1), abs=1e-9)
    # the fingers' free part: from the hand body's front face (z = hz1) to the tips
    assert panda.finger_length == pytest.approx(tip - hz1, abs=1e-9)
    assert panda.palm_thickness == pytest.approx(hz1 - min(hz0, FINGER_MOUNT + fz0), abs=1e-9)
    # the palm box is centred on the jaws' line: it encloses the (slightly off-centre) hand
    assert panda.palm_width == pytest.approx(2 * max(-hy0, hy1, TRAVEL + fy1), abs=1e-9)
    assert panda.palm_width >= hy1 - hy0
    assert panda.palm_height == pytest.approx(2 * max(-hx0, hx1), abs=1e-9)
    # the pad: the finger's vertices on its innermost plane (within 0.2 mm) span it
    flat = finger.vertices[finger.vertices[:, 1] <= fy0 + 2e-4]
    assert panda.pad_length == pytest.approx(fz1 - flat[:, 2].min(), abs=1e-9)
    assert panda.pad_height == pytest.approx(2 * min(-flat[:, 0].min(), flat[:, 0].max()),
                                             abs=1e-9)
    assert panda.depth == pytest.approx(panda.pad_length / 2)


@pytest.mark.parametrize("which, tolerance", [("urdf", 1e-9), ("builtin", 1e-4)])
def test_panda_boxes_enclose_its_meshes(panda, meshes, which, tolerance):
    """Every vertex of the opened Panda hand (its meshes placed here by panda.urdf's joints,
    the right finger turned half a turn about z) lies in the boxes of the model: the one read
    from the URDF exactly, the built-in to its rounding (0.1 mm), both opened to the pads'
    real gap."""
    from forceclosure.gripper.collision import hand_boxes

    finger, hand = meshes
    model = panda if which == "urdf" else gripper_named("panda")
    F = np.asarray(finger.vertices)
    left = F + np.array([0, TRAVEL, FINGER_MOUNT])
    right = F * np.array([-1, -1, 1]) + np.array([0, -TRAVEL, FINGER_MOUNT])
    centre = model.tip_offset - model.depth  # the jaw centre on the approach axis (z)
    boxes = hand_boxes(model, panda.width_max, clearance=0.0)
    for part in (left, right, np.asarray(hand.vertices)):
        # the jaw frame: x the approach (hand z), y the closing axis (hand y), z = x * y
        local = np.column_stack([part[:, 2] - centre, part[:, 1], -part[:, 0]])
        inside = np.zeros(len(local), bool)
        for _, extents, middle in boxes:
            inside |= np.all(np.abs(local - middle) <= extents / 2 + tolerance, axis=1)
        assert inside.all(), local[~inside][:3]


def test_panda_matches_the_builtin(panda):
    """The built-in was measured by hand from the same files (rounded to 0.1 mm)."""
    builtin = gripper_named("panda")
    for field in ("width_max", "tip_offset", "finger_length", "finger_thickness",
                  "finger_height", "palm_thickness", "palm_width", "palm_height", "pad_length",
                  "pad_height", "depth"):
        assert getattr(panda, field) == pytest.approx(getattr(builtin, field), abs=5e-4), field
    assert panda.name == "panda"


def test_the_palm_is_found_or_named(panda):
    # the whole robot's URDF: the fingers' nearest common parent is panda_hand
    assert gripper_from_urdf(PANDA, palm_link="panda_hand") == panda
    assert gripper_from_urdf(PANDA, finger_links=("panda_leftfinger", "panda_rightfinger")
                             ) == panda
    # panda_link8 holds the hand fixed, turned 45 degrees about the approach: same sizes
    turned = gripper_from_urdf(PANDA, palm_link="panda_link8")
    for field, value in panda.shape().items():
        if isinstance(value, float):
            assert getattr(turned, field) == pytest.approx(value, abs=1e-12), field
    with pytest.raises(InputError, match="palm_link 'panda_leftfinger' is not above both"):
        gripper_from_urdf(PANDA, palm_link="panda_leftfinger")
    with pytest.raises(InputError, match="no link named 'wrist'"):
        gripper_from_urdf(PANDA, palm_link="wrist")


def _box_hand(tmp_path: Path, right_axis: str = "1 0 0", extra: str = "") -> Path:
    """A box hand under a turned arm link: palm 0.12 (x) by 0.03 (y) by 0.02 (z, from 0 to
    0.02), fingers 0.01 by 0.02 by 0.05 from z 0.02 to 0.07, their inner faces at x = +-0.01
    closed and +-0.04 open (each slides 0.03 along x); the right finger's frame is turned
    half a turn about z."""
    text = f"""<?xml version="1.0"?>
<robot name="boxhand">
  <link name="world"/>
  <link name="arm"><collision><origin xyz="0 0 -0.2"/><geometry><box size="0.05 0.05 0.3"/>
    </geometry></collision></link>
  <joint name="lift" type="prismatic"><parent link="world"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="0" upper="1" effort="1" velocity="1"/></joint>
  <joint name="wrist" type="fixed"><parent link="arm"/><child link="hand"/>
    <origin xyz="0.3 -0.2 0.1" rpy="0.3 -0.2 1.1"/></joint>
  <link name="hand"><collision><origin xyz="0 0 0.01"/><geometry><box size="0.12 0.03 0.02"/>
    </geometry></collision></link>
  <link name="left"><collision><origin xyz="0.005 0 0.025"/><geometry>
    <box size="0.01 0.02 0.05"/></geometry></collision></link>
  <link name="right"><collision><origin xyz="0.005 0 0.025"/><geometry>
    <box size="0.01 0.02 0.05"/></geometry></collision></link>
  <joint name="j_left" type="prismatic"><parent link="hand"/><child link="left"/>
    <origin xyz="0.01 0 0.02"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.03" effort="1" velocity="1"/></joint>
  <joint name="j_right" type="prismatic"><parent link="hand"/><child link="right"/>
    <origin xyz="-0.01 0 0.02" rpy="0 0 3.14159265358979"/><axis xyz="{right_axis}"/>
    <limit lower="0" upper="0.03" effort="1" velocity="1"/><mimic joint="j_left"/></joint>
  {extra}
</robot>
"""
    path = tmp_path / "boxhand.urdf"
    path.write_text(text)
    return path


def test_box_hand_in_closed_form(tmp_path):
    path = _box_hand(tmp_path)
    # three prismatic joints (the arm's lift too): the fingers must be named
    with pytest.raises(InputError, match=r"3 prismatic joints .*finger_links="):
        gripper_from_urdf(path)
    hand = gripper_from_urdf(path, finger_links=("left", "right"))
    expected = {"width_max": 0.08, "tip_offset": 0.07, "finger_length": 0.05,
                "finger_thickness": 0.01, "finger_height": 0.02, "palm_thickness": 0.02,
                "palm_width": 0.12, "palm_height": 0.03, "pad_length": 0.05, "pad_height": 0.02,
                "depth": 0.025}
    for field, value in expected.items():
        assert getattr(hand, field) == pytest.approx(value, abs=1e-12), field
    assert hand.name == "boxhand"
    assert gripper_from_urdf(path, finger_links=("left", "right"), palm_link="hand") == hand
    # a third slider on the palm: the model has two fingers
    thumb = """<link name="thumb"><collision><geometry><box size="0.01 0.01 0.01"/></geometry>
      </collision></link><joint name="j_thumb" type="prismatic"><parent link="hand"/>
      <child link="thumb"/><axis xyz="0 1 0"/><limit lower="0" upper="0.01" effort="1"
      velocity="1"/></joint>"""
    (tmp_path / "thumb").mkdir()
    with pytest.raises(InputError, match="the palm 'hand' carries the prismatic joint 'j_thumb'"):
        gripper_from_urdf(_box_hand(tmp_path / "thumb", extra=thumb),
                          finger_links=("left", "right"))


def test_hands_the_model_cannot_stand_for(tmp_path):
    with pytest.raises(InputError, match="degrees apart: not a parallel-jaw hand"):
        gripper_from_urdf(_box_hand(tmp_path, right_axis="0 1 0"), finger_links=("left", "right"))
    # the PR2 gripper's fingers turn (revolute joints)
    with pytest.raises(InputError, match=r"^pr2_gripper.urdf: no prismatic joints, only turning "
                                         r"ones \(left_gripper_joint, right_gripper_joint\)"):
        gripper_from_urdf(DATA / "pr2_gripper.urdf")
    # each WSG-50 finger file is one link: no hand
    for side in ("left", "right"):
        with pytest.raises(InputError, match="1 link and no joints: a single part"):
            gripper_from_urdf(DATA / "gripper" / f"wsg50_one_motor_gripper_{side}_finger.urdf")
    # R2D2's gripper, named: its fingers turn
    with pytest.raises(InputError, match="moves on the revolute joint 'left_gripper_joint'"):
        gripper_from_urdf(DATA / "r2d2.urdf", finger_links=("left_gripper", "right_gripper"))
    with pytest.raises(InputError, match="no such URDF file"):
        gripper_from_urdf(tmp_path / "none.urdf")


def test_make_gripper_takes_a_urdf(panda):
    assert make_gripper(str(PANDA)) == panda
    assert make_gripper(str(PANDA), pad_radius=0.005).pad_radius == 0.005
    with pytest.raises(InputError, match=r"width: the panda gripper opens 0\.0797"):
        make_gripper(str(PANDA), width=0.1)


def test_cli_grasps_with_a_urdf_hand(capsys, panda):
    duck = str(DATA / "duck_vhacd.urdf")
    assert main(["grasps", duck, "--gripper", str(PANDA), "--count", "20", "--mu", "0.5",
                 "--approaches", "2", "--depths", "1", "--no-epsilon", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["gripper"] == "panda"
    assert summary["width"] == panda.width_max
    assert summary["candidates"] == 20
    assert main(["grasps", duck, "--gripper", str(DATA / "pr2_gripper.urdf")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "not a parallel-jaw hand" in err[0]
    assert main(["grasps", duck, "--gripper", str(PANDA), "--width", "0.1"]) == 2
    assert "has its own opening" in capsys.readouterr().err


def test_links_are_named_on_the_command_line(tmp_path, capsys, panda):
    path = _box_hand(tmp_path)
    assert make_gripper(str(path), links=",left,right") == gripper_from_urdf(
        path, finger_links=("left", "right"))
    assert make_gripper(str(PANDA), links="panda_hand") == panda
    with pytest.raises(InputError, match="links: name a URDF hand's links"):
        make_gripper("panda", links="panda_hand")
    with pytest.raises(InputError, match="give PALM, PALM,FINGER1,FINGER2"):
        make_gripper(str(PANDA), links="a,b")
    assert main(["grasps", "cube", "--gripper", str(path), "--mu", "0.5"]) == 2
    assert "name the finger links" in capsys.readouterr().err
    assert main(["grasps", "cube", "--gripper", str(path), "--gripper-links", ",left,right",
                 "--count", "3", "--mu", "0.5", "--no-epsilon", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["width"] == pytest.approx(0.08)
