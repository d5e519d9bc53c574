"""``two_finger_closure`` checks and conditions its pairs inside the compiled pass (issue 26).

Its verdicts must stay those of the NumPy reference (Corollary 3 from angles; Theorem 1 for
spatial soft pairs the corollary does not close) on pairs as users give them: normals of
any length, huge and tiny coordinates, broadcast shapes, rows on the cone's boundary; they
must not change when the pair is scaled, and bad rows are refused in one line naming the
row and the problem.
"""

from __future__ import annotations

import numpy as np
import pytest

from forceclosure.analysis.two_finger import SERIAL_BELOW, two_finger_closure
from forceclosure.errors import InputError


def _agree(ours, theirs) -> None:
    assert np.array_equal(ours.code, theirs.code)
    finite = np.isfinite(theirs.least_friction)
    assert np.array_equal(finite, np.isfinite(ours.least_friction))
    assert np.allclose(ours.least_friction[finite], theirs.least_friction[finite], rtol=1e-9)


def _planar_pairs(rng, n):
    """Random pairs, normals of lengths 1e-9 to 1e120 (both of the kernel's paths), rows on
    the boundary (friction exactly the tangent of the angle of ``PQ``), coincident points,
    zero and huge friction, coordinates near 1e200 and 1e-200."""
    p, q = rng.normal(size=(n, 2)), rng.normal(size=(n, 2))
    d = q - p
    n_p = -d + rng.normal(0, 0.4, (n, 2))
    n_q = d + rng.normal(0, 0.4, (n, 2))
    n_p *= 10.0 ** rng.uniform(-9, 120, (n, 1))
    n_q *= 10.0 ** rng.uniform(-9, 120, (n, 1))
    mu = rng.uniform(0, 1.5, n)
    k = n // 10
    q[:k] = p[:k]  # coincident
    p[k:2 * k], q[k:2 * k] = [-1, 0], np.c_[np.ones(k), rng.integers(-4, 5, k) / 4]
    n_p[k:2 * k], n_q[k:2 * k] = [-3, 0], [0.5, 0]
    mu[k:2 * k] = np.abs(q[k:2 * k, 1]) / 2  # on the boundary: marginal
    mu[2 * k:3 * k], mu[3 * k:4 * k] = 0.0, 1e7
    p[4 * k:5 * k] *= 1e200
    q[4 * k:5 * k] *= 1e200
    p[5 * k:6 * k] *= 1e-200
    q[5 * k:6 * k] *= 1e-200
    return p, n_p, q, n_q, mu


@pytest.mark.parametrize("n", [50, SERIAL_BELOW + 10])  # the calling thread, and slices in threads
def test_planar_pairs_agree_with_the_reference(n):
    rng = np.random.default_rng(n)
    p, n_p, q, n_q, mu = _planar_pairs(rng, n)
    ours = two_finger_closure(p, n_p, q, n_q, mu)
    _agree(ours, two_finger_closure(p, n_p, q, n_q, mu, engine="reference"))
    assert set(np.unique(ours.code)) == {0, 1, 2}
    # the boundary rows are marginal (exactly on the cone) or none (the fingers' angles
    # differ only in the sign of the offset; |offset| 0 is a head-on pinch at friction 0)
    k = n // 10
    offset = np.abs(q[k:2 * k, 1])
    assert np.all(ours.code[k:2 * k][offset > 0] == 1)
    # the angles are read from the pairs as given
    assert np.allclose(np.tan(np.maximum(ours.angle_p, ours.angle_q))[k:2 * k][offset > 0],
                       offset[offset > 0] / 2)


