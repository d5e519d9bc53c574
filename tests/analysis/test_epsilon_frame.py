"""Epsilon does not change when a grasp is turned, moved, scaled or its contacts reordered.

The Ferrari–Canny epsilon is measured on inscribed pyramids, and a pyramid has an
orientation about its cone's axis. Taken from the coordinate axes it turned the
value with the object (issue 24: x 0.67-1.66 on duck grasps); taken from the grasp
(``geometry.cones.fill_frame``) it cannot. Independent truths here: the same grasp
turned (property tests, hypothesis), the pyramid rule written again in this file
with its own wrenches and Qhull, a closed form for the head-on soft pinch derived
by hand (its wrench hull is a free sum), and the inscribed bracket for the one case
the rule leaves to a coordinate axis.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull
from scipy.spatial.transform import Rotation

from forceclosure import point_contact
from forceclosure.analysis.batch import epsilon_batch
from forceclosure.analysis.quality import epsilon
from forceclosure.geometry.cones import grasp_tangents

#: Relative change of epsilon allowed between a grasp and its turned, moved, scaled,
#: reordered copy: round-off (about 1e-16 / FRAME_TOL where a fallback is near-degenerate).
BOUND = 1e-9


def _pinches(rng, n):
    """``n`` two-pad grasps (soft, ``(n, 2, 3)``), most near antipodal; a few exactly
    degenerate: head-on (every contact on one line, normals along it: the rule's last
    resort) and collinear with one pad tilted (the other contacts' normals decide)."""
    centre = rng.normal(size=(n, 1, 3))
    axis = rng.normal(size=(n, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    half = rng.uniform(0.05, 1.0, (n, 1, 1))
    offset = rng.normal(0, 0.2, (n, 2, 3)) * half
    P = centre + half * np.stack([-axis, axis], axis=1) + offset
    N = np.stack([-axis, axis], axis=1) + rng.normal(0, 0.15, (n, 2, 3))
    P[:2] = centre[:2] + half[:2] * np.stack([-axis[:2], axis[:2]], axis=1)  # head-on
    N[:2] = np.stack([-axis[:2], axis[:2]], axis=1)
    P[2] = P[1]
    N[2, 0] = -axis[1]
    N[2, 1] = axis[1] + 0.15 * np.cross(axis[1], [0.0, 0.0, 1.0])  # the second pad tilted
    return P, N / np.linalg.norm(N, axis=2, keepdims=True)


def _triples(rng, n):
    """``n`` three-hard-finger grasps on a sphere; two symmetric: three fingers 120 degrees
    apart on a circle pointing at its centre (the centroid on every normal line: the other
    contacts decide)."""
    P = rng.normal(size=(n, 3, 3))
    P /= np.linalg.norm(P, axis=2, keepdims=True)
    N = P + rng.normal(0, 0.3, P.shape)
    for g in range(2):
        u, v = np.linalg.qr(rng.normal(size=(3, 3)))[0][:, :2].T
        angles = rng.uniform(0, 2 * np.pi) + np.array([0, 2, 4]) * np.pi / 3
        radial = np.cos(angles)[:, None] * u + np.sin(angles)[:, None] * v
        P[g] = rng.uniform(0.3, 2) * radial + rng.normal(size=3)
        N[g] = radial
    return P, N / np.linalg.norm(N, axis=2, keepdims=True)


def _moved(P, N, rotvec, shift, scale, order):
    R = Rotation.from_rotvec(rotvec).as_matrix()
    return scale * P[:, order] @ R.T + np.asarray(shift), N[:, order] @ R.T


def _assert_same(moved, base):
    np.testing.assert_allclose(moved, base, rtol=BOUND, atol=1e-12)


vectors = st.tuples(*[st.floats(-4, 4)] * 3)


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**32 - 1), vectors, vectors, st.floats(0.01, 100), st.booleans())
def test_two_soft_pads_turned_moved_scaled_and_swapped(seed, rotvec, shift, scale, coupled):
    rng = np.random.default_rng(seed)
    P, N = _pinches(rng, 12)
    mu = rng.uniform(0.3, 1.0, (12, 2))
    torsion = rng.uniform(0.02, 0.2, (12, 2)) if coupled else None
    base = epsilon_batch(P, N, mu=mu, model="soft", torsion=torsion)
    assert np.sum(base > 0) >= 4  # closed pinches, head-on ones among them
    assert np.all(base[:3] > 0)
    Pm, Nm = _moved(P, N, rotvec, shift, scale, [1, 0])
    moved = epsilon_batch(Pm, Nm, mu=mu[:, ::-1], model="soft",
                          torsion=None if torsion is None else scale * torsion[:, ::-1])
    _assert_same(moved, base)


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 2**32 - 1), vectors, vectors, st.floats(0.01, 100),
       st.permutations([0, 1, 2]))
