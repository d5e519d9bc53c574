"""Robust labels: grasp-samples per second (ray casting, verdicts, epsilon), kernels warm.

    uv run python benchmarks/bench_robust.py [--grasps 1000] [--samples 100]

Samples antipodal jaw poses on pybullet_data's bunny and duck, then times
:func:`forceclosure.gripper.robust.robust_labels` (soft pads, exact-cone verdicts)
with and without the expected epsilon, and its parts: the one ray query of
all perturbed poses, and the verdicts of all the pairs in one batch call.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np


def main() -> None:
    import pybullet_data

    from forceclosure.analysis.two_finger import pair_codes
    from forceclosure.gripper.jaw import ParallelJaw, jaw_contacts, surface_mesh
    from forceclosure.gripper.labels import grasp_labels
    from forceclosure.gripper.robust import robust_labels
    from forceclosure.objects.io import load_object

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grasps", type=int, default=1000)
    parser.add_argument("--samples", type=int, default=100)
    args = parser.parse_args()
    data = pybullet_data.getDataPath()
    gripper = ParallelJaw(1.5)
    mu = 0.5
    # warm the kernels
    robust_labels("cube", grasp_labels("cube", ParallelJaw(3.0), 0.5, 4, least_friction=False),
                  ParallelJaw(3.0), 0.5, samples=4)
    print(f"{args.grasps} grasps x {args.samples} samples, soft pads, mu {mu}, "
          "pose 1% of the opening, angle 0.05 rad, mu 0.05")
    for name in ("bunny.obj", "duck_vhacd.obj"):
        obj = load_object(os.path.join(data, name))
        labels = grasp_labels(obj, gripper, mu, args.grasps, seed=0, least_friction=False)
        total = len(labels) * args.samples
        poly, mesh = surface_mesh(obj)
        c = np.repeat(labels.center, args.samples, axis=0)
        d = np.repeat(labels.closing_axis, args.samples, axis=0)
        t = time.perf_counter()
        points, normals, _, reasons = jaw_contacts(mesh, poly.size, c, d,
                                                   np.full(len(c), gripper.width_max))
        rays = time.perf_counter() - t
        ok = reasons == None  # noqa: E711
        t = time.perf_counter()
        pair_codes(points[ok], normals[ok], mu, "soft")
        verdicts = time.perf_counter() - t
        t = time.perf_counter()
        r = robust_labels(obj, labels, gripper, mu, samples=args.samples, epsilon=False)
        fc = time.perf_counter() - t
        t = time.perf_counter()
        r = robust_labels(obj, labels, gripper, mu, samples=args.samples)
        full = time.perf_counter() - t
        print(f"{name}: ray query {total / rays:,.0f}/s, verdicts {ok.sum() / verdicts:,.0f}/s; "
              f"P(FC) {total / fc:,.0f} grasp-samples/s ({fc:.2f} s); with expected epsilon "
              f"{total / full:,.0f}/s ({full:.2f} s); mean P(FC) {r.probability.mean():.3f}")


if __name__ == "__main__":
    main()
