"""Property tests: a verdict does not depend on the frame, the scale or the order."""

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from forceclosure import Verdict, analyze, point_contact

CLEAR = 1e-3
coord = st.floats(-2, 2, allow_nan=False)
models = st.sampled_from(["frictionless", "hard", "soft"])


@st.composite
def grasps(draw, dim):
    k = draw(st.integers(2, 5 if dim == 2 else 4))
    out = []
    for _ in range(k):
        p = np.array([draw(coord) for _ in range(dim)])
        n = np.array([draw(st.floats(-1, 1)) for _ in range(dim)])
        if np.linalg.norm(n) < 0.1:
            n[0] = 1.0
        out.append((p, n, draw(models), draw(st.floats(0, 1.2))))
    return out


def _build(spec, R=None, shift=0.0, scale=1.0):
    d = len(spec[0][0])
    R = np.eye(d) if R is None else R
    return [point_contact(scale * (R @ p) + shift, R @ n, m, mu) for p, n, m, mu in spec]


def _rotation(dim, angle, axis):
    if dim == 2:
        c, s = np.cos(angle), np.sin(angle)
        return np.array([[c, -s], [s, c]])
    axis = np.asarray(axis, float)
    axis = axis / np.linalg.norm(axis) if np.linalg.norm(axis) > 1e-3 else np.array([0, 0, 1.0])
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


def _same(a, b):
    """Verdicts agree; where either is near the boundary they may not flip closure <-> none."""
    assert {a.verdict, b.verdict} != {Verdict.CLOSURE, Verdict.NONE}
    clear = all(x.margin is not None and abs(x.margin) > CLEAR and x.sigma_ratio > CLEAR
                for x in (a, b))
    if clear or Verdict.MARGINAL not in (a.verdict, b.verdict):
        assert a.verdict is b.verdict
    if min(a.sigma_ratio, b.sigma_ratio) > CLEAR:  # numerical rank is clear-cut
        assert a.rank == b.rank


@given(st.integers(2, 3).flatmap(lambda d: st.tuples(st.just(d), grasps(d))),
       st.floats(0, 2 * np.pi), st.tuples(coord, coord, coord), st.floats(0.01, 100),
       st.randoms(use_true_random=False))
def test_rigid_motion_scaling_and_order(dim_spec, angle, axis, scale, rnd):
    dim, spec = dim_spec
    base = analyze(_build(spec))
    R = _rotation(dim, angle, axis)
    shift = np.array(axis[:dim]) * 10
    _same(base, analyze(_build(spec, R, shift, scale)))
    shuffled = list(spec)
    rnd.shuffle(shuffled)
    _same(base, analyze(_build(shuffled)))


@given(st.integers(2, 3).flatmap(lambda d: st.tuples(st.just(d), grasps(d))),
       st.tuples(coord, coord, coord), st.floats(0.1, 10))
def test_torque_reference_point_and_scale(dim_spec, ref, length):
    dim, spec = dim_spec
    g = _build(spec)
    _same(analyze(g), analyze(g, reference=np.array(ref[:dim]) * 5, length_scale=length))
