"""Pair labels in one compiled pass (:func:`forceclosure.analysis.two_finger.pair_labels`,
behind :func:`forceclosure.gripper.labels.label_grasps`) against truths computed here.

* Planar pairs, and spatial soft pairs with antiparallel normals: Corollary 3 written out
  in this file (the angles between the contacts' line and the inward normals, by
  ``arctan2``; closed iff both are inside the cones, squeezing or spreading; μ* = tan of
  the larger angle).
* Other spatial soft pairs: Theorem 1 by an LP written here (scipy's HiGHS) on 32-edge
  pyramids, inscribed (its closure proves closure) and circumscribed (its failure proves
  failure); μ* bracketed by the same two LPs at 2 % above and below it.
* Lines exactly on a cone's edge: never ``closure``.
* Bad rows: one :class:`~forceclosure.errors.InputError` naming the first bad pair.
"""

import numpy as np
import pytest
from scipy.optimize import linprog

import forceclosure.analysis.two_finger as two_finger
from forceclosure.analysis.two_finger import pair_labels
from forceclosure.errors import InputError
from forceclosure.gripper.labels import label_grasps

BAND = 1e-5  # radians: truths closer than this to the cone's edge are not asserted


def _corollary3(P, N, mu):
    """Code truth (-1: too near the edge to assert) and μ* of planar or antiparallel pairs."""
    v = P[:, 1] - P[:, 0]

    def angle(u, w):  # angle between u and w, rows
        if u.shape[1] == 2:
            cross = np.abs(u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0])
        else:
            cross = np.linalg.norm(np.cross(u, w), axis=1)
        return np.arctan2(cross, np.sum(u * w, axis=1))

    a_p = angle(v, -N[:, 0])
    a_q = angle(-v, -N[:, 1])
    worst = np.minimum(np.maximum(a_p, a_q), np.maximum(np.pi - a_p, np.pi - a_q))
    gap = worst - np.arctan(mu)
    truth = np.where(gap < -BAND, 2, np.where(gap > BAND, 0, -1))
    star = np.where(worst < np.pi / 2, np.tan(np.minimum(worst, np.pi / 2 - 1e-300)), np.inf)
    return truth, star


def _closes(p, n, mu, edges=32):
    """Theorem 1 by an LP: do two soft fingers (pyramids of ``edges`` edges, friction ``mu``,
    and the pure torques about each normal) positively span the wrench space?"""
    ref = p.mean(axis=0)
    scale = np.linalg.norm(p[0] - ref)
    cols = []
    theta = 2 * np.pi * np.arange(edges) / edges
    for pi, ni in zip(p, n, strict=True):
        ni = ni / np.linalg.norm(ni)
        t1 = np.cross(ni, np.eye(3)[np.argmin(np.abs(ni))])
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(ni, t1)
        f = -ni + mu * (np.cos(theta)[:, None] * t1 + np.sin(theta)[:, None] * t2)
        cols += [np.hstack([f, np.cross(pi - ref, f) / scale]), [[0, 0, 0, *ni], [0, 0, 0, *-ni]]]
    W = np.vstack(cols).T
    if np.linalg.matrix_rank(W, tol=1e-9) < 6:
        return False
    m = W.shape[1]
    # maximise s: W x = 0, sum x = 1, x >= s
    c = np.zeros(m + 1)
    c[-1] = -1
    A_eq = np.vstack([np.hstack([W, np.zeros((6, 1))]), np.r_[np.ones(m), 0.0]])
    A_ub = np.hstack([-np.eye(m), np.ones((m, 1))])
    r = linprog(c, A_ub=A_ub, b_ub=np.zeros(m), A_eq=A_eq, b_eq=np.r_[np.zeros(6), 1.0],
                bounds=[(0, None)] * m + [(None, 1)], method="highs")
    return r.status == 0 and -r.fun > 1e-9


def _bracket(p, n, mu, edges=32):
    """1 proved closed (inscribed pyramid), 0 proved not (circumscribed), -1 neither."""
    if _closes(p, n, mu, edges):
        return 1
    return -1 if _closes(p, n, mu / np.cos(np.pi / edges), edges) else 0


def _near_antipodal(rng, n, spread):
    x = np.array([1.0, 0, 0])
    P = np.stack([-x + rng.normal(0, 0.3, (n, 3)), x + rng.normal(0, 0.3, (n, 3))], axis=1)
    N = np.stack([-x + rng.normal(0, spread, (n, 3)), x + rng.normal(0, spread, (n, 3))],
                 axis=1)
    return P, N * rng.uniform(0.1, 10, (n, 2, 1))  # any lengths: the kernel makes them unit