def test_three_hard_fingers_turned_moved_scaled_and_reordered(seed, rotvec, shift, scale, order):
    rng = np.random.default_rng(seed)
    P, N = _triples(rng, 12)
    mu = rng.uniform(0.4, 1.2, (12, 3))
    base = epsilon_batch(P, N, mu=mu)
    Pm, Nm = _moved(P, N, rotvec, shift, scale, order)
    _assert_same(epsilon_batch(Pm, Nm, mu=mu[:, order]), base)


def test_the_reference_path_is_invariant_too():
    """One contact list through ``quality.epsilon`` (Qhull), L1 and Linf, turned and reversed."""
    rng = np.random.default_rng(5)
    P, N = _triples(rng, 3)
    Pm, Nm = _moved(P, N, [0.3, -1.2, 2.0], [5.0, -2.0, 1.0], 3.0, [2, 1, 0])
    for g in range(3):
        for norm in ("L1", "Linf") if g == 2 else ("L1",):
            a, b = (epsilon([point_contact(p, n, "hard", 0.8) for p, n in zip(*g_, strict=True)],
                            norm) for g_ in ((P[g], N[g]), (Pm[g], Nm[g])))
            assert b.value == pytest.approx(a.value, rel=BOUND, abs=1e-12), (g, norm)
            assert a.cone == "8-edge inscribed pyramids oriented by the grasp"


@pytest.fixture(scope="module")
def duck_grasps():
    """Closed soft-pad grasps sampled on pybullet_data's duck (2 units across)."""
    pybullet_data = pytest.importorskip("pybullet_data")
    from forceclosure.gripper.jaw import ParallelJaw
    from forceclosure.gripper.labels import grasp_labels
    from forceclosure.objects.io import load_object

    duck = load_object(os.path.join(pybullet_data.getDataPath(), "duck.obj"))
    jaw = ParallelJaw(2.0, pad_radius=0.1)
    labels = grasp_labels(duck, jaw, 0.5, 40, seed=0, least_friction=False, collision=False)
    closed = np.flatnonzero(labels.code == 2)[:12]
    assert len(closed) == 12
    return labels.points[closed], labels.normals[closed], jaw.torsion(0.5), labels.epsilon[closed]


def test_real_duck_grasps_turned(duck_grasps):
    P, N, torsion, labelled = duck_grasps
    base = epsilon_batch(P, N, mu=0.5, model="soft", torsion=torsion)
    np.testing.assert_array_equal(base, labelled)  # the labels' epsilon is this one
    assert np.all(base > 0)
    for seed in range(3):
        R = Rotation.random(random_state=seed)
        Pm, Nm = _moved(P, N, R.as_rotvec(), [0.5 * seed, -3.0, 7.0], 1.0, [1, 0])
        _assert_same(epsilon_batch(Pm, Nm, mu=0.5, model="soft", torsion=torsion), base)
        # the coordinate axes' pyramids, as before: the turn changes them (the test has teeth)
        a, b = (epsilon_batch(p, n, mu=0.5, model="soft", torsion=torsion, orientation="axes")
                for p, n in ((P, N), (Pm, Nm)))
        assert np.any(np.abs(a - b) > 0.05 * np.maximum(a, b))


