"""The compiled kernels against the reference path, exact rationals and closed forms.

Any disagreement in verdict or rank, or a margin differing by more than the
reference LP's own accuracy, is a failure. The grasp families include the
degenerate ones: rank-deficient, boundary, coincident, parallel and
antiparallel, zero friction, mixed contact models.
"""

from __future__ import annotations

import math
import multiprocessing
import os
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from exact import planar_hard_wrenches, positively_spans, spatial_pyramid4_wrenches
from forceclosure import Cone, InputError, point_contact
from forceclosure.analysis.batch import analyze_batch, least_friction_batch
from forceclosure.analysis.closure import decide
from forceclosure.analysis.quality import least_friction_reference
from forceclosure.analysis.two_finger import two_finger_closure

#: Grasps compared with the reference path in total: 2k in the README's test command (about
#: 14 s of setup); the long agreement profile (.ci/run, README) sets
#: FORCECLOSURE_AGREEMENT_GRASPS to 100k (about 3.5 minutes on two cores).
GRASPS = int(os.environ.get("FORCECLOSURE_AGREEMENT_GRASPS", 2_000))
#: Margins agree to this (relative, for large margins): HiGHS, behind the reference,
#: meets its constraints to 1e-7, and the margin 1 - m s scales an error in s by m.
MARGIN_ATOL = 1e-6


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _sphere(rng, n, k, d, jitter):
    p = _unit(rng.normal(size=(n, k, d)))
    return p, p + rng.normal(0, jitter, (n, k, d))