def test_planar_and_antiparallel_pairs_follow_corollary_3():
    rng = np.random.default_rng(11)
    P3, N3 = _near_antipodal(rng, 2000, 0.3)
    N3[:, 1] = -N3[:, 0] * rng.uniform(0.5, 2, (2000, 1))  # antiparallel normals
    N3[:300, 1] *= -1  # parallel: never closed
    P3[300:500] = P3[300:500, ::-1]  # spreading inside a ring
    N3[300:500] = -N3[300:500, ::-1]
    P2, N2 = P3[..., :2].copy(), rng.normal(size=(2000, 2, 2))
    P2[:1000], N2[:1000] = P3[:1000, :, :2], N3[:1000, :, :2]
    for P, N in ((P3, N3), (P2, N2), (P3 * 2.0**70, N3)):  # units of 2**70: same answers
        for mu in (0.1, 0.37, 1.0):
            truth, star = _corollary3(P, N, mu)
            decided = truth >= 0
            assert decided.sum() > 1900
            for model in ("soft",) + (("hard",) if P.shape[2] == 2 else ()):
                code, least = pair_labels(P, N, mu, model)
                assert np.array_equal(code[decided], truth[decided])
                assert np.array_equal(np.isinf(least), np.isinf(star))
                np.testing.assert_allclose(least[np.isfinite(star)], star[np.isfinite(star)],
                                           rtol=1e-9)
        assert np.sum(truth == 2) > 100 and np.sum(truth == 0) > 300


def test_general_soft_pairs_against_an_lp():
    rng = np.random.default_rng(12)
    P, N = _near_antipodal(rng, 2000, 0.4)
    mu = 0.55
    code, least = pair_labels(P, N, mu)
    assert set(np.unique(code)) <= {0, 1, 2}
    picked = np.r_[np.flatnonzero(code == 2)[:40], np.flatnonzero(code == 0)[:40]]
    proofs = [_bracket(P[g], N[g], mu) for g in picked]
    for g, proof in zip(picked, proofs, strict=True):
        assert proof == -1 or proof == (code[g] == 2), g
    assert sum(proof != -1 for proof in proofs) > 70
    # μ*: closed 2 % above it, not closed 2 % below it
    finite = np.flatnonzero(np.isfinite(least) & (least > 0.05) & (least < 3))[:25]
    assert len(finite) == 25
    for g in finite:
        assert _bracket(P[g], N[g], 1.02 * least[g]) == 1, g
        assert _bracket(P[g], N[g], 0.98 * least[g]) == 0, g


def test_spatial_hard_pairs_never_close():
    rng = np.random.default_rng(13)
    P, N = _near_antipodal(rng, 500, 0.1)
    code, least, _ = label_grasps(P, N, 1.0, contact="hard", epsilon=False)
    assert np.all(code == 0) and np.all(np.isinf(least))


@pytest.mark.parametrize("mu", [0.25, 0.5, 0.75])
def test_lines_on_a_cones_edge_are_never_closure(mu):
    """Lines tilted by atan(mu) from antiparallel normals (on the edge to round-off; at
    whole-number offsets and no turn, exactly), turned about the jaw axis and moved."""
    rng = np.random.default_rng(14)
    n = 400
    phi = rng.uniform(0, 2 * np.pi, n)
    phi[:100] = 0.0  # these exactly on the edge in floating point
    up = np.stack([np.zeros(n), np.cos(phi), np.sin(phi)], axis=1)
    base = rng.integers(-8, 8, (n, 1, 3)).astype(float)
    P = base + np.stack([[-1.0, 0, 0] + 0 * up, [1.0, 0, 0] + 2 * mu * up], axis=1)
    N = np.array([[-1.0, 0, 0], [1.0, 0, 0]])[None].repeat(n, axis=0)
    code, least = pair_labels(P, N, mu)
    assert np.all(code != 2)
    np.testing.assert_allclose(least, mu, rtol=1e-12)
    # in the plane (no turn: exactly on the edge)
    code2, least2 = pair_labels(P[:100, :, :2], N[:100, :, :2], mu)
    assert np.all(code2 != 2) and np.all(least2 == mu)
    # a general soft pair at its own μ*: on the boundary of closure
    Pg, Ng = _near_antipodal(rng, 300, 0.3)
    _, star = pair_labels(Pg, Ng, mu)
    ok = np.isfinite(star)
    code_g = np.array([pair_labels(Pg[g:g + 1], Ng[g:g + 1], star[g])[0][0]
                       for g in np.flatnonzero(ok)[:100]])
    assert np.all(code_g != 2)