@pytest.mark.parametrize("seed, mu", list(enumerate([0.0, 0.3, 1.5, 1e7, 1e10])))
def test_one_friction_for_all_agrees_with_the_reference(seed, mu):
    """One friction for every pair takes the vectorised pass (``kernels.pairs._common_planar``)
    on the calling thread and in slices: the reference's verdicts, huge friction (``mu T``
    beyond 1) included."""
    rng = np.random.default_rng(seed + 11)
    p, n_p, q, n_q, _ = _planar_pairs(rng, SERIAL_BELOW + 10)
    for rows in (slice(0, 60), slice(None)):
        ours = two_finger_closure(p[rows], n_p[rows], q[rows], n_q[rows], mu)
        _agree(ours, two_finger_closure(p[rows], n_p[rows], q[rows], n_q[rows], mu,
                                        engine="reference"))


def test_the_vectorised_planar_pass_is_the_scalar_path_bit_for_bit():
    """``_common_planar`` gives each row it decides the code and μ* of the scalar path
    (``_conditioned_pair``, one pair at a time), to the last bit, and leaves it every row
    outside its case (bad input, huge or tiny values, coincident points, ``mu T >= 1``)."""
    from forceclosure.kernels import pairs as kernel

    rng = np.random.default_rng(17)
    p, n_p, q, n_q, mu = _planar_pairs(rng, 3000)
    n_p[:30] = 0.0
    p[30:60, 0] = np.nan
    p[60:90] *= 2.0**70
    n_q[90:120] *= 1e-15
    n_q[120:150] = -n_p[120:150]  # antiparallel, and the points on the normals' line:
    q[120:150] = p[120:150] + n_p[120:150]  # c_P = 0 at one end at times
    n_p[150:200] = [1.0, 0.0]
    p[150:200], q[150:200] = [0.0, 0.0], np.c_[np.zeros(50), rng.normal(size=50)]  # c = 0
    tol = 1e-9
    T = np.tan(tol)
    for one, friction in ((True, 0.3), (True, 2e9), (False, mu)):
        mus = np.array([friction]) if one else friction
        step = 0 if one else 1
        code, least = np.empty(len(p), np.int8), np.empty(len(p))
        kernel._common_planar(p, n_p, q, n_q, mus, mus, step, step, T, 1e300, code, least)
        done = code != kernel._REDO
        if one and friction == 2e9:  # mu T >= 1: every row to the scalar path
            assert not done.any()
            continue
        assert done.mean() > 0.5 and not done[:120].any()
        for i in np.flatnonzero(done):
            m = mus[i * step]
            c, star = kernel._conditioned_pair(2, p[i, 0], p[i, 1], 0.0, q[i, 0], q[i, 1], 0.0,
                                               n_p[i, 0], n_p[i, 1], 0.0, n_q[i, 0],
                                               n_q[i, 1], 0.0, m, m, -1.0, -1.0, T, tol,
                                               False, 1e300)
            assert (code[i], np.float64(least[i]).view(np.int64)) == (
                c, np.float64(star).view(np.int64)), i


def test_broadcast_pairs_agree_with_the_reference():
    rng = np.random.default_rng(5)
    p = rng.normal(size=(40, 30, 2))
    q = rng.normal(size=(30, 2))
    n_p, n_q = np.array([-2.0, 0.1]), rng.normal(size=(40, 1, 2)) * 7
    mu = rng.uniform(0, 2, (40, 30))
    ours = two_finger_closure(p, n_p, q, n_q, mu)
    assert ours.code.shape == (40, 30)
    _agree(ours, two_finger_closure(p, n_p, q, n_q, mu, engine="reference"))


def test_spatial_pairs_agree_with_the_reference():
    rng = np.random.default_rng(6)
    n = 150
    p, q = rng.normal(size=(n, 3)), rng.normal(size=(n, 3))
    d = q - p
    n_p = (-d + rng.normal(0, 0.3, (n, 3))) * 10.0 ** rng.uniform(-9, 120, (n, 1))
    n_q = (d + rng.normal(0, 0.3, (n, 3))) * 10.0 ** rng.uniform(-9, 120, (n, 1))
    n_q[:30] = -n_p[:30] * 3  # antiparallel: Corollary 3 is an iff
    n_q[30:40] = n_p[30:40]  # parallel: never closed
    p[40:60] *= 1e200
    q[40:60] *= 1e200
    mu = rng.uniform(0.1, 1.0, n)
    for model in ("soft", "hard"):
        ours = two_finger_closure(p, n_p, q, n_q, mu, model=model)
        _agree(ours, two_finger_closure(p, n_p, q, n_q, mu, model=model, engine="reference"))
    assert ours.code.max() == 0  # hard fingers in space: never (rank 5)


