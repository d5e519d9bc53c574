"""Grasp-matrix metrics against hand computations and independent formulas.

* Two contacts pinching the unit cube: the grasp matrix written out by hand.
* Any hard contacts, torques about their centroid ``c`` per length ``L``:
  ``G Gᵀ = [[k I, 0], [0, J / L²]]`` with ``J = Σ (|r|² I - r rᵀ)``, ``r = p - c``
  (the off-diagonal block is ``[Σ r]× / L = 0``), so the singular values are
  ``√k`` and the square roots of the eigenvalues of ``J / L²`` — the inertia
  tensor of unit masses at the contacts.
* Hull volumes of simplices: ``|det(w_i - w_0)| / D!`` (a tetrahedron for a
  planar pair with friction, a 6-simplex for seven frictionless contacts).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from forceclosure.analysis.metrics import grasp_matrix, grasp_metrics
from forceclosure.errors import InputError

PAIR_P = np.array([[[-0.5, 0, 0], [0.5, 0, 0]]])
PAIR_N = np.array([[[-1.0, 0, 0], [1, 0, 0]]])


def test_cube_pinch_by_hand():
    # r = -+(1, 0, 0) after dividing by L = 0.5. Hard: columns (e, r x e) for the three
    # axes at each contact: G G^T = diag(2, 2, 2, 0, 2, 2) (torque about x from nothing;
    # about y, z: (+-1)^2 from each contact); so sigma = sqrt(2) five times and 0
    hard = grasp_metrics(PAIR_P, PAIR_N, mu=0.5, model="hard")
    G = grasp_matrix(PAIR_P, PAIR_N, "hard")[0]
    assert np.allclose(G @ G.T, np.diag([2, 2, 2, 0, 2, 2]))
    assert hard.sigma_min[0] == pytest.approx(0.0, abs=1e-12)
    assert hard.sigma_max[0] == pytest.approx(math.sqrt(2))
    assert hard.isotropy[0] == pytest.approx(0.0, abs=1e-12)
    assert hard.volume[0] == 0.0  # rank 5: the hull is flat
    assert hard.reference[0].tolist() == [0, 0, 0] and hard.length_scale[0] == 0.5
    # soft: the torsions (0, -+e_x) add 1 + 1 to the torque about x: G G^T = 2 I
    soft = grasp_metrics(PAIR_P, PAIR_N, mu=0.5, model="soft")
    assert soft.sigma_min[0] == pytest.approx(math.sqrt(2))
    assert soft.isotropy[0] == pytest.approx(1.0)
    assert soft.volume[0] > 0
    # frictionless: one column each, (e_x, 0) and (-e_x, 0): G G^T = diag(2, 0, 0, 0, 0, 0)
    fl = grasp_metrics(PAIR_P, PAIR_N, model="frictionless")
    assert fl.sigma_max[0] == pytest.approx(math.sqrt(2)) and fl.sigma_min[0] == 0.0


def test_hard_contacts_singular_values_are_the_inertia_formula():
    rng = np.random.default_rng(3)
    for k in (3, 4, 6):
        P = rng.normal(size=(5, k, 3)) * 2 + 1
        N = rng.normal(size=(5, k, 3))
        m = grasp_metrics(P, N, model="hard")
        for g in range(5):
            r = P[g] - P[g].mean(axis=0)
            L = np.max(np.linalg.norm(r, axis=1))
            J = sum(np.dot(v, v) * np.eye(3) - np.outer(v, v) for v in r) / L**2
            sv = np.sqrt(np.concatenate([[k] * 3, np.linalg.eigvalsh(J)]))
            assert m.sigma_min[g] == pytest.approx(sv.min(), rel=1e-9)
            assert m.sigma_max[g] == pytest.approx(sv.max(), rel=1e-9)
            assert m.isotropy[g] == pytest.approx(sv.min() / sv.max(), rel=1e-9)
            assert m.length_scale[g] == pytest.approx(L)


def test_metrics_do_not_depend_on_the_frame():
    rng = np.random.default_rng(5)
    P = rng.normal(size=(4, 3, 3))
    N = rng.normal(size=(4, 3, 3))
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    a = grasp_metrics(P, N, mu=0.4, model="soft")
    b = grasp_metrics(3.0 * P @ Q.T + [1, -2, 5], N @ Q.T, mu=0.4, model="soft")
    for name in ("sigma_min", "sigma_max", "isotropy"):
        assert np.allclose(getattr(a, name), getattr(b, name), rtol=1e-9)
    # the volume too, up to the pyramids' orientation about each normal (not rotated along)
    c = grasp_metrics(3.0 * P + [1, -2, 5], N, mu=0.4, model="soft")
    assert np.allclose(a.volume, c.volume, rtol=1e-9)


def test_planar_pair_volume_is_a_tetrahedron_by_hand():
    # fingers at (-+1, 0), normals -+x, mu 0.5, L = 1: wrenches (fx, fy, x fy - y fx)
    # (1, .5, -.5), (1, -.5, .5), (-1, .5, .5), (-1, -.5, -.5); edges from the first:
    # (0, -1, 1), (-2, 0, 1), (-2, -1, 0), determinant 4: volume 4 / 6
    m = grasp_metrics([[[-1, 0], [1, 0]]], [[[-1.0, 0], [1, 0]]], mu=0.5, model="hard")
    assert m.volume[0] == pytest.approx(2 / 3, rel=1e-12)
    # planar hard pair, G: columns (t, r x t), (-n, r x -n) per finger; G G^T = diag(2, 2, 2)
    assert m.sigma_min[0] == pytest.approx(math.sqrt(2)) and m.isotropy[0] == pytest.approx(1)


def test_seven_frictionless_contacts_volume_is_a_six_simplex():
    rng = np.random.default_rng(11)
    P = rng.uniform(-1, 1, size=(3, 7, 3))
    N = rng.normal(size=(3, 7, 3))
    N /= np.linalg.norm(N, axis=2, keepdims=True)
    m = grasp_metrics(P, N, model="frictionless")
    for g in range(3):
        c = P[g].mean(axis=0)
        L = np.max(np.linalg.norm(P[g] - c, axis=1))
        W = np.array([np.concatenate([-n, np.cross(p - c, -n) / L])
                      for p, n in zip(P[g], N[g], strict=True)])
        truth = abs(np.linalg.det(W[1:] - W[0])) / math.factorial(6)
        assert truth > 0
        assert m.volume[g] == pytest.approx(truth, rel=1e-9)
        # frictionless G is W transposed: 6 x 7, singular values of W
        sv = np.linalg.svd(W, compute_uv=False)
        assert m.sigma_min[g] == pytest.approx(sv.min(), rel=1e-9)


def test_bad_input_is_refused():
    with pytest.raises(InputError):
        grasp_metrics([[[0, 0, 0]]], [[[0, 0, 0]]])
    with pytest.raises(InputError):
        grasp_metrics(PAIR_P, PAIR_N, model="sticky")
