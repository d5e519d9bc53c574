"""``grasps --metrics``, ``--task-mass`` and ``--no-epsilon`` against hand computations.

* Grasp-matrix metrics of the cube's pinches: ``G Gᵀ`` written out in the test. A contact
  at ``r = (p - c) / L`` (``c`` the pair's midpoint, ``L`` its half-width, so ``|r| = 1``)
  with forces along an orthonormal triad contributes ``[[I, -[r]×], [[r]×, |r|² I - r rᵀ]]``
  (whatever the tangents), and a soft pad's torsion ``(0, n)`` adds ``n nᵀ`` to the torque
  block; the singular values are the square roots of the eigenvalues.
* The task wrench: the cube (centre of mass at the origin) squeezed across a face pair
  ``±e`` by two soft pads (torsion free, pad radius 0), gravity ``g ⟂ e``. Force balance
  along ``e`` gives equal normal forces ``N``; the other forces and torques give the pads'
  friction ``t₁ + t₂ = -m g`` and ``t₁ - t₂ = D N`` with ``D = 2 d / w`` (``d`` the offset of
  the contacts across ``e``, ``w`` their distance along it). ``|tᵢ| ≤ μ N`` and ``N ≤ F``:
  the weight is held iff ``(4μ² - |D|²) F² - 2 m |g·D| F - m² |g|² ≥ 0`` (for a head-on
  pinch, ``2 μ F ≥ m |g|``). The library's pyramids are bracketed by the cones of friction
  ``μ cos(π/8)`` and ``μ / cos(π/8)``: the test asserts "resists" when the smaller cone
  holds and "fails" when the larger does not, and never a verdict against the exact cone.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from forceclosure.analysis.task import gravity_wrench, resist_wrench, resist_wrench_batch
from forceclosure.app.cli import main
from forceclosure.gripper.jaw import ParallelJaw
from forceclosure.gripper.labels import grasp_labels, label_metrics

COS8 = math.cos(math.pi / 8)


def _cross_matrix(r):
    return np.array([[0, -r[2], r[1]], [r[2], 0, -r[0]], [-r[1], r[0], 0]])


def _hand_singular_values(p, n, soft):
    """Singular values of a pair's grasp matrix from ``G Gᵀ`` summed by hand."""
    c = p.mean(axis=0)
    L = np.linalg.norm(p[0] - c)
    GGt = np.zeros((6, 6))
    for pi, ni in zip(p, n, strict=True):
        r = (pi - c) / L
        R = _cross_matrix(r)
        GGt[:3, :3] += np.eye(3)
        GGt[:3, 3:] += -R
        GGt[3:, :3] += R
        GGt[3:, 3:] += np.dot(r, r) * np.eye(3) - np.outer(r, r)
        if soft:
            u = ni / np.linalg.norm(ni)
            GGt[3:, 3:] += np.outer(u, u)
    return np.sqrt(np.clip(np.linalg.eigvalsh(GGt), 0, None))


def test_cube_pinch_metrics_by_hand(tmp_path):
    out = tmp_path / "cube.npz"
    assert main(["grasps", "cube", "--width", "3", "--count", "30", "--mu", "0.4",
                 "--no-least-friction", "--no-collision", "--metrics", "--out", str(out)]) == 0
    z = np.load(out)
    for g in range(30):
        sv = _hand_singular_values(z["points"][g], z["normals"][g], soft=True)
        assert z["sigma_min"][g] == pytest.approx(sv.min(), rel=1e-9)
        assert z["sigma_max"][g] == pytest.approx(sv.max(), rel=1e-9)
        assert z["isotropy"][g] == pytest.approx(sv.min() / sv.max(), rel=1e-9)
        assert z["volume"][g] > 0  # soft pads: rank 6, a solid hull
    # hard contacts: rank 5 by hand (nothing about the line), so sigma_min 0 and no volume
    hard = grasp_labels("cube", ParallelJaw(3.0), 0.4, 10, contact="hard", collision=False,
                        least_friction=False)
    m = label_metrics(hard)
    for g in range(10):
        sv = _hand_singular_values(hard.points[g], hard.normals[g], soft=False)
        assert sv.min() < 1e-7 and m.sigma_min[g] == pytest.approx(0, abs=1e-7)
        assert m.sigma_max[g] == pytest.approx(sv.max(), rel=1e-9)
    assert np.all(m.volume == 0)


