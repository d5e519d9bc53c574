"""The unresisted motion reported to the user, checked in object coordinates."""

import numpy as np
import pytest

from forceclosure import Cone, Verdict, analyze, motion_of, point_contact
from forceclosure.contacts import tangent_basis


def _velocity(twist, p):
    if len(p) == 2:
        omega, v = twist[0], twist[1:]
        return v + omega * np.array([-p[1], p[0]])
    return twist[3:] + np.cross(twist[:3], p)


def _forces(contact, edges=8):
    """The finger's generating forces, written out again here: -n ± mu t / pyramid rim."""
    n = contact.normal
    if contact.model == "frictionless" or contact.mu == 0:
        return [-n]
    if len(n) == 2:
        t = np.array([-n[1], n[0]])
        return [-n + contact.mu * t, -n - contact.mu * t]
    t1, t2 = tangent_basis(n)
    r = contact.mu / np.cos(np.pi / edges)  # circumscribed: a `none` holds for it
    return [-n + r * (np.cos(a) * t1 + np.sin(a) * t2)
            for a in 2 * np.pi * np.arange(edges) / edges]


@pytest.mark.parametrize("dim", [2, 3])
def test_no_contact_resists_the_reported_motion(dim):
    rng = np.random.default_rng(dim + 10)
    checked = 0
    for _ in range(80):
        k = int(rng.integers(2, 5))
        pts = rng.uniform(-1, 1, (k, dim)) * 3 + rng.uniform(-5, 5, dim)
        normals = rng.normal(size=(k, dim))
        model = "hard" if dim == 2 else str(rng.choice(["hard", "frictionless"]))
        grasp = [point_contact(p, n, model, rng.uniform(0, 0.6))
                 for p, n in zip(pts, normals, strict=True)]
        a = analyze(grasp, cone=Cone(8, "circumscribed") if dim == 3 else "exact")
        if a.verdict is not Verdict.NONE:
            continue
        checked += 1
        scale = np.max(np.abs(pts)) + 1
        for c in grasp:
            for f in _forces(c):
                work = f @ _velocity(a.twist, c.point)
                assert work >= -1e-9 * scale, (work, a.motion.describe())
                if a.motion.both_ways:
                    assert abs(work) <= 1e-9 * scale
    assert checked > 20


def test_decoded_axis_is_the_screw_axis():
    rng = np.random.default_rng(1)
    for _ in range(50):
        twist = rng.normal(size=6)
        m = motion_of(twist)
        assert m.kind == "screw"
        # the velocity of the axis point is along the axis: v = pitch * omega
        v = _velocity(m.twist, m.point)
        np.testing.assert_allclose(v, m.pitch * m.direction, atol=1e-9)
        twist2 = rng.normal(size=3)
        centre = motion_of(twist2).point
        np.testing.assert_allclose(_velocity(motion_of(twist2).twist, centre), 0, atol=1e-9)


def test_translation_is_recognised():
    assert motion_of([0, 0, 0, 1, 2, 2]).describe() == (
        "translation along (0.333, 0.667, 0.667)")
    assert motion_of([0, 3, 4]).direction.tolist() == [0.6, 0.8]


# -- the rule in words (issue 24, item 11): hand-derived twists --------------------------

def _about_origin(omega, v_c, c):
    """The twist about the origin of a motion with angular velocity ``omega`` whose point
    ``c`` moves with ``v_c``: v_0 = v_c - omega x c (written out by hand)."""
    omega, v_c, c = (np.asarray(a, dtype=float) for a in (omega, v_c, c))
    return np.concatenate([omega, v_c - np.cross(omega, c)])


@pytest.mark.parametrize("turn, kind", [(0.4e-6, "translation"), (0.6e-6, "rotation")])
def test_negligible_rotation_is_a_translation(turn, kind):
    """An object of size L = 2 centred at (5, 0, 0) lifted at unit speed while turning at
    ``turn`` rad per metre about y: its points move by at most 2 x turn sideways, within
    the tolerance 1e-6 of the lift for 0.4e-6 (a translation), beyond it for 0.6e-6."""
    t = _about_origin([0, turn, 0], [0, 0, 1], [5, 0, 0])
    m = motion_of(t, length_scale=2.0, reference=[5, 0, 0])
    assert m.kind == kind
    if kind == "translation":
        assert m.describe() == "translation along (0, 0, 1)"
        np.testing.assert_allclose(m.twist, t / 1.0)  # kept whole: still the certificate
    else:
        # the axis: parallel to y, where the lift cancels, 1 / turn from the centre along x
        np.testing.assert_allclose(m.direction, [0, 1, 0], atol=1e-12)
        np.testing.assert_allclose(m.point, [5 + 1 / turn, 0, 0], rtol=1e-9)
        assert m.pitch == 0.0


def test_the_rule_does_not_depend_on_the_origin():
    """A pure rotation about the z axis through an object at (1e7, 0, 0): about the origin
    its twist has |v| = 1e7, but the object's own points turn in place."""
    t = _about_origin([0, 0, 1], [0, 0, 0], [1e7, 0, 0])
    m = motion_of(t, length_scale=1.0, reference=[1e7, 0, 0])
    assert m.kind == "rotation"
    np.testing.assert_allclose(m.point, [1e7, 0, 0])
    assert m.describe() == "rotation about the axis through (1e+07, 0, 0) with direction (0, 0, 1)"


@pytest.mark.parametrize("distance, pitch, kind", [
    (0.0, 5e-7, "rotation"), (0.0, 2e-6, "screw"),          # axis through the centre, L = 1
    (1e3, 5e-4, "rotation"), (1e3, 2e-3, "screw")])          # axis 1000 away: 1e-6 x 1001
def test_pitch_negligible_at_the_objects_scale_is_a_rotation(distance, pitch, kind):
    """A screw about a z axis at ``distance`` from the object's centre (the origin, L = 1)
    with ``pitch``: a rotation when |pitch| <= 1e-6 (L + distance)."""
    t = _about_origin([0, 0, 1], np.cross([0, 0, 1], [-distance, 0, 0]) + np.array([0, 0, pitch]),
                      [0, 0, 0])
    m = motion_of(t, length_scale=1.0)
    assert m.kind == kind
    assert m.pitch == (pytest.approx(pitch) if kind == "screw" else 0.0)
    np.testing.assert_allclose(m.point[:2], [distance, 0], atol=1e-9)


def test_planar_rule():
    assert motion_of([1e-9, 1, 0]).describe() == "translation along (1, 0)"
    m = motion_of([1e-3, 1, 0])              # v + omega x c = 0 at c = (0, 1000)
    assert m.kind == "rotation" and np.allclose(m.point, [0, 1000])


def test_a_box_on_a_table_is_lifted_off_it():
    """A cube's four bottom corners on a table (hard fingers, mu 0.5), as a simulator gives
    them, 0.1 mm apart in height: force-direction closure fails (every force points up), and
    the motion reported is the translation straight up, which every generating force (the
    pyramid written out here) does positive work on: not a rotation about a far axis."""
    corners = [(-1, -1, 0.0), (1, -1, 1e-4), (1, 1, 0.0), (-1, 1, -1e-4)]
    grasp = [point_contact(np.array(p) * [0.05, 0.05, 1], [0, 0, -1], "hard", 0.5)
             for p in corners]
    a = analyze(grasp)
    assert a.verdict is Verdict.NONE and not a.force_direction_closure
    assert a.motion.kind == "translation" and not a.motion.both_ways
    assert a.motion.describe() == "translation along (0, 0, 1)"
    for c in grasp:
        for f in _forces(c):
            assert f @ _velocity(a.twist, c.point) > 0.5
