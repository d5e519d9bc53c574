"""The exact cones' ``marginal`` settled at once, from the turn about two pinching fingers
that every cone lies on one side of (``geometry.cones.one_sided``), against the ladder of
pyramids it skips and an LP of its own.

Grasps with two fingers opposed within their cones are the family: the forces at those
two do no work on the rotation about the line through them, so unless the third finger's
cone straddles it, the grasp is marginal at every pyramid up to 256 edges, which the
ladder (``closure._decide``) used to build and solve in full. Ground truth here is that
ladder with the shortcut switched off, and the 256-edge inscribed pyramid's margin from
scipy's LP written out below.
"""

import numpy as np
import pytest
from scipy.optimize import linprog

from forceclosure import Cone, Verdict, generating_wrenches, point_contact
from forceclosure.analysis import closure
from forceclosure.analysis.batch_analysis import analyze_batch
from forceclosure.analysis.closure import analyze_explained
from forceclosure.geometry.cones import one_sided

MU = 0.5


def _opposed(rng, n, jitter=0.1):
    """Two fingers pinching along a chord of the unit sphere (normals along it, within
    their cones) and a third on the sphere, its normal about the radius."""
    p = rng.normal(size=(n, 3, 3))
    p /= np.linalg.norm(p, axis=2, keepdims=True)
    chord = p[:, 0] - p[:, 1]
    normals = p + rng.normal(scale=0.2, size=p.shape)
    normals[:, 0] = chord + rng.normal(scale=jitter, size=(n, 3))
    normals[:, 1] = -chord + rng.normal(scale=jitter, size=(n, 3))
    return p, normals / np.linalg.norm(normals, axis=2, keepdims=True)


def _grasp(P, N, mu=MU, models=("hard",) * 3):
    return [point_contact(P[i], N[i], models[i], mu) for i in range(len(P))]


def _margin_256(P, N, mu=MU):
    """Theorem 1's margin ``m max min lam`` of the 256-edge inscribed pyramids, by linprog."""
    W = generating_wrenches(_grasp(P, N, mu), Cone(256)).wrenches
    U = W / np.linalg.norm(W, axis=0)
    d, m = U.shape
    # variables lam (m) and s: max s, U lam = 0, sum lam = 1, lam - s >= 0
    c = np.r_[np.zeros(m), -1.0]
    A_eq = np.r_[np.c_[U, np.zeros(d)], [np.r_[np.ones(m), 0.0]]]
    A_ub = np.c_[-np.eye(m), np.ones(m)]
    r = linprog(c, A_ub=A_ub, b_ub=np.zeros(m), A_eq=A_eq, b_eq=np.r_[np.zeros(d), 1.0],
                bounds=[(None, None)] * (m + 1), method="highs")
    assert r.status == 0
    return m * r.x[-1]


@pytest.fixture
def ladder(monkeypatch):
    """``analyze`` by the reference path with the shortcut off: every pyramid to 256 edges."""
    def full(grasp):
        with monkeypatch.context() as m:
            m.setattr(closure, "_one_sided", lambda *a: False)
            return closure.decide(grasp, "exact", closure.TOLERANCE)[0]
    return full


def test_the_docstring_grasp_is_marginal_by_the_whole_ladder_too(ladder):
    P = np.array([[-1.0, 0, 0], [1.0, 0, 0], [0.0, 0, 1]])
    N = np.array([[-1.0, 0, 0], [1.0, 0, 0], [0.0, 1, 0]])
    a = analyze_explained(_grasp(P, N))
    assert a.verdict is Verdict.MARGINAL
    assert "one side of a turn about two contacts" in a.cone
    full = ladder(_grasp(P, N))
    assert full.verdict is Verdict.MARGINAL and full.rank == a.rank == 6
    assert _margin_256(P, N) <= 1e-9


