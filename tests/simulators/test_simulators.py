"""Contacts from simulators (issue 17, item 5), against real pybullet and MuJoCo scenes.

The ground truth is the scene itself: where the faces of the boxes are (set by hand),
friction coefficients combined by hand by each simulator's documented rule, and what the
simulation does when a disturbance is applied. The verdict is compared with the
simulation's outcome on clear cases only:

* two finger pads squeezing a box with force F (friction mu): ``closure``; a disturbance of
  0.3 x (2 mu F) leaves the box in place, one of 1.2 x (2 mu F) pushes it out (closure says a
  finger force exists that resists, not that F does);
* two point fingertips squeezing a box: hard fingers give ``none`` (the rotation about the
  line through the contacts is unresisted, Nguyen's and DESIGN.md's classic case) and a small
  torque about that line spins the box; soft fingers with a torsional coefficient gamma give
  ``closure``, and the box holds a torque below 2 gamma F and spins under one above it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from forceclosure import InputError, analyze

pb = pytest.importorskip("pybullet")
pybullet_data = pytest.importorskip("pybullet_data")
try:
    import mujoco
except ImportError:  # the `mujoco` extra; the pybullet tests still run
    mujoco = None
needs_mujoco = pytest.mark.skipif(mujoco is None, reason="mujoco is not installed")

from forceclosure.simulators import contacts_from_mujoco, contacts_from_pybullet  # noqa: E402

HALF = 0.05       # every box object: a 10 cm cube centred at the origin (pinch scenes)
PAD = 0.03        # finger pads: half-size across the pinch axis
SQUEEZE = 10.0    # N, each finger


# ---------------------------------------------------------------- pybullet scenes


@pytest.fixture
def client():
    cid = pb.connect(pb.DIRECT)
    yield cid
    if pb.isConnected(physicsClientId=cid):
        pb.disconnect(physicsClientId=cid)


def box_on_plane(cid, box_friction=0.5, plane_friction=0.8):
    pb.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=cid)
    pb.setGravity(0, 0, -10, physicsClientId=cid)
    plane = pb.loadURDF("plane.urdf", physicsClientId=cid)
    shape = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[HALF] * 3, physicsClientId=cid)
    box = pb.createMultiBody(1.0, shape, basePosition=[0, 0, HALF], physicsClientId=cid)
    pb.changeDynamics(plane, -1, lateralFriction=plane_friction, physicsClientId=cid)
    pb.changeDynamics(box, -1, lateralFriction=box_friction, physicsClientId=cid)
    for _ in range(60):
        pb.stepSimulation(physicsClientId=cid)
    return plane, box


def pinch(cid, fingertip="pad", spinning=0.0, friction=0.5, offset=0.0, settle=60,
          box_friction=1.0):
    """A free 0.2 kg box between two fingers on prismatic joints along x, no gravity.

    Finger lateralFriction ``friction``, box ``box_friction`` (Bullet combines them into
    their product); the fingers' spinningFriction ``spinning``, the box's 0.
    The left finger is ``offset`` above the box's centre, the right one below.
    """
    pb.setGravity(0, 0, 0, physicsClientId=cid)
    cube = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[HALF] * 3, physicsClientId=cid)
    box = pb.createMultiBody(0.2, cube, physicsClientId=cid)
    if fingertip == "pad":
        tip = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[0.01, PAD, PAD],
                                      physicsClientId=cid)
    else:
        tip = pb.createCollisionShape(pb.GEOM_SPHERE, radius=0.01, physicsClientId=cid)
    hand = pb.createMultiBody(
        0, -1, -1, [0, 0, 0], linkMasses=[0.1, 0.1], linkCollisionShapeIndices=[tip, tip],
        linkVisualShapeIndices=[-1, -1],
        linkPositions=[[-HALF - 0.01, 0, offset], [HALF + 0.01, 0, -offset]],
        linkOrientations=[[0, 0, 0, 1]] * 2, linkInertialFramePositions=[[0, 0, 0]] * 2,
        linkInertialFrameOrientations=[[0, 0, 0, 1]] * 2, linkParentIndices=[0, 0],
        linkJointTypes=[pb.JOINT_PRISMATIC] * 2, linkJointAxis=[[1, 0, 0]] * 2,
        physicsClientId=cid)
    pb.changeDynamics(box, -1, lateralFriction=box_friction, physicsClientId=cid)
    for j in (0, 1):
        pb.changeDynamics(hand, j, lateralFriction=friction, spinningFriction=spinning,
                          physicsClientId=cid)
        pb.setJointMotorControl2(hand, j, pb.VELOCITY_CONTROL, force=0, physicsClientId=cid)
    squeeze_pybullet(cid, box, hand, settle)
    return box, hand


def squeeze_pybullet(cid, box, hand, steps, force=(0, 0, 0), torque=(0, 0, 0)):
    """Squeeze with SQUEEZE newtons per finger while pushing the box; its motion after."""
    start = np.array(pb.getBasePositionAndOrientation(box, physicsClientId=cid)[0])
    for _ in range(steps):
        pb.setJointMotorControl2(hand, 0, pb.TORQUE_CONTROL, force=SQUEEZE, physicsClientId=cid)
        pb.setJointMotorControl2(hand, 1, pb.TORQUE_CONTROL, force=-SQUEEZE,
                                 physicsClientId=cid)
        at = pb.getBasePositionAndOrientation(box, physicsClientId=cid)[0]
        pb.applyExternalForce(box, -1, force, at, pb.WORLD_FRAME, physicsClientId=cid)
        pb.applyExternalTorque(box, -1, torque, pb.WORLD_FRAME, physicsClientId=cid)
        pb.stepSimulation(physicsClientId=cid)
    end = np.array(pb.getBasePositionAndOrientation(box, physicsClientId=cid)[0])
    spin = np.array(pb.getBaseVelocity(box, physicsClientId=cid)[1])
    return float(np.linalg.norm(end - start)), spin


# ---------------------------------------------------------------- pybullet tests


def test_pybullet_box_on_plane(client):
    """The box's four bottom corners, normals out of the box (down), friction 0.5 x 0.8."""
    plane, box = box_on_plane(client)
    contacts = contacts_from_pybullet(box, client)
    assert len(contacts) == 4
    corners = np.array([c.point for c in contacts])
    assert np.allclose(np.abs(corners[:, :2]), HALF, atol=1e-4)
    assert np.allclose(corners[:, 2], 0.0, atol=1e-3)
    assert {tuple(np.sign(p[:2])) for p in corners} == {(1, 1), (1, -1), (-1, 1), (-1, -1)}
    for c in contacts:
        assert np.allclose(c.normal, [0, 0, -1], atol=1e-9)
        assert c.model == "hard" and c.mu == pytest.approx(0.5 * 0.8, rel=1e-12)
    # The same contacts seen from the plane: its outward normal is up, its points at z = 0.
    ground = contacts_from_pybullet(plane, client, other_ids=[box])
    assert len(ground) == 4
    for c in ground:
        assert np.allclose(c.normal, [0, 0, 1], atol=1e-9)
        assert abs(c.point[2]) < 1e-9
    # A box resting on a table alone is not held: nothing stops it being lifted.
    assert analyze(contacts).verdict.value == "none"


