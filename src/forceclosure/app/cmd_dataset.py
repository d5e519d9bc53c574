"""``forceclosure dataset INPUT... --out DIR``: synthesis, analysis or labelled jaw poses over
many objects, resumably (:func:`forceclosure.datasets.run.run_dataset`)."""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import Any

from ..errors import InputError, printable
from ..extras import require
from .common import FINGERS_HELP, outside_meshes_option, synthesis_options
from .dataset_options import robust_settings, task_settings

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``dataset`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    t = sub.add_parser("dataset", help="synthesize or analyse over many objects, resumably",
                       description="Run synthesize (or, with --analyze, the analysis of each "
                                   "object's grasp file) on every object of a set: files, "
                                   "folders (searched recursively) and glob patterns. Results "
                                   "go to DIR: a record per object as it finishes, and "
                                   "results.parquet. Re-running the same command resumes; "
                                   "records whose input or options changed are computed "
                                   "again. One run at a time per DIR (a second is refused).")
    t.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="object files, folders or glob patterns (polygons, meshes, URDFs)")
    t.add_argument("--out", required=True, metavar="DIR", help="the results folder")
    t.add_argument("--fingers", type=int, default=None, help=FINGERS_HELP)
    synthesis_options(t)
    t.add_argument("--analyze", action="store_true",
                   help="analyse the grasps given per object instead of synthesizing")
    t.add_argument("--grasps", default="", metavar="PATTERN",
                   help="with --analyze: each object's grasp file, with {dir}, {stem} and "
                        "{name} filled in, plain names only (default {dir}/{stem}.grasps.npz "
                        "or .json)")
    outside_meshes_option(t)
    t.add_argument("--workers", type=int, default=None,
                   help="local worker processes (default: all cores; 1 runs in this process)")
    t.add_argument("--scheduler", metavar="ADDRESS",
                   help="run on a Dask cluster, e.g. tcp://host:8786 (its workers must see "
                        "the input files at the same paths)")
    t.add_argument("--timeout", type=float, default=None, metavar="SECONDS",
                   help="time limit per object, held inside compiled code on the local pool "
                        "(its worker is killed); 'inf' or none: no limit (default)")
    t.add_argument("--retry-failed", action="store_true",
                   help="compute failed and timed-out objects again")
    t.add_argument("--json", action="store_true", help="print the summary as JSON")
    # parallel-jaw grasps per object (docs/datasets.md, docs/gripper.md)
    t.add_argument("--gripper", metavar="NAME|FILE.urdf",
                   help="instead of regions, sample --count jaw poses the hand can take on "
                        "every mesh and label them (verdict, least friction, epsilon, "
                        "collision): an .npz per object and grasps.parquet; needs --mu, and "
                        "--width for the generic 'parallel-jaw' (built-ins 'panda', "
                        "'robotiq-2f85', 'graspnet', or a hand's .urdf: metres)")
    t.add_argument("--width", type=float, default=None,
                   help="with --gripper parallel-jaw: the widest opening (object units)")
    t.add_argument("--count", type=int, default=None,
                   help="with --gripper: jaw poses per object (default 1000)")
    t.add_argument("--pad-radius", type=float, default=None,
                   help="with --gripper and soft contacts: torsion bounded by (2/3) mu radius "
                        "times the normal force; 0: the paper's soft finger (unlimited); "
                        "default: bounded by the hand's rectangular pad")
    t.add_argument("--no-least-friction", action="store_true",
                   help="with --gripper: skip the least friction (saved as NaN)")
    from .dataset_options import add_grasps_options

    add_grasps_options(t)  # grasps's labelling and export options, same names and meanings
    # not given: the job's own defaults (regions: synthesize's; --gripper: soft contacts),
    # so that region-only options given with --gripper can be refused
    t.set_defaults(run=run, mu=None, contact=None, top=None, margin=None,
                   construction=None, method=None, samples=None)


def _dataset_job(args: argparse.Namespace):
    """The dataset's job: regions (synthesis or analysis; options not given take Job's
    defaults, those of synthesize) or, with --gripper, labelled jaw poses."""
    from ..datasets.gripper_job import GripperJob
    from ..datasets.job import Job
    from .dataset_options import given_grasps_options, grasps_job_options

    regions = {"--fingers": args.fingers, "--top": args.top, "--margin": args.margin,
               "--construction": args.construction, "--method": args.method,
               "--samples": args.samples, "--analyze": args.analyze or None,
               "--grasps": args.grasps or None}
    gripper = {"--width": args.width, "--count": args.count, "--pad-radius": args.pad_radius,
               "--no-least-friction": args.no_least_friction or None}
    common = {"seed": args.seed, "timeout": args.timeout, "allow_open": args.allow_open,
              "allow_outside_meshes": args.allow_outside_meshes}
    if args.gripper:
        given = [flag for flag, value in regions.items() if value is not None]
        if given:
            raise InputError(f"{given[0]} is for regions (synthesize, --analyze), not for "
                             f"--gripper {args.gripper}")
        if args.gripper == "parallel-jaw" and args.width is None:
            raise InputError("--gripper parallel-jaw needs --width (or name a built-in hand: "
                             "--gripper panda, robotiq-2f85 or graspnet)")
        if args.mu is None:
            raise InputError(f"--gripper {args.gripper} needs --mu")
        if args.contact == "frictionless":
            raise InputError("--contact frictionless: a parallel-jaw gripper has soft or hard "
                             "contacts")
        if args.contact == "hard" and args.pad_radius:
            raise InputError("--pad-radius couples a soft pad's torsion; hard contacts have "
                             "none (drop it, or --contact soft)")
        return GripperJob(width=args.width, mu=args.mu,
                          count=1000 if args.count is None else args.count,
                          contact=args.contact or "soft", pad_radius=args.pad_radius,
                          least_friction=not args.no_least_friction, hand=args.gripper,
                          **grasps_job_options(args, robust_settings(args),
                                               task_settings(args)), **common)
    given = [flag for flag, value in gripper.items() if value is not None]
    given += given_grasps_options(args)
    if given:
        raise InputError(f"{given[0]} is for --gripper parallel-jaw")
    options = {"fingers": args.fingers, "contact": args.contact, "mu": args.mu,
               "top": args.top, "margin": args.margin, "construction": args.construction,
               "method": args.method, "samples": args.samples}
    return Job(mode="analyze" if args.analyze else "synthesize", grasps=args.grasps,
               **{k: v for k, v in options.items() if v is not None}, **common)


def run(args: argparse.Namespace) -> int:
    from ..datasets.run import run_dataset

    if args.workers is not None and args.workers < 1:
        raise InputError(f"--workers must be at least 1, got {args.workers}")
    if args.scheduler and args.workers is not None:
        raise InputError("--workers is for the local pool; a Dask cluster has its own workers")
    job = _dataset_job(args)
    outputs = [f for _, f in getattr(job, "exports", ())] + [
        f for f in (getattr(job, "plot", None), getattr(job, "html", None)) if f]
    inside = {os.path.abspath(args.out), os.path.abspath(os.path.join(args.out, "objects"))}
    for folder in outputs:
        if os.path.abspath(folder) in inside:
            raise InputError(f"{folder}: the dataset's own folder; write exports and pictures "
                             "elsewhere")
    if args.scheduler:
        Client = require("distributed", "--scheduler (a Dask cluster)", "dask").Client
        try:
            client = Client(args.scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as e:
            raise InputError(f"--scheduler {args.scheduler}: cannot connect "
                             f"({str(e).splitlines()[0] if str(e) else type(e).__name__})"
                             ) from None
        with client:
            workers = len(client.nthreads())
            summary = run_dataset(args.inputs, args.out, job, executor=client.get_executor(),
                                  workers=workers, retry_failed=args.retry_failed)
    else:
        summary = run_dataset(args.inputs, args.out, job, workers=args.workers,
                              retry_failed=args.retry_failed)
    table = os.path.join(args.out, "grasps.parquet") if args.gripper else None
    exported = _dataset_exports(args.out, job)
    if args.json:
        extra: dict[str, Any] = {"grasps_table": str(table)} if table else {}
        if exported is not None:
            extra["exports"] = exported
        json.dump({**summary.to_dict(), **extra}, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        print(summary)
        if table:
            print(f"grasps: {table} (one row per grasp), labels per object in "
                  f"{os.path.join(args.out, 'objects')} (.npz)")
    if summary.interrupted:
        return 130
    return 2 if summary.failed or summary.timeout or (exported or {}).get("errors") else 0


def _dataset_exports(out: str, job: Any) -> dict[str, Any] | None:
    """``dataset --export/--plot/--html``: the report of the files written (printed: one
    line per kind and per object that could not be exported, on standard error), or None."""
    kinds = [*getattr(job, "exports", ()),
             *((k, getattr(job, k, None)) for k in ("plot", "html") if getattr(job, k, None))]
    if not kinds:
        return None
    from ..datasets.inputs import EXPORTS_FILE

    try:
        with open(os.path.join(out, EXPORTS_FILE), encoding="utf-8") as f:
            report = json.load(f)
    except (OSError, ValueError):
        return None
    for kind, folder in kinds:
        print(f"forceclosure: export {kind}: {report['files'].get(kind, 0):,} files in "
              f"{printable(folder)}", file=sys.stderr)
    for line in report["errors"]:
        print(f"forceclosure: error: export {printable(line)}", file=sys.stderr)
    return report
