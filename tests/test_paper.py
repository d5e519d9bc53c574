"""The paper's own cases, and the corollaries against the general test."""

import json
import math
from importlib import resources

import numpy as np
import pytest

from forceclosure import Verdict, analyze, point_contact
from forceclosure.analysis.equilibrium import nonmarginal_equilibrium
from forceclosure.analysis.two_finger import two_finger_closure

ROOT = resources.files("forceclosure") / "examples"


def _example(name, index):
    grasp = json.loads((ROOT / name).read_text())["grasps"][index]
    return [point_contact(c["point"], c["normal"], c.get("model", "hard"), c.get("mu", 0.0),
                          c.get("torsion")) for c in grasp["contacts"]]


def test_cube_seven_frictionless_contacts_close_and_any_six_do_not():
    cube = _example("spatial.json", 3)
    assert len(cube) == 7
    assert analyze(cube).verdict is Verdict.CLOSURE
    for drop in range(7):
        rest = cube[:drop] + cube[drop + 1:]
        a = analyze(rest)
        assert a.verdict is Verdict.NONE
        assert "at least 7" in a.reason


def test_planar_frictionless_needs_four_contacts():
    rng = np.random.default_rng(3)
    for _ in range(200):
        angles = rng.uniform(0, 2 * np.pi, 3)
        pts = rng.uniform(-1, 1, (3, 2))
        normals = np.stack([np.cos(angles), np.sin(angles)], axis=1)
        grasp = [point_contact(p, n, "frictionless") for p, n in zip(pts, normals, strict=True)]
        assert analyze(grasp).verdict is Verdict.NONE
    square = _example("planar.json", 4)
    assert len(square) == 4 and analyze(square).verdict is Verdict.CLOSURE


def test_antipodal_hard_fingers_in_space_are_rank_five():
    grasp = [point_contact([x, 0.3, 0.2], [x, 0, 0], "hard", 0.5) for x in (-1, 1)]
    a = analyze(grasp)
    assert a.verdict is Verdict.NONE and a.rank == 5
    assert a.force_direction_closure and not a.torque_closure
    # The unresisted motion: spin about the line through the contacts.
    assert a.motion.kind == "rotation"
    np.testing.assert_allclose(np.abs(a.motion.direction), [1, 0, 0], atol=1e-9)
    np.testing.assert_allclose(a.motion.point, [0, 0.3, 0.2], atol=1e-9)
    assert "rotation in either direction about the axis through (0, 0.3, 0.2)" in a.explain()


def test_antipodal_soft_fingers_in_space_are_closed():
    for torsion in (None, 0.01):
        grasp = [point_contact([x, 0.3, 0.2], [x, 0, 0], "soft", 0.5, torsion) for x in (-1, 1)]
        a = analyze(grasp)
        assert a.verdict is Verdict.CLOSURE and a.rank == 6
        # the certificate: contact forces in equilibrium
        f = a.contact_forces
        np.testing.assert_allclose(f.sum(axis=0), 0, atol=1e-9)


def _random_pairs(rng, n, d):
    p = rng.uniform(-1, 1, (n, d))
    q = rng.uniform(-1, 1, (n, d))
    # normals near the direction away from the other finger, so that many pairs close
    n_p = (p - q) / np.linalg.norm(p - q, axis=1, keepdims=True) + rng.normal(0, 0.6, (n, d))
    n_q = (q - p) / np.linalg.norm(p - q, axis=1, keepdims=True) + rng.normal(0, 0.6, (n, d))
    mu = rng.uniform(0.05, 1.0, n)
    return p, n_p, q, n_q, mu


def test_corollary_3_is_exact_in_the_plane():
    rng = np.random.default_rng(2)
    p, n_p, q, n_q, mu = _random_pairs(rng, 150, 2)
    closed = two_finger_closure(p, n_p, q, n_q, mu)
    gap = np.maximum(closed.angle_p, closed.angle_q) - np.arctan(mu)
    for i in range(len(p)):
        a = analyze([point_contact(p[i], n_p[i], "hard", mu[i]),
                     point_contact(q[i], n_q[i], "hard", mu[i])])
        if abs(gap[i]) > 1e-4:
            assert a.verdict.value == closed.verdict[i], (i, gap[i])
            assert a.verdict is (Verdict.CLOSURE if gap[i] < 0 else Verdict.NONE)
    assert 20 < np.sum(closed.force_closure) < 130