@pytest.mark.parametrize("push, slides", [(0.35, False), (0.45, True)])
def test_pybullet_friction_is_the_one_bullet_simulates(client, push, slides):
    """The adapter reports 0.5 x 0.8 = 0.4; the box (1 kg, g = 10) holds a push of 0.35 mg
    and slides under 0.45 mg, which no other rule (min 0.5, max 0.8, mean 0.65, geometric
    mean 0.63) allows."""
    _, box = box_on_plane(client)
    assert [c.mu for c in contacts_from_pybullet(box, client)] == [pytest.approx(0.4)] * 4
    start = np.array(pb.getBasePositionAndOrientation(box, physicsClientId=client)[0])
    for _ in range(240):
        at = pb.getBasePositionAndOrientation(box, physicsClientId=client)[0]
        pb.applyExternalForce(box, -1, [push * 10.0, 0, 0], at, pb.WORLD_FRAME,
                              physicsClientId=client)
        pb.stepSimulation(physicsClientId=client)
    moved = np.linalg.norm(np.array(
        pb.getBasePositionAndOrientation(box, physicsClientId=client)[0]) - start)
    # 0.45 mg - 0.4 mg = 0.5 N on 1 kg for 1 s: 0.25 m
    assert moved > 0.1 if slides else moved < 1e-3


def test_pybullet_pinched_box(client):
    """Pads on the box's faces x = -0.05 and x = +0.05: eight corners of the pads, normals
    -x and +x; closure; the box stays under 0.3 x 2 mu F and is pushed out by 1.2 x 2 mu F."""
    box, hand = pinch(client)
    contacts = contacts_from_pybullet(box, client, other_ids=[hand])
    assert len(contacts) == 8
    for c in contacts:
        side = np.sign(c.point[0])
        assert abs(c.point[0]) == pytest.approx(HALF, abs=1e-3)
        assert np.allclose(np.abs(c.point[1:]), PAD, atol=1e-3)      # the pads' corners
        assert np.allclose(c.normal, [side, 0, 0], atol=1e-4)         # out of the box
        assert c.mu == pytest.approx(0.5)
    assert sum(c.point[0] < 0 for c in contacts) == 4
    assert analyze(contacts).verdict.value == "closure"
    limit = 2 * 0.5 * SQUEEZE
    held, _ = squeeze_pybullet(client, box, hand, 240, force=(0, 0, 0.3 * limit))
    assert held < 1e-3
    pushed, _ = squeeze_pybullet(client, box, hand, 240, force=(0, 0, 1.2 * limit))
    assert pushed > 0.1


