"""Labelling sampled parallel-jaw poses: forceclosure against GraspNet's and Dex-Net's labellers.

All rows start from the same antipodal jaw poses (sampled once, on pybullet_data's bunny
and duck, opening 1.5, soft pads, mu 0.5) and are timed in one process. CPU time
(``time.process_time``, all threads) is the measure, wall time and the load average are
printed beside it; ratios are of CPU time, which survives a loaded machine.

* **ours**: :func:`forceclosure.gripper.labels.label_grasps` (one compiled pass: verdict
  with exact cones and the exact least friction μ*), and for the end-to-end rows one
  vectorised ray query (:func:`forceclosure.gripper.jaw.jaw_contacts`) before it.
* **GraspNet**, as GraspNet-1Billion labels a grasp: the antipodal angle test (graspnetAPI's
  ``force_closure``: each contact's inward normal within ``atan(mu)`` of the line to the
  other contact) at its ten friction values 0.1, 0.2, ..., 1.0, the label the least value
  that passes. Written here in its strongest fair form: vectorised NumPy over all poses,
  no inverse cosine (the worse contact's cosine against the ten thresholds' cosines, one
  ``searchsorted``). End to end it gets the same vectorised ray query as ours. Its test is
  only sufficient in space (it misses pairs closed by the pads' torques) and passes lines
  on the cone's edge.
* **Dex-Net**, as Dex-Net labels a grasp: one grasp at a time in Python, its contacts by
  casting the two jaws' rays for that grasp (Dex-Net's ``close_fingers``, with trimesh's
  accelerator instead of its SDF line search: faster), its ``force_closure`` (the same
  angle test, at mu), and with ε its ``ferrari_canny_L1`` (the Qhull hull of the soft
  wrenches, then a min-norm QP in every facet; ``cvxopt``), timed on a few closed grasps
  and charged to the share its test closes.

Rows: labels of given contact pairs (verdict and μ*); end to end on the same poses (ray
casting and labels); end to end with ε. Collision of the hand is left out of every row.

    uv run --extra bench python benchmarks/bench_gripper.py [--poses 20000] [--baseline 1000]
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
from bench_batch import dexnet_pair

#: GraspNet-1Billion's friction values: the label is the least that passes.
GRASPNET_MU = np.round(np.arange(1, 11) * 0.1, 1)
#: ``-cos(atan(mu))`` of those values (ascending): an angle is within ``atan(mu)`` iff its
#: cosine is at least ``cos(atan(mu)) = 1 / sqrt(1 + mu**2)``.
_NEG_COS = -1.0 / np.sqrt(1.0 + GRASPNET_MU**2)
_LABELS = np.append(GRASPNET_MU, np.inf)


def graspnet_labels(P, N):
    """GraspNet's labels of ``(n, 2, 3)`` contact pairs, vectorised: the least of
    :data:`GRASPNET_MU` at which graspnetAPI's ``force_closure`` passes (each contact's
    inward normal within ``atan(mu)`` of the line to the other contact, both on the right
    side), ``inf`` where none does. Its strongest form found: no inverse cosine (the worse
    contact's cosine, compared with the ten thresholds' cosines by one ``searchsorted``);
    the same labels as its arccos test, which this ran before (2.5-2.8x slower)."""
    d = P[:, 1] - P[:, 0]
    n_1, n_2 = N[:, 0], N[:, 1]
    proj_1 = -np.einsum("ij,ij->i", n_1, d) / np.sqrt(np.einsum("ij,ij->i", n_1, n_1))
    proj_2 = np.einsum("ij,ij->i", n_2, d) / np.sqrt(np.einsum("ij,ij->i", n_2, n_2))
    with np.errstate(invalid="ignore", divide="ignore"):  # coincident points: NaN, no label
        cos = np.minimum(proj_1, proj_2) / np.sqrt(np.einsum("ij,ij->i", d, d))
    return _LABELS[np.searchsorted(_NEG_COS, -cos)]


def soft_wrenches(P, N, mu, edges=8, soft=True):
    """Wrenches of one pair, about its midpoint per its half-width: an inscribed pyramid per
    contact, plus (``soft``) the two-sided torque about each normal."""
    ref = P.mean(axis=0)
    scale = max(np.linalg.norm(P - ref, axis=1).max(), 1e-12)
    angles = 2 * np.pi * np.arange(edges) / edges
    cols = []
    for p, n in zip(P, N, strict=True):
        helper = np.eye(3)[np.argmin(np.abs(n))]
        t1 = np.cross(n, helper)
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        forces = -n + mu * (np.cos(angles)[:, None] * t1 + np.sin(angles)[:, None] * t2)
        cols.append(np.hstack([forces, np.cross(p - ref, forces) / scale]))
        if soft:
            cols.append(np.array([[0, 0, 0, *n], [0, 0, 0, *(-n)]]))
    return np.vstack(cols).T


def min_norm_in_facet(V):
    """The nearest point to the origin of the simplex with vertices ``V`` (columns), by a
    cvxopt QP: Dex-Net's ``min_norm_vector_in_facet``."""
    import cvxopt

    cvxopt.solvers.options["show_progress"] = False
    m = V.shape[1]
    x = cvxopt.solvers.qp(cvxopt.matrix(V.T @ V + 1e-10 * np.eye(m)), cvxopt.matrix(np.zeros(m)),
                          cvxopt.matrix(-np.eye(m)), cvxopt.matrix(np.zeros(m)),
                          cvxopt.matrix(np.ones((1, m))), cvxopt.matrix(np.ones(1)))["x"]
    x = np.array(x).ravel()
    return float(np.linalg.norm(V @ x))


