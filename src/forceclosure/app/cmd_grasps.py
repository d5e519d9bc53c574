"""``forceclosure grasps OBJECT``: jaw poses a hand can take, labelled
(:func:`forceclosure.gripper.pipeline.label_poses`), with their summary, files and pictures."""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from ..datasets.progress import bar_size
from ..errors import InputError, printable
from ..extras import require
from .common import outside_meshes_option
from .dataset_options import DEFAULT_F_MAX, add_robust_options, robust_settings, task_settings

__all__ = ["add_parser", "run", "shared_js"]


def add_parser(sub: Any) -> None:
    """Register the ``grasps`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    g = sub.add_parser("grasps", help="sample parallel-jaw grasps on a mesh and label them",
                       description="Sample parallel-jaw poses the hand can take on a mesh "
                                   "(closing lines through surface points, the approach and "
                                   "depth searched for a pose that clears the object, the "
                                   "contacts where the pads first meet it and press) and label "
                                   "each: verdict with exact cones, least friction, "
                                   "Ferrari-Canny epsilon.")
    g.add_argument("object", metavar="OBJECT",
                   help="a mesh or URDF file, or a bundled polyhedron")
    g.add_argument("--part", metavar="NAME", help="the URDF link to read")
    g.add_argument("--allow-open", action="store_true",
                   help="accept open or non-manifold meshes (oriented outward, with a "
                        "warning) instead of refusing them")
    outside_meshes_option(g)
    g.add_argument("--gripper", metavar="NAME|FILE.urdf",
                   help="the hand: a built-in with its real sizes ('panda': Franka Emika's, "
                        "'robotiq-2f85': Robotiq's 2F-85, as the parallel jaw its "
                        "fingertips act as, 'graspnet': GraspNet-1Billion's model; metres), "
                        "a hand's URDF file (two fingers on prismatic joints, measured from "
                        "their geometry; a robot's URDF with its hand works too), or "
                        "'parallel-jaw' (the "
                        "default), a generic hand sized from --width")
    g.add_argument("--gripper-links", metavar="PALM[,FINGER1,FINGER2]",
                   help="with --gripper FILE.urdf: the hand's root link (its frame is the "
                        "hand's) and its two finger links, where the URDF does not make them "
                        "plain (default: the children of its two prismatic joints, and their "
                        "nearest common parent); ',F1,F2' names the fingers alone")
    g.add_argument("--width", type=float, default=None,
                   help="the generic gripper's widest opening (object units)")
    g.add_argument("--count", type=int, default=1000, help="grasps to sample (default 1000)")
    g.add_argument("--mu", type=float, default=0.3, help="friction coefficient (default 0.3)")
    g.add_argument("--contact", choices=("soft", "hard"), default="soft",
                   help="soft pads (default) or hard point contacts (two never close in space)")
    g.add_argument("--pad-radius", type=float, default=None,
                   help="soft pads' torsion: bounded by (2/3) mu radius times the normal "
                        "force; 0: the paper's soft finger (unlimited); default: bounded by "
                        "the hand's rectangular pad (mu times its mean radius)")
    g.add_argument("--seed", type=int, default=0, help="random seed of the sampling")
    g.add_argument("--no-least-friction", action="store_true",
                   help="skip the least friction (saved as NaN): microseconds a grasp for "
                        "soft pads, milliseconds with --pad-radius or hard contacts")
    g.add_argument("--out", metavar="FILE.npz", help="save the poses, contacts and labels, "
                                                      "atomically")
    g.add_argument("--json", action="store_true", help="print the summary as JSON")
    add_robust_options(g)
    # collision, export and picture (docs/gripper.md)
    g.add_argument("--no-collision", action="store_true",
                   help="skip checking the opened hand (fingers and palm as boxes) against the "
                        "object; 'collides' is then not saved")
    g.add_argument("--clearance", type=float, default=None, metavar="D",
                   help="each finger's pad stands D off its contact in the collision check "
                        "(default 0.01 x the gripper's opening)")
    g.add_argument("--approaches", type=int, default=None, metavar="K",
                   help="approach axes tried per closing line, turned about it in even "
                        "steps; the first pose at which the hand is clear is kept "
                        "(default 12; 1: the sampler's axis alone)")
    g.add_argument("--tilt", type=float, default=0.0, metavar="SHARE",
                   help="spread the closing lines about the surface normals over this share "
                        "(0 to 1) of the friction cone's half-angle (default 0: along the "
                        "normals, where flat pads meet a surface flush)")
    g.add_argument("--support-plane", action="store_true",
                   help="rest the object on a table in its most stable pose (trimesh's "
                        "stable poses): the hand must not cross the table; poses stay in "
                        "the object's frame, the plane is in the summary and the labels' meta")
    g.add_argument("--depths", type=int, default=None, metavar="K",
                   help="fingertip depths tried per approach axis, spread over the pad "
                        "(default 3; 1: the pad's middle)")
    g.add_argument("--export", nargs=2, action="append", default=[], metavar=("KIND", "FILE"),
                   help="also write the labelled poses for a trainer, atomically: 'graspnet "
                        "FILE.npy' (graspnetAPI's GraspGroup array, N x 17) or 'acronym "
                        "FILE.h5' (ACRONYM's HDF5 layout; needs the 'export' extra); "
                        "repeatable")
    g.add_argument("--graspnet-score", choices=("friction", "epsilon"), default="friction",
                   help="the GraspGroup score: 1.1 - least friction (GraspNet's, default) or "
                        "the Ferrari-Canny epsilon; -1 for grasps that do not close or collide")
    g.add_argument("--plot", metavar="FILE.png",
                   help="save a picture (.png or .svg) of the best jaw poses, one panel each: "
                        "the object, the hand coloured by label, the contacts and their "
                        "friction cones, a caption")
    g.add_argument("--plot-top", type=int, default=10, metavar="K",
                   help="how many of the best poses the picture and the page draw "
                        "(default 10)")
    g.add_argument("--html", metavar="FILE.html",
                   help="save an interactive view (.html, self-contained, works offline, "
                        "about 2 MB) of the object and its best jaw poses, coloured by "
                        "label, one highlighted at a time")
    g.add_argument("--html-shared", action="store_true",
                   help="with --html: write plotly.js once beside the page (plotly.min.js, "
                        "4.8 MB) and a small page that loads it (its figure only, tens of kB; "
                        "keep the two together), for folders of many pages")
    # grasp-matrix metrics, the task wrench, skipping epsilon (issue 17; docs/gripper.md)
    g.add_argument("--metrics", action="store_true",
                   help="also the grasp-matrix metrics of every grasp: smallest and largest "
                        "singular values, isotropy, wrench-hull volume (saved as sigma_min, "
                        "sigma_max, isotropy, volume; about 1 ms a grasp)")
    g.add_argument("--task-mass", type=float, metavar="M",
                   help="also test every grasp against the object's weight (mass M, at the "
                        "mesh's centre of mass, uniform density): task_verdict 0 fails, "
                        "1 undecided, 2 resists, and task_spare; two LPs a grasp (about 0.5 ms)")
    g.add_argument("--gravity", metavar="GX,GY,GZ",
                   help="gravity of the task test, object frame (default 0,0,-9.81; write "
                        "--gravity=-9.81,0,0 when the first is negative)")
    g.add_argument("--f-max", type=float, metavar="F",
                   help="the task test's bound on each jaw's normal force, in the units of "
                        f"mass x gravity (default {DEFAULT_F_MAX:g}: N with kg and m/s^2)")
    g.add_argument("--no-epsilon", action="store_true",
                   help="skip the Ferrari-Canny epsilon (saved as NaN), most of the labelling "
                        "time: verdicts (and least friction) only")
    g.set_defaults(run=run)


@contextmanager
def _bar(stage: str, total: int, unit: str) -> Iterator[Callable[[int], object]]:
    """A stage's progress bar on standard error (none when it is not a terminal)."""
    from tqdm import tqdm

    with tqdm(total=total, unit=unit, unit_scale=True, file=sys.stderr, disable=None,
              **bar_size(), desc=stage) as bar:
        yield bar.update


