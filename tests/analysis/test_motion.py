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