def test_pybullet_fingertips_hard_versus_soft(client):
    """Two fingertips on the box's centre line. Hard fingers: ``none``, the unresisted motion
    a rotation about the x axis, and the box spins under a torque of 0.05 N m about it.
    Soft fingers (spinningFriction 0.02 on the tips and 0 on the box, lateralFriction 0.5 on
    the tips and 2 on the box: Bullet combines 0.02 x 2 + 0 x 0.5 = 0.04): ``closure``; the
    box holds 0.6 N m < 2 x 0.04 x F = 0.8 N m, which neither the sum nor the larger of the
    two spinning frictions (0.02: 0.4 N m) would allow, and spins under 1.0 N m."""
    box, hand = pinch(client, fingertip="sphere")
    hard = contacts_from_pybullet(box, client)
    assert len(hard) == 2
    assert np.allclose(sorted(c.point[0] for c in hard), [-HALF, HALF], atol=1e-3)
    result = analyze(hard)
    assert result.verdict.value == "none"
    assert result.motion.kind == "rotation"
    assert np.allclose(np.abs(result.motion.direction), [1, 0, 0], atol=1e-9)
    _, spin = squeeze_pybullet(client, box, hand, 120, torque=(0.05, 0, 0))
    assert spin[0] > 5.0
    pb.disconnect(physicsClientId=client)

    cid = pb.connect(pb.DIRECT)
    try:
        box, hand = pinch(cid, fingertip="sphere", spinning=0.02, box_friction=2.0)
        soft = contacts_from_pybullet(box, cid, model="soft")
        assert [(c.mu, c.torsion) for c in soft] == [(1.0, pytest.approx(0.04))] * 2
        assert analyze(soft).verdict.value == "closure"
        _, spin = squeeze_pybullet(cid, box, hand, 240, torque=(0.6, 0, 0))
        assert abs(spin[0]) < 1e-2
        _, spin = squeeze_pybullet(cid, box, hand, 240, torque=(1.0, 0, 0))
        assert spin[0] > 5.0
    finally:
        pb.disconnect(physicsClientId=cid)


@pytest.mark.parametrize("friction, verdict", [(0.2, "none"), (1.0, "closure")])
def test_pybullet_slanted_pinch(client, friction, verdict):
    """Soft fingertips at (-0.05, 0, 0.03) and (0.05, 0, -0.03): the line through them is
    atan(0.06 / 0.1) = 31 degrees off the normals (Corollary 3). Friction 0.2 (11 degrees):
    ``none``, and the squeeze alone turns the box (about y) until the line enters the cones;
    friction 1.0 (45 degrees): ``closure``, and the box stays put."""
    box, hand = pinch(client, fingertip="sphere", spinning=0.02, friction=friction,
                      offset=0.03, settle=3)
    contacts = contacts_from_pybullet(box, client, model="soft")
    assert len(contacts) == 2
    for c in contacts:
        side = np.sign(c.point[0])
        assert np.allclose(c.point, [side * HALF, 0, -side * 0.03], atol=2e-3)
        assert np.allclose(c.normal, [side, 0, 0], atol=0.05)
        assert c.mu == pytest.approx(friction)
    assert analyze(contacts).verdict.value == verdict
    squeeze_pybullet(client, box, hand, 240)
    orn = pb.getBasePositionAndOrientation(box, physicsClientId=client)[1]
    turned = abs(pb.getEulerFromQuaternion(orn)[1])
    assert turned > 0.3 if verdict == "none" else turned < 1e-2


def test_pybullet_merge_keeps_distinct_points_and_drops_repeats(client):
    """The pad scene's eight corners are 6 cm apart: no merge tolerance below that joins
    them, and one larger than the pad joins each pad's four corners into one contact."""
    box, _ = pinch(client)
    assert len(contacts_from_pybullet(box, client, merge=0.0)) == 8
    assert len(contacts_from_pybullet(box, client, merge=0.05)) == 8
    assert len(contacts_from_pybullet(box, client, merge=0.2)) == 2


def one_line(excinfo) -> str:
    text = str(excinfo.value)
    assert "\n" not in text
    return text