def test_corollary_3_in_space_is_sufficient_and_exact_for_antiparallel_normals():
    rng = np.random.default_rng(3)
    p, n_p, q, n_q, mu = _random_pairs(rng, 120, 3)
    n_q[:40] = -n_p[:40]  # antiparallel normals: Corollary 3 is iff
    closed = two_finger_closure(p, n_p, q, n_q, mu)
    gap = np.maximum(closed.angle_p, closed.angle_q) - np.arctan(mu)
    beyond = 0
    for i in range(len(p)):
        a = analyze([point_contact(p[i], n_p[i], "soft", mu[i]),
                     point_contact(q[i], n_q[i], "soft", mu[i])])
        assert a.verdict.value == closed.verdict[i] or abs(gap[i]) < 1e-4
        if gap[i] < -1e-4:
            assert a.verdict is Verdict.CLOSURE  # sufficient
        if i < 40 and gap[i] > 1e-4:
            assert a.verdict is Verdict.NONE  # necessary for antiparallel normals
        beyond += i >= 40 and gap[i] > 1e-4 and a.verdict is Verdict.CLOSURE
    assert beyond > 0  # closure outside the corollary's condition does happen


@pytest.mark.parametrize("rel", [0.999, 1.001])
def test_exact_cones_decide_pairs_on_a_hair(rel):
    """Soft pairs whose angle is 0.1% inside/outside the cone: the closed form is
    exact for circular cones, so the bracketed LP verdict must match it, while an
    8-edge inscribed pyramid alone would call the inside ones non-closed."""
    rng = np.random.default_rng(int(rel * 1000))
    for _ in range(8):
        mu = rng.uniform(0.2, 1.0)
        angle = rel * math.atan(mu)
        phi = rng.uniform(0, 2 * np.pi)
        # finger at the origin with normal -x; the other at distance 2 along a direction
        # making `angle` with +x, its normal along that same direction
        u = np.array([math.cos(angle), math.sin(angle) * math.cos(phi),
                      math.sin(angle) * math.sin(phi)])
        grasp = [point_contact([0, 0, 0], [-1, 0, 0], "soft", mu),
                 point_contact(2 * u, u, "soft", mu)]
        want = two_finger_closure(grasp[0].point, grasp[0].normal,
                                  grasp[1].point, grasp[1].normal, mu)
        a = analyze(grasp)
        assert a.verdict.value == str(want.verdict)
        assert a.verdict is (Verdict.CLOSURE if rel < 1 else Verdict.NONE)


def test_corollary_4_certifies_and_theorem_1_agrees():
    rng = np.random.default_rng(4)
    certified = 0
    for _ in range(60):
        d = int(rng.choice([2, 3]))
        p, n_p, q, n_q, mu = _random_pairs(rng, 1, d)
        model = "hard" if d == 2 else "soft"
        grasp = [point_contact(p[0], n_p[0], model, mu[0]),
                 point_contact(q[0], n_q[0], model, mu[0])]
        # forces along PQ, opposite: always in equilibrium
        f = (q[0] - p[0]) * rng.uniform(0.5, 2)
        cert = nonmarginal_equilibrium(grasp, [f, -f])
        if cert.certified:
            certified += 1
            assert analyze(grasp).verdict is Verdict.CLOSURE
        if not cert.certified and cert.cone_gap > 1e-3:
            pytest.fail("in equilibrium and strictly inside the cones, yet not certified")
    assert certified > 10


def test_corollary_4_refuses_what_it_cannot_certify():
    pinch = [point_contact([-1, 0], [-1, 0], "hard", 0.3),
             point_contact([1, 0], [1, 0], "hard", 0.3)]
    assert not nonmarginal_equilibrium(pinch, [[1, 0], [-1, 0.1]]).certified  # unbalanced
    hard = [point_contact([x, 0, 0], [x, 0, 0], "hard", 0.3) for x in (-1, 1)]
    cert = nonmarginal_equilibrium(hard, [[1, 0, 0], [-1, 0, 0]])
    assert not cert.certified and "line" in cert.reason
    edge = [point_contact([-1, 0], [-1, 0], "hard", 0.3),
            point_contact([1, 0.6], [1, 0], "hard", 0.3)]
    f = np.array([2, 0.6])
    assert not nonmarginal_equilibrium(edge, [f, -f]).certified  # on the cone's edge


def test_the_explanation_is_worked_out_when_read_and_travels_with_the_result():
    """``analyze`` decides with the compiled kernel and explains (Theorems 2 and 3, the
    certificate, the motion) on first reading, by the reference path; the result pickles."""
    import pickle

    closed = analyze([point_contact([-1, 0, 0], [-1, 0, 0], "soft", 0.5),
                      point_contact([1, 0.2, 0], [1, 0, 0], "soft", 0.5)])
    assert "_explained" not in closed.__dict__  # nothing computed yet
    forces = closed.contact_forces
    assert np.allclose(forces.sum(axis=0), 0, atol=1e-9) and np.all(forces[:, 0] * [-1, 1] < 0)
    assert closed.force_direction_closure and closed.torque_closure
    loose = analyze([point_contact([x, 0.3, 0.2], [x, 0, 0], "hard", 0.5) for x in (-1, 1)])
    again = pickle.loads(pickle.dumps(loose))
    assert again.verdict is loose.verdict and again.rank == 5
    assert again.motion.kind == "rotation" and not again.torque_closure
    assert "rotation" in again.explain()
