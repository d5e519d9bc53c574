"""``forceclosure warmup``: compile the batch kernels now rather than on first use."""

from __future__ import annotations

import argparse
import sys
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``warmup`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    w = sub.add_parser("warmup", help="compile the batch kernels now (once per installation; "
                                      "otherwise on first use)")
    w.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    """Compile every batch kernel now, one line each, instead of on first use."""
    import time

    import numpy as np

    from ..analysis.batch import analyze_batch, epsilon_batch, least_friction_batch
    from ..analysis.two_finger import SERIAL_BELOW, two_finger_closure
    from ..gripper.jaw import ParallelJaw
    from ..gripper.labels import grasp_labels

    points = np.array([[[1.0, 0, 0], [-1, 0.5, 0], [-1, -0.5, 0.1]]])  # three hard fingers
    normals = np.array([[[1.0, 0, 0], [-1, 0, 0], [-1, 0, 0]]])
    many = [np.repeat(a, 257, axis=0) for a in (points, normals)]  # more than a block
    steps = [
        ("verdicts, Theorem 1 (one grasp, and batches)", lambda: (
            analyze_batch(points, normals, mu=0.5), analyze_batch(*many, mu=0.5))),
        ("least friction", lambda: least_friction_batch(points, normals)),
        ("Ferrari-Canny epsilon", lambda: epsilon_batch(points, normals, mu=0.5)),
        ("two-finger pairs, Corollary 3", lambda: [  # one pair, and a batch for the threads
            two_finger_closure(np.zeros((k, 3)), [0.0, 0, 1], [0.0, 0, -1], [0.0, 0, -1], 0.5)
            for k in (1, SERIAL_BELOW)]),
        ("parallel-jaw pads and labels", lambda: grasp_labels(
            "cube", ParallelJaw(3.0), 0.5, 4, approaches=1, depths=1)),
    ]
    from .. import kernels
    from ..kernels import compiling_announced

    kernels.COMPILE_AFTER = 0  # compile now, not after a few answers from the reference path
    compiling_announced()  # each step says what it compiles, and how long it took
    total = time.perf_counter()
    for k, (label, run) in enumerate(steps, start=1):
        print(f"[{k}/{len(steps)}] {label} ...", end=" ", flush=True, file=sys.stderr)
        start = time.perf_counter()
        run()
        print(f"{time.perf_counter() - start:.1f} s", file=sys.stderr)
    print(f"forceclosure: kernels ready in {time.perf_counter() - total:.1f} s (cached for "
          "later runs)", file=sys.stderr)
    return 0