def _own_epsilon(P, N, mu, k=8, torsion=None):
    """Epsilon written again from the documented rule: ``t1`` the direction to the contacts'
    centroid in the tangent plane, ``t2 = n x t1``, edges ``-n + mu (cos t1 + sin t2)`` at
    ``2 pi r / k``; torques about the centroid over the largest distance from it; soft pads
    ``± torsion n`` (coupled) or the pure torques ``(0, ±n)``; the hull by Qhull."""
    c = P.mean(axis=0)
    s = np.max(np.linalg.norm(P - c, axis=1))
    theta = 2 * np.pi * np.arange(k) / k
    W = []
    for p, n in zip(P, N, strict=True):
        d = (c - p) - np.dot(c - p, n) * n
        assert np.linalg.norm(d) > 1e-3 * s  # the rule's first case
        t1 = d / np.linalg.norm(d)
        t2 = np.cross(n, t1)
        for a in theta:
            f = -n + mu * (np.cos(a) * t1 + np.sin(a) * t2)
            tau = np.cross(p - c, f) / s
            if torsion is None:
                W.append(np.r_[f, tau])
            else:
                W += [np.r_[f, tau + torsion * n / s], np.r_[f, tau - torsion * n / s]]
        if torsion is None and len(P) == 2:
            W += [np.r_[0, 0, 0, n], np.r_[0, 0, 0, -n]]
    return float(np.min(-ConvexHull(np.array(W)).equations[:, -1]))


def test_the_documented_rule_written_again():
    """The compiled epsilon equals Qhull's on pyramids built here by the documented rule."""
    rng = np.random.default_rng(11)
    P, N = _triples(rng, 40)
    P, N = P[2:], N[2:]  # generic grasps: the rule's first case
    ours = epsilon_batch(P, N, mu=0.7)
    checked = 0
    for g in range(len(P)):
        truth = _own_epsilon(P[g], N[g], 0.7)
        if truth > 1e-6:
            assert ours[g] == pytest.approx(truth, rel=1e-9), g
            checked += 1
        elif truth < -1e-6:
            assert ours[g] == 0.0
    P, N = _pinches(rng, 30)
    P, N = P[3:], N[3:]
    for torsion in (None, 0.05):
        ours = epsilon_batch(P, N, mu=0.6, model="soft", torsion=torsion)
        for g in range(len(P)):
            truth = _own_epsilon(P[g], N[g], 0.6, torsion=torsion)
            if truth > 1e-6:
                assert ours[g] == pytest.approx(truth, rel=1e-9), g
                checked += 1
    assert checked > 30


@pytest.mark.parametrize("mu, half, torsion, edges", [
    (0.5, 1.0, None, 8), (0.3, 2.0, None, 8), (0.8, 0.5, None, 5),
    (0.5, 1.0, 0.1, 8), (0.5, 1.0, 0.9, 8), (1.2, 3.0, 0.5, 6)])
def test_head_on_soft_pinch_closed_form(mu, half, torsion, edges):
    """Two soft pads at ``c ± L a`` with normals ``±a``: every pyramid edge of pad 1 is
    ``(f_x, tau_x, u1, u2) = (1, 0, sqrt2 mu e_r, 0)`` and of pad 2 ``(-1, 0, 0, sqrt2 mu
    e_r)`` in the orthonormal coordinates ``u1, u2 = (g ± J h) / sqrt2`` (``g`` the
    tangential force, ``h`` the torque about the tangents), whatever the pyramids' turn:
    the two ``k``-gons lie in orthogonal planes. The polar of the hull is then a product,
    its farthest vertex at ``y0 = ±1``: with ``c = mu cos(pi / k)``, ``1 / eps^2 = 2 + 2 /
    c^2`` for the paper's pure torques (a free sum with ``[-1, 1] tau_x``), and
    ``max(1 + 2 / c^2, L^2 / gamma^2)`` for torsion ``gamma`` coupled to the normal force."""
    a = Rotation.random(random_state=edges).apply([1.0, 0, 0])
    centre = np.array([3.0, -1.0, 2.0])
    grasp = [point_contact(centre - half * a, -a, "soft", mu, torsion),
             point_contact(centre + half * a, a, "soft", mu, torsion)]
    c = mu * math.cos(math.pi / edges)
    if torsion is None:
        want = 1 / math.sqrt(2 + 2 / c**2)
    else:
        want = min(1 / math.sqrt(1 + 2 / c**2), torsion / half)
    assert epsilon(grasp, edges=edges).value == pytest.approx(want, rel=1e-12)
    P = np.array([[g.point for g in grasp]])
    N = np.array([[g.normal for g in grasp]])
    got = epsilon_batch(P, N, mu=mu, model="soft", torsion=torsion, edges=edges)
    assert got[0] == pytest.approx(want, rel=1e-12)


