"""``forceclosure analyze FILE``: the verdict of each grasp of a grasp file, in words or JSON.

A JSON grasp file is analysed grasp by grasp (:func:`forceclosure.io.grasp_file.result_record`);
an ``.npz`` of arrays a chunk at a time (:func:`forceclosure.io.grasp_arrays.analyze_npz`),
its results saved with ``--out`` and resumed after Ctrl-C.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
from typing import Any

from ..datasets.progress import bar_size
from ..errors import InputError, printable
from ..files.read import read_text
from ..tolerance import TOLERANCE
from ..verdicts import closed_median
from .common import error

__all__ = ["ANY_POSITIVE", "add_parser", "analyze_file", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``analyze`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    p = sub.add_parser("analyze", help="is each grasp in a grasp file force-closure?",
                       description="Analyse the grasps of a JSON grasp file "
                                   "(schema: forceclosure/schemas/grasp-file.schema.json; "
                                   "'-' reads standard input), "
                                   "or of an .npz file of arrays (points, normals, mu, model; "
                                   "see docs/analysis.md), any number of grasps, in chunks.")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--json", action="store_true",
                   help="print JSON for machines (for .npz: the summary)")
    p.add_argument("--no-quality", action="store_true",
                   help="skip epsilon and least friction (faster)")
    p.add_argument("--out", metavar="RESULTS.npz",
                   help=".npz input: save verdict codes, ranks and margins in exactly this "
                        "file, atomically; on Ctrl-C the grasps done are saved (partial) and "
                        "the same command resumes them")
    p.add_argument("--epsilon", action="store_true",
                   help=".npz input: also the Ferrari-Canny epsilon of the closed grasps "
                        "(saved as 'epsilon' with --out)")
    p.add_argument("--chunk", type=int, default=65_536,
                   help=".npz input: grasps read and analysed at a time (default 65536)")
    p.set_defaults(run=run)


#: A least friction below this is reported as "any positive friction": the bisection's
#: smallest steps are within the verdict's tolerance band, where the test cannot tell a
#: grasp that closes with any friction from one that needs a trace of it.
ANY_POSITIVE = 100 * TOLERANCE


def _read(path: str) -> str:
    return read_text(path, what="a JSON grasp file")


def _human(record: dict[str, Any], label: str, explanation: str) -> str:
    lines = [f"{printable(label)}: {explanation}"]
    nulls = record.get("null_reasons", {})
    quality = []
    if record.get("epsilon") is not None and None not in (record["reference"],
                                                          record["length_scale"]):
        ref = ", ".join(f"{x:.3g}" for x in record["reference"])
        quality.append(f"epsilon {record['epsilon']:.3g} (L1; torques about ({ref}) "
                       f"per length {record['length_scale']:.3g})")
    if "epsilon" in nulls and nulls.get("epsilon") != nulls.get("least_friction"):
        quality.append(f"epsilon {nulls['epsilon']}")
    if "least_friction" in nulls:  # not computed: say so, not "no friction closes it"
        quality.append(("epsilon and least friction " if "epsilon" in nulls else
                        "least friction ") + nulls["least_friction"])
    elif "least_friction" in record and record["verdict"] is not None:
        mu = record["least_friction"]
        quality.append("no friction coefficient closes it" if mu is None
                       else "least friction 0 (closed without friction)" if mu == 0
                       else f"least friction {mu:.2g}, within the test's tolerance of 0: any "
                            "positive friction closes it" if mu < ANY_POSITIVE
                       else f"least friction {mu:.4g}")
    if quality:
        lines.append("  " + "; ".join(quality))
    return "\n".join(lines)


def analyze_file(grasp_file, as_json: bool, quality: bool, out) -> int:
    from ..io.grasp_file import result_record

    records, status = [], 0
    for entry in grasp_file.grasps:
        record, analysis = result_record(entry, grasp_file.cone, quality)
        if analysis is None:
            error(record["error"])
            status = 2
        elif not as_json:
            print(_human(record, entry.label, analysis.explain()), file=out)
        records.append(record)
    if as_json:
        json.dump({"results": records}, out, indent=2, allow_nan=False)
        out.write("\n")
    return status


def run(args: argparse.Namespace) -> int:
    from ..io.grasp_file import parse_grasp_file

    if args.file.endswith(".npz"):
        return _analyze_arrays(args)
    if args.out:
        raise InputError("--out is for .npz grasp files; JSON results go to standard output "
                         "with --json")
    if args.epsilon:
        raise InputError("--epsilon is for .npz grasp files; a JSON grasp file's analysis "
                         "reports epsilon unless --no-quality")
    grasp_file = parse_grasp_file(_read(args.file), args.file)
    return analyze_file(grasp_file, args.json, not args.no_quality, sys.stdout)


def _analyze_arrays(args: argparse.Namespace) -> int:
    """A large grasp set from an .npz: a chunk at a time, a progress bar, a summary; with
    --out, the results saved atomically, also on Ctrl-C (partial, resumed by a re-run)."""
    import time
    from contextlib import nullcontext

    import numpy as np
    from tqdm import tqdm

    from ..files.saves import patient
    from ..io.grasp_arrays import ERROR, AnalysisInterrupted, analyze_npz, open_npz, resumable

    if args.chunk < 1:
        raise InputError(f"--chunk must be a positive number of grasps, got {args.chunk}")
    if args.out:
        from ..files.atomic import check_output

        check_output(args.out, inputs=[args.file])
    info = open_npz(args.file)
    resume, source = None, None
    if args.out:
        from ..files.read import fingerprint

        source = fingerprint(args.file)
        resume = resumable(args.out, source, args.epsilon)
    before = 0 if resume is None or resume.done is None else resume.done
    start = time.perf_counter()
    try:
        with patient() if args.out else nullcontext(), \
             tqdm(total=info.count, initial=before, unit=" grasps", unit_scale=True,
                  file=sys.stderr, disable=None, **bar_size(),
                  desc=printable(os.path.basename(args.file), 40)) as bar:
            results = analyze_npz(args.file, chunk=args.chunk, epsilon=args.epsilon,
                                  progress=bar.update, resume=resume)
    except AnalysisInterrupted as stop:
        return _interrupted(args, stop.results, source)
    seconds = time.perf_counter() - start
    shown = results.errors[:20]
    for line in shown:
        error(line)
    if len(results.errors) > len(shown):
        error(f"... and {len(results.errors) - len(shown)} more grasps with bad input (their "
               "verdict is -1 in the results)")
    earlier = int(np.sum(results.code[:before] == ERROR))
    if earlier:
        error(f"{earlier:,} grasps with bad input among the {before:,} analysed before this "
               "run resumed (their verdict is -1 in the results)")
    if args.out:
        _save(_with_input(results, source), args.out)
    counts = results.counts()
    ran = info.count - before
    summary = {"file": args.file, "grasps": info.count, "contacts": info.contacts,
               "dim": info.dim, "models": info.models, "cone": str(info.cone), **counts,
               "seconds": round(seconds, 3),
               "grasps_per_second": round(ran / seconds) if seconds > 0 else None,
               "out": args.out, "resumed": before}
    if results.epsilon is not None:
        summary["epsilon_median"] = closed_median(results.epsilon, results.code)
    if args.json:
        json.dump(summary, sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
    else:
        kind = "planar" if info.dim == 2 else "spatial"
        print(f"{printable(args.file)}: {info.count:,} grasps of {info.contacts} "
              f"{'/'.join(sorted(set(info.models)))} contacts ({kind}, {info.cone} cones)")
        print(f"  closure {counts['closure']:,}, marginal {counts['marginal']:,}, "
              f"none {counts['none']:,}, bad input {counts['errors']:,}")
        if summary.get("epsilon_median") is not None:
            print(f"  epsilon (L1, 8-edge pyramids) of the closed grasps: median "
                  f"{summary['epsilon_median']:.4g}")
        if before:
            print(f"  resumed: {before:,} grasps were analysed before, by an interrupted run")
        print(f"  {seconds:.2f} s ({summary['grasps_per_second'] or 0:,} grasps/s)"
              + (f"; results in {printable(args.out)}" if args.out else ""))
    return 2 if results.errors or earlier else 0


def _with_input(results, source: str | None):
    from dataclasses import replace

    return replace(results, input=source)


def _save(results, out: str) -> None:
    """Save with Ctrl-C held off: a second Ctrl-C must not lose what the first one saves."""
    from ..files.saves import holding

    try:
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread: signals are not ours to handle
        previous = None
    try:
        with holding():  # the process waits for the save before it exits on Ctrl-C
            results.save(out)
    finally:
        if previous is not None:
            signal.signal(signal.SIGINT, previous)


def _interrupted(args: argparse.Namespace, results, source: str | None) -> int:
    total = len(results.code)
    if not args.out:
        _interrupt_line(f"interrupted after {results.done:,} of {total:,} grasps; nothing "
                        "saved (give --out to keep the results and resume them)")
        return 130
    _save(_with_input(results, source), args.out)
    _interrupt_line(f"interrupted: {results.done:,} of {total:,} grasps analysed, saved in "
                    f"{printable(args.out)} (partial); run the same command again to resume")
    return 130


def _interrupt_line(message: str) -> None:
    print(f"forceclosure: {message}", file=sys.stderr)