def _holds(p, n, mass, g, mu, f_max):
    """Whether the pinch holds the weight with circular cones of friction ``mu`` (module
    docstring), or None when the pads are not on opposite faces or gravity is not
    perpendicular to their normals."""
    e = n[0] / np.linalg.norm(n[0])
    if np.dot(e, n[1] / np.linalg.norm(n[1])) > -1 + 1e-12 \
            or abs(np.dot(e, g)) > 1e-9 * np.linalg.norm(g):
        return None
    u = p[1] - p[0]
    w = abs(np.dot(u, e))
    D = 2 * (u - np.dot(u, e) * e) / w
    W = mass * np.asarray(g)
    return (4 * mu**2 - D @ D) * f_max**2 - 2 * abs(W @ D) * f_max - W @ W >= 0


@pytest.mark.parametrize("mass", [1.0, 2.5])
def test_cube_task_against_the_friction_bound(tmp_path, mass):
    mu, f_max, g = 0.3, 70.0, np.array([0, 0, -9.81])
    out = tmp_path / "cube.npz"
    assert main(["grasps", "cube", "--width", "3", "--count", "150", "--mu", str(mu),
                 "--pad-radius", "0",  # the closed form's pads: torsion unbounded
                 "--tilt", "0.5",  # lines across half the friction cone: both outcomes occur
                 "--no-least-friction", "--no-collision", "--no-epsilon",
                 "--task-mass", str(mass), "--out", str(out)]) == 0  # default --f-max 70
    z = np.load(out)
    verdict, spare = z["task_verdict"], z["task_spare"]
    assert verdict.dtype == np.int8 and spare.shape == (150,)
    assert np.all(spare <= z["task_spare_upper"] + 1e-9)
    seen = {"resists": 0, "fails": 0}
    for i in range(150):
        p, n = z["points"][i], z["normals"][i]
        exact = _holds(p, n, mass, g, mu, f_max)
        if exact is None:  # across z (the pad below carries the weight), or near an edge
            continue
        assert verdict[i] == (2 if exact else 0) or verdict[i] == 1
        if _holds(p, n, mass, g, mu * COS8, f_max):
            assert verdict[i] == 2 and spare[i] >= 1
            seen["resists"] += 1
        if not _holds(p, n, mass, g, mu / COS8, f_max):
            assert verdict[i] == 0 and spare[i] < 1
            seen["fails"] += 1
    assert seen["resists"] >= 5 and seen["fails"] >= 5  # both sides are exercised
    # head-on: 2 mu F >= m g decides it (a mass well above and well below)
    P = np.array([[-1.0, 0.1, 0.2], [1.0, 0.1, 0.2]])
    N = np.array([[-1.0, 0, 0], [1.0, 0, 0]])
    assert _holds(P, N, 2 * mu * f_max / 9.81 * 0.9, g, mu * COS8, f_max)
    assert not _holds(P, N, 2 * mu * f_max / 9.81 * 1.1, g, mu, f_max)


def test_task_summary_and_center_of_mass(tmp_path, capsys):
    # a 2 x 1 x 1 box off the origin, as another tool writes it: the weight acts at its centre
    import trimesh

    box = trimesh.creation.box(extents=[2, 1, 1])
    box.apply_translation([5, -1, 3])
    path = tmp_path / "box.stl"
    box.export(path)
    assert main(["grasps", str(path), "--width", "3", "--count", "20", "--mu", "0.5",
                 "--no-least-friction", "--no-collision", "--no-epsilon", "--task-mass", "2",
                 "--gravity=0,-10,0", "--f-max", "50", "--json"]) == 0
    import json

    s = json.loads(capsys.readouterr().out)
    assert s["task"]["center_of_mass"] == pytest.approx([5, -1, 3])
    assert s["task"]["mass"] == 2 and s["task"]["gravity"] == [0, -10, 0]
    assert s["task"]["f_max"] == 50
    assert s["task"]["resists"] + s["task"]["undecided"] + s["task"]["fails"] == 20
    assert s["epsilon_median"] is None and "metrics" not in s


