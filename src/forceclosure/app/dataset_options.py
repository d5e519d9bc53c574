"""``forceclosure dataset --gripper``: the options it shares with ``forceclosure grasps``.

Same names, meanings and defaults as ``grasps``'s; given without ``--gripper`` they are
refused. Light to import (no numpy: ``forceclosure --help`` loads nothing heavy); the job
is :class:`forceclosure.datasets.gripper_job.GripperJob`.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from ..errors import InputError
from ..gripper.settings import ROBUST_DEFAULTS, TASK_DEFAULTS

__all__ = ["DEFAULT_F_MAX", "GRASPS_OPTIONS", "add_grasps_options",
           "add_robust_options", "given_grasps_options", "grasps_job_options", "robust_settings",
           "task_settings"]

#: ``dataset`` options that are ``grasps``'s, with the same names, meanings and defaults
#: (:func:`add_grasps_options`), as (flag, attribute, is a switch).
GRASPS_OPTIONS = (("--gripper-links", "gripper_links", False),
                  ("--no-collision", "no_collision", True), ("--clearance", "clearance", False),
                  ("--approaches", "approaches", False), ("--depths", "depths", False),
                  ("--tilt", "tilt", False), ("--no-epsilon", "no_epsilon", True),
                  ("--robust", "robust", True), ("--robust-samples", "robust_samples", False),
                  ("--pose-sigma", "pose_sigma", False), ("--angle-sigma", "angle_sigma", False),
                  ("--mu-sigma", "mu_sigma", False), ("--normal-sigma", "normal_sigma", False),
                  ("--robust-confidence", "robust_confidence", False),
                  ("--no-robust-epsilon", "no_robust_epsilon", True),
                  ("--metrics", "metrics", True), ("--task-mass", "task_mass", False),
                  ("--gravity", "gravity", False), ("--f-max", "f_max", False),
                  ("--export", "export", False), ("--graspnet-score", "graspnet_score", False),
                  ("--plot", "plot", False), ("--html", "html", False),
                  ("--plot-top", "plot_top", False), ("--support-plane", "support_plane", True))


def add_grasps_options(parser: Any) -> None:
    """Add ``grasps``'s labelling and export options to the ``dataset`` parser (defaults
    None, resolved by :class:`GripperJob` as ``grasps`` resolves them, so that one given
    without ``--gripper`` can be refused)."""
    p = parser
    p.add_argument("--gripper-links", metavar="PALM[,FINGER1,FINGER2]",
                   help="with --gripper FILE.urdf: the hand's root link and its two finger "
                        "links (as grasps --gripper-links)")
    p.add_argument("--no-collision", action="store_true",
                   help="with --gripper: as grasps --no-collision (no hand-object check)")
    p.add_argument("--clearance", type=float, metavar="D",
                   help="with --gripper: each pad stands D off its contact in the collision "
                        "check (default 0.01 x the opening)")
    p.add_argument("--approaches", type=int, metavar="K",
                   help="with --gripper: approach axes tried per closing line (default 12)")
    p.add_argument("--depths", type=int, metavar="K",
                   help="with --gripper: fingertip depths tried per approach (default 3)")
    p.add_argument("--support-plane", action="store_true",
                   help="with --gripper: rest each object on a table in its most stable pose; "
                        "the hand must not cross it (as grasps --support-plane)")
    p.add_argument("--tilt", type=float, metavar="SHARE",
                   help="with --gripper: the closing lines' spread about the normals, a share "
                        "of the friction cone's half-angle (default 0)")
    p.add_argument("--no-epsilon", action="store_true",
                   help="with --gripper: skip the Ferrari-Canny epsilon (saved as NaN)")
    add_robust_options(p, "with --gripper: ")
    p.add_argument("--metrics", action="store_true",
                   help="with --gripper: also the grasp-matrix metrics (arrays in each .npz)")
    p.add_argument("--task-mass", type=float, metavar="M",
                   help="with --gripper: also test every grasp against the object's weight "
                        "(as grasps --task-mass; arrays in each .npz)")
    p.add_argument("--gravity", metavar="GX,GY,GZ",
                   help="gravity of the task test (default 0,0,-9.81)")
    p.add_argument("--f-max", type=float, metavar="F",
                   help="the task test's bound on each jaw's normal force (default 70)")
    p.add_argument("--export", nargs=2, action="append", default=None,
                   metavar=("KIND", "FOLDER"),
                   help="with --gripper: also write each object's labelled poses for a "
                        "trainer, FOLDER/<object>.npy ('graspnet') or .h5 ('acronym'), as "
                        "'forceclosure export' does, after every run; repeatable")
    p.add_argument("--graspnet-score", choices=("friction", "epsilon"),
                   help="the graspnet exports' score (default friction)")
    p.add_argument("--plot", metavar="FOLDER",
                   help="with --gripper: also a picture of each object's best jaw poses, "
                        "FOLDER/<object>.png (grasps --plot's), after every run")
    p.add_argument("--html", metavar="FOLDER",
                   help="with --gripper: also an interactive view of each object's best jaw "
                        "poses, FOLDER/<object>.html (grasps --html-shared's: each page small, "
                        "all loading one FOLDER/plotly.min.js; keep them together)")
    p.add_argument("--plot-top", type=int, metavar="K",
                   help="how many of the best poses the pictures and pages draw (default 10)")


def add_robust_options(group: Any, note: str = "") -> None:
    """The options of ``grasps --robust`` (issue 17: Monte Carlo over pose, friction and
    normal noise), on ``grasps`` and ``dataset`` alike; ``note`` begins the help of
    ``--robust``."""
    group.add_argument("--robust", action="store_true",
                       help=f"{note}also the probability of force closure and the expected "
                            "epsilon under noise, with confidence intervals (saved as "
                            "robust_* arrays)")
    group.add_argument("--robust-samples", type=int, metavar="K",
                       help="noise samples per grasp (default 100; at least 2)")
    group.add_argument("--pose-sigma", type=float, metavar="S",
                       help="jaw translation noise per axis, object units (default 1%% of the "
                            "opening)")
    group.add_argument("--angle-sigma", type=float, metavar="RAD",
                       help="closing-axis rotation noise about each perpendicular axis, "
                            "radians (default 0.05)")
    group.add_argument("--mu-sigma", type=float, metavar="S",
                       help="friction noise, absolute, clipped at 0 (default 0.05)")
    group.add_argument("--normal-sigma", type=float, metavar="RAD",
                       help="contact normal noise per tangent axis, radians (default 0)")
    group.add_argument("--robust-confidence", type=float, metavar="C",
                       help="confidence of the intervals (default 0.95)")
    group.add_argument("--no-robust-epsilon", action="store_true",
                       help="skip the expected epsilon (saved as NaN): the probability alone, "
                            "about ten times faster")


def grasps_job_options(args: Any, robust: dict[str, Any] | None,
                       task: dict[str, Any] | None) -> dict[str, Any]:
    """:class:`GripperJob`'s keyword arguments from the options of
    :func:`add_grasps_options` (``robust`` and ``task``: ``grasps``'s checked settings)."""
    if robust is not None:
        robust = {**robust, "epsilon": not args.no_robust_epsilon}
    return {"hand_links": args.gripper_links, "collision": not args.no_collision,
            "clearance": args.clearance,
            "approaches": args.approaches, "depths": args.depths,
            "tilt": 0.0 if args.tilt is None else args.tilt, "epsilon": not args.no_epsilon,
            "robust": robust, "metrics": bool(args.metrics), "task": task,
            "exports": tuple(tuple(e) for e in args.export or ()),
            "graspnet_score": args.graspnet_score or "friction", "plot": args.plot,
            "html": args.html, "plot_top": 10 if args.plot_top is None else args.plot_top,
            "support_plane": bool(args.support_plane)}


def given_grasps_options(args: Any) -> list[str]:
    """The flags of :func:`add_grasps_options` given on the command line."""
    return [flag for flag, name, switch in GRASPS_OPTIONS
            if (getattr(args, name) if switch else getattr(args, name) is not None)]


#: ``grasps --f-max`` default: each jaw's normal force, N.
DEFAULT_F_MAX: float = TASK_DEFAULTS["f_max"]


def robust_settings(args: argparse.Namespace) -> dict[str, Any] | None:
    """The ``grasps --robust`` settings, checked (None without ``--robust``)."""
    given = [f for f, v in (("--robust-samples", args.robust_samples),
                            ("--pose-sigma", args.pose_sigma), ("--angle-sigma", args.angle_sigma),
                            ("--mu-sigma", args.mu_sigma), ("--normal-sigma", args.normal_sigma),
                            ("--robust-confidence", args.robust_confidence))
             if v is not None] + (["--no-robust-epsilon"] if args.no_robust_epsilon else [])
    if not args.robust:
        if given:
            raise InputError(f"{given[0]} needs --robust")
        return None
    given_values = {"samples": args.robust_samples, "pose_sigma": args.pose_sigma,
                    "angle_sigma": args.angle_sigma, "mu_sigma": args.mu_sigma,
                    "normal_sigma": args.normal_sigma, "confidence": args.robust_confidence}
    # pose_sigma None: 1 % of the opening, once the hand is known
    settings = {k: ROBUST_DEFAULTS[k] if v is None else v for k, v in given_values.items()}
    if settings["samples"] < 2:
        raise InputError(f"--robust-samples must be a whole number >= 2 (an interval needs "
                         f"two), got {settings['samples']}")
    for flag in ("pose_sigma", "angle_sigma", "mu_sigma", "normal_sigma"):
        if settings[flag] is not None and not (math.isfinite(settings[flag])
                                               and settings[flag] >= 0):
            raise InputError(f"--{flag.replace('_', '-')} must be finite and >= 0, got "
                             f"{settings[flag]}")
    if not 0 < settings["confidence"] < 1:
        raise InputError(f"--robust-confidence must be strictly between 0 and 1, got "
                         f"{settings['confidence']}")
    return settings


def task_settings(args: argparse.Namespace) -> dict[str, Any] | None:
    """The ``grasps --task-mass`` settings, checked (None without ``--task-mass``)."""
    if args.task_mass is None:
        for flag, value in (("--gravity", args.gravity), ("--f-max", args.f_max)):
            if value is not None:
                raise InputError(f"{flag} needs --task-mass")
        return None
    if not (math.isfinite(args.task_mass) and args.task_mass > 0):
        raise InputError(f"--task-mass must be a finite positive mass, got {args.task_mass}")
    gravity = list(TASK_DEFAULTS["gravity"])
    if args.gravity is not None:
        try:
            gravity = [float(x) for x in args.gravity.split(",")]
        except ValueError:
            gravity = []
        if len(gravity) != 3 or not all(math.isfinite(x) for x in gravity):
            raise InputError(f"--gravity must be three finite numbers GX,GY,GZ, got "
                             f"{args.gravity!r}")
        if not any(gravity):
            raise InputError("--gravity is zero: there is no weight to resist")
    f_max = DEFAULT_F_MAX if args.f_max is None else args.f_max
    if not (math.isfinite(f_max) and f_max > 0):
        raise InputError(f"--f-max must be a finite positive force, got {f_max}")
    return {"mass": args.task_mass, "gravity": gravity, "f_max": f_max,
            "edges": TASK_DEFAULTS["edges"]}
