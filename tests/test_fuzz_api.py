"""Fuzzing the public API: every call returns a result or raises InputError, never another
exception, and a ``closure`` (or ``none``) verdict on random grasps agrees with a check
written here (NumPy rank and a SciPy LP on the primitive wrenches, in the grasp's own frame).

Inputs are adversarial: no contacts, NaN and infinities, huge finite and subnormal values,
mismatched shapes, zero normals, friction from 0 to 1e300, extreme tolerances.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.optimize import linprog

import forceclosure as fc
from forceclosure.analysis.batch import analyze_batch, epsilon_batch, least_friction_batch
from forceclosure.analysis.quality import epsilon, least_friction
from forceclosure.analysis.two_finger import two_finger_closure
from forceclosure.errors import InputError

#: Examples per test: 150, the same ones every run (about 30 s for the file); set
#: FORCECLOSURE_FUZZ_EXAMPLES for a longer, random search.
_EXAMPLES = os.environ.get("FORCECLOSURE_FUZZ_EXAMPLES")
FUZZ = settings(max_examples=int(_EXAMPLES or 150), deadline=None, derandomize=not _EXAMPLES,
                suppress_health_check=list(HealthCheck))

#: Floats a careless or hostile caller might pass.
NASTY = st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.3, 1e-300, 5e-324, -5e-324, 1e300, -1e300,
                         1e289, -1e289, 1.7e308, -1.7e308, math.nan, math.inf, -math.inf,
                         1e16, 1e154, 2.0**64])
VALUE = st.one_of(NASTY, st.floats(-10, 10), st.floats(allow_nan=True, allow_infinity=True))
FRICTION = st.one_of(NASTY, st.floats(0, 5), st.sampled_from([1e4, 1e5, 1e20, 1e300]))


def _arrays(draw, n, k, d):
    return np.array(draw(st.lists(VALUE, min_size=n * k * d, max_size=n * k * d)),
                    dtype=float).reshape(n, k, d)


@st.composite
def batch_inputs(draw):
    n = draw(st.integers(0, 3))
    k = draw(st.integers(0, 4))
    d = draw(st.sampled_from([1, 2, 3, 3, 2, 4]))
    points = _arrays(draw, n, k, d)
    normals = _arrays(draw, n, k, draw(st.sampled_from([d, d, d, d + 1])))
    mu = draw(st.one_of(FRICTION, st.lists(FRICTION, min_size=max(k, 1), max_size=max(k, 1))))
    model = draw(st.sampled_from(["hard", "soft", "frictionless", "sticky", ["hard"] * k]))
    torsion = draw(st.one_of(st.none(), FRICTION))
    tol = draw(st.one_of(st.just(1e-6), NASTY, st.just("x")))
    return points, normals, mu, model, torsion, tol


def _returns_or_refuses(call):
    try:
        return call()
    except InputError as e:
        text = str(e)
        assert text and "\n" not in text, repr(text)
        return None


@FUZZ
@given(batch_inputs())
def test_batch_functions_return_or_refuse(args):
    points, normals, mu, model, torsion, tol = args
    for call in (
        lambda: analyze_batch(points, normals, mu=mu, model=model, torsion=torsion, tol=tol),
        lambda: least_friction_batch(points, normals, model=model, torsion=torsion, tol=tol),
        lambda: epsilon_batch(points, normals, mu=mu, model=model, torsion=torsion, tol=tol),
    ):
        result = _returns_or_refuses(call)
        if result is not None:
            assert len(result) == len(points)


@FUZZ
@given(st.lists(st.tuples(st.lists(VALUE, min_size=2, max_size=3),
                          st.lists(VALUE, min_size=2, max_size=3),
                          st.sampled_from(["hard", "soft", "frictionless"]), FRICTION,
                          st.one_of(st.none(), FRICTION)), min_size=0, max_size=4),
       st.one_of(st.none(), VALUE), st.sampled_from(["exact", fc.Cone(4), "pyramid"]))
def test_contact_functions_return_or_refuse(spec, length_scale, cone):
    contacts = _returns_or_refuses(
        lambda: [fc.point_contact(p, n, m, mu, t) for p, n, m, mu, t in spec])
    if contacts is None:
        return
    analysis = _returns_or_refuses(
        lambda: fc.analyze(contacts, cone=cone, length_scale=length_scale))
    if analysis is not None:  # nothing returned is NaN or infinite
        for value in (analysis.twist, analysis.margin, analysis.contact_forces):
            assert value is None or np.all(np.isfinite(value)), analysis
    for call in (
        lambda: least_friction(contacts, cone=cone),
        lambda: epsilon(contacts, length_scale=length_scale),
    ):
        _returns_or_refuses(call)


@FUZZ
@given(st.lists(VALUE, min_size=8, max_size=8), FRICTION, st.sampled_from(["soft", "hard"]),
       st.sampled_from([2, 3]))
def test_two_finger_closure_returns_or_refuses(values, mu, model, d):
    p, n_p, q, n_q = (values[2 * i: 2 * i + 2] + [0.0] * (d - 2) for i in range(4))
    _returns_or_refuses(lambda: two_finger_closure(p, n_p, q, n_q, mu, model=model))


def _independent(points, normals, mu):
    """Planar hard fingers: (rank, LP margin) of the primitive wrenches, in the grasp's frame.

    Force directions ``cos(a) (-n) ± sin(a) t`` with ``a = atan(mu)`` (no overflow at any
    friction); torques about the centroid over the largest distance from it, all computed
    after dividing the points by their largest coordinate.
    """
    big = np.max(np.abs(points))
    p = points / big
    n = normals / np.max(np.abs(normals), axis=1, keepdims=True)
    n = n / np.linalg.norm(n, axis=1, keepdims=True)
    arm = p - p.mean(axis=0)
    arm = arm / np.max(np.linalg.norm(arm, axis=1))
    t = np.stack([-n[:, 1], n[:, 0]], axis=1)
    a = np.arctan(mu)
    cols = []
    for i in range(len(p)):
        for s in (1.0, -1.0):
            f = math.cos(a[i]) * -n[i] + s * math.sin(a[i]) * t[i]
            cols.append([f[0], f[1], arm[i, 0] * f[1] - arm[i, 1] * f[0]])
    W = np.array(cols).T
    W = W / np.linalg.norm(W, axis=0)
    m = W.shape[1]
    # max s: W lam = 0, sum lam = 1, lam >= s
    c = np.zeros(m + 1)
    c[-1] = -1.0
    A_eq = np.vstack([np.hstack([W, np.zeros((3, 1))]), np.append(np.ones(m), 0.0)])
    b_eq = np.array([0.0, 0.0, 0.0, 1.0])
    A_ub = np.hstack([-np.eye(m), np.ones((m, 1))])
    res = linprog(c, A_ub=A_ub, b_ub=np.zeros(m), A_eq=A_eq, b_eq=b_eq,
                  bounds=[(0, None)] * m + [(None, None)], method="highs")
    return np.linalg.matrix_rank(W), (m * res.x[-1] if res.status == 0 else -np.inf)


@FUZZ
@given(st.integers(0, 2**32 - 1), st.integers(2, 5), st.integers(-11, 289),
       st.sampled_from([0.05, 0.3, 1.0, 30.0, 1e8, 1e16, 1e154, 1e300]))
def test_verdicts_agree_with_an_independent_check(seed, k, exponent, mu):
    rng = np.random.default_rng(seed)
    angles = rng.uniform(0, 2 * np.pi, k)
    points = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    normals = points + rng.normal(0, 0.4, (k, 2))  # roughly outward, not exactly
    points = points * 10.0**exponent  # above 1e-12: not one point (contacts.frame)
    mus = np.full(k, mu)
    batch = analyze_batch(points[None], normals[None], mu=mus).verdict[0]
    single = fc.analyze([fc.point_contact(p, n, "hard", mu) for p, n in
                         zip(points, normals, strict=True)]).verdict.value
    rank, margin = _independent(points, normals, mus)
    # friction is monotone: closed with less (the library's cap, 1e4) is closed with more
    capped_rank, capped_margin = _independent(points, normals, np.minimum(mus, 1e4))
    for verdict in (batch, single):
        if verdict == "closure":
            assert capped_rank == 3 and capped_margin > 0, (verdict, rank, margin)
        elif verdict == "none":
            assert rank < 3 or margin < 1e-6, (verdict, rank, margin)
    if rank == 3 and margin > 1e-3 and mu <= 1e4:  # clearly closed, friction not capped
        assert batch == single == "closure"


@pytest.mark.parametrize("mu", [1e15, 1e16, 1e20, 1e154, 1e300])
def test_a_pinch_stays_closed_with_unbounded_friction(mu):
    # Corollary 3: the segment PQ is 0.1 rad from both normals, inside any cone wider than that
    p, n = [[-1, 0], [1, 0.2]], [[-1, 0], [1, 0]]
    grasp = [fc.point_contact(a, b, "hard", mu) for a, b in zip(p, n, strict=True)]
    assert fc.analyze(grasp).verdict.value == "closure"
    assert analyze_batch([p], [n], mu=mu).verdict.tolist() == ["closure"]
    # fingers on one side: no friction closes them (with half-space cones the tangential
    # generators are only reciprocal to the escaping twist, so it is not proved 'none')
    same = [fc.point_contact([-1, 0], [-1, 0], "hard", mu),
            fc.point_contact([-1, 1], [-1, 0], "hard", mu)]
    assert fc.analyze(same).verdict.value != "closure"


@pytest.mark.parametrize("scale", [1e-300, 1e-100, 1e-6, 1e6, 1e100, 1e300])
def test_length_scale_does_not_change_the_verdict(scale):
    closed = [fc.point_contact([-1, 0], [-1, 0], "hard", 0.3),
              fc.point_contact([1, 0.2], [1, 0], "hard", 0.3)]
    apart = [fc.point_contact([-1, 0], [-1, 0], "hard", 0.3),
             fc.point_contact([1, 1.0], [1, 0], "hard", 0.3)]   # 0.46 rad > atan(0.3)
    assert fc.analyze(closed, length_scale=scale).verdict.value == "closure"
    assert fc.analyze(apart, length_scale=scale).verdict.value == "none"


@pytest.mark.parametrize("size", [1e-300, 1e-15, 1e-12 * 4, 1e100, 1e289])
def test_huge_and_tiny_grasps_keep_their_verdict(size):
    # a pinch across (Corollary 3: closed at any size), normals of length 1e300; points
    # closer than 1e-12 are one point (contacts.frame), which nothing closes
    p = np.array([[-1.0, 0.0], [1.0, 0.2]]) * size
    n = np.array([[-1.0, 0.0], [1.0, 0.0]]) * 1e300
    grasp = [fc.point_contact(a, b, "hard", 0.3) for a, b in zip(p, n, strict=True)]
    verdicts = [fc.analyze(grasp).verdict.value,
                analyze_batch(p[None], n[None], mu=0.3).verdict[0],
                str(two_finger_closure(p[0], n[0], p[1], n[1], 0.3).verdict)]
    if size > 1e-12:
        assert verdicts == ["closure"] * 3
    else:
        assert "closure" not in verdicts


def test_sampling_nothing_is_refused_in_one_line():
    """Triangles of zero (or overflowing) area have nothing to sample: one line, not numpy's
    'probabilities contain NaN'."""
    from forceclosure.synthesis.spatial.patches import uniform_in_triangles

    zero = np.zeros((2, 3))
    huge = np.array([[0, 0, 0], [1e300, 0, 0], [0, 1e300, 0]], dtype=float)[:, None, :]
    for a, b, c in ((zero, zero, zero), (huge[0], huge[1], huge[2])):
        with pytest.raises(InputError, match="nothing to sample from"):
            uniform_in_triangles(a, b, c, 5, np.random.default_rng(0))