def test_no_epsilon_keeps_the_verdicts(tmp_path, capsys):
    a, b = tmp_path / "a.npz", tmp_path / "b.npz"
    common = ["grasps", "cube", "--width", "3", "--count", "40", "--mu", "0.3", "--seed", "4",
              "--no-collision"]
    assert main([*common, "--out", str(a)]) == 0
    assert main([*common, "--no-epsilon", "--out", str(b)]) == 0
    za, zb = np.load(a), np.load(b)
    assert np.array_equal(za["code"], zb["code"]) and np.any(za["code"] == 2)
    assert np.array_equal(za["least_friction"], zb["least_friction"])
    closed = za["epsilon"][za["code"] == 2]  # 0 where only the exact cones close
    assert np.all(closed >= 0) and np.any(closed > 0) and np.all(np.isnan(zb["epsilon"]))
    for name in ("sigma_min", "task_verdict"):  # optional arrays: absent when not asked
        assert name not in za.files
    capsys.readouterr()
    assert main([*common, "--no-epsilon", "--json"]) == 0
    assert '"epsilon_median": null' in capsys.readouterr().out


@pytest.mark.parametrize("extra, message", [
    (["--task-mass", "-1"], "--task-mass"),
    (["--task-mass", "0"], "--task-mass"),
    (["--task-mass", "nan"], "--task-mass"),
    (["--task-mass", "1", "--gravity", "1,2"], "--gravity"),
    (["--task-mass", "1", "--gravity", "a,b,c"], "--gravity"),
    (["--task-mass", "1", "--gravity", "0,inf,0"], "--gravity"),
    (["--task-mass", "1", "--gravity", "0,0,0"], "--gravity"),
    (["--task-mass", "1", "--f-max", "0"], "--f-max"),
    (["--task-mass", "1", "--f-max", "-3"], "--f-max"),
    (["--gravity", "0,0,-9.81"], "needs --task-mass"),
    (["--f-max", "10"], "needs --task-mass"),
    (["--no-epsilon", "--graspnet-score", "epsilon"], "--no-epsilon"),
])
def test_refusals(capsys, extra, message):
    assert main(["grasps", "cube", "--width", "3", "--count", "5", *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err


def test_task_refused_on_an_open_mesh(tmp_path, capsys):
    import trimesh

    box = trimesh.creation.box(extents=[1, 1, 1])
    box.update_faces(np.arange(len(box.faces)) != 0)  # one triangle gone: open
    path = tmp_path / "open.stl"
    box.export(path)
    assert main(["grasps", str(path), "--allow-open", "--width", "2", "--count", "5",
                 "--task-mass", "1"]) == 2
    errors = [line for line in capsys.readouterr().err.splitlines() if "error" in line]
    assert len(errors) == 1 and "closed mesh" in errors[0]  # (after the mesh's warnings)


@pytest.mark.parametrize("model, torsion", [("soft", None), ("soft", 0.05), ("hard", None)])
def test_stacked_lps_answer_as_one_at_a_time(model, torsion):
    # the batch stacks grasps' LPs into one; each must come out as resist_wrench's own LP
    rng = np.random.default_rng(7)
    P, N = rng.normal(size=(40, 3, 3)), rng.normal(size=(40, 3, 3))
    w = gravity_wrench(0.3, [0.1, 0.2, -0.1])
    names, seen = {0: "fails", 1: "undecided", 2: "resists"}, set()
    for f_max in (2.0, 50.0):
        code, spare, upper = resist_wrench_batch(P, N, w, mu=0.5, model=model,
                                                 torsion=torsion, f_max=f_max)
        for g in range(40):
            t = resist_wrench(P[g], N[g], w, mu=0.5, model=model, torsion=torsion,
                              f_max=f_max)
            assert spare[g] == pytest.approx(t.spare, rel=1e-7, abs=1e-9)
            assert upper[g] == pytest.approx(t.spare_upper, rel=1e-7, abs=1e-9)
            assert names[int(code[g])] == t.verdict
        seen |= set(code.tolist())
    assert seen >= {0, 2}


def test_unbounded_blocks_fall_back_to_single_lps():
    # a pure torque about the soft pads' common normal: any multiple is resisted (inf)
    P = np.array([[[-1.0, 0, 0], [1, 0, 0]]] * 3)
    code, spare, upper = resist_wrench_batch(P, P.copy(), [0, 0, 0, 1, 0, 0], mu=0.5)
    assert code.tolist() == [2, 2, 2] and np.all(np.isinf(spare)) and np.all(np.isinf(upper))