def test_the_vectorised_rows_are_the_scalar_paths_bit_for_bit():
    """The branch-free pass (``kernels.pairs._common_rows``) gives each row it decides the
    code and μ* of the scalar path (``pair_verdict_kernel``, one pair at a time), to the
    last bit, and leaves it every row outside its case: bad input, huge or tiny values,
    coincident points, parallel and antiparallel normals, rows beyond the screen."""
    from forceclosure.kernels import pairs as kernel

    rng = np.random.default_rng(16)
    P, N = _near_antipodal(rng, 6000, 0.4)
    N[:300, 1] = -N[:300, 0] * 2.0  # antiparallel
    N[300:600, 1] = N[300:600, 0] * 3.0  # parallel
    P[600:700, 1] = P[600:700, 0]  # coincident
    P[700:800] *= 2.0**70
    P[800:900, 0, 1] = np.nan
    N[900:1000, 1] *= 1e-11 / np.linalg.norm(N[900:1000, 1], axis=1, keepdims=True)  # unit first
    N[1000:1100, 0] *= 1e120
    N[1100:1200, 0] = 0.0
    P[1200:1300] *= 1e295  # too large
    P[1300:1400] = rng.normal(size=(100, 2, 3))  # anything at all
    N[1300:1400] = rng.normal(size=(100, 2, 3))
    mu_max, big = two_finger.MU_MAX, two_finger.MAX_COORDINATE
    for mu in (0.0, 0.3, 0.55, 1.5, 1e5):
        code, least = np.empty(len(P), np.int8), np.empty(len(P))
        kernel._common_rows(P, N, mu, np.tan(1e-9), 1e-9, mu_max, big, code, least)
        ref_code, ref_least = np.empty(len(P), np.int8), np.empty(len(P))
        kernel.pair_verdict_kernel(P[:, 0].copy(), N[:, 0].copy(), P[:, 1].copy(),
                                   N[:, 1].copy(), np.array([mu]), np.array([mu]), 1e-9, False,
                                   big, ref_code, ref_least)
        ref_least[ref_least > mu_max] = np.inf
        done = code != kernel._REDO
        assert done[1400:].mean() > 0.9 and not done[:1300].any()
        assert np.array_equal(code[done], ref_code[done])
        assert np.array_equal(least[done].view(np.int64), ref_least[done].view(np.int64))
    # and the kernel's answers, over all rows, are the scalar path's
    P[800:900, 0, 1], N[1100:1200, 0], P[1200:1300] = 0.0, 1.0, 1.0  # no bad rows left
    code, least = pair_labels(P, N, 0.3)
    kernel.pair_verdict_kernel(P[:, 0].copy(), N[:, 0].copy(), P[:, 1].copy(), N[:, 1].copy(),
                               np.array([0.3]), np.array([0.3]), 1e-9, False, big, ref_code,
                               ref_least)
    decided = ref_code != kernel.UNDECIDED  # the rest by Theorem 1
    assert decided.mean() > 0.9
    assert np.array_equal(code[decided], ref_code[decided])
    assert np.array_equal(least, np.where(ref_least > mu_max, np.inf, ref_least))


def test_the_pool_and_the_calling_thread_agree(monkeypatch):
    rng = np.random.default_rng(15)
    P, N = _near_antipodal(rng, 3000, 0.3)
    serial = pair_labels(P, N, 0.4)
    monkeypatch.setattr(two_finger, "SERIAL_BELOW", 1)
    pooled = pair_labels(P, N, 0.4)
    assert np.array_equal(serial[0], pooled[0]) and np.array_equal(serial[1], pooled[1])


@pytest.mark.parametrize("bad, message", [
    (lambda P, N: P.__setitem__((7, 1, 2), np.nan), "pair at index 7: .*non-finite"),
    (lambda P, N: N.__setitem__((5, 0, 0), np.inf), "pair at index 5: .*non-finite"),
    (lambda P, N: N.__setitem__((9, 1), 0.0), "pair at index 9: a normal is a zero vector"),
    (lambda P, N: P.__setitem__((4, 0, 1), 1e300), "pair at index 4: .*too large"),
])
def test_bad_rows_are_named(bad, message):
    rng = np.random.default_rng(16)
    P, N = _near_antipodal(rng, 20, 0.2)
    bad(P, N)
    N[12, 0] = 0.0  # a later bad row: the first one is named
    for call in (lambda: pair_labels(P, N, 0.5),
                 lambda: label_grasps(P, N, 0.5, epsilon=False),
                 lambda: label_grasps(P, N, 0.5, contact="hard", epsilon=False)):
        with pytest.raises(InputError, match=message) as info:
            call()
        assert "\n" not in str(info.value)
    with pytest.raises(InputError, match="mu"):
        pair_labels(P, N, -0.1)
    with pytest.raises(InputError, match="shape"):
        pair_labels(P[:, :1], N[:, :1], 0.5)
