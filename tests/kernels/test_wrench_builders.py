"""The compiled kernels build the reference's generating wrenches bit for bit.

``kernels.theorem1.wrenches`` (scalar loops, compiled) and
``contacts.primitive_wrenches`` (vectorised NumPy, the reference) are two
implementations of one contact model; they share its source of truth
(``geometry.cones``: the pyramid's edge angles, its radius, the tangent
basis, the grasp's own pyramid frames), and this test holds them to it:
every column equal to the last bit (``np.array_equal``, not ``allclose``),
over every model, both dimensions, pyramid sizes from 3 to 256 edges, both
fits, both orientations, coupled and uncoupled torsion, and random points,
normals and friction.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from forceclosure.contacts import Cone, primitive_wrenches
from forceclosure.geometry.cones import pyramid_divisor
from forceclosure.kernels.theorem1 import (
    EXACT_EDGES,
    FRICTIONLESS,
    HARD,
    SOFT,
    columns_per_grasp,
    wrenches,
)

CODES = {"frictionless": FRICTIONLESS, "hard": HARD, "soft": SOFT}
finite = st.floats(-1e3, 1e3, allow_nan=False, allow_infinity=False)


@st.composite
def grasps(draw):
    d = draw(st.sampled_from([2, 3]))
    k = draw(st.integers(1, 4))
    points = np.array(draw(st.lists(st.lists(finite, min_size=d, max_size=d),
                                    min_size=k, max_size=k)))
    normals = np.array(draw(st.lists(
        st.lists(st.floats(-1, 1), min_size=d, max_size=d).filter(
            lambda v: np.linalg.norm(v) > 1e-3), min_size=k, max_size=k)))
    normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
    models = draw(st.lists(st.sampled_from(list(CODES)), min_size=k, max_size=k))
    mu = np.array(draw(st.lists(st.floats(0, 5), min_size=k, max_size=k)))
    torsion = np.array(draw(st.lists(st.one_of(st.just(np.nan), st.floats(0, 1)),
                                     min_size=k, max_size=k)))
    edges = draw(st.one_of(st.integers(3, 40), st.sampled_from(EXACT_EDGES.tolist())))
    fit = draw(st.sampled_from(["inscribed", "circumscribed"]))
    reference = np.array(draw(st.lists(finite, min_size=d, max_size=d)))
    scale = draw(st.floats(1e-3, 1e3))
    return points, normals, models, mu, torsion, Cone(edges, fit), reference, scale


def compiled(points, normals, models, mu, torsion, cone, reference, scale):
    k, d = points.shape
    m_max = columns_per_grasp(k, d, cone.edges)
    W = np.full((6, m_max), np.nan)
    two = np.zeros(m_max, dtype=np.bool_)
    rim = np.zeros((2, cone.edges + 1))
    divisor = pyramid_divisor(cone.edges, cone.fit == "circumscribed")
    m = wrenches(points, normals, mu, torsion, np.array([CODES[x] for x in models]),
                 cone.edges, divisor, reference, scale, W, two, rim)
    return W[:3 if d == 2 else 6, :m], two[:m]


def reference_path(points, normals, models, mu, torsion, cone, reference, scale):
    blocks, pure = [], []
    for i, model in enumerate(models):
        tors = None if np.isnan(torsion[i]) else torsion[i:i + 1]
        w = primitive_wrenches(points[i:i + 1], normals[i:i + 1], model, mu[i:i + 1], tors,
                               reference[None], np.array([scale]), cone)[0]
        blocks.append(w)
        flags = np.zeros(w.shape[1], dtype=bool)
        if model == "soft" and points.shape[1] == 3 and tors is None:
            flags[-2:] = True  # the paper's two-sided pure torques come last
        pure.append(flags)
    return np.concatenate(blocks, axis=1), np.concatenate(pure)


@settings(max_examples=400, deadline=None)
@given(grasps())
def test_kernel_and_reference_build_the_same_bits(grasp):
    W_kernel, two_kernel = compiled(*grasp)
    W_reference, two_reference = reference_path(*grasp)
    assert W_kernel.shape == W_reference.shape
    assert np.array_equal(W_kernel, W_reference)
    assert np.array_equal(two_kernel, two_reference)


def test_every_model_dimension_and_fit_is_compared():
    """The cases hypothesis may not draw, each once: a 256-edge circumscribed pyramid (the
    exact-cone bracket's last), coupled and uncoupled soft fingers, mixed models."""
    rng = np.random.default_rng(3)
    for d in (2, 3):
        for fit in ("inscribed", "circumscribed"):
            for edges in (3, 8, 256):
                for models in (["frictionless"] * 3, ["hard"] * 3, ["soft"] * 3,
                               ["hard", "soft", "frictionless"]):
                    for torsion in (np.full(3, np.nan), rng.uniform(0, 0.2, 3)):
                        n = rng.normal(size=(3, d))
                        grasp = (rng.normal(size=(3, d)), n / np.linalg.norm(n, axis=1)[:, None],
                                 models, rng.uniform(0, 2, 3), torsion, Cone(edges, fit),
                                 rng.normal(size=d), float(rng.uniform(0.1, 3)))
                        W_kernel, two_kernel = compiled(*grasp)
                        W_reference, two_reference = reference_path(*grasp)
                        assert np.array_equal(W_kernel, W_reference), (d, fit, edges, models)
                        assert np.array_equal(two_kernel, two_reference)


def test_a_hard_finger_by_hand():
    """Independent truth: the 4-edge inscribed pyramid of a hard finger at (1, 0, 0) with
    normal +x and mu 0.5, torques about the origin: forces -x + 0.5 (±y or ±z)."""
    grasp = (np.array([[1.0, 0.0, 0.0]]), np.array([[1.0, 0.0, 0.0]]), ["hard"],
             np.array([0.5]), np.array([np.nan]), Cone(4, "inscribed"), np.zeros(3), 1.0)
    W, _ = compiled(*grasp)
    forces = {tuple(np.round(f, 12) + 0.0) for f in W[:3].T}
    assert forces == {(-1.0, 0.5, 0.0), (-1.0, -0.5, 0.0), (-1.0, 0.0, 0.5), (-1.0, 0.0, -0.5)}
    # moment p x f with p = (1, 0, 0): (0, -f_z, f_y)
    assert np.allclose(W[3:], np.array([np.zeros(4), -W[2], W[1]]))
    assert np.array_equal(W, reference_path(*grasp)[0])


@settings(max_examples=100, deadline=None)
@given(grasps())
def test_pyramids_oriented_by_the_grasp_build_the_same_bits(grasp):
    """The grasp's own pyramid frames (``geometry.cones.fill_frame``), compiled and not, and
    the wrenches built on them: equal to the last bit."""
    points, normals, models, mu, torsion, cone, reference, scale = grasp
    if points.shape[1] == 2:
        return
    from forceclosure.geometry.cones import grasp_tangents
    from forceclosure.kernels.quality import grasp_frames

    frames = np.empty((len(points), 2, 3))
    grasp_frames(points, normals, frames)
    t1, t2 = grasp_tangents(points, normals)
    assert np.array_equal(frames[:, 0], t1) and np.array_equal(frames[:, 1], t2)
    k = len(points)
    W = np.full((6, columns_per_grasp(k, 3, cone.edges)), np.nan)
    two = np.zeros(W.shape[1], dtype=np.bool_)
    m = wrenches(points, normals, mu, torsion, np.array([CODES[x] for x in models]), cone.edges,
                 pyramid_divisor(cone.edges, cone.fit == "circumscribed"), reference, scale, W,
                 two, np.zeros((2, cone.edges + 1)), frames)
    blocks = []
    for i, model in enumerate(models):
        tors = None if np.isnan(torsion[i]) else torsion[i:i + 1]
        blocks.append(primitive_wrenches(points[i:i + 1], normals[i:i + 1], model, mu[i:i + 1],
                                         tors, reference[None], np.array([scale]), cone,
                                         (t1[i:i + 1], t2[i:i + 1]))[0])
    assert np.array_equal(W[:, :m], np.concatenate(blocks, axis=1))
