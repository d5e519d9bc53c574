"""The compiled epsilon (wrench hull in the kernel) against Qhull, rationals and a closed form."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.spatial import ConvexHull
from test_kernels import _families

from exact import (
    hull_distance_squared,
    planar_hard_wrenches,
    positively_spans,
    spatial_pyramid4_wrenches,
)
from forceclosure import InputError
from forceclosure.analysis.batch import epsilon_batch
from forceclosure.kernels.hull import hull_radius


def _point_sets():
    """Point sets in 3 to 6 dimensions, many of them degenerate for a hull."""
    rng = np.random.default_rng(3)
    for d in (3, 4, 5, 6):
        cube = np.array(list(itertools.product([-1.0, 1.0], repeat=d))) + 0.1
        yield f"cube {d}", cube  # facets of 2^(d-1) coplanar points
        yield f"cross-polytope {d}", np.vstack([np.eye(d), -np.eye(d)]) * 2 - 0.3
        yield f"cube with repeats {d}", np.vstack([cube, cube[:5], np.zeros((3, d))])
        yield f"lattice {d}", np.array(list(itertools.product([-1.0, 0, 1.0], repeat=d)))
        yield f"origin outside {d}", rng.normal(size=(3 * d, d)) + 3.0
        for _ in range(15):
            yield f"gaussian {d}", rng.normal(size=(rng.integers(d + 1, 60), d))


def test_hull_radius_matches_qhull_on_hard_point_sets():
    for name, X in _point_sets():
        ours = hull_radius(np.ascontiguousarray(X), len(X))
        theirs = float(np.min(-ConvexHull(X).equations[:, -1]))
        assert not np.isnan(ours), name  # none of these needs the fallback
        assert abs(ours - theirs) <= 1e-9, (name, ours, theirs)


def test_hull_radius_refuses_flat_point_sets():
    rng = np.random.default_rng(4)
    X = np.c_[rng.normal(size=(30, 5)), np.zeros(30)]  # all in one hyperplane of R^6
    assert np.isnan(hull_radius(X, 30))
    assert np.isnan(hull_radius(X[:4, :4].copy(), 4))  # fewer than d + 1 points


@given(st.floats(0.05, 3.0), st.floats(0.01, 100.0), st.floats(0, 2 * np.pi),
       st.tuples(st.floats(-10, 10), st.floats(-10, 10)))
def test_planar_pinch_closed_form(mu, half_width, angle, shift):
    """Two hard fingers head-on: the wrench tetrahedron's faces are mu / sqrt(mu^2 + 2) away.

    The four wrenches ``(±1, ±mu, ∓mu)`` (torques about the midpoint, over the
    half-width) have the facet normal ``(mu^2, mu, mu)`` and offset ``mu^2``;
    by symmetry all four facets are as near.
    """
    u = np.array([math.cos(angle), math.sin(angle)])
    P = np.array([[-half_width * u, half_width * u]]) + np.array(shift)
    N = np.array([[-u, u]])
    ours = epsilon_batch(P, N, mu=mu)
    assert ours[0] == pytest.approx(mu / math.sqrt(mu * mu + 2), rel=1e-9)


def test_exact_rational_planar_hard_fingers():
    """Three fingers with 3-4-5 normals: epsilon equals the exact nearest facet, in rationals."""
    rng = np.random.default_rng(21)
    dirs = [(1, 0), (0, 1), (-1, 0), (0, -1), (Fraction(3, 5), Fraction(4, 5)),
            (Fraction(-4, 5), Fraction(3, 5)), (Fraction(-3, 5), Fraction(-4, 5)),
            (Fraction(4, 5), Fraction(-3, 5))]
    n, k = 300, 3
    pts = rng.integers(-3, 4, (n, k, 2))
    nrm = rng.integers(0, 8, (n, k))
    mus = rng.integers(0, 5, (n, k))
    P = pts / 2.0
    N = np.array([[[float(c) for c in dirs[j]] for j in row] for row in nrm])
    ours = epsilon_batch(P, N, mu=mus / 4)
    checked = 0
    for g in range(n):
        points = [[Fraction(int(v), 2) for v in p] for p in pts[g]]
        centre = [sum(p[j] for p in points) / k for j in range(2)]
        arms = [[p[j] - centre[j] for j in range(2)] for p in points]
        scale2 = max(a[0] ** 2 + a[1] ** 2 for a in arms)
        W = planar_hard_wrenches(arms, [dirs[j] for j in nrm[g]],
                                 [Fraction(int(m), 4) for m in mus[g]])
        if not positively_spans(W):
            assert ours[g] == 0.0, g
            continue
        exact = hull_distance_squared(W, [Fraction(1), Fraction(1), scale2])
        if exact > Fraction(1, 10**12):  # clear of the boundary, where 'marginal' gives 0
            assert ours[g] ** 2 == pytest.approx(float(exact), rel=1e-12), g
            checked += 1
    assert checked > 20


@pytest.mark.long  # 10 s; the agreement on every family stays in the default run
def test_exact_rational_spatial_pyramids():
    """Cube-face grasps with 4-edge pyramids: the kernel's 6-D hull against exact enumeration.

    The pyramids on the coordinate axes (``orientation="axes"``), as ``exact.py`` builds them
    in rationals; the grasp's own orientation is held to Qhull in test_epsilon_frame.py.
    """
    rng = np.random.default_rng(22)
    axes = np.concatenate([np.eye(3), -np.eye(3)])
    n, k = 200, 3
    N = axes[rng.integers(0, 6, (n, k))]
    twice = rng.integers(-2, 3, (n, k, 3)) * (1 - np.abs(N)).astype(int) + 2 * N.astype(int)
    mus = rng.integers(1, 3, (n, k))
    ours = epsilon_batch(twice / 2.0, N, mu=mus / 2, edges=4, orientation="axes")
    checked = 0
    for g in np.flatnonzero(ours > 0)[:8]:
        points = [[Fraction(int(v), 2) for v in p] for p in twice[g]]
        centre = [sum(p[j] for p in points) / k for j in range(3)]
        arms = [[p[j] - centre[j] for j in range(3)] for p in points]
        scale2 = max(sum(a * a for a in arm) for arm in arms)
        W = spatial_pyramid4_wrenches(arms, N[g].astype(int).tolist(),
                                      [Fraction(int(m), 2) for m in mus[g]])
        assert positively_spans(W), g
        exact = hull_distance_squared(W, [Fraction(1)] * 3 + [scale2] * 3)
        assert ours[g] ** 2 == pytest.approx(float(exact), rel=1e-12), g
        checked += 1
    assert checked == 8


def test_epsilon_agrees_with_the_reference_on_every_family():
    """Qhull per grasp (the reference) and the kernel, on the agreement families, degenerate ones
    included; where a verdict is too near the boundary the kernel defers, so values match."""
    total = 0
    for name, P, N, mu, model, torsion, _ in _families(500, seed=31):
        ours = epsilon_batch(P, N, mu=mu, model=model, torsion=torsion)
        theirs = epsilon_batch(P, N, mu=mu, model=model, torsion=torsion, engine="reference")
        assert np.all(ours >= 0), name
        np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-9, err_msg=name)
        total += int(np.sum(theirs > 0))
    assert total > 60  # enough closed grasps to mean something


@given(st.integers(0, 2**32 - 1), st.floats(0, 2 * np.pi), st.floats(0.01, 100),
       st.tuples(st.floats(-5, 5), st.floats(-5, 5)))
def test_planar_epsilon_is_invariant(seed, angle, scale, shift):
    """Rotation, translation, scaling and contact order leave a planar grasp's epsilon alone."""
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(20, 3, 2))
    N = P + rng.normal(0, 0.4, P.shape)
    mu = rng.uniform(0.1, 1, (20, 3))
    base = epsilon_batch(P, N, mu=mu)
    c, s = math.cos(angle), math.sin(angle)
    R = np.array([[c, -s], [s, c]])
    order = rng.permutation(3)
    moved = epsilon_batch(scale * P[:, order] @ R.T + np.array(shift), N[:, order] @ R.T,
                          mu=mu[:, order])
    np.testing.assert_allclose(moved, base, rtol=1e-7, atol=1e-9)