def _families(n_total: int, seed: int = 7):
    """(name, points, normals, mu, model, torsion, cone) with about ``n_total`` grasps."""
    rng = np.random.default_rng(seed)
    share = max(n_total // 100, 1)
    out = []

    def add(name, P, N, mu, model, torsion=None, cone="exact"):
        out.append((name, P, N, mu, model, torsion, cone))

    n = 14 * share
    P, N = _sphere(rng, n, 2, 2, 0.3)
    add("planar 2 hard", P, N, rng.uniform(0, 0.8, (n, 2)), "hard")
    P, N = _sphere(rng, n, 3, 2, 0.5)
    add("planar 3 mixed", P, N, rng.uniform(0, 0.8, (n, 3)), ["hard", "frictionless", "soft"],
        np.where(rng.random((n, 3)) < 0.5, np.nan, rng.uniform(0, 0.1, (n, 3))))
    P, N = _sphere(rng, n, 4, 2, 0.4)
    add("planar 4 frictionless", P, N, 0.0, "frictionless")
    # degenerate planar: boundary pairs, coincident points, collinear contacts
    n = 6 * share
    y = rng.integers(-4, 5, n) / 4
    P = np.stack([np.stack([-np.ones(n), np.zeros(n)], 1), np.stack([np.ones(n), y], 1)], 1)
    N = np.array([[-1.0, 0.0], [1.0, 0.0]])[None].repeat(n, 0)
    mu = np.abs(y)[:, None] / 2 * rng.choice([0.5, 1.0, 1.0, 2.0], (n, 1))
    P[: n // 6, 1] = P[: n // 6, 0]  # coincident
    add("planar boundary pairs", P, N, np.repeat(mu, 2, 1), "hard")
    P = np.zeros((n, 4, 2))
    P[:, :, 0] = rng.integers(-3, 4, (n, 4))
    N = np.tile(np.array([[0.0, 1], [0, -1], [0, 1], [0, -1]]), (n, 1, 1))
    add("planar collinear frictionless", P, N, 0.0, "frictionless")
    n = 14 * share
    P, N = _sphere(rng, n, 3, 3, 0.3)
    add("spatial 3 hard 8-edge", P, N, rng.uniform(0, 0.8, (n, 3)), "hard", None, Cone(8))
    P, N = _sphere(rng, n, 3, 3, 0.3)
    add("spatial 3 hard 6-edge circumscribed", P, N, rng.uniform(0, 0.8, (n, 3)), "hard", None,
        Cone(6, "circumscribed"))
    P, N = _sphere(rng, n, 2, 3, 0.3)
    add("spatial 2 soft", P, N, rng.uniform(0, 0.8, (n, 2)), "soft")
    n = 7 * share
    P, N = _sphere(rng, n, 2, 3, 0.3)
    add("spatial 2 soft coupled", P, N, rng.uniform(0, 0.8, (n, 2)), "soft",
        rng.uniform(0, 0.2, (n, 2)), Cone(8))
    P, N = _sphere(rng, n, 7, 3, 0.3)
    add("spatial 7 frictionless", P, N, 0.0, "frictionless")
    # degenerate spatial: antipodal pairs (rank 5 for hard), antiparallel soft, cube faces
    n = 5 * share
    y = rng.integers(-2, 3, (n, 2)) / 4
    P = np.stack([np.c_[-np.ones(n), y], np.c_[np.ones(n), y + rng.integers(0, 2, (n, 1)) / 4]], 1)
    N = np.array([[-1.0, 0, 0], [1.0, 0, 0]])[None].repeat(n, 0)
    add("spatial antipodal hard", P, N, 0.5, "hard", None, Cone(4))
    add("spatial antipodal soft", P, N, rng.choice([0.0, 0.125, 0.5], (n, 1)), "soft", None,
        Cone(4))
    axes = np.concatenate([np.eye(3), -np.eye(3)])
    face = rng.integers(0, 6, (n, 7))
    N = axes[face]
    P = N + (rng.integers(-2, 3, (n, 7, 3)) / 4) * (1 - np.abs(N))
    add("cube faces mixed", P, N, rng.choice([0.0, 0.25], (n, 7)),
        ["frictionless"] * 4 + ["hard", "soft", "frictionless"], None, Cone(4))
    n = 2 * share
    P, N = _sphere(rng, n, 3, 3, 0.2)
    add("spatial 3 hard exact", P, N, rng.uniform(0.2, 0.6, (n, 3)), "hard")
    return out


def _reference_chunk(args):
    P, N, mu, model, torsion, cone = args
    from forceclosure.analysis.batch_analysis import validate_grasps

    grasps = validate_grasps(P, N, mu, model, torsion)
    rows = []
    for g in range(len(P)):
        vc, _, _ = decide(grasps.contacts(g), cone)
        rows.append((vc.verdict.code, vc.rank, np.nan if vc.margin is None else vc.margin))
    return rows


@pytest.fixture(scope="module")
def agreement():
    """Kernel and reference answers for every family (the reference on two processes
    in the long profile)."""
    families = _families(GRASPS)
    jobs = []
    for name, P, N, mu, model, torsion, cone in families:
        n, k = P.shape[:2]
        mu_ = np.broadcast_to(np.asarray(mu, float), (n, k))
        tor_ = None if torsion is None else np.broadcast_to(torsion, (n, k))
        for lo in range(0, n, 500):
            s = slice(lo, lo + 500)
            jobs.append((name, (P[s], N[s], mu_[s], model, None if tor_ is None else tor_[s],
                                cone)))
    if GRASPS > 10_000:  # the long profile: worth two processes' start-up
        with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
            answers = list(pool.map(_reference_chunk, [j for _, j in jobs]))
    else:  # beside the other test worker, in this process
        answers = [_reference_chunk(j) for _, j in jobs]
    reference = {}
    for (name, _), rows in zip(jobs, answers, strict=True):
        reference.setdefault(name, []).extend(rows)
    out = []
    for name, P, N, mu, model, torsion, cone in families:
        ours = analyze_batch(P, N, mu=mu, model=model, torsion=torsion, cone=cone)
        out.append((name, ours, np.array(reference[name]), (P, N, mu, model, torsion, cone)))
    return out


def test_families_cover_the_requested_number_of_grasps(agreement):
    assert sum(len(ours) for _, ours, _, _ in agreement) >= 0.95 * GRASPS
    codes = np.concatenate([ref[:, 0] for _, _, ref, _ in agreement])
    assert {0, 1, 2} <= set(codes.astype(int).tolist())  # every verdict occurs


def test_verdicts_and_ranks_agree_with_the_reference(agreement):
    for name, ours, ref, _ in agreement:
        bad = np.flatnonzero(ours.code != ref[:, 0])
        assert len(bad) == 0, f"{name}: {len(bad)} verdicts differ, first grasp {bad[:5]}"
        bad = np.flatnonzero(ours.rank != ref[:, 1])
        assert len(bad) == 0, f"{name}: {len(bad)} ranks differ, first grasp {bad[:5]}"


def test_margins_agree_with_the_reference(agreement):
    for name, ours, ref, _ in agreement:
        theirs = ref[:, 2]
        assert np.array_equal(np.isnan(ours.margin), np.isnan(theirs)), name
        both = ~np.isnan(theirs)
        err = np.abs(ours.margin[both] - theirs[both]) / np.maximum(1.0, np.abs(theirs[both]))
        assert err.max(initial=0.0) <= MARGIN_ATOL, f"{name}: margin off by {err.max():.3g}"


def test_single_grasps_agree_with_the_reference(agreement):
    """``analyze`` on one grasp (the compiled kernel on the calling thread) and batches of
    one block or less (the serial kernel) give the reference's verdict, rank and margin."""
    from forceclosure import analyze

    for name, _, ref, (P, N, mu, model, torsion, cone) in agreement:
        n, k = P.shape[:2]
        mu_ = np.broadcast_to(np.asarray(mu, float), (n, k))
        tor_ = np.broadcast_to(np.nan if torsion is None else torsion, (n, k))
        models = [model] * k if isinstance(model, str) else list(model)
        small = analyze_batch(P[:40], N[:40], mu=mu_[:40], model=model,
                              torsion=None if torsion is None else tor_[:40], cone=cone)
        assert np.array_equal(small.code, ref[:40, 0]), name
        for g in range(0, min(n, 40), 4):
            grasp = [point_contact(P[g, i], N[g, i], models[i], float(mu_[g, i]),
                                   None if np.isnan(tor_[g, i]) else float(tor_[g, i]))
                     for i in range(k)]
            a = analyze(grasp, cone=cone)
            assert a.verdict.code == ref[g, 0] and a.rank == ref[g, 1], (name, g)
            if a.margin is not None and np.isfinite(ref[g, 2]):  # as the batch's margins
                assert abs(a.margin - ref[g, 2]) <= MARGIN_ATOL * max(1.0, abs(ref[g, 2])), \
                    (name, g)


def test_unresisted_twists_do_no_negative_work(agreement):
    """Every ``none`` twist, checked against the grasp's wrenches built here about the origin."""
    for name, ours, _, (P, N, mu, model, torsion, cone) in agreement:
        if isinstance(cone, Cone) and cone.fit == "circumscribed":
            continue  # the twist refutes the circumscribed pyramid, not the inscribed one
        idx = np.flatnonzero(ours.code == 0)[:300]
        n, k, d = P.shape
        mu_ = np.broadcast_to(np.asarray(mu, float), (n, k))
        models = [model] * k if isinstance(model, str) else model
        for g in idx:
            t = ours.twist[g]
            omega, v = (t[:1], t[1:]) if d == 2 else (t[:3], t[3:])
            for i in range(k):
                c = point_contact(P[g, i], N[g, i], models[i], mu_[g, i],
                                  None if torsion is None or np.isnan(
                                      np.broadcast_to(torsion, (n, k))[g, i])
                                  else float(np.broadcast_to(torsion, (n, k))[g, i]))
                edges = cone.edges if isinstance(cone, Cone) else 256
                from forceclosure import generating_wrenches

                W = generating_wrenches([c], Cone(edges), reference=np.zeros(d),
                                        length_scale=1.0).wrenches
                work = W[:d].T @ v + (W[d:].T @ omega if d == 3 else W[d] * omega[0])
                scale = np.abs(W).max() * np.abs(t).max()
                assert work.min() >= -1e-7 * scale, f"{name}: grasp {g} twist does work " \
                                                    f"{work.min():.3g}"


def test_pairs_agree_with_the_reference():
    rng = np.random.default_rng(3)
    n = 1_000_000
    p, q = rng.normal(size=(n, 2)), rng.normal(size=(n, 2))
    n_p, n_q = p * rng.uniform(0.1, 3, (n, 1)), q + rng.normal(0, 0.3, (n, 2))
    mu = rng.uniform(0, 1.5, n)
    # degenerate rows: coincident, exactly on the boundary, zero friction, huge friction
    q[:1000] = p[:1000]
    p[1000:2000], q[1000:2000] = [-1, 0], np.c_[np.ones(1000), rng.integers(-4, 5, 1000) / 4]
    n_p[1000:2000], n_q[1000:2000] = [-1, 0], [1, 0]
    mu[1000:2000] = np.abs(q[1000:2000, 1]) / 2
    mu[2000:3000], mu[3000:4000] = 0.0, 1e7
    # a friction per pair, and one for all (the vectorised pass, kernels.pairs._common_planar)
    for friction in (mu, 0.45):
        ours = two_finger_closure(p, n_p, q, n_q, friction)
        theirs = two_finger_closure(p, n_p, q, n_q, friction, engine="reference")
        assert np.array_equal(ours.code, theirs.code)
        assert set(np.unique(ours.code)) == {0, 1, 2}
        finite = np.isfinite(theirs.least_friction)
        assert np.array_equal(finite, np.isfinite(ours.least_friction))
        assert np.allclose(ours.least_friction[finite], theirs.least_friction[finite],
                           rtol=1e-9)


def test_spatial_pairs_agree_with_the_reference():
    rng = np.random.default_rng(4)
    n = 400
    p, q = _unit(rng.normal(size=(n, 3))), _unit(rng.normal(size=(n, 3)))
    n_p, n_q = p + rng.normal(0, 0.2, (n, 3)), q + rng.normal(0, 0.2, (n, 3))
    n_q[:100] = -n_p[:100]  # antiparallel: Corollary 3 is an iff
    mu = rng.uniform(0.1, 1.0, n)
    for model in ("soft", "hard"):
        ours = two_finger_closure(p, n_p, q, n_q, mu, model=model)
        theirs = two_finger_closure(p, n_p, q, n_q, mu, model=model, engine="reference")
        assert np.array_equal(ours.code, theirs.code)
        assert np.array_equal(ours.least_friction, theirs.least_friction) or np.allclose(
            ours.least_friction, theirs.least_friction, rtol=1e-9)
    assert ours.code.max() == 0  # hard fingers in space: never


def test_exact_rational_planar_hard_fingers():
    """Rational grasps with 3-4-5 normals: the kernel's clear verdicts match exact Theorem 1."""
    rng = np.random.default_rng(11)
    dirs = np.array([[1, 0], [0, 1], [-1, 0], [0, -1], [3 / 5, 4 / 5], [-4 / 5, 3 / 5],
                     [-3 / 5, -4 / 5], [4 / 5, -3 / 5]])
    n, k = 300, 3
    P = rng.integers(-3, 4, (n, k, 2)) / 2
    N = dirs[rng.integers(0, 8, (n, k))]
    mu = rng.integers(0, 5, (n, k)) / 4
    ours = analyze_batch(P, N, mu=mu, model="hard")
    for g in range(n):
        truth = positively_spans(planar_hard_wrenches(P[g], N[g], mu[g]))
        if ours.code[g] == 2:
            assert truth, g
        elif ours.code[g] == 0:
            assert not truth, g
    assert 0 < ours.force_closure.sum() < n


def test_exact_rational_spatial_pyramids():
    rng = np.random.default_rng(12)
    axes = np.concatenate([np.eye(3), -np.eye(3)])
    n, k = 200, 3
    N = axes[rng.integers(0, 6, (n, k))]
    P = N + (rng.integers(-2, 3, (n, k, 3)) / 2) * (1 - np.abs(N))
    mu = rng.integers(0, 3, (n, k)) / 2
    ours = analyze_batch(P, N, mu=mu, model="hard", cone=Cone(4))
    for g in range(n):
        truth = positively_spans(spatial_pyramid4_wrenches(P[g], N[g], mu[g]))
        if ours.code[g] == 2:
            assert truth, g
        elif ours.code[g] == 0:
            assert not truth, g
    assert 0 < ours.force_closure.sum() < n


def _rotation3(angle, axis):
    axis = _unit(np.asarray(axis, float) + np.array([0, 0, 1e-3]))
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


@given(st.integers(0, 2**32 - 1), st.floats(0, 2 * np.pi), st.floats(0.01, 100),
       st.tuples(*[st.floats(-5, 5)] * 3), st.sampled_from(["hard", "soft", "frictionless"]))
def test_compiled_verdicts_are_invariant(seed, angle, scale, shift, model):
    """Rotation, translation, scaling and contact order change no clear verdict.

    A pyramid is fixed to the world's axes (``tangent_basis``), so a rotated
    grasp gets other pyramids: pyramids are checked under translation, scaling
    and reordering only, and exact circular cones under all four, where
    closure and none never swap (near the boundary the answer is marginal).
    """
    rng = np.random.default_rng(seed)
    k = 7 if model == "frictionless" else 3
    P, N = _sphere(rng, 50, k, 3, 0.4)
    mu = rng.uniform(0, 1, (50, k))
    order = rng.permutation(k)
    moved_P, moved_mu = scale * P[:, order] + np.array(shift), mu[:, order]
    base = analyze_batch(P, N, mu=mu, model=model, cone=Cone(8))
    moved = analyze_batch(moved_P, N[:, order], mu=moved_mu, model=model, cone=Cone(8))
    clear = (np.abs(base.margin) > 0.05) & (np.abs(moved.margin) > 0.05)
    assert np.array_equal(base.code[clear], moved.code[clear])
    R = _rotation3(angle, shift)
    exact = analyze_batch(P, N, mu=mu, model=model, cone="exact")
    turned = analyze_batch(moved_P @ R.T, N[:, order] @ R.T, mu=moved_mu, model=model,
                           cone="exact")
    assert not np.any(np.abs(exact.code.astype(int) - turned.code) == 2)


def test_least_friction_matches_closed_forms_and_the_reference():
    rng = np.random.default_rng(5)
    # antiparallel soft fingers in space: Corollary 3 is exact, mu* = tan(angle of PQ);
    # each grasp bisects on pyramids of up to 256 edges, so a few suffice
    n = 16
    y = rng.uniform(-0.5, 0.5, (n, 2))
    P = np.stack([np.c_[-np.ones(n), np.zeros((n, 2))], np.c_[np.ones(n), y]], 1)
    N = np.array([[-1.0, 0, 0], [1.0, 0, 0]])[None].repeat(n, 0)
    exact = np.linalg.norm(y, axis=1) / 2
    got = least_friction_batch(P, N, model="soft")
    # exact cones are decided to within cos(pi/256) of the boundary
    assert np.allclose(got, exact, rtol=1e-4)
    # general grasps: the compiled bisection against the reference's, grasp by grasp
    P, N = _sphere(rng, 60, 3, 3, 0.3)
    ours = least_friction_batch(P, N, model="hard", cone=Cone(8))
    for g in range(len(P)):
        ref = least_friction_reference(
            [point_contact(P[g, i], N[g, i], "hard") for i in range(3)], cone=Cone(8))
        assert (math.isinf(ref) and math.isinf(ours[g])) or math.isclose(ours[g], ref,
                                                                         rel_tol=1e-5), g


def test_least_friction_with_exact_cones_is_the_reference_bisection():
    """The compiled bisection skips pyramids an earlier step has decided (cones grow with
    friction); it must land where the reference's full ladder at every step lands."""
    rng = np.random.default_rng(8)
    P, N = _sphere(rng, 6, 3, 3, 0.2)
    ours = least_friction_batch(P, N, model="hard")
    for g in range(len(P)):
        ref = least_friction_reference([point_contact(P[g, i], N[g, i], "hard")
                                        for i in range(3)])
        # both bisect the cone's half-angle to rtol 1e-6 of their own brackets
        assert (math.isinf(ref) and math.isinf(ours[g])) or math.isclose(
            math.atan(ours[g]), math.atan(ref), rel_tol=3e-6), g
    assert np.isfinite(ours).sum() >= 4


def test_a_bisection_step_is_the_ladders_verdict_whatever_came_before():
    """A step skips what earlier steps proved, and only that: with a large tolerance an
    inscribed pyramid marginal at a larger friction (its singular value ratio below tol)
    closes at a smaller one (a reviewer's grasp, 2026-12-03)."""
    from forceclosure.contacts import model_codes
    from forceclosure.kernels import theorem1 as T

    P = np.array([[-0.019381991189871387, 0.3643000354433765, -0.9310799227743396],
                  [0.7652496784989465, -0.13418559311370626, 0.6295928495130657],
                  [-0.3869799604336708, 0.8054963952116629, 0.4488006991123911]])
    N = np.array([[0.309108745006784, 0.6269680318821612, -0.7150964066181149],
                  [0.8255383650125865, 0.29086460196338976, 0.48361574748660163],
                  [-0.6847684481886304, 0.4540641069991291, 0.5700157533791662]])
    tol = 0.5
    work = T.work_arrays(T.columns_per_grasp(3, 3, 256), 256)
    ref, y, tors, model = np.empty(3), np.empty(6), np.full(3, np.nan), model_codes(["hard"] * 3)
    known = np.empty((2, 6))
    known[0, :], known[1, :] = -1.0, np.inf
    seen = []
    for f in (2.5, 1.8, 3.0, 1.2, 2.0):
        mu = np.full(3, f)
        step = T._bisection_step(P, N, mu, tors, model, 8, 0, True, tol, work, ref, y, known)
        full = T.grasp(P, N, mu, tors, model, 8, 0, True, tol, work, ref, y)[0]
        assert (step == T.CLOSURE) == (full == T.CLOSURE), f
        seen.append(int(full))
    assert T.CLOSURE in seen and T.MARGINAL in seen  # the case that tripped the first version


def test_least_friction_batch_is_the_loop_over_friction_values_done_right():
    """GraspNet's way (six friction values, a pass each) brackets the one-pass answer."""
    rng = np.random.default_rng(6)
    P, N = _sphere(rng, 5000, 2, 2, 0.5)
    star = least_friction_batch(P, N)
    for mu in (0.1, 0.2, 0.4, 0.6, 0.8, 1.0):
        closed = two_finger_closure(P[:, 0], N[:, 0], P[:, 1], N[:, 1], mu).force_closure
        clear = np.abs(star - mu) > 1e-5
        assert np.array_equal(closed[clear], (star < mu)[clear])


def test_bad_arrays_are_refused_in_one_line():
    P = np.zeros((2, 2, 2))
    P[1, 1] = [np.nan, 0]
    with pytest.raises(InputError, match="grasp 2, contact 2: 'point' has a non-finite"):
        analyze_batch(P, np.ones((2, 2, 2)))
    with pytest.raises(InputError, match="pair at index 1: a normal is a zero vector"):
        two_finger_closure(np.zeros((3, 2)), [[1, 0], [0, 0], [1, 0]], np.ones((3, 2)),
                           np.ones((3, 2)), 0.3)
    with pytest.raises(InputError, match="non-finite"):
        two_finger_closure([0, 0], [1, 0], [np.inf, 0], [1, 0], 0.3)
    with pytest.raises(InputError, match="engine"):
        analyze_batch(np.ones((1, 2, 2)), np.ones((1, 2, 2)), engine="fast")


def test_one_block_runs_on_the_calling_thread(monkeypatch):
    """Batches of one block or less do not wake the thread pool (their kernel sees one
    thread), larger ones get every thread, and the caller's thread count is restored."""
    import numba

    from forceclosure.analysis import friction
    from forceclosure.kernels import theorem1

    seen = []
    real = theorem1.least_friction_kernel

    def spy(*args):
        seen.append(numba.get_num_threads())
        return real(*args)

    monkeypatch.setattr(theorem1, "least_friction_kernel", spy)
    rng = np.random.default_rng(3)
    p = rng.normal(size=(theorem1.BLOCK + 1, 3, 3))
    p /= np.linalg.norm(p, axis=-1, keepdims=True)
    before = numba.get_num_threads()
    small = friction.least_friction_batch(p[:2], -p[:2], cone=Cone(8))
    large = friction.least_friction_batch(p, -p, cone=Cone(8))
    assert seen == [1, before]
    assert numba.get_num_threads() == before
    np.testing.assert_array_equal(small, large[:2])  # the same answers either way
