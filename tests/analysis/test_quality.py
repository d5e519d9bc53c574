import math

import numpy as np
import pytest

from forceclosure import Cone, Verdict, analyze, generating_wrenches, point_contact
from forceclosure.analysis.batch import analyze_batch, least_friction_batch
from forceclosure.analysis.quality import epsilon, least_friction, least_friction_reference
from forceclosure.analysis.two_finger import two_finger_closure


@pytest.mark.parametrize("mu", [0.2, 0.5, 1.0])
def test_epsilon_of_a_symmetric_pinch_has_a_closed_form(mu):
    # The four wrenches (±1, ±mu, ∓mu) are a tetrahedron about the origin; by
    # symmetry every face is as near, so epsilon is the distance to one face.
    a, b, c = np.array([1, mu, -mu]), np.array([1, -mu, mu]), np.array([-1, mu, mu])
    n = np.cross(b - a, c - a)
    want = abs(n @ a) / np.linalg.norm(n)
    grasp = [point_contact([-1, 0], [-1, 0], "hard", mu), point_contact([1, 0], [1, 0], "hard", mu)]
    assert epsilon(grasp).value == pytest.approx(want, rel=1e-9)
    assert epsilon(grasp, "Linf").value >= epsilon(grasp).value
    if mu == 0.5:
        assert want == pytest.approx(1 / 3)


def test_epsilon_is_zero_without_closure_and_grows_with_friction():
    off = [point_contact([-1, 0], [-1, 0], "hard", 0.3), point_contact([1, 1], [1, 0], "hard", 0.3)]
    assert epsilon(off).value == 0.0
    values = [epsilon([point_contact([-1, 0], [-1, 0], "hard", m),
                       point_contact([1, 0], [1, 0], "hard", m)]).value for m in (0.1, 0.3, 0.6)]
    assert values == sorted(values) and values[0] > 0