@given(st.integers(0, 2**32 - 1), st.floats(0.01, 100), st.tuples(*[st.floats(-5, 5)] * 3))
def test_spatial_epsilon_is_invariant_under_translation_scaling_and_order(seed, scale, shift):
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(20, 3, 3))
    P /= np.linalg.norm(P, axis=2, keepdims=True)
    N = P + rng.normal(0, 0.3, P.shape)
    mu = rng.uniform(0.2, 1, (20, 3))
    base = epsilon_batch(P, N, mu=mu)
    order = rng.permutation(3)
    moved = epsilon_batch(scale * P[:, order] + np.array(shift), N[:, order], mu=mu[:, order])
    np.testing.assert_allclose(moved, base, rtol=1e-7, atol=1e-9)


def test_linf_takes_the_reference_path():
    P = np.array([[[-1.0, 0], [1, 0]]])
    N = np.array([[[-1.0, 0], [1, 0]]])
    from forceclosure import point_contact
    from forceclosure.analysis.quality import epsilon

    grasp = [point_contact(p, n, "hard", 0.5) for p, n in zip(P[0], N[0], strict=True)]
    assert epsilon_batch(P, N, mu=0.5, norm="Linf")[0] == epsilon(grasp, "Linf").value > 0


@pytest.mark.parametrize("kwargs, message", [
    ({"norm": "L2"}, "norm must be 'L1' or 'Linf'"),
    ({"edges": 2}, "'edges' must be an integer >= 3"),
    ({"engine": "gpu"}, "engine must be 'compiled' or 'reference'"),
    ({"mu": -1.0}, "grasp 1, contact 1: 'mu' must be finite and >= 0"),
])
def test_bad_arguments_are_refused_in_one_line(kwargs, message):
    P = np.array([[[-1.0, 0], [1, 0]]])
    with pytest.raises(InputError, match=message) as err:
        epsilon_batch(P, P, **{"mu": 0.5, **kwargs})
    assert "\n" not in str(err.value)
