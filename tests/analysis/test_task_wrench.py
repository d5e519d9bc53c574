"""The task-wrench test against closed forms and an LP written independently here.

Closed form: a box held by two antipodal soft pads at ``(-+1, 0, 0)`` with
friction ``mu``, each pressing at most ``f_max``, against its weight ``m g``
along a direction perpendicular to the closing axis, centre of mass on the
pads' line. The squeeze cancels; friction holds up to ``mu f_max`` at each
pad along any tangent direction (circular cones), the torques of the two
equal friction forces cancel about the centre. So it holds iff ``2 mu
f_max >= m g``, with spare ``s* = 2 mu f_max / (m g)`` exactly for circular
cones. An inscribed ``k``-edge pyramid reaches only ``mu cos(delta)``
along a direction ``delta`` away from its nearest edge, so the module's
``spare`` must lie in ``[cos(pi/k) s*, s*]`` and ``spare_upper`` in ``[s*, s* /
cos(pi/k)]``.

Independent LP: the same question in another formulation — contact forces
``f_i`` as variables (not weights of generators), each pyramid by its facets
(H-form: ``f · u_j <= mu cos(pi/k) f_n`` for the facet normals ``u_j`` at
the mid-angles between edges), physical torques about the origin, coupled
torsion ``|tau_i| <= gamma f_n``. Same pyramids (edges at angles ``2 pi
j / k`` from ``t1`` of :func:`forceclosure.contacts.tangent_basis`, the
library's documented convention), so the maxima must agree.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import linprog

from forceclosure.analysis.task import gravity_wrench, resist_wrench, resist_wrench_batch
from forceclosure.contacts import tangent_basis
from forceclosure.errors import InputError

P2 = [[-1.0, 0, 0], [1, 0, 0]]
N2 = [[-1.0, 0, 0], [1, 0, 0]]


@pytest.mark.parametrize("phi", [0.0, 0.2, math.pi / 8, 1.0, 2.5])
@pytest.mark.parametrize("edges", [4, 8, 16])
def test_box_against_gravity_brackets_the_closed_form(phi, edges):
    mu, f_max, mass = 0.4, 10.0, 0.6
    g = 9.81 * np.array([0, math.cos(phi), math.sin(phi)])  # perpendicular to x
    truth = 2 * mu * f_max / (mass * 9.81)
    t = resist_wrench(P2, N2, gravity_wrench(mass, [0, 0, 0], g), mu=mu, f_max=f_max,
                      edges=edges)
    c = math.cos(math.pi / edges)
    assert c * truth * (1 - 1e-9) <= t.spare <= truth * (1 + 1e-9)
    assert truth * (1 - 1e-9) <= t.spare_upper <= truth / c * (1 + 1e-9)
    # resisting spare * weight: the forces balance it with normal forces within f_max
    w = t.spare * gravity_wrench(mass, [0, 0, 0], g)
    assert np.allclose(t.forces.sum(axis=0), -w[:3], atol=1e-7)
    assert np.all(-np.einsum("ij,ij->i", t.forces, np.array(N2)) <= f_max * (1 + 1e-9))


@pytest.mark.parametrize("ratio, verdict", [(1.25, "resists"), (0.8, "fails"),
                                            (1.02, "undecided")])
def test_verdicts_on_either_side(ratio, verdict):
    # 2 mu f_max = ratio * m g; the weight along the diagonal of y and z (mid-way between
    # the 8-edge pyramids' edges at multiples of 45 degrees from the axes)
    mu, mass = 0.5, 1.0
    f_max = ratio * mass * 9.81 / (2 * mu)
    g = 9.81 * np.array([0, math.cos(math.pi / 8), math.sin(math.pi / 8)])
    t = resist_wrench(P2, N2, gravity_wrench(mass, [0, 0, 0], g), mu=mu, f_max=f_max)
    assert t.verdict == verdict
    assert t.resists == (verdict == "resists")


def test_torque_about_the_closing_axis():
    # centre of mass 0.3 off the pads' line along y, weight along -z: a torque 0.3 m g
    # about x. Hard pads resist no torque about their line; pads with coupled torsion
    # (|tau| <= gamma f_n each) need 2 gamma f_n >= 0.3 m g, friction 2 mu f_n >= m g
    mu, gamma, f_max, mass = 0.5, 0.05, 10.0, 1.0
    w = gravity_wrench(mass, [0, 0.3, 0], [0, 0, -9.81])
    assert resist_wrench(P2, N2, w, mu=mu, model="hard", f_max=f_max).spare == 0.0
    t = resist_wrench(P2, N2, w, mu=mu, torsion=gamma, f_max=f_max)
    truth = min(2 * mu * f_max, 2 * gamma * f_max / 0.3) / (mass * 9.81)  # torsion binds
    assert t.spare == pytest.approx(truth, rel=1e-7)  # z is an edge of both pyramids here
    assert abs(t.torsion).sum() == pytest.approx(0.3 * mass * 9.81 * t.spare, rel=1e-7)
    # the paper's soft finger: torque about the normal unbounded, friction binds
    t = resist_wrench(P2, N2, w, mu=mu, f_max=f_max)
    assert t.spare == pytest.approx(2 * mu * f_max / (mass * 9.81), rel=1e-7)


def test_planar_cones_are_exact():
    # two fingers at (-+1, 0) squeezing along x, weight along -y: 2 mu f_max / (m g), and
    # the planar cones are exact, so both bounds agree
    mu, f_max, mass = 0.3, 4.0, 0.5
    t = resist_wrench([[-1, 0], [1, 0]], [[-1.0, 0], [1, 0]], [0.0, -mass * 9.81, 0.0],
                      mu=mu, model="hard", f_max=f_max)
    truth = 2 * mu * f_max / (mass * 9.81)
    assert t.spare == pytest.approx(truth, rel=1e-9)
    assert t.spare_upper == pytest.approx(truth, rel=1e-9)
    assert t.verdict == ("resists" if truth >= 1 else "fails")


def _independent_lp(P, N, w, mu, gamma, f_max, k):
    """max s: forces f_i in inscribed k-pyramids (facet form), |tau_i| <= gamma f_n,i,
    f_n,i <= f_max, sum f_i + s F = 0, sum p_i x f_i + tau_i n_i + s T = 0."""
    n = len(P)
    nv = 4 * n + 1  # f_i (3), tau_i (1), s
    t1, t2 = tangent_basis(np.asarray(N))
    A_ub, b_ub, A_eq = [], [], np.zeros((6, nv))
    for i in range(n):
        fi = slice(4 * i, 4 * i + 3)
        for j in range(k):
            ang = 2 * math.pi * j / k + math.pi / k
            u = math.cos(ang) * t1[i] + math.sin(ang) * t2[i]
            row = np.zeros(nv)
            row[fi] = u + mu * math.cos(math.pi / k) * N[i]  # f.u <= mu cos(pi/k) (-f.n)
            A_ub.append(row)
            b_ub.append(0.0)
        row = np.zeros(nv)
        row[fi] = -N[i]  # f_n <= f_max
        A_ub.append(row)
        b_ub.append(f_max)
        for sign in (1, -1):  # +-tau <= gamma f_n
            row = np.zeros(nv)
            row[4 * i + 3] = sign
            row[fi] = gamma * N[i]
            A_ub.append(row)
            b_ub.append(0.0)
        A_eq[:3, fi] = np.eye(3)
        A_eq[3:, fi] = np.array([np.cross(P[i], e) for e in np.eye(3)]).T
        A_eq[3:, 4 * i + 3] = N[i]
    A_eq[:, -1] = w
    c = np.zeros(nv)
    c[-1] = -1
    bounds = [(None, None)] * (4 * n) + [(0, None)]
    res = linprog(c, A_ub=np.array(A_ub), b_ub=b_ub, A_eq=A_eq, b_eq=np.zeros(6),
                  bounds=bounds, method="highs")
    assert res.status == 0
    return res.x[-1]


def test_against_an_independent_lp_on_random_grasps():
    rng = np.random.default_rng(2)
    checked = 0
    for _ in range(16):
        k = int(rng.integers(3, 7))
        dirs = rng.normal(size=(k, 3))
        dirs /= np.linalg.norm(dirs, axis=1)[:, None]
        P = 0.1 * dirs + [0.3, -0.2, 0.5]  # on a sphere of radius 0.1, off the origin
        N = dirs  # outward normals of the sphere
        mu, gamma, f_max = float(rng.uniform(0.2, 0.8)), 0.002, 5.0
        w = np.concatenate([rng.normal(size=3), 0.05 * rng.normal(size=3)])
        t = resist_wrench(P, N, w, mu=mu, torsion=gamma, f_max=f_max, edges=8)
        truth = _independent_lp(P, N, w, mu, gamma, f_max, 8)
        assert t.spare == pytest.approx(truth, rel=1e-6, abs=1e-9)
        checked += truth > 0
    assert checked >= 8  # most random grasps resist some multiple of their wrench


def test_bad_input_is_refused():
    w = gravity_wrench(1.0, [0, 0, 0])
    with pytest.raises(InputError):
        resist_wrench(P2, N2, np.zeros(6), mu=0.5)
    with pytest.raises(InputError):
        resist_wrench(P2, N2, w[:5], mu=0.5)
    with pytest.raises(InputError):
        resist_wrench(P2, N2, w, mu=0.5, f_max=0.0)
    with pytest.raises(InputError):
        resist_wrench(P2, N2, w, mu=-1.0)
    with pytest.raises(InputError):
        gravity_wrench(-1.0, [0, 0, 0])


@pytest.mark.parametrize("unit", [1e-100, 1e-20, 1.0, 1e20, 1e100])
def test_units_do_not_reach_the_lp(unit):
    """The box squeezed across x (resist_wrench's example): friction holds 2 mu f_max = 10
    against a weight of 4, spare 2.5 in any units; HiGHS once refused weights of 1e100
    ("Model error", an internal error) and took f_max >= 1e20 for no bound at all."""
    P = [[-1, 0, 0], [1, 0, 0]]
    N = [[-1, 0, 0], [1, 0, 0]]
    w = gravity_wrench(0.4 * unit, [0, 0, 0], g=[0, 0, -10])
    t = resist_wrench(P, N, w, mu=0.5, f_max=10.0 * unit)
    assert t.verdict == "resists" and t.spare == pytest.approx(2.5, rel=1e-6)
    code, spare, _ = resist_wrench_batch([P, P], [N, N], w, mu=0.5, f_max=10.0 * unit)
    assert code.tolist() == [2, 2] and spare == pytest.approx([2.5, 2.5], rel=1e-6)
    if unit >= 1:  # the forces found are the units' too: each pad presses at most f_max
        assert np.all(np.abs(t.forces[:, 0]) <= 10.0 * unit * (1 + 1e-6))