def dexnet_epsilon(W):
    """Dex-Net's ``ferrari_canny_L1``: the Qhull hull, then a min-norm QP in every facet."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = ConvexHull(W.T)
    except QhullError:
        return 0.0
    return min(min_norm_in_facet(W[:, f]) for f in hull.simplices)


def dexnet(mesh, centers, closing, width, mu):
    """Dex-Net's loop: per grasp, two rays and its ``force_closure`` at ``mu``; the contacts
    and verdicts."""
    from forceclosure.gripper.jaw import cast_first

    out = []
    for c, d in zip(centers, closing, strict=True):
        half = (0.5 * width + 1e-3) * d
        tri, _, pts = cast_first(mesh, np.array([c - half, c + half]), np.array([d, -d]))
        if np.any(tri < 0):
            out.append((None, None, False))
            continue
        normals = mesh.face_normals[tri]
        out.append((pts, normals, dexnet_pair(pts[0], normals[0], pts[1], normals[1], mu)))
    return out


def timed(fn, repeats=1):
    """``(result, cpu, wall)`` of ``fn()``: the least CPU time of ``repeats`` runs."""
    best = None
    for _ in range(repeats):
        c, w = time.process_time(), time.perf_counter()
        result = fn()
        cpu, wall = time.process_time() - c, time.perf_counter() - w
        if best is None or cpu < best[1]:
            best = (result, cpu, wall)
    return best


def row(what, n_ours, ours, n_theirs, theirs, baseline):
    """One table row: rates per CPU-second and per wall-second, the CPU ratio, the load."""
    r_ours, r_theirs = n_ours / ours[1], n_theirs / theirs[1]
    print(f"  {what:34} {r_ours:12,.0f} {n_ours / ours[2]:12,.0f} | {baseline:10} "
          f"{r_theirs:12,.0f} {n_theirs / theirs[2]:12,.0f} | {r_ours / r_theirs:7.1f}x "
          f"| {os.getloadavg()[0]:5.2f}")


def bench_object(name: str, args: argparse.Namespace, width: float, mu: float) -> None:
    """The rows of one pybullet_data object."""
    import pybullet_data

    from forceclosure.gripper.antipodal import sample_antipodal
    from forceclosure.gripper.jaw import jaw_contacts, surface_mesh
    from forceclosure.gripper.labels import label_grasps

    path = os.path.join(pybullet_data.getDataPath(), name)
    poly, mesh = surface_mesh(path)
    s = sample_antipodal(path, mu, args.poses, seed=0, width_max=width)  # shared
    n = len(s)
    widths = np.full(n, width)
    print(f"{name}: {n:,} poses")

    # 1. labels of given contact pairs (the sampler's), verdict and μ*
    P, N = s.points, s.normals
    ours = timed(lambda: label_grasps(P, N, mu, epsilon=False), args.repeats)
    gn = timed(lambda: graspnet_labels(P, N), args.repeats)
    row("contact pairs: verdict, mu*", n, ours, n, gn, "GraspNet")
    m = min(args.baseline, n)
    dx = timed(lambda: [dexnet_pair(P[g, 0], N[g, 0], P[g, 1], N[g, 1], mu)
                        for g in range(m)])
    row("contact pairs: verdict", n, ours, m, dx, "Dex-Net")
    code = ours[0][0]
    gn_least = gn[0]
    print(f"    closure at mu {mu}: ours {np.mean(code == 2):.1%}, GraspNet's test "
          f"{np.mean(gn_least <= mu):.1%} (sufficient only); ours closes every pair "
          f"GraspNet's passes: {bool(np.all(code[gn_least <= mu - 1e-9] == 2))}")

    # 2. end to end on the same poses: ray casting and labels
    def ours_end_to_end(eps=False):
        pts, nrm, _, reasons = jaw_contacts(mesh, poly.size, s.center,
                                            s.closing_axis, widths)
        ok = reasons == None  # noqa: E711
        return ok, label_grasps(pts[ok], nrm[ok], mu, epsilon=eps)

    def graspnet_end_to_end():
        pts, nrm, _, reasons = jaw_contacts(mesh, poly.size, s.center,
                                            s.closing_axis, widths)
        ok = reasons == None  # noqa: E711
        return ok, graspnet_labels(pts[ok], nrm[ok])

    ours = timed(ours_end_to_end, args.repeats)
    gn = timed(graspnet_end_to_end, args.repeats)
    row("rays + verdict, mu*", n, ours, n, gn, "GraspNet")
    dx = timed(lambda: dexnet(mesh, s.center[:m], s.closing_axis[:m], width, mu))
    row("rays + verdict", n, ours, m, dx, "Dex-Net")
    rays = timed(lambda: jaw_contacts(mesh, poly.size, s.center, s.closing_axis,
                                      widths), args.repeats)
    print(f"    the shared ray query alone: {n / rays[1]:,.0f} poses/CPU-s")

    # 3. end to end with ε: ours against Dex-Net's loop with its own ε
    ours_eps = timed(lambda: ours_end_to_end(True))
    closed = [g for g, (pts, nrm, fc) in enumerate(dx[0]) if fc][:5]
    each = timed(lambda: [dexnet_epsilon(soft_wrenches(dx[0][g][0], dx[0][g][1], mu))
                          for g in closed])
    share = np.mean([fc for _, _, fc in dx[0]])
    per_pose_cpu = dx[1] / m + share * each[1] / max(len(closed), 1)
    per_pose_wall = dx[2] / m + share * each[2] / max(len(closed), 1)
    row("rays + verdict, mu*, eps", n, ours_eps, 1, (None, per_pose_cpu, per_pose_wall),
        "Dex-Net")
    print(f"    Dex-Net's ferrari_canny_L1: {each[1] / max(len(closed), 1):.2f} CPU-s a "
          f"closed grasp, {share:.0%} of poses closed by its test")


def main() -> None:
    from forceclosure.gripper.labels import label_grasps

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=20_000)
    parser.add_argument("--baseline", type=int, default=1_000,
                        help="poses Dex-Net's per-grasp loop labels (its rate is per pose)")
    parser.add_argument("--repeats", type=int, default=3,
                        help="runs of each vectorised row (the least CPU time is kept)")
    args = parser.parse_args()
    width, mu = 1.5, 0.5
    warm = (np.array([[[-1.0, 0, 0], [1, 0.1, 0]]] * 20_000),
            np.array([[[-1.0, 0, 0], [1, 0, 0]]] * 20_000))
    label_grasps(*warm, mu, epsilon=False)  # kernels (and the threads) warm
    label_grasps(warm[0][:10], warm[1][:10], mu)
    graspnet_labels(*warm)
    print(f"{args.poses:,} poses (Dex-Net: the first {args.baseline:,}), soft pads, mu {mu}, "
          f"opening {width}; {os.cpu_count()} CPUs")
    print(f"  {'labels':34} {'ours/CPU-s':>12} {'ours/s':>12} | {'baseline':10} "
          f"{'theirs/CPU-s':>12} {'theirs/s':>12} | {'CPU ratio':>8} | load")
    for name in ("bunny.obj", "duck_vhacd.obj"):
        bench_object(name, args, width, mu)


if __name__ == "__main__":
    main()