def test_frames_turn_with_the_grasp_in_every_case():
    """The tangents themselves: turned with the grasp (up to the pyramid's half turn where
    the rule's sign is free) — centroid, other contacts, other normals, and head-on."""
    rng = np.random.default_rng(8)
    R = Rotation.from_rotvec([0.4, -2.2, 0.9]).as_matrix()
    Pp, Np = _pinches(rng, 3)
    Pt, Nt = _triples(rng, 3)
    for P, N in ((Pp[2], Np[2]), (Pt[0], Nt[0]), (Pt[2], Nt[2])):
        t1, t2 = grasp_tangents(P, N)
        u1, u2 = grasp_tangents(P[::-1] @ R.T * 7.0 - 3.0, N[::-1] @ R.T)
        sign = np.sign(np.sum(u1[::-1] * (t1 @ R.T), axis=1))[:, None]
        np.testing.assert_allclose(u1[::-1], sign * t1 @ R.T, atol=1e-9)
        np.testing.assert_allclose(u2[::-1], sign * t2 @ R.T, atol=1e-9)
        np.testing.assert_allclose(np.sum(t1 * N, axis=1), 0, atol=1e-12)
        np.testing.assert_allclose(np.cross(t1, t2), N, atol=1e-12)
    # head-on (the last resort, one coordinate axis for both pads): the two frames keep
    # their relative turn, so the pair turns together about the line (a symmetry)
    P, N = Pp[0], Np[0]
    t1, _ = grasp_tangents(P, N)
    u1, _ = grasp_tangents(P[::-1] @ R.T * 7.0 - 3.0, N[::-1] @ R.T)[0][::-1], None
    assert np.dot(u1[0], u1[1]) == pytest.approx(np.dot(t1[0], t1[1]), abs=1e-12)
    assert np.dot(np.cross(u1[0], u1[1]), R @ N[1]) == pytest.approx(
        np.dot(np.cross(t1[0], t1[1]), N[1]), abs=1e-12)
    np.testing.assert_allclose(np.sum(u1 * (N @ R.T), axis=1), 0, atol=1e-12)


def test_a_symmetric_grasp_left_to_an_axis_stays_in_the_inscribed_bracket():
    """Four fingers at a regular tetrahedron's vertices pointing at its centre: about each
    normal the others balance to second order, and the pyramid's turn comes from a
    coordinate axis (the rule's case D2). Its epsilon, turned or not, stays in the bracket
    of every inscribed 8-edge pyramid: above the circular cones' at friction ``mu cos(pi/8)``
    (so above any pyramid inside those: here one at radius ``mu cos(pi/8)``, turned at
    random) and below theirs at ``mu`` (so below any pyramid around those: here one at
    ``mu / cos(pi/8)``)."""
    vertices = np.array([[1.0, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]]) / math.sqrt(3)
    mu = 0.5
    low = _hard_hull(vertices, vertices, mu * math.cos(math.pi / 8), 8)
    high = _hard_hull(vertices, vertices, mu / math.cos(math.pi / 8), 8)
    assert 0 < low < high
    for seed in range(4):
        R = Rotation.random(random_state=seed).as_matrix() if seed else np.eye(3)
        value = epsilon_batch(vertices[None] @ R.T, vertices[None] @ R.T, mu=mu)[0]
        assert low <= value <= high