def test_pybullet_errors(client):
    _, box = box_on_plane(client)
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box + 10, client)
    assert f"no body with id {box + 10}" in one_line(e)
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box, client, other_ids=[box])   # only the box itself
    assert "has no contacts with bodies" in one_line(e)
    floating = pb.createMultiBody(1.0, pb.createCollisionShape(
        pb.GEOM_SPHERE, radius=0.1, physicsClientId=client), basePosition=[5, 5, 5],
        physicsClientId=client)
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(floating, client)
    assert "has no contacts" in one_line(e)
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box, client, model="sticky")
    assert "'model'" in one_line(e)
    pb.disconnect(physicsClientId=client)
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box, client)
    assert one_line(e) == f"pybullet: client {client} is not connected"


# ---------------------------------------------------------------- MuJoCo scenes

# Elliptic cones and the no-slip solver: MuJoCo's soft contacts otherwise creep slowly under
# any tangential load, which would blur "stays" in the disturbance tests.
OPTION = '<option gravity="{g}" timestep="0.002" cone="elliptic" noslip_iterations="20"/>'

ON_PLANE = """<mujoco>{option}<worldbody>
  <geom name="floor" type="plane" size="1 1 .1" friction="0.6 0.01 0"/>
  <body name="box" pos="0 0 .05"><freejoint/>
    <geom name="box" type="box" size=".05 .05 .05" mass="1" friction="0.4 0.02 0" condim="4"/>
  </body></worldbody></mujoco>"""

PINCH = """<mujoco>{option}<worldbody>
  <body name="box"><freejoint/>
    <geom type="box" size=".05 .05 .05" mass="0.2" friction="0.3 0 0" condim="{condim}"/></body>
  <body name="left" pos="-.06 0 0"><joint name="l" type="slide" axis="1 0 0"/>
    <geom name="left" type="{tip}" size="{size}" mass="0.1" friction="0.5 {spin} 0"
          condim="{condim}"/></body>
  <body name="right" pos=".06 0 0"><joint name="r" type="slide" axis="1 0 0"/>
    <geom name="right" type="{tip}" size="{size}" mass="0.1" friction="0.5 {spin} 0"
          condim="{condim}"/></body>
</worldbody><actuator><motor joint="l"/><motor joint="r"/></actuator></mujoco>"""


def mujoco_pinch(tip="box", condim=3, spin=0.0):
    size = f".01 {PAD} {PAD}" if tip == "box" else ".01"
    xml = PINCH.format(option=OPTION.format(g="0 0 0"), tip=tip, size=size, condim=condim,
                       spin=spin)
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    squeeze_mujoco(m, d, 100)
    return m, d


def squeeze_mujoco(m, d, steps, force=(0, 0, 0), torque=(0, 0, 0)):
    box = m.body("box").id
    start = d.qpos[:3].copy()
    for _ in range(steps):
        d.ctrl[:] = [SQUEEZE, -SQUEEZE]
        d.xfrc_applied[box] = [*force, *torque]
        mujoco.mj_step(m, d)
    return float(np.linalg.norm(d.qpos[:3] - start)), d.qvel[3:6].copy()


# ---------------------------------------------------------------- MuJoCo tests


@needs_mujoco
def test_mujoco_box_on_plane():
    """Four corners on the box's bottom face, normals down; friction the element-wise
    maximum of the two geoms' (0.6, 0.02); condim max(3, 4) = 4: soft fingers."""
    m = mujoco.MjModel.from_xml_string(ON_PLANE.format(option=OPTION.format(g="0 0 -10")))
    d = mujoco.MjData(m)
    for _ in range(200):
        mujoco.mj_step(m, d)
    bottom = d.qpos[2] - 0.05          # the box's bottom face, from its pose
    contacts = contacts_from_mujoco(m, d, body="box")
    assert len(contacts) == 4
    for c in contacts:
        assert np.allclose(c.normal, [0, 0, -1], atol=1e-9)
        assert c.point[2] == pytest.approx(bottom, abs=1e-9)       # moved by dist / 2
        assert np.allclose(np.abs(c.point[:2] - d.qpos[:2]), 0.05, atol=1e-6)
        assert (c.model, c.mu, c.torsion) == ("soft", 0.6, 0.02)
    assert bottom < 0                   # the box sinks into the floor a little ...
    floor = contacts_from_mujoco(m, d, geom="floor")
    for c in floor:                     # ... and the floor's own points stay at z = 0
        assert np.allclose(c.normal, [0, 0, 1], atol=1e-9)
        assert abs(c.point[2]) < 1e-9
    assert analyze(contacts).verdict.value == "none"


