"""Labelling sampled parallel-jaw poses: forceclosure against the Dex-Net/graspnetAPI pipeline.

Both start from the same jaw poses (antipodal samples on pybullet_data's
bunny and duck, opening 1.5, soft pads, mu 0.5) and produce the same labels:
the contact pair by ray casting, the verdict, the least friction and the
Ferrari-Canny epsilon. Timed in one run, on the same poses:

* **ours**: one vectorised ray query (:func:`forceclosure.gripper.jaw.jaw_contacts`)
  and :func:`forceclosure.gripper.labels.label_grasps` (closed-form pair verdicts with
  exact cones, exact least friction, the compiled epsilon);
* **the pipeline**, re-implemented from its published algorithms, grasp by
  grasp as those tools run: the two rays cast for this grasp (trimesh, the same
  accelerator); Dex-Net's force-closure test as a min-norm QP (``cvxopt``) on
  the hard-finger wrenches of 8-edge pyramids (Dex-Net's ``num_cone_faces``),
  closure when the hull comes within 1e-3 of the origin (no rank check: a
  pair of hard fingers in space has rank 5 and is never force-closure, yet
  passes whenever it can balance); GraspNet's least friction as the first of
  six values that passes the two-finger angle test; and the epsilon of the
  soft-finger wrenches (the pyramids and the torque about each normal) as the
  nearest facet of their Qhull hull (GraspIt!'s way, cheaper than Dex-Net's
  QP per facet: a ratio measured against it is a lower bound).

Collision of the hand is left out of both (the pipeline has none of its own).
A second row times both without the epsilon (GraspNet's own labels have
none: the verdict and the least friction).

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
from bench_batch import graspnet_loop, min_norm_qp_closure, qhull_epsilon


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


def pipeline(mesh, centers, closing, width, mu, epsilon=True):
    """The per-grasp pipeline: rays, wrenches, QP verdict, six-value friction, Qhull epsilon
    (GraspNet's labels have no epsilon: ``epsilon=False``)."""
    from forceclosure.gripper.jaw import cast_first

    out = []
    for c, d in zip(centers, closing, strict=True):
        half = (0.5 * width + 1e-3) * d
        tri, _, pts = cast_first(mesh, np.array([c - half, c + half]), np.array([d, -d]))
        if np.any(tri < 0):
            out.append((False, np.inf, 0.0))
            continue
        normals = mesh.face_normals[tri]
        closed = min_norm_qp_closure(soft_wrenches(pts, normals, mu, soft=False))
        star = graspnet_loop(pts[None, 0], normals[None, 0], pts[None, 1], normals[None, 1])[0]
        out.append((closed, star, qhull_epsilon(soft_wrenches(pts, normals, mu))
                    if closed and epsilon else 0.0))
    return out


def main() -> None:
    import pybullet_data

    from forceclosure.gripper.antipodal import sample_antipodal
    from forceclosure.gripper.jaw import jaw_contacts, surface_mesh
    from forceclosure.gripper.labels import label_grasps

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=20_000)
    parser.add_argument("--baseline", type=int, default=1_000,
                        help="poses the per-grasp pipeline labels (its rate is per pose)")
    args = parser.parse_args()
    width, mu = 1.5, 0.5
    label_grasps(np.array([[[-1.0, 0, 0], [1, 0.1, 0]]]), np.array([[[-1.0, 0, 0], [1, 0, 0]]]),
                 mu)  # kernels warm
    print(f"{args.poses:,} poses (the pipeline: the first {args.baseline:,}), soft pads, "
          f"mu {mu}, opening {width}")
    print(f"{'object':16} {'ours (poses/s)':>15} {'pipeline (poses/s)':>19} {'ratio':>7} "
          f"{'closure: ours / QP / angle test':>32}")
    for name in ("bunny.obj", "duck_vhacd.obj"):
        path = os.path.join(pybullet_data.getDataPath(), name)
        poly, mesh = surface_mesh(path)
        s = sample_antipodal(path, mu, args.poses, seed=0, width_max=width)
        widths = np.full(len(s), width)
        t = time.perf_counter()
        points, normals, _, reasons = jaw_contacts(mesh, poly.size, s.center, s.closing_axis,
                                                   widths)
        ok = reasons == None  # noqa: E711
        code, _, _ = label_grasps(points[ok], normals[ok], mu)
        ours = len(s) / (time.perf_counter() - t)
        m = min(args.baseline, len(s))
        t = time.perf_counter()
        theirs = pipeline(mesh, s.center[:m], s.closing_axis[:m], width, mu)
        base = m / (time.perf_counter() - t)
        mine = np.zeros(len(s), dtype=bool)
        mine[np.flatnonzero(ok)] = code == 2
        qp = sum(bool(a[0]) for a in theirs)
        angle = sum(a[1] <= mu for a in theirs)
        shares = f"{mine[:m].mean():.0%} / {qp / m:.0%} / {angle / m:.0%}"
        print(f"{name:16} {ours:15,.0f} {base:19,.0f} {ours / base:6.0f}x {shares:>32}")
        t = time.perf_counter()
        points_, normals_, _, reasons_ = jaw_contacts(mesh, poly.size, s.center, s.closing_axis,
                                                      widths)
        ok_ = reasons_ == None  # noqa: E711
        label_grasps(points_[ok_], normals_[ok_], mu, epsilon=False)
        ours_bare = len(s) / (time.perf_counter() - t)
        t = time.perf_counter()
        pipeline(mesh, s.center[:m], s.closing_axis[:m], width, mu, epsilon=False)
        base_bare = m / (time.perf_counter() - t)
        print(f"{'  no epsilon':16} {ours_bare:15,.0f} {base_bare:19,.0f} "
              f"{ours_bare / base_bare:6.0f}x   (GraspNet's labels: verdict and least friction)")
        closed = np.flatnonzero(mine[:m])[:5]
        t = time.perf_counter()
        for g in closed:  # Dex-Net's own epsilon, on a few closed grasps
            dexnet_epsilon(soft_wrenches(points[g], normals[g], mu))
        each = (time.perf_counter() - t) / max(len(closed), 1)
        dexnet = 1 / (1 / base + qp / m * each)  # its epsilon for the grasps its QP closes
        print(f"{'':16} with Dex-Net's own epsilon (a QP in each facet of the hull, "
              f"{each:.2f} s a closed grasp): {dexnet:,.0f} poses/s, ours {ours / dexnet:,.0f}x")


if __name__ == "__main__":
    main()