def _hard_hull(P, N, mu, k):
    """Epsilon of hard fingers with ``k``-edge pyramids turned any way (here: a fixed
    random turn per contact), by Qhull."""
    rng = np.random.default_rng(0)
    c = P.mean(axis=0)
    s = np.max(np.linalg.norm(P - c, axis=1))
    W = []
    for p, n in zip(P, N, strict=True):
        t1 = np.cross(n, rng.normal(size=3))
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        for a in 2 * np.pi * (np.arange(k) + rng.uniform()) / k:
            f = -n + mu * (np.cos(a) * t1 + np.sin(a) * t2)
            W.append(np.r_[f, np.cross(p - c, f) / s])
    return float(np.min(-ConvexHull(np.array(W)).equations[:, -1]))


def test_a_pinch_the_circular_cones_close_has_positive_epsilon():
    """Antiparallel pads (faces of a box) are closed iff the jaws' line is inside both cones
    (Corollary 3: ``tan(tilt) < mu``). Each pad's first pyramid edge lies in the plane of
    its normal and that line (case A), so the pyramid holds the line as far as the circle
    does: epsilon > 0 exactly when Corollary 3 closes the pair. The coordinate axes'
    pyramids hold it only as far as ``mu cos(pi/8)`` in some directions."""
    rng = np.random.default_rng(4)
    n = 200
    a = Rotation.random(n, random_state=4).apply([1.0, 0, 0])
    side = np.cross(a, rng.normal(size=(n, 3)))
    side /= np.linalg.norm(side, axis=1, keepdims=True)
    mu = 0.5
    tilt = np.arctan(mu * rng.uniform(0.85, 1.15, n))  # around the cone's edge
    half = rng.uniform(0.1, 2, (n, 1))
    P = np.stack([-half * a, half * (a + 2 * np.tan(tilt)[:, None] * side)], axis=1)
    N = np.stack([-a, a], axis=1)
    clear = np.abs(np.tan(tilt) - mu) > 1e-6
    closed = np.tan(tilt) < mu
    eps = epsilon_batch(P, N, mu=mu, model="soft", torsion=0.01)
    np.testing.assert_array_equal((eps > 0)[clear], closed[clear])
    axes = epsilon_batch(P, N, mu=mu, model="soft", torsion=0.01, orientation="axes")
    assert np.sum(closed & (axes == 0)) > 5


def test_the_wrench_hull_volume_turns_with_the_grasp_too():
    """``grasp_metrics``' volume is of the same hull as epsilon: the same pyramids, so the
    same value for the turned, moved, scaled, reordered grasp (the singular values never
    depended on the tangents' turn)."""
    from forceclosure.analysis.metrics import grasp_metrics

    rng = np.random.default_rng(9)
    P, N = _triples(rng, 6)
    Pm, Nm = _moved(P, N, [1.1, 0.2, -0.7], [4.0, 0.0, -9.0], 2.0, [1, 2, 0])
    a = grasp_metrics(P, N, mu=0.6)
    b = grasp_metrics(Pm, Nm, mu=0.6)
    assert np.all(a.volume > 0)
    np.testing.assert_allclose(b.volume, a.volume, rtol=1e-9)
    np.testing.assert_allclose(b.sigma_min, a.sigma_min, rtol=1e-9)


def test_an_unknown_orientation_is_refused_in_one_line():
    from forceclosure import InputError

    P = np.array([[[-1.0, 0, 0], [1, 0, 0]]])
    for call in (lambda: epsilon_batch(P, P, mu=0.5, orientation="world"),
                 lambda: epsilon([point_contact(p, p, "soft", 0.5) for p in P[0]],
                                 orientation="world")):
        with pytest.raises(InputError, match="orientation must be 'grasp' or 'axes'") as err:
            call()
        assert "\n" not in str(err.value)