def test_least_friction_planar_pairs_match_the_angle():
    rng = np.random.default_rng(5)
    for _ in range(20):
        y = rng.uniform(-1.5, 1.5)
        grasp = [point_contact([-1, 0], [-1, 0]), point_contact([1, y], [1, 0])]
        assert least_friction(grasp) == pytest.approx(abs(y) / 2, abs=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_least_friction_is_the_closure_threshold(dim):
    """Just above mu*, closure; just below, not: checked with the general test."""
    if dim == 2:
        pts = [[-1, 0], [1, 0.4], [0.2, 1]]
        nrm = [[-1, 0.2], [1, 0.1], [0.3, 1]]
    else:
        pts = [[1, 0, 0.1], [-0.5, 0.8, 0], [-0.5, -0.8, 0.2]]
        nrm = [[1, 0.1, 0], [-0.5, 0.8, 0.3], [-0.5, -0.8, 0]]
    grasp = [point_contact(p, n, "hard") for p, n in zip(pts, nrm, strict=True)]
    mu = least_friction(grasp)
    assert 0 < mu < math.inf
    above = [c.with_friction(mu * 1.01) for c in grasp]
    below = [c.with_friction(mu * 0.99) for c in grasp]
    assert analyze(above).verdict is Verdict.CLOSURE
    assert analyze(below).verdict is not Verdict.CLOSURE


def _soft_pairs(count, seed):
    """Spatial soft pairs, squeezing and (every third) spreading, normals tilted at random."""
    rng = np.random.default_rng(seed)
    for i in range(count):
        p, q = rng.normal(size=3), rng.normal(size=3)
        d = (q - p) / np.linalg.norm(q - p)
        n_p, n_q = -d + rng.normal(scale=0.5, size=3), d + rng.normal(scale=0.5, size=3)
        yield (p, q, -n_p, -n_q) if i % 3 == 2 else (p, q, n_p, n_q)


def test_least_friction_of_soft_pairs_in_space_is_the_closure_threshold():
    """The closed form for two spatial soft fingers (docs/analysis.md) against Theorem 1:
    the general test with exact cones says closure at mu* (1 + 3e-4) and not at mu*
    (1 - 3e-4), squeezing and spreading; exact cones are decided to 7.5e-5 relative."""
    batch = []
    for p, q, n_p, n_q in _soft_pairs(24, 3):
        batch.append((p, q, n_p, n_q))
        grasp = [point_contact(p, n_p, "soft"), point_contact(q, n_q, "soft")]
        mu = least_friction(grasp)
        if not math.isfinite(mu):
            assert analyze([c.with_friction(1e3) for c in grasp]).verdict is not Verdict.CLOSURE
            continue
        above = [c.with_friction(mu * (1 + 3e-4)) for c in grasp]
        below = [c.with_friction(mu * (1 - 3e-4)) for c in grasp]
        assert analyze(above).verdict is Verdict.CLOSURE
        assert analyze(below).verdict is not Verdict.CLOSURE
    P = np.array([[p, q] for p, q, _, _ in batch])
    N = np.array([[a, b] for _, _, a, b in batch])
    fast = least_friction_batch(P, N, model="soft")
    ref = np.array([least_friction_reference([point_contact(p, a, "soft"),
                                              point_contact(q, b, "soft")])
                    for p, q, a, b in batch])
    assert np.array_equal(np.isinf(fast), np.isinf(ref))
    assert np.allclose(fast[np.isfinite(fast)], ref[np.isfinite(ref)], rtol=1e-9)


def test_soft_pairs_in_space_are_decided_as_theorem_1_decides_them():
    """The compiled pair verdict (closed form, unequal friction too) against Theorem 1's
    general test with exact cones; only pairs within 1e-3 rad of the boundary may differ
    (exact cones are decided to 7.5e-5 relative, and then only as marginal)."""
    rng = np.random.default_rng(21)
    pairs = list(_soft_pairs(400, 22))
    P = np.array([[p, q] for p, q, _, _ in pairs])
    N = np.array([[a, b] for _, _, a, b in pairs])
    mu = rng.uniform(0.05, 1.5, size=(len(pairs), 2))
    ours = two_finger_closure(P[:, 0], N[:, 0], P[:, 1], N[:, 1], mu[:, 0], mu[:, 1])
    theirs = analyze_batch(P, N, mu=mu, model="soft", engine="reference").code
    moved = []
    for scale in (1 - 1e-3, 1 + 1e-3):  # the verdict at friction moved by 1e-3 relative
        moved.append(analyze_batch(P, N, mu=mu * scale, model="soft").code)
    clear = moved[0] == moved[1]
    assert np.array_equal(ours.code[clear], theirs[clear])
    assert clear.sum() >= 380 and {0, 2} <= set(ours.code.tolist())


def test_spreading_pairs_close_as_corollary_3_says():
    """Corollary 3 holds for "PQ, or QP": two fingers pushing apart inside a slot close it.
    Checked against Theorem 1 (analyze) in the plane, at random tilts."""
    rng = np.random.default_rng(8)
    for _ in range(30):
        p, q = np.array([-1.0, 0]), np.array([1.0, rng.uniform(-1, 1)])
        n_p = np.array([1.0, rng.uniform(-0.6, 0.6)])  # facing Q: the finger pushes away
        n_q = np.array([-1.0, rng.uniform(-0.6, 0.6)])
        mu = rng.uniform(0.05, 1.0)
        pair = two_finger_closure(p, n_p, q, n_q, mu)
        want = analyze([point_contact(p, n_p, "hard", mu), point_contact(q, n_q, "hard", mu)])
        assert str(pair.verdict) == want.verdict.value or "marginal" in (str(pair.verdict),
                                                                          want.verdict.value)
        star = least_friction([point_contact(p, n_p), point_contact(q, n_q)])
        angle = max(np.arccos(np.dot(p - q, -n_p) / np.linalg.norm(p - q) / np.linalg.norm(n_p)),
                    np.arccos(np.dot(q - p, -n_q) / np.linalg.norm(p - q) / np.linalg.norm(n_q)))
        assert star == pytest.approx(np.tan(angle), rel=1e-9)


@pytest.mark.long  # 6 s; test_kernels' least friction against closed forms and the reference stays
def test_least_friction_of_point_contacts_is_the_reference_bisection_compiled():
    """least_friction on point contacts runs one compiled bisection; with exact cones it
    agrees with the bisection over full analyses to the precision exact cones are decided
    to (1 - cos(pi/256), relative), in a small fraction of its time (benchmarked)."""
    rng = np.random.default_rng(11)
    for _ in range(6):
        P = rng.normal(size=(3, 3))
        P /= np.linalg.norm(P, axis=1, keepdims=True)
        grasp = [point_contact(p, p + rng.normal(scale=0.2, size=3), "hard") for p in P]
        fast, ref = least_friction(grasp), least_friction_reference(grasp)
        assert (math.isinf(fast) and math.isinf(ref)) or fast == pytest.approx(ref, rel=1e-4)


def test_least_friction_extremes():
    cube_like = [point_contact([1, 0.5], [1, 0], "frictionless"),
                 point_contact([-1, -0.5], [-1, 0], "frictionless"),
                 point_contact([0.5, 1], [0, 1], "frictionless"),
                 point_contact([-0.5, -1], [0, -1], "frictionless")]
    assert least_friction(cube_like) == 0.0
    same_side = [point_contact([0, 0], [0, 1]), point_contact([1, 0], [0, 1])]
    assert least_friction(same_side) == math.inf
    hard_pair = [point_contact([x, 0, 0], [x, 0, 0], "hard") for x in (-1, 1)]
    assert least_friction(hard_pair) == math.inf


def _least_work(twist, points, normals, mu):
    """Least work, per unit wrench, of ``twist = (omega, v)`` on hard-finger wrenches.

    The wrenches are a 64-edge inscribed pyramid per contact, about the origin:
    a twist refuting the circular cone (or any circumscribed pyramid) does no
    negative work on them.
    """
    d = points.shape[1]
    contacts = [point_contact(p, n, "hard", m)
                for p, n, m in zip(points, normals, mu, strict=True)]
    W = generating_wrenches(contacts, Cone(64), reference=np.zeros(d), length_scale=1.0).wrenches
    omega, v = (twist[:1], twist[1:]) if d == 2 else (twist[:3], twist[3:])
    work = W[:d].T @ v + (W[d:].T @ omega)
    return float(np.min(work / np.linalg.norm(W, axis=0))) / np.abs(twist).max()


def test_batch_matches_single_analysis():
    rng = np.random.default_rng(9)
    for dim in (2, 3):
        n, k = 30, 3
        P = rng.uniform(-1, 1, (n, k, dim))
        N = -P + rng.normal(0, 0.5, (n, k, dim))
        mu = rng.uniform(0, 0.8, (n, k))
        batch = analyze_batch(P, N, mu=mu, model="hard", explain=True)
        for g in range(n):
            single = analyze([point_contact(P[g, i], N[g, i], "hard", mu[g, i])
                              for i in range(k)])
            assert batch.verdict[g] == single.verdict.value
            assert batch.rank[g] == single.rank
            assert batch.force_direction_closure[g] == single.force_direction_closure
            assert batch.torque_closure[g] == single.torque_closure
            if single.twist is not None:
                # a twist is a certificate, not unique: it must be one for this grasp
                assert _least_work(batch.twist[g], P[g], N[g], mu[g]) >= -1e-9
            else:
                assert np.all(np.isnan(batch.twist[g]))
        assert len(set(batch.verdict)) >= 2


def test_vectorised_pairs_shape():
    p = np.zeros((4, 5, 2))
    q = np.ones((4, 5, 2))
    r = two_finger_closure(p, -np.ones(2), q, np.ones(2), 0.1)
    assert r.verdict.shape == (4, 5) and np.all(r.force_closure)


def test_least_friction_of_a_soft_pair_with_a_pyramid_is_that_pyramids():
    """With a fixed pyramid the closed form (exact cones) does not apply: the answer closes
    the grasp with that pyramid, and less does not (an offset at 45 degrees to its edges)."""
    grasp = [point_contact([-1, 0, 0], [-1, 0, 0], "soft"),
             point_contact([1, 0.2, 0.2], [1, 0, 0], "soft")]
    exact = least_friction(grasp)
    square = least_friction(grasp, cone=Cone(4))
    assert square > exact * 1.2  # the 4-edge pyramid is narrowest at 45 degrees
    for use in (exact, square):
        assert least_friction_reference(grasp, cone=Cone(4) if use == square else "exact") \
            == pytest.approx(use, rel=1e-4)
    closes = [analyze([c.with_friction(square * f) for c in grasp], cone=Cone(4)).verdict
              for f in (0.99, 1.01)]
    assert closes == [Verdict.NONE, Verdict.CLOSURE] or closes[0] is not Verdict.CLOSURE


def test_pair_codes_read_friction_per_pair_on_every_path():
    from forceclosure.analysis.two_finger import pair_codes

    P = np.array([[[-1, 0, 0], [1, 0.2, 0]]] * 2, dtype=float)
    N = np.array([[[-1, 0, 0], [1, 0, 0]]] * 2, dtype=float)
    mu = [0.05, 0.5]  # one per pair: the first too little for the 0.1 offset
    assert pair_codes(P, N, mu).tolist() == [0, 2]
    assert pair_codes(P, N, mu, torsion=0.01).tolist() == [0, 2]
