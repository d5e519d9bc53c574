"""Robust labels: grasp-samples per CPU-second (pads closed again, verdicts), kernels warm.

    uv run python benchmarks/bench_robust.py [--grasps 300] [--samples 100] [--epsilon]

Labels ``--grasps`` jaw poses of the Panda hand on pybullet_data's duck (the
``forceclosure grasps duck_vhacd.urdf --gripper panda --robust`` path) and of a
generic 1.5-wide hand with 0.3 pads on the bunny, then times
:func:`forceclosure.gripper.robust.robust_labels` (soft pads, exact-cone verdicts,
the probability of closure; ``--epsilon`` adds the expected epsilon) in CPU time
(``time.process_time``, every thread of the process) beside wall time and the load
average, and its stages' CPU time per sample: the candidate triangles of each
sample's closing line (``line_candidates``), the pads' first touch, pressure,
nearest pressed point and torsional lever (``pad_contacts``, one compiled pass; its
kernel-per-step path, where it runs, shows each kernel), and the verdicts
(``pair_codes``). The machine these run on is shared: read the rate with the load
beside it.
"""

from __future__ import annotations

import argparse
import os
import time
from dataclasses import replace

from _tables import parse, table


def _timed(module, name: str, spent: dict[str, float]) -> None:
    """Wrap ``module.name`` to add its CPU time to ``spent[name]``."""
    original = getattr(module, name)

    def wrapper(*args, **kwargs):
        start = time.process_time()
        try:
            return original(*args, **kwargs)
        finally:
            spent[name] = spent.get(name, 0.0) + time.process_time() - start

    setattr(module, name, wrapper)


def main() -> None:
    import pybullet_data

    import forceclosure.analysis.two_finger as two_finger
    import forceclosure.gripper.pads as pads
    from forceclosure.gripper.grippers import gripper_named
    from forceclosure.gripper.jaw import ParallelJaw
    from forceclosure.gripper.labels import grasp_labels
    from forceclosure.gripper.robust import robust_labels
    from forceclosure.objects.io import load_object

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grasps", type=int, default=300)
    parser.add_argument("--samples", type=int, default=100)
    parser.add_argument("--epsilon", action="store_true", help="also the expected epsilon")
    args = parse(parser)
    data = pybullet_data.getDataPath()
    mu = 0.5
    # warm the kernels
    robust_labels("cube", grasp_labels("cube", ParallelJaw(3.0), 0.5, 4, least_friction=False),
                  ParallelJaw(3.0), 0.5, samples=4)
    spent: dict[str, float] = {}
    for name in ("pad_extremes", "pad_pressure", "pad_nearest", "pad_lever",
                 "line_candidates", "pad_contacts"):
        _timed(pads, name, spent)
    _timed(two_finger, "pair_codes", spent)
    print(f"{args.grasps} grasps x {args.samples} samples, soft pads, mu {mu}, pose sigma 1% "
          "of the opening, angle sigma 0.05 rad, mu sigma 0.05")
    bunny_hand = replace(ParallelJaw(1.5), pad_length=0.3, pad_height=0.3)
    rows = []
    for name, hand in (("duck_vhacd.urdf", gripper_named("panda")), ("bunny.obj", bunny_hand)):
        obj = load_object(os.path.join(data, name))
        labels = grasp_labels(obj, hand, mu, args.grasps, seed=0, least_friction=False,
                              epsilon=False)
        total = len(labels) * args.samples
        spent.clear()
        load = os.getloadavg()[0]
        wall, cpu = time.perf_counter(), time.process_time()
        r = robust_labels(obj, labels, hand, mu, samples=args.samples, epsilon=args.epsilon)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        stages = ", ".join(f"{k} {1e6 * v / total:.1f}" for k, v in spent.items())
        print(f"{name} ({hand.name}, {len(labels)} poses): {total / cpu:,.0f} grasp-samples per "
              f"CPU-second ({cpu:.2f} CPU-s, {wall:.2f} s wall, load {load:.2f}); mean P(FC) "
              f"{r.probability.mean():.3f}\n  CPU us per sample: {stages}")
        rows.append([f"{name}, `{hand.name}`", f"{total / cpu / 1e3:,.1f}k",
                     stages])
    table("robust", ["object, hand", "grasp-samples per CPU-second",
                     "CPU µs a sample, by stage"], rows)


if __name__ == "__main__":
    main()