@needs_mujoco
@pytest.mark.parametrize("push, slides", [(0.5, False), (0.7, True)])
def test_mujoco_friction_is_the_maximum(push, slides):
    """With the maximum (0.6) the 1 kg box holds a push of 0.5 mg; with the minimum (0.4)
    it would slide. Under 0.7 mg it slides."""
    m = mujoco.MjModel.from_xml_string(ON_PLANE.format(option=OPTION.format(g="0 0 -10")))
    d = mujoco.MjData(m)
    for _ in range(200):
        mujoco.mj_step(m, d)
    start = d.qpos[:3].copy()
    for _ in range(500):
        d.xfrc_applied[m.body("box").id] = [push * 10.0, 0, 0, 0, 0, 0]
        mujoco.mj_step(m, d)
    moved = float(np.linalg.norm(d.qpos[:3] - start))
    speed = float(np.linalg.norm(d.qvel[:3]))
    # sliding: (0.7 - 0.6) x 10 N on 1 kg for 1 s; held: the soft contact's ~1 mm give, at rest
    assert (moved > 0.1 and speed > 0.5) if slides else (moved < 5e-3 and speed < 1e-2)


@needs_mujoco
def test_mujoco_pinched_box():
    """As in pybullet: eight pad corners, normals -x and +x, friction max(0.3, 0.5) = 0.5,
    closure; the box stays under 0.3 x 2 mu F and is pushed out by 1.2 x 2 mu F."""
    m, d = mujoco_pinch()
    contacts = contacts_from_mujoco(m, d, body="box")
    assert len(contacts) == 8
    for c in contacts:
        side = np.sign(c.point[0])
        assert abs(c.point[0]) == pytest.approx(HALF, abs=1e-3)
        assert np.allclose(np.abs(c.point[1:]), PAD, atol=1e-6)
        assert np.allclose(c.normal, [side, 0, 0], atol=1e-9)
        assert (c.model, c.mu) == ("hard", 0.5)
    assert analyze(contacts).verdict.value == "closure"
    limit = 2 * 0.5 * SQUEEZE
    held, _ = squeeze_mujoco(m, d, 500, force=(0, 0, 0.3 * limit))
    assert held < 1e-3
    pushed, _ = squeeze_mujoco(m, d, 500, force=(0, 0, 1.2 * limit))
    assert pushed > 0.1


@needs_mujoco
def test_mujoco_fingertips_hard_versus_soft():
    """condim 3 fingertips: hard, ``none``, the box spins under 0.05 N m about x.
    condim 4 with torsional friction 0.02: soft, ``closure``; the box holds
    0.2 N m < 2 x 0.02 x F = 0.4 N m and spins under 0.6 N m."""
    m, d = mujoco_pinch(tip="sphere", condim=3)
    hard = contacts_from_mujoco(m, d, body="box")
    assert [c.model for c in hard] == ["hard", "hard"]
    result = analyze(hard)
    assert result.verdict.value == "none" and result.motion.kind == "rotation"
    assert np.allclose(np.abs(result.motion.direction), [1, 0, 0], atol=1e-9)
    assert squeeze_mujoco(m, d, 250, torque=(0.05, 0, 0))[1][0] > 5.0

    m, d = mujoco_pinch(tip="sphere", condim=4, spin=0.02)
    soft = contacts_from_mujoco(m, d, body="box")
    assert [(c.model, c.torsion) for c in soft] == [("soft", 0.02)] * 2
    assert analyze(soft).verdict.value == "closure"
    assert abs(squeeze_mujoco(m, d, 500, torque=(0.2, 0, 0))[1][0]) < 1e-2
    assert squeeze_mujoco(m, d, 500, torque=(0.6, 0, 0))[1][0] > 5.0


@needs_mujoco
def test_mujoco_condim_one_is_frictionless_and_inner_cones():
    m, d = mujoco_pinch(tip="sphere", condim=1)
    assert {(c.model, c.mu) for c in contacts_from_mujoco(m, d, body="box")} == {
        ("frictionless", 0.0)}
    # "inner": the largest circular cone inside MuJoCo's own (elliptic here: a soft
    # finger's sliding and spin coefficients each over sqrt 2; a hard finger's unchanged).
    m, d = mujoco_pinch(tip="sphere", condim=4, spin=0.02)
    inner = contacts_from_mujoco(m, d, body="box", friction="inner")
    assert [(c.mu, c.torsion) for c in inner] == [
        (pytest.approx(0.5 / math.sqrt(2)), pytest.approx(0.02 / math.sqrt(2)))] * 2
    hard = contacts_from_mujoco(m, d, body="box", friction="inner", contact_model="hard")
    assert [c.mu for c in hard] == [0.5, 0.5]


