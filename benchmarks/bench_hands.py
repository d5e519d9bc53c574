"""Poses a real hand can take: closure-and-clear counts before and after issue 24.

For each object (pybullet_data's duck, teddy, mug and ``random_urdfs/000`` …
``019``), ``--count`` poses are labelled two ways in one process:

* **before**: what ``forceclosure grasps OBJ --width 0.08 --mu 0.5`` did
  until issue 24: the ray-contact antipodal sampler
  (:func:`forceclosure.gripper.antipodal.sample_antipodal`, lines inside the
  friction cone), the paper's soft pads (unbounded torsion), and the
  generic 0.08 box hand tried at 8 approach axes
  (:func:`forceclosure.gripper.collision.choose_approach`);
* **now**: ``forceclosure grasps OBJ --gripper panda --mu 0.5`` with its
  defaults (:func:`forceclosure.gripper.labels.grasp_labels`: lines along
  the normals, pads that touch where they meet the object and press 1 mm,
  12 approach axes × 3 depths searched, pad-bounded torsion).

It prints, per object, the poses returned, the clear ones and those both
closed and clear, with the CPU seconds of each; the totals; and the ratio of
closure-and-clear counts. Run it with::

    uv run python benchmarks/bench_hands.py --count 2000
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import pybullet_data
from _tables import parse, table

from forceclosure.analysis.two_finger import pair_codes
from forceclosure.gripper.antipodal import sample_antipodal
from forceclosure.gripper.collision import choose_approach
from forceclosure.gripper.grippers import gripper_named
from forceclosure.gripper.jaw import ParallelJaw
from forceclosure.gripper.labels import grasp_labels
from forceclosure.objects.io import load_object

D = pybullet_data.getDataPath()
OBJECTS = ["duck_vhacd.urdf", "teddy_vhacd.urdf", os.path.join("objects", "mug.urdf")] + [
    os.path.join("random_urdfs", f"{k:03d}", f"{k:03d}.urdf") for k in range(20)]


def before(obj, count: int, mu: float) -> tuple[int, int, int]:
    hand = ParallelJaw(0.08, pad_radius=0)
    s = sample_antipodal(obj, mu, count, seed=0, width_max=hand.width_max)
    code = pair_codes(s.points, s.normals, mu, "soft", None)
    _, hit = choose_approach(obj, s, hand, approaches=8)
    return len(s), int(np.sum(~hit)), int(np.sum(~hit & (code == 2)))


def now(obj, count: int, mu: float) -> tuple[int, int, int]:
    labels = grasp_labels(obj, gripper_named("panda"), mu, count, seed=0,
                          least_friction=False, epsilon=False)
    clear = ~labels.collides
    return len(labels), int(clear.sum()), int(np.sum(clear & (labels.code == 2)))


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--count", type=int, default=2000)
    p.add_argument("--mu", type=float, default=0.5)
    p.add_argument("--objects", type=int, default=len(OBJECTS), help="the first K objects")
    args = parse(p)
    print(f"load {os.getloadavg()[0]:.2f}; {args.count} poses an object, mu {args.mu}")
    print(f"{'object':32} {'before: poses clear closed&clear  cpu':>40} "
          f"{'now: poses clear closed&clear  cpu':>38}")
    totals = np.zeros((2, 3), dtype=np.int64)
    cpu = np.zeros(2)
    rows = []
    for name in OBJECTS[:args.objects]:
        obj = load_object(os.path.join(D, name), allow_open=True)
        row, cells = [], []
        for k, run in enumerate((before, now)):
            start = time.process_time()
            counts = run(obj, args.count, args.mu)
            seconds = time.process_time() - start
            totals[k] += counts
            cpu[k] += seconds
            row.append(f"{counts[0]:6d} {counts[1]:6d} {counts[2]:8d} {seconds:6.1f}s")
            cells += [f"{counts[1]:,}", f"{counts[2]:,}", f"{seconds:.1f} s"]
        print(f"{name:32} {row[0]:>40} {row[1]:>38}")
        rows.append([f"`{name}`", *cells])
    print(f"{'total':32} {totals[0][0]:6d} {totals[0][1]:6d} {totals[0][2]:8d} {cpu[0]:6.1f}s"
          f"   {totals[1][0]:6d} {totals[1][1]:6d} {totals[1][2]:8d} {cpu[1]:6.1f}s")
    rows.append(["**total**", *(f"{c:,}" for c in totals[0][1:]), f"{cpu[0]:.1f} s",
                 *(f"{c:,}" for c in totals[1][1:]), f"{cpu[1]:.1f} s"])
    table("hands", ["object", "before: clear", "before: closure and clear", "before: CPU",
                    "now: clear", "now: closure and clear", "now: CPU"], rows)
    ratio = totals[1][2] / max(1, totals[0][2])
    print(f"closure and clear: {ratio:.1f} x before; clear share now "
          f"{totals[1][1] / max(1, totals[1][0]):.2f}; load {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