def _gripper_of(args: argparse.Namespace):
    """The hand of ``--gripper`` (a built-in, or the generic one of ``--width``)."""
    from ..gripper.grippers import GENERIC, make_gripper

    name = args.gripper or GENERIC
    if name == GENERIC and args.width is None:
        raise InputError("--width: give the gripper's opening, or a built-in hand with "
                         "--gripper (panda, robotiq-2f85, graspnet)")
    if name != GENERIC and args.width is not None:
        raise InputError(f"--width: --gripper {name} has its own opening; drop --width")
    try:
        return make_gripper(name, args.width, args.pad_radius, args.gripper_links,
                            allow_outside_meshes=getattr(args, "allow_outside_meshes", False))
    except InputError as e:
        raise InputError(f"--gripper {name}: {str(e).replace('links', '--gripper-links', 1)}"
                         if str(e).startswith("links") else f"--gripper {name}: {e}") from None


def run(args: argparse.Namespace) -> int:
    """Sample parallel-jaw grasps on a mesh and label them: verdict, least friction, epsilon."""
    import math

    from ..gripper.hand_poses import APPROACHES, DEPTHS, units_warning
    from ..gripper.pipeline import label_poses
    from ..objects.io import load_object

    if args.width is not None and not (math.isfinite(args.width) and args.width > 0):
        raise InputError(f"--width must be a finite positive opening, got {args.width}")
    if args.count < 0:
        raise InputError(f"--count must be a whole number >= 0, got {args.count}")
    if not 0 <= args.tilt <= 1:
        raise InputError(f"--tilt must be a share from 0 to 1, got {args.tilt}")
    if not (math.isfinite(args.mu) and args.mu > 0):
        raise InputError(f"--mu must be finite and positive, got {args.mu}")
    if args.pad_radius is not None and not (math.isfinite(args.pad_radius)
                                            and 0 <= args.pad_radius <= 1e150):
        raise InputError(f"--pad-radius must be finite and >= 0, got {args.pad_radius}")
    if args.contact == "hard" and args.pad_radius:
        raise InputError("--pad-radius couples a soft pad's torsion; hard contacts have none "
                         "(drop it, or --contact soft)")
    robust = robust_settings(args)
    task = task_settings(args)
    if args.no_epsilon and args.graspnet_score == "epsilon":
        raise InputError("--graspnet-score epsilon needs the epsilon: drop --no-epsilon")
    if args.clearance is not None and not (math.isfinite(args.clearance)
                                           and args.clearance >= 0):
        raise InputError(f"--clearance must be finite and >= 0, got {args.clearance}")
    if args.clearance is not None and args.no_collision:
        raise InputError("--clearance is the collision check's; it has no use with "
                         "--no-collision")
    if (args.html or args.plot) and args.plot_top < 0:
        raise InputError(f"--plot-top must be a whole number >= 0, got {args.plot_top}")
    for flag, value in (("--approaches", args.approaches), ("--depths", args.depths)):
        if value is None:
            continue
        if value < 1:
            raise InputError(f"{flag} must be a whole number >= 1, got {value}")
        if args.no_collision:
            raise InputError(f"{flag} is searched by the collision check; it has no use with "
                             "--no-collision")
    gripper = _gripper_of(args)
    if args.html_shared and not args.html:
        raise InputError("--html-shared is a way to write the --html page: give --html too")
    if args.html:
        from ..files.atomic import check_output

        require("plotly", "the interactive HTML view", "view")  # before any work
        from ..pictures.view import check_html_path

        check_html_path(args.html)
        if args.html in [args.out, args.plot, *(path for _, path in args.export)]:
            raise InputError("--html, --export, --out and --plot: each needs its own file")
        check_output(args.html, inputs=[args.object])
        if args.html_shared:
            from ..pictures.page import PLOTLY_JS

            beside = shared_js(args.html)
            if beside in [args.out, args.plot, *(path for _, path in args.export)]:
                raise InputError(f"--html-shared writes {PLOTLY_JS} beside the page: --out, "
                                 "--plot and --export need other files")
            check_output(beside, inputs=[args.object])
    if args.out:
        from ..files.atomic import check_output

        if not args.out.lower().endswith(".npz"):
            raise InputError(f"--out {args.out}: labels are saved as .npz")
        check_output(args.out, inputs=[args.object])
    _check_exports(args)
    if args.plot:
        from ..files.atomic import check_output
        from ..pictures.grasp_plot import check_plot_path

        check_plot_path(args.plot)
        check_output(args.plot, inputs=[args.object])
    obj = load_object(args.object, allow_open=args.allow_open, part=args.part,
                      allow_outside_meshes=args.allow_outside_meshes)
    for note in obj.warnings:
        print(f"forceclosure: warning: {obj.name}: {note}", file=sys.stderr)
    if task is not None and getattr(obj, "watertight", True) is False:
        raise InputError(f"{obj.name}: --task-mass needs a closed mesh for its centre of mass; "
                         "this one is open")
    warning = units_warning(gripper, obj.size)
    if warning:
        print(f"forceclosure: warning: {obj.name}: {warning}", file=sys.stderr)
    support = None
    if args.support_plane:
        from ..gripper.support import support_plane

        if args.no_collision:
            raise InputError("--support-plane is part of the collision check; it has no use "
                             "with --no-collision")
        support = support_plane(obj)
    found = label_poses(obj, gripper, args.mu, args.count, args.seed, args.contact,
                        least_friction=not args.no_least_friction,
                        collision=not args.no_collision, clearance=args.clearance,
                        approaches=APPROACHES if args.approaches is None else args.approaches,
                        epsilon=not args.no_epsilon,
                        depths=DEPTHS if args.depths is None else args.depths, tilt=args.tilt,
                        support=support, stage=_bar, metrics=args.metrics, task=task,
                        robust=None if robust is None else {
                            **robust, "epsilon": not args.no_robust_epsilon})
    labels, robust, metrics, task = found.labels, found.robust, found.metrics, found.task
    if args.out:
        from ..io.export import with_object_source

        with_object_source(labels, args.object, args.part, args.allow_open,
                           args.allow_outside_meshes).save(args.out)
    _write_exports(args, labels, gripper, obj)
    if args.plot or args.html:
        from ..pictures.plot import upright_axis

        up = upright_axis(args.object, obj)
    if args.plot:
        from ..pictures.grasp_plot import plot_grasps

        plot_grasps(obj, labels, args.plot, top=args.plot_top, gripper=gripper, up=up)
    if args.html:
        from ..pictures.view import write_grasps_html

        write_grasps_html(obj, labels, args.html, top=args.plot_top, gripper=gripper, up=up,
                          shared_js=args.html_shared)
    counts, lf = labels.counts(), found.summary["least_friction_median"]
    head = dict(found.summary)
    tail = {k: head.pop(k) for k in ("approaches", "depths", "hand_poses_tried",
                                     "support_plane", "seconds", "grasps_per_second")}
    summary = {"object": args.object, **head,
               "exports": [{"kind": kind, "file": path} for kind, path in args.export],
               "plot": args.plot, "html": args.html,
               "html_plotly_js": shared_js(args.html) if args.html_shared else None,
               **tail, "out": args.out}
    if robust is not None:
        summary["robust"] = robust
    if metrics is not None:
        summary["metrics"] = metrics
    if task is not None:
        summary["task"] = task
    if args.json:
        json.dump(summary, sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
        return 0
    print(f"{printable(args.object)}: {len(labels):,} jaw poses of the {gripper.name} gripper "
          f"(of {args.count:,} asked; {labels.meta['attempts']:,} closing lines drawn), "
          f"{args.contact} contacts, mu {args.mu:g}, opening up to {gripper.width_max:g}")
    if labels.collides is not None:
        print(f"  closure and clear: {summary['closure_clear']:,} of {len(labels):,} "
              f"(clear {len(labels) - summary['collides']:,}; closure {counts['closure']:,})")
    if support is not None:
        print(f"  on a table: normal {[round(float(x), 6) for x in support.normal]}, offset "
              f"{support.offset:.6g} (object frame; its most stable pose, probability "
              f"{support.probability:.3g}); no hand crosses it")
    for reason, n in labels.meta["rejected"].items():
        print(f"  {n:,} lines made no pose: {reason}")
    print(f"  closure {counts['closure']:,}, marginal {counts['marginal']:,}, "
          f"none {counts['none']:,}")
    print("  least friction: " + ("not computed" if args.no_least_friction or not len(labels)
                                  else "median: none closes" if lf is None
                                  else f"median {lf:.4g}")
          + (f"; epsilon (L1) of the closed: median {summary['epsilon_median']:.4g}"
             if summary["epsilon_median"] is not None
             else "; epsilon not computed" if args.no_epsilon else ""))
    if metrics is not None:
        print("  grasp matrix: median " + (
            "of none" if metrics["sigma_min_median"] is None else
            f"sigma_min {metrics['sigma_min_median']:.4g}, sigma_max "
            f"{metrics['sigma_max_median']:.4g}, isotropy {metrics['isotropy_median']:.4g}, "
            f"wrench-hull volume {metrics['volume_median']:.4g}")
            + f"; {metrics['seconds']:.2f} s")
    if task is not None:
        g = ",".join(f"{x:g}" for x in task["gravity"])
        print(f"  task: mass {task['mass']:g} under gravity {g} at the centre of mass "
              f"({', '.join(f'{x:.4g}' for x in task['center_of_mass'])}), jaws pressing "
              f"at most {task['f_max']:g}: resists {task['resists']:,}, undecided "
              f"{task['undecided']:,}, fails {task['fails']:,}"
              + (f"; spare median {task['spare_median']:.4g}"
                 if task["spare_median"] is not None else "")
              + f"; {task['seconds']:.2f} s ({task['grasps_per_second'] or 0:,} grasps/s)")
    if robust is not None:
        print(f"  robust ({robust['samples']} samples a grasp; pose sigma "
              f"{robust['pose_sigma']:g}, angle sigma {robust['angle_sigma']:g} rad, mu sigma "
              f"{robust['mu_sigma']:g}, normal sigma {robust['normal_sigma']:g} rad): "
              + ("no grasps" if robust["probability_mean"] is None else
                 f"P(closure) mean {robust['probability_mean']:.3g}, median "
                 f"{robust['probability_median']:.3g}"
                 + (f"; expected epsilon median {robust['epsilon_median']:.4g}"
                    if robust["epsilon_median"] is not None else "")
                 + f"; {robust['seconds']:.2f} s ({robust['samples_per_second'] or 0:,} "
                   "samples/s)"))
    if labels.collides is None:
        print("  collision: not checked")
    else:
        print(f"  collides: {summary['collides']:,} (closure {summary['collides_closure']:,}, "
              f"marginal {summary['collides_marginal']:,}, none {summary['collides_none']:,}; "
              f"verdicts kept: they are of the contacts); {summary['approaches']} approach "
              f"ax{'i' if summary['approaches'] == 1 else 'e'}s x {summary['depths']} "
              f"depth{'' if summary['depths'] == 1 else 's'} searched per closing line "
              f"({summary['hand_poses_tried']:,} hand poses checked)")
    print(f"  {summary['seconds']:.2f} s ({summary['grasps_per_second'] or 0:,} grasps/s)"
          + (f"; labels in {printable(args.out)}" if args.out else ""))
    for kind, path in args.export:
        print(f"  {kind} export in {printable(path)}")
    if args.plot:
        print(f"  picture of the {min(args.plot_top, len(labels))} best: {printable(args.plot)}")
    if args.html:
        print(f"  interactive view of the {min(args.plot_top, len(labels))} best: "
              f"{printable(args.html)}"
              + (f" (loads {printable(shared_js(args.html))})" if args.html_shared else ""))
    return 0


def shared_js(page: str) -> str:
    """The plotly.js file a ``--html-shared`` page loads: beside it."""
    from ..pictures.page import PLOTLY_JS

    return os.path.join(os.path.dirname(page), PLOTLY_JS)


def _check_exports(args: argparse.Namespace) -> None:
    """Refuse a bad ``--export`` before any work: its kind, extension, place, and h5py."""
    from ..files.atomic import check_output
    from ..io.export import KINDS, acronym_object, require_h5py

    for kind, path in args.export:
        if kind not in KINDS:
            raise InputError(f"--export: unknown kind {kind!r}; the kinds are "
                             + ", ".join(f"{k} ({'/'.join(e)})" for k, e in KINDS.items()))
        if not path.lower().endswith(KINDS[kind]):
            raise InputError(f"--export {kind} {path}: written as {' or '.join(KINDS[kind])}")
        check_output(path, inputs=[args.object, *([args.out] if args.out else [])])
        if kind == "acronym":
            require_h5py()
            acronym_object(args.object, path, part=args.part, load_surface=False,
                           allow_outside_meshes=args.allow_outside_meshes)
        if kind == "graspnet" and args.graspnet_score == "friction" and args.no_least_friction:
            raise InputError("--export graspnet: the friction score needs the least friction; "
                             "drop --no-least-friction or pass --graspnet-score epsilon")
    paths = [path for _, path in args.export] + [p for p in (args.out, args.plot) if p]
    if len(set(paths)) < len(paths):
        raise InputError("--export, --out and --plot: each needs its own file")


def _write_exports(args: argparse.Namespace, labels, gripper, obj=None) -> None:
    from ..io.export import save_acronym, save_graspnet

    for kind, path in args.export:
        if kind == "graspnet":
            save_graspnet(path, labels, gripper, score=args.graspnet_score)
        else:
            found = save_acronym(path, labels, args.object, gripper=gripper, part=args.part,
                                 allow_outside_meshes=args.allow_outside_meshes, surface=obj)
            if found.note:
                print(f"forceclosure: {printable(path)}: {found.note}", file=sys.stderr)