def test_settled_grasps_are_marginal_by_the_ladder_and_by_an_lp_of_their_own(ladder):
    rng = np.random.default_rng(11)
    P, N = _opposed(rng, 40)
    settled = 0
    for g in range(len(P)):
        a = analyze_explained(_grasp(P[g], N[g]))
        full = ladder(_grasp(P[g], N[g]))
        assert (a.verdict, a.rank) == (full.verdict, full.rank), g
        if "one side of a turn about two contacts" in a.cone:
            settled += 1
            assert a.verdict is Verdict.MARGINAL
            assert _margin_256(P[g], N[g]) <= 0.25 * closure.TOLERANCE, g
    assert settled >= 10  # the family is the shortcut's: most of it is settled at once


def test_the_kernel_agrees_with_the_ladder_on_the_family(ladder):
    rng = np.random.default_rng(12)
    P, N = _opposed(rng, 300)
    ours = analyze_batch(P, N, mu=MU)
    assert (ours.verdict == "marginal").sum() >= 60
    for g in range(0, 300, 5):
        full = ladder(_grasp(P[g], N[g]))
        assert (ours.code[g], ours.rank[g]) == (full.verdict.code, full.rank), g


def test_mixed_models_take_the_shortcut_and_soft_fingers_do_not(ladder):
    rng = np.random.default_rng(13)
    P, N = _opposed(rng, 30)
    for models in (("hard", "hard", "frictionless"), ("soft", "soft", "hard")):
        ours = analyze_batch(P, N, mu=MU, model=list(models))
        for g in range(0, 30, 3):
            full = ladder(_grasp(P[g], N[g], models=models))
            assert ours.code[g] == full.verdict.code, (models, g)


def test_what_proves_nothing():
    P = np.array([[-1.0, 0, 0], [1.0, 0, 0], [0.0, 0, 1]])
    N = np.array([[-1.0, 0, 0], [1.0, 0, 0], [0.0, 1, 0]])
    ref, mu = P.mean(axis=0), np.full(3, MU)
    assert one_sided(P, N, mu, ref, 1.0, 768, 1e-6)
    assert not one_sided(P, N, mu, ref, 1.0, 768, 1e-11)  # below round-off's reach
    # the third finger's cone straddles the turn once its axis is more than 90 degrees
    # less the cone's half-angle (atan 0.5, 26.6 degrees) from the motion there (-y)
    N2 = N.copy()
    N2[2] = [0.0, 0.6, 0.8]  # 53 degrees: still on one side
    assert one_sided(P, N2, mu, ref, 1.0, 768, 1e-6)
    N2[2] = [0.0, 0.3, np.sqrt(0.91)]  # 72.5 degrees: across, and no other turn serves
    assert not one_sided(P, N2, mu, ref, 1.0, 768, 1e-6)
    # the same in another frame (moved, turned, scaled): the same answers
    R = np.linalg.qr(np.random.default_rng(1).normal(size=(3, 3)))[0]
    for normals, holds in ((N, True), (N2, False)):
        Q = 3.0 * P @ R.T + [5.0, -2.0, 7.0]
        assert one_sided(Q, normals @ R.T, mu, Q.mean(axis=0), 2.0, 768, 1e-6) is holds
    # frictionless fingers: the pinch's two do no work, the third pushes along -y
    assert one_sided(P, N, np.zeros(3), ref, 1.0, 768, 1e-6)


def test_never_on_a_closed_grasp():
    """No turn can have every cone on one side of it when the grasp closes: on random
    grasps the ladder closes, no turn about two contacts proves a thing."""
    rng = np.random.default_rng(14)
    p = rng.normal(size=(250, 3, 3))
    p /= np.linalg.norm(p, axis=2, keepdims=True)
    n = p + rng.normal(scale=0.2, size=p.shape)
    n /= np.linalg.norm(n, axis=2, keepdims=True)
    closed = 0
    for g in range(len(p)):
        grasp = _grasp(p[g], n[g])
        vc, ws = closure.decide(grasp, "exact", closure.TOLERANCE)[:2]
        if vc.verdict is not Verdict.CLOSURE:
            continue
        closed += 1
        assert not one_sided(p[g], n[g], np.full(3, MU), ws.reference, ws.length_scale, 768,
                             closure.TOLERANCE), g
    assert closed >= 60