@needs_mujoco
def test_mujoco_errors():
    m = mujoco.MjModel.from_xml_string(ON_PLANE.format(option=OPTION.format(g="0 0 -10")))
    d = mujoco.MjData(m)
    with pytest.raises(InputError) as e:
        contacts_from_mujoco(m, d, body="box")          # no collision detection run yet
    assert "has no contacts" in one_line(e)
    mujoco.mj_forward(m, d)
    with pytest.raises(InputError) as e:
        contacts_from_mujoco(m, d, body="lid")
    assert one_line(e) == "mujoco: no body named 'lid' in the model"
    with pytest.raises(InputError) as e:
        contacts_from_mujoco(m, d, geom=7)
    assert one_line(e) == "mujoco: no geom with id 7 (the model has 2)"
    with pytest.raises(InputError) as e:
        contacts_from_mujoco(m, d, body="box", geom="box")
    assert "exactly one" in one_line(e)
    with pytest.raises(InputError) as e:
        contacts_from_mujoco(m, d, body="box", friction="outer")
    assert "'friction'" in one_line(e)


# ---------------------------------------------------------------- one signature (issue 24)

def gripper_on_table(cid):
    """A 0.2 kg box (friction 1) on plane.urdf, squeezed by a hand that is one multibody:
    a palm (its base) 2 cm above the box, not touching it, and two finger pads (links 0
    and 1, friction 0.5) on prismatic joints along x, 10 N each. Gravity on."""
    pb.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=cid)
    pb.setGravity(0, 0, -10, physicsClientId=cid)
    plane = pb.loadURDF("plane.urdf", physicsClientId=cid)
    cube = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[HALF] * 3, physicsClientId=cid)
    box = pb.createMultiBody(0.2, cube, basePosition=[0, 0, HALF], physicsClientId=cid)
    palm = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[0.08, 0.02, 0.01],
                                   physicsClientId=cid)
    pad = pb.createCollisionShape(pb.GEOM_BOX, halfExtents=[0.01, PAD, PAD],
                                  physicsClientId=cid)
    drop = 2 * HALF + 0.03 - HALF            # palm centre to box centre, along -z
    hand = pb.createMultiBody(
        0, palm, -1, [0, 0, 2 * HALF + 0.03], linkMasses=[0.1, 0.1],
        linkCollisionShapeIndices=[pad, pad], linkVisualShapeIndices=[-1, -1],
        linkPositions=[[-HALF - 0.01, 0, -drop], [HALF + 0.01, 0, -drop]],
        linkOrientations=[[0, 0, 0, 1]] * 2, linkInertialFramePositions=[[0, 0, 0]] * 2,
        linkInertialFrameOrientations=[[0, 0, 0, 1]] * 2, linkParentIndices=[0, 0],
        linkJointTypes=[pb.JOINT_PRISMATIC] * 2, linkJointAxis=[[1, 0, 0]] * 2,
        physicsClientId=cid)
    pb.changeDynamics(box, -1, lateralFriction=1.0, physicsClientId=cid)
    for j in (0, 1):
        pb.changeDynamics(hand, j, lateralFriction=0.5, physicsClientId=cid)
        pb.setJointMotorControl2(hand, j, pb.VELOCITY_CONTROL, force=0, physicsClientId=cid)
    squeeze_pybullet(cid, box, hand, 60)
    return plane, box, hand