@pytest.mark.parametrize("d", [2, 3])
def test_verdicts_do_not_change_with_units_or_normal_lengths(d):
    """Scaling every point by a factor (here 1e-6 to 1e250; points within 1e-12 of each other,
    in units of the larger coordinate or 1, count as coincident) and each normal by its own
    positive factor leaves every verdict as it was."""
    rng = np.random.default_rng(7 + d)
    n = 400
    p, q = rng.normal(size=(n, d)), rng.normal(size=(n, d))
    n_p = -(q - p) + rng.normal(0, 0.3, (n, d))
    n_q = (q - p) + rng.normal(0, 0.3, (n, d))
    mu = rng.uniform(0.05, 1.2, n)
    base = two_finger_closure(p, n_p, q, n_q, mu).code
    clear = base != 1
    for scale in (1e-6, 3.0, 1e100, 1e250):
        s = rng.uniform(1e-8, 1e90, (n, 1))
        code = two_finger_closure(p * scale, n_p * s, q * scale, n_q * s[::-1], mu).code
        assert np.array_equal(code[clear], base[clear])


def _message(*args, **kwargs) -> str:
    with pytest.raises(InputError) as caught:
        two_finger_closure(*args, **kwargs)
    return str(caught.value)


def test_bad_rows_are_named_in_one_line():
    P, N, Q = np.zeros((2, 3, 2)), np.ones((2, 3, 2)), np.ones((2, 3, 2))
    P[1, 2] = [np.nan, 0]
    assert _message(P, N, Q, N, 0.3) == (
        "pair at index (1, 2): a point or normal has a non-finite "
        "coordinate")
    assert _message([0, 0], [1, 0], [np.inf, 0], [1, 0], 0.3) == (
        "the pair: a point or normal has a non-finite coordinate")
    normals = [[1, 0], [1e-13, 0], [1, 0]]
    assert _message(np.zeros((3, 2)), normals, np.ones((3, 2)), np.ones((3, 2)), 0.3) == (
        "pair at index 1: a normal is a zero vector")
    # a coordinate too large is named before any non-finite value
    assert _message([np.nan, 0], [1, 0], [1e300, 0], [1, 0], 0.3) == (
        "'q' has a coordinate beyond 1e+290, too large to compute with")
    big = np.zeros((SERIAL_BELOW + 5, 3))
    big[SERIAL_BELOW + 3] = [0, 0, -1e291]
    assert _message(big, [1, 0, 0], np.ones(3), [1, 0, 0], 0.3) == (
        "'p' has a coordinate beyond 1e+290, too large to compute with")
    assert _message(np.zeros((3, 2)), [1, 0], np.ones((3, 2)), [1, 0], [0.3, -1, 0.2]) == (
        "'mu_p' must be finite and >= 0")
    assert _message([0, 0], [1, 0], [1, 0], [1, 0], 0.3, np.nan) == (
        "'mu_q' must be finite and >= 0")
    for message in (_message(P, N, Q, N, 0.3), _message(big, [1, 0, 0], np.ones(3),
                                                        [1, 0, 0], 0.3)):
        assert "\n" not in message
    # a normal of length 1e-11 is a direction, not a zero vector
    tiny = two_finger_closure([-1, 0], [-1e-11, 0], [1, 0.2], [1, 0], 0.3)
    assert str(tiny.verdict) == "closure" and np.isclose(float(tiny.least_friction), 0.1)
