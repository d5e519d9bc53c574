"""Epsilon of duck grasps, and of the same grasps turned and moved: does the value change?

    uv run python benchmarks/bench_epsilon_frame.py [--grasps 60] [--pad-radius 0 0.01]

Samples parallel-jaw poses on pybullet_data's duck_vhacd.urdf (a Panda-sized
opening, 0.08, friction 0.5, soft pads, as issue 24 did), keeps the first
``--grasps`` closed ones, turns and moves each by its own random rigid motion,
and prints epsilon turned / epsilon as sampled for the pyramids oriented by the
coordinate axes (the earlier default) and by the grasp (the default now), and
the CPU time of each over the closed grasps (kernels warm).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from _tables import parse, table


def main() -> None:
    import pybullet_data

    from forceclosure.objects.io import load_object

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grasps", type=int, default=60)
    parser.add_argument("--pad-radius", type=float, nargs="+", default=[0.0])
    parser.add_argument("--seed", type=int, default=0)
    args = parse(parser)
    duck = load_object(os.path.join(pybullet_data.getDataPath(), "duck_vhacd.urdf"))
    rows = []
    for radius in args.pad_radius:
        rows += turned(duck, radius, args)
    table("epsilon_frame", ["pyramids oriented by", "pad radius", "ratio", "off by > 5 %",
                            "0 in one pose only", "largest change", "CPU a grasp"], rows)


def turned(duck, radius: float, args) -> list:
    """The table's rows for one pad radius: epsilon turned / as sampled, both orientations."""
    from scipy.spatial.transform import Rotation

    from forceclosure.analysis.batch import epsilon_batch
    from forceclosure.gripper.jaw import ParallelJaw
    from forceclosure.gripper.labels import grasp_labels

    jaw = ParallelJaw(0.08, pad_radius=radius)
    mu = 0.5
    labels = grasp_labels(duck, jaw, mu, 10 * args.grasps, seed=args.seed,
                          least_friction=False, collision=False, epsilon=False)
    closed = np.flatnonzero(labels.code == 2)[:args.grasps]
    P, N = labels.points[closed], labels.normals[closed]
    R = Rotation.random(len(P), random_state=args.seed + 1).as_matrix()
    shift = np.random.default_rng(args.seed + 2).normal(0, 0.5, (len(P), 1, 3))
    turned = (np.einsum("gij,gkj->gki", R, P) + shift, np.einsum("gij,gkj->gki", R, N))
    torsion = jaw.torsion(mu)
    print(f"duck_vhacd.urdf: {len(P)} closed grasps (width 0.08, mu {mu}, soft pads, "
          f"pad radius {jaw.pad_radius}), each turned and moved at random")
    rows = []
    for orientation in ("axes", "grasp"):
        def eps(points, normals, orientation=orientation):
            return epsilon_batch(points, normals, mu=mu, model="soft", torsion=torsion,
                                 orientation=orientation)

        eps(P[:2], N[:2])  # warm
        start = time.process_time()
        a = eps(P, N)
        cpu = time.process_time() - start
        b = eps(*turned)
        both = (a > 0) & (b > 0)
        ratio = b[both] / a[both]
        print(f"  pyramids oriented by the {orientation:5s}: turned / sampled "
              f"{ratio.min():.4f} .. {ratio.max():.4f}, "
              f"{int(np.sum(np.abs(ratio - 1) > 0.05))} of {int(both.sum())} change by > 5 %, "
              f"largest change {np.max(np.abs(ratio - 1)):.1e}; 0 in one only: "
              f"{int(np.sum((a > 0) != (b > 0)))}; {1e6 * cpu / len(P):.0f} us CPU a grasp")
        rows.append([{"axes": "coordinate axes (before)", "grasp": "the grasp (now)"}[orientation],
                     f"{radius:g}", f"{ratio.min():.4f}–{ratio.max():.4f}",
                     f"{int(np.sum(np.abs(ratio - 1) > 0.05))} of {int(both.sum())}",
                     f"{int(np.sum((a > 0) != (b > 0)))}",
                     f"{np.max(np.abs(ratio - 1)):.1e}", f"{1e3 * cpu / len(P):.2f} ms"])
    return rows


if __name__ == "__main__":
    main()