def test_pybullet_fingers_of_a_gripper_on_a_table(client):
    """Keeping only the fingers' contacts gives the pads' eight corners on the box's faces
    x = -0.05 and x = +0.05 (normals -x, +x, friction 0.5 x 1), and closure; one link keeps
    its own four; the table's are the box's bottom corners (normal down), the one motion
    they leave is lifting the box straight up; the old name other_ids means fingers."""
    plane, box, hand = gripper_on_table(client)
    centre, turn = pb.getBasePositionAndOrientation(box, physicsClientId=client)
    centre = np.array(centre)
    axis_x = np.array(pb.getMatrixFromQuaternion(turn, physicsClientId=client))[[0, 3, 6]]
    everything = contacts_from_pybullet(box, client)
    pads = contacts_from_pybullet(body=box, client=client, fingers=[hand])
    table = contacts_from_pybullet(box, client, fingers=[plane])
    assert len(pads) == 8 and 1 <= len(table) <= 4        # Bullet keeps at most 4 a pair
    assert len(everything) == len(pads) + len(table)      # the palm touches nothing
    for c in pads:
        side = np.sign(c.point[0])
        assert abs(c.point[0] - centre[0]) == pytest.approx(HALF, abs=1e-3)
        assert np.allclose(np.abs(c.point[1:] - centre[1:]), PAD, atol=1e-3)
        # the face's normal, from the pose (Bullet's is from before the last step's motion)
        assert np.allclose(c.normal, side * axis_x, atol=1e-5)
        assert c.mu == pytest.approx(0.5)
    assert analyze(pads).verdict.value == "closure"
    left = contacts_from_pybullet(box, client, fingers=[(hand, 0)])
    assert len(left) == 4 and all(c.point[0] < 0 for c in left)
    assert len(contacts_from_pybullet(box, client, fingers=[(hand, 0), (hand, 1)])) == 8
    assert [c.point.tolist() for c in contacts_from_pybullet(box, client, other_ids=[hand])] \
        == [c.point.tolist() for c in pads]
    # Bullet bounds each tangential impulse by mu (a box around the circle): "inner" is "nominal"
    inner = contacts_from_pybullet(box, client, fingers=[hand], friction="inner")
    assert [c.mu for c in inner] == [c.mu for c in pads]
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box, client, fingers=[hand], friction="outer")
    assert one_line(e) == "pybullet: 'friction' must be 'nominal' or 'inner', got 'outer'"
    for c in table:                                       # the bottom face's corners
        assert np.allclose(c.normal, [0, 0, -1], atol=1e-6) and abs(c.point[2]) < 1e-3
        assert np.allclose(np.abs(c.point[:2] - centre[:2]), HALF, atol=1e-3)
        assert c.mu == pytest.approx(1.0)
    lifted = analyze(table)
    assert lifted.verdict.value == "none" and lifted.motion.kind == "translation"
    assert np.allclose(lifted.motion.direction, [0, 0, 1], atol=1e-6)
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box, client, fingers=[(hand, 2)])
    assert one_line(e) == "pybullet: body 2 has no link 2 ('fingers'; its links are -1 to 1)"
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box, client, model="hard", contact_model="hard")
    assert one_line(e) == ("pybullet: give 'contact_model' or its older name 'model', "
                           "not both")
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box, client, fingers=[(hand, -1)])   # the palm: not touching
    assert "has no contacts with bodies 2 (link -1)" in one_line(e)


def test_pybullet_soft_fingers_need_spinning_friction(client):
    """pybullet's default spinningFriction is 0: Bullet then simulates no torsion, so a soft
    finger is refused in one line naming the bodies; given torsion, or spinning friction on
    the fingers, it is a soft finger with that coefficient (0.01 x 1 + 0 x 0.5)."""
    _, box, hand = gripper_on_table(client)
    with pytest.raises(InputError) as e:
        contacts_from_pybullet(box, client, fingers=[hand], contact_model="soft")
    assert one_line(e).startswith(f"pybullet: contact_model='soft' but body {box} and body "
                                  f"{hand} (link 0) combine to spinning friction 0")
    given = contacts_from_pybullet(box, client, fingers=[hand], contact_model="soft",
                                   torsion=0.003)
    assert {(c.model, c.torsion) for c in given} == {("soft", 0.003)}
    for j in (0, 1):
        pb.changeDynamics(hand, j, spinningFriction=0.01, physicsClientId=client)
    soft = contacts_from_pybullet(box, client, fingers=[hand], contact_model="soft")
    assert [c.torsion for c in soft] == [pytest.approx(0.01)] * 8


GRIPPER = """<mujoco>{option}<worldbody>
  <geom name="floor" type="plane" size="1 1 .1" friction="0.2 0 0"/>
  <body name="box" pos="0 0 .05"><freejoint/>
    <geom name="box" type="box" size=".05 .05 .05" mass="0.2" friction="0.3 0 0"/></body>
  <body name="palm" pos="0 0 .13"><geom name="palm" type="box" size=".08 .02 .01"/>
    <body name="left" pos="-.06 0 -.08"><joint name="l" type="slide" axis="1 0 0"/>
      <geom name="left" type="box" size=".01 {pad} {pad}" mass="0.1" friction="0.5 0 0"/>
    </body>
    <body name="right" pos=".06 0 -.08"><joint name="r" type="slide" axis="1 0 0"/>
      <geom name="right" type="box" size=".01 {pad} {pad}" mass="0.1" friction="0.5 0 0"/>
    </body></body>
</worldbody><actuator><motor joint="l"/><motor joint="r"/></actuator></mujoco>"""


@needs_mujoco
def test_mujoco_fingers_of_a_gripper_on_a_table():
    """As in pybullet: the two finger bodies (or their geoms) give the pads' eight corners,
    friction max(0.3, 0.5); the floor's geom gives the bottom corners, friction
    max(0.3, 0.2); the palm touches nothing; names and ids alike."""
    m = mujoco.MjModel.from_xml_string(GRIPPER.format(option=OPTION.format(g="0 0 -10"),
                                                      pad=PAD))
    d = mujoco.MjData(m)
    squeeze_mujoco(m, d, 200)
    centre = d.qpos[:3]
    axis_x = d.xmat[m.body("box").id].reshape(3, 3)[:, 0]
    everything = contacts_from_mujoco(m, d, body="box")
    pads = contacts_from_mujoco(m, d, body="box", fingers=["left", "right"])
    table = contacts_from_mujoco(m, d, body="box", finger_geoms=["floor"])
    assert len(pads) == 8 and 1 <= len(table) <= 4
    assert len(everything) == len(pads) + len(table)      # the palm touches nothing
    for c in pads:
        side = np.sign(c.point[0])
        assert abs(c.point[0] - centre[0]) == pytest.approx(HALF, abs=1e-3)
        assert np.allclose(np.abs(c.point[1:] - centre[1:]), PAD, atol=1e-3)
        assert np.allclose(c.normal, side * axis_x, atol=1e-9)   # the face's, from the pose
        assert (c.model, c.mu) == ("hard", 0.5)
    assert analyze(pads).verdict.value == "closure"
    ids = [m.body("left").id, m.body("right").id]
    assert len(contacts_from_mujoco(m, d, body=m.body("box").id, fingers=ids)) == 8
    left = contacts_from_mujoco(m, d, body="box", finger_geoms=[m.geom("left").id])
    assert len(left) == 4 and all(c.point[0] < centre[0] for c in left)
    both = contacts_from_mujoco(m, d, body="box", fingers=["left"], finger_geoms=["right"])
    assert len(both) == 8
    for c in table:                                       # the bottom face's corners
        assert np.allclose(c.normal, [0, 0, -1], atol=1e-9) and c.mu == 0.3
        assert np.allclose(np.abs(c.point[:2] - centre[:2]), HALF, atol=1e-3)
    with pytest.raises(InputError) as e:
        contacts_from_mujoco(m, d, body="box", fingers=["palm"])
    assert one_line(e).startswith("mujoco: body 'box' has no contacts with bodies ['palm']")
    with pytest.raises(InputError) as e:
        contacts_from_mujoco(m, d, body="box", fingers=["thumb"])
    assert one_line(e) == "mujoco: no body named 'thumb' in the model ('fingers')"
    with pytest.raises(InputError) as e:
        contacts_from_mujoco(m, d, body="box", fingers=["left"], contact_model="soft")
    assert "contact_model='soft' but the contact of geoms" in one_line(e)
    assert "condim 3" in one_line(e)
    given = contacts_from_mujoco(m, d, body="box", fingers=["left"], contact_model="soft",
                                 torsion=0.002)
    assert {(c.model, c.torsion) for c in given} == {("soft", 0.002)}


def test_pybullet_duck_resting_on_a_table_is_lifted_off_it(client):
    """pybullet_data's duck (duck_vhacd.urdf) settled on plane.urdf: four contacts under it,
    normals down within 1e-5. Nothing holds it down, so the motion reported is lifting it
    straight up (before issue 24: "screw motion about the axis through (0.237, 0.181, ...),
    pitch 1.44e-06", the LP's rotation about an axis 30 cm away). Every friction-cone edge
    at every contact (written out here) does positive work on that motion."""
    pb.setAdditionalSearchPath(pybullet_data.getDataPath(), physicsClientId=client)
    pb.setGravity(0, 0, -10, physicsClientId=client)
    pb.loadURDF("plane.urdf", physicsClientId=client)
    duck = pb.loadURDF("duck_vhacd.urdf", [0, 0, 0.05], physicsClientId=client)
    for _ in range(500):
        pb.stepSimulation(physicsClientId=client)
    contacts = contacts_from_pybullet(duck, client)
    assert len(contacts) >= 3
    assert all(np.allclose(c.normal, [0, 0, -1], atol=1e-5) for c in contacts)
    result = analyze(contacts)
    assert result.verdict.value == "none" and not result.force_direction_closure
    assert result.motion.kind == "translation" and not result.motion.both_ways
    assert np.allclose(result.motion.direction, [0, 0, 1], atol=1e-5)
    assert result.explain().endswith("unresisted: " + result.motion.describe())
    omega, v = result.twist[:3], result.twist[3:]
    for c in contacts:
        t1 = np.cross(c.normal, [1.0, 0, 0])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(c.normal, t1)
        for a in np.linspace(0, 2 * np.pi, 16, endpoint=False):
            force = -c.normal + c.mu * (np.cos(a) * t1 + np.sin(a) * t2)
            assert force @ (v + np.cross(omega, c.point)) > 0.1
