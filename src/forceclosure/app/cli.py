"""The ``forceclosure`` command.

``forceclosure analyze FILE`` reads a grasp file (one grasp or many; see
``forceclosure/schemas/grasp-file.schema.json``) and says, for each grasp, whether it is
force-closure, what failed, and which motion nothing resists;
``--json`` prints the same for machines. ``forceclosure demo`` analyses the
bundled examples.

Exit status: 0 when every grasp was analysed, 2 when the input (or one grasp
of it) was bad, or the results could not be written — each problem reported
in one line, the good grasps still analysed — 130 when interrupted (Ctrl-C;
``analyze FILE.npz --out`` then saves the grasps done, to be resumed), and 1
on an internal error.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import signal
import sys
from importlib import resources
from typing import Any, NoReturn

from .. import __version__
from ..errors import InputError, clip, printable
from ..extras import require
from ..files.read import read_text
from ..synthesis.table import DEFAULT, names
from ..tolerance import TOLERANCE
from ..verdicts import VERDICT_WORDS, VerdictCode
from .progress import bar_size

__all__ = ["ANY_POSITIVE", "DEFAULT_F_MAX", "FLAGS", "SWITCHES", "as_flags", "build_parser",
           "main"]

#: A least friction below this is reported as "any positive friction": the bisection's
#: smallest steps are within the verdict's tolerance band, where the test cannot tell a
#: grasp that closes with any friction from one that needs a trace of it.
ANY_POSITIVE = 100 * TOLERANCE

#: The library's errors name its parameters (``fingers=2, contact='hard': ...``, ``mu must
#: be ...``); the command line says them as its flags. The one table from the one to the
#: other, applied by :func:`as_flags` to every input error :func:`main` prints.
FLAGS = {"fingers": "--fingers", "contact": "--contact", "mu": "--mu", "top": "--top",
         "method": "--method", "construction": "--construction", "margin": "--margin",
         "samples": "--samples", "seed": "--seed"}
#: Parameters that a ``--no-...`` flag turns off: ``least_friction=False`` is
#: ``--no-least-friction``.
SWITCHES = {"least_friction": "--no-least-friction", "epsilon": "--no-epsilon"}

_NAMES = "|".join(FLAGS)
_ASSIGNED = re.compile(rf"(?<![-\w.])({_NAMES})=('[^']*'|[^\s,:;()']+)(, (?=(?:{_NAMES})=))?")
_SWITCHED = re.compile(rf"(?<![-\w.])({'|'.join(SWITCHES)})=False\b")
_SUBJECT = re.compile(rf"({_NAMES}) must ")


def as_flags(message: str) -> str:
    """A library error message as the command line says it: parameters as flags.

    Examples
    --------
    >>> as_flags("fingers=2, contact='hard': a spatial grasp needs at least 3 hard fingers")
    '--fingers 2 --contact hard: a spatial grasp needs at least 3 hard fingers'
    >>> as_flags("mu must be a positive number, got -1")
    '--mu must be a positive number, got -1'
    >>> as_flags("method='faces': not 4 soft; use method='mesh'")
    '--method faces: not 4 soft; use --method mesh'
    >>> as_flags("the least friction was not computed (least_friction=False)")
    'the least friction was not computed (--no-least-friction)'
    >>> as_flags("--mu must be finite")   # a message already in flags is left as it is
    '--mu must be finite'
    """
    def flag(match: re.Match[str]) -> str:
        value = match.group(2)
        if len(value) >= 2 and value[0] == value[-1] == "'":
            value = value[1:-1]
        return f"{FLAGS[match.group(1)]} {value}" + (" " if match.group(3) else "")

    message = _ASSIGNED.sub(flag, message)
    message = _SWITCHED.sub(lambda m: SWITCHES[m.group(1)], message)
    subject = _SUBJECT.match(message)
    if subject:
        message = FLAGS[subject.group(1)] + message[len(subject.group(1)):]
    return message


# numpy, scipy and the library's own modules are imported where a command needs them, so
# that `forceclosure --help` answers at once


def _read(path: str) -> str:
    return read_text(path, what="a JSON grasp file")


def _error(message: str) -> None:
    """One line on standard error, safe for a terminal (names may hold escapes)."""
    print(f"forceclosure: error: {printable(message)}", file=sys.stderr)


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


def _analyze_file(grasp_file, as_json: bool, quality: bool, out) -> int:
    from ..io.grasp_file import result_record

    records, status = [], 0
    for entry in grasp_file.grasps:
        record, analysis = result_record(entry, grasp_file.cone, quality)
        if analysis is None:
            _error(record["error"])
            status = 2
        elif not as_json:
            print(_human(record, entry.label, analysis.explain()), file=out)
        records.append(record)
    if as_json:
        json.dump({"results": records}, out, indent=2, allow_nan=False)
        out.write("\n")
    return status


def _cmd_analyze(args: argparse.Namespace) -> int:
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
    return _analyze_file(grasp_file, args.json, not args.no_quality, sys.stdout)


def _analyze_arrays(args: argparse.Namespace) -> int:
    """A large grasp set from an .npz: a chunk at a time, a progress bar, a summary; with
    --out, the results saved atomically, also on Ctrl-C (partial, resumed by a re-run)."""
    import time
    from contextlib import nullcontext

    import numpy as np
    from tqdm import tqdm

    from ..io.grasp_arrays import ERROR, AnalysisInterrupted, analyze_npz, open_npz
    from .interrupt import patient

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
        resume = _partial_results(args.out, source, args.epsilon)
    before = 0 if resume is None else resume.done
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
        _error(line)
    if len(results.errors) > len(shown):
        _error(f"... and {len(results.errors) - len(shown)} more grasps with bad input (their "
               "verdict is -1 in the results)")
    earlier = int(np.sum(results.code[:before] == ERROR))
    if earlier:
        _error(f"{earlier:,} grasps with bad input among the {before:,} analysed before this "
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
        closed = results.epsilon[results.code == VerdictCode.CLOSURE]
        summary["epsilon_median"] = float(np.median(closed)) if len(closed) else None
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


def _partial_results(out: str, source: str, epsilon: bool):
    """The partial results in ``out`` to resume, or None when there are none there (no file,
    or complete results, which are replaced); refused when they are of another input."""
    from ..io.grasp_arrays import load_results

    if not os.path.exists(out):
        return None
    try:
        saved = load_results(out)
    except InputError:
        return None  # not results of a partial run: replaced, as any complete file is
    if not saved.partial:
        return None
    if saved.input != source:
        raise InputError(f"{clip(out)}: holds the partial results of another grasp file (or "
                         "of an earlier version of this one); remove it to start again, or "
                         "give another --out")
    if (saved.epsilon is not None) != epsilon:
        flag = "with" if saved.epsilon is not None else "without"
        raise InputError(f"{clip(out)}: holds partial results computed {flag} --epsilon; "
                         f"resume {flag} it, or remove the file to start again")
    return saved


def _save(results, out: str) -> None:
    """Save with Ctrl-C held off: a second Ctrl-C must not lose what the first one saves."""
    from .interrupt import holding

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


def _cmd_demo(args: argparse.Namespace) -> int:
    from ..io.grasp_file import parse_grasp_file

    examples = resources.files("forceclosure") / "examples"
    print(f"forceclosure {__version__}: Nguyen (1988) force-closure analysis on the bundled "
          "examples\n")
    status = 0
    for name in ("planar.json", "spatial.json"):
        print(f"== {name} ==")
        grasp_file = parse_grasp_file((examples / name).read_text(encoding="utf-8"), name)
        status = max(status, _analyze_file(grasp_file, False, True, sys.stdout))
        print()
    _demo_objects()
    print("\nAnalyse your own grasps with: forceclosure analyze GRASPS.json [--json]")
    print("Inspect an object (a file or a bundled name): "
          "forceclosure inspect OBJECT --plot out.png")
    print("Find grasps and their regions: forceclosure synthesize OBJECT --mu 0.3 "
          "--plot out.png")
    print("  on a polyhedron or mesh: forceclosure synthesize OBJECT.stl --fingers 3 "
          "--contact hard --mu 0.5 --plot out.png --html out.html")
    print("Whole object sets, resumable, on all cores or a Dask cluster: "
          "forceclosure dataset FOLDER --out results/")
    return status


def _demo_objects() -> None:
    """Planar synthesis on the bundled polygons; two soft fingers on each polyhedron."""
    import numpy as np

    from ..analysis.closure import analyze
    from ..contacts import point_contact
    from ..objects import POLYGONS, POLYHEDRA, bundled
    from ..synthesis.best import synthesize

    print("== bundled polygons: the best two-finger grasp, mu 0.3, and its independent "
          "regions ==")
    for name in POLYGONS:
        found = synthesize(bundled(name), 2, "hard", 0.3, top=1).found
        if not found:
            print(f"  {name:17} no force-closure grasp with two fingers at mu 0.3")
            continue
        r = found[0]
        print(f"  {name:17} edges {r.edges[0]} + {r.edges[1]}: segments "
              f"{r.lengths[0]:.3g} and {r.lengths[1]:.3g} long, certified {r.certify().holds}")
    print("== bundled polyhedra: two soft fingers, mu 0.3, at the middles of the most opposed "
          "faces ==")
    for name in POLYHEDRA:
        obj = bundled(name)
        sites = [(f.to_world(np.asarray(f.polygon.centroid)), f.normal) for f in obj.faces]
        normals = np.array([n for _, n in sites])
        i, j = np.unravel_index(np.argmin(normals @ normals.T), (len(sites),) * 2)
        grasp = [point_contact(*sites[k], "soft", 0.3) for k in (i, j)]
        print(f"  {name:17} faces {i} + {j}: {analyze(grasp).verdict.value}")
    from ..synthesis import soft_pair_regions, three_hard_regions

    cube = bundled("cube")
    print("== the cube: independent regions on its faces, mu 0.5 ==")
    pair = soft_pair_regions(cube, 0, 1, 0.5)
    print(f"  two soft fingers, top and bottom (§5.2): regions of area {pair.min_area:.3g} "
          f"each; certified: {pair.certify().holds} ({pair.certify().method})")
    three = three_hard_regions(cube, (0, 1, 1), 0.5)
    print(f"  three hard fingers, one on top, two below (§5.3, class "
          f"{three.grasp_class.number}): smallest region {three.min_area:.3g}; certified: "
          f"{three.certify().holds} ({three.certify().method})")
    from ..gripper.jaw import ParallelJaw
    from ..gripper.labels import grasp_labels

    labels = grasp_labels(cube, ParallelJaw(3.0), 0.5, 20, seed=0)
    clear = int(np.sum(~labels.collides & (labels.code == VerdictCode.CLOSURE)))
    print(f"== the cube in a parallel-jaw hand opening 3 (docs/gripper.md), mu 0.5 ==\n"
          f"  20 poses the hand can take: closure and clear {clear}, least friction median "
          f"{float(np.median(labels.least_friction)):.3g}")


def _rounded(values, size: float) -> list:
    """Coordinates for people (:func:`forceclosure.synthesis.regions.rounded`)."""
    from ..synthesis.regions import rounded

    return rounded(values, size)


def _cmd_objects(args: argparse.Namespace) -> int:
    from ..objects import POLYGONS, POLYHEDRA

    print("Bundled objects (use the name wherever a file is expected):\n")
    for kind, table in (("polygons", POLYGONS), ("polyhedra", POLYHEDRA)):
        print(f"{kind}:")
        for name, (description, _) in table.items():
            print(f"  {name:18} {description}")
    return 0


def _cmd_constructions(args: argparse.Namespace) -> int:
    import textwrap

    from ..synthesis.table import constructions

    table = constructions()
    if args.json:
        json.dump([{"dim": c.dim, "fingers": c.fingers, "contact": c.contact, "name": c.name,
                    "paper": c.paper, "method": c.method, "searched": c.described,
                    "bound": c.bound is not None, "prune": c.prune is not None}
                   for c in table], sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    print("The constructions synthesize chooses from (by object, --fingers, --contact and "
          "--construction;\nthe mesh method where none fits):\n")
    for c in table:
        where = "polygon" if c.dim == 2 else "polyhedron"
        fingers = "any number of" if c.fingers is None else str(c.fingers)
        contact = "" if c.contact == "any" else f" {c.contact}"
        print(f"  {where}, {fingers}{contact} fingers, {c.name}: {c.paper}")
        print(textwrap.fill(f"searches {c.described}", 96, initial_indent=" " * 6,
                            subsequent_indent=" " * 6))
    return 0


def _cmd_inspect(args: argparse.Namespace) -> int:
    import numpy as np

    from ..objects.io import load_object
    from ..objects.polygon import in_units

    _check_picture(args.plot, args.object)
    obj = load_object(args.object, allow_open=True, part=args.part,  # describe open meshes too
                      allow_outside_meshes=args.allow_outside_meshes)
    info = obj.summary()
    unit, square = in_units(info.get("units")), in_units(info.get("units"), 2)
    if args.json:
        json.dump(info, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        for warning in info.get("warnings", []):
            print(f"forceclosure: warning: {obj.name}: {warning}", file=sys.stderr)
        lo, hi = np.asarray(info["bounds"])
        print(f"{obj.name}: {info['kind']}")
        if obj.dim == 2:
            print(f"  {info['vertices']} vertices, {info['edges']} edges, {info['holes']} holes;"
                  f" {'convex' if info['convex'] else 'non-convex'}")
            print(f"  area {info['area']:.6g}{square}, perimeter {info['perimeter']:.6g}{unit}")
        else:
            print(f"  {info['vertices']} vertices, {info['triangles']} triangles -> "
                  f"{info['faces']} planar faces ({info['merged_faces']} merged from several "
                  "triangles)")
            tight = "watertight"
            if not info["watertight"]:
                facts = [f"{info['boundary_edges']} boundary edges in {info['holes']} "
                         f"hole{'s' if info['holes'] != 1 else ''}"] if info["holes"] else []
                if info["non_manifold_edges"]:
                    facts.append(f"{info['non_manifold_edges']} non-manifold edges")
                tight = f"{'open' if info['holes'] else 'non-manifold'} (not watertight): " + (
                    ", ".join(facts))
            volume = f", volume {info['volume']:.6g}" if info["volume"] is not None else ""
            print(f"  {tight}{volume}, area {info['area']:.6g}")
            if info["defects"] and not args.allow_open:
                print(f"  the file is {' and '.join(info['defects'])}: synthesize and dataset "
                      "need --allow-open for it")
        print(f"  size {info['size']:.6g}{unit} (bounding-box diagonal), bounds "
              f"{_rounded(lo, obj.size)} to {_rounded(hi, obj.size)}")
    if args.plot:
        from ..pictures.plot import plot_object, upright_axis

        plot_object(obj, args.plot, up=upright_axis(args.object, obj))
        print(f"  picture: {args.plot}", file=sys.stderr if args.json else sys.stdout)
    return 0


def _cmd_synthesize(args: argparse.Namespace) -> int:
    from ..objects.io import load_object
    from ..synthesis.best import synthesize

    if args.html and not args.html.lower().endswith((".html", ".htm")):
        raise InputError(f"--html {args.html}: an interactive view is saved as .html")
    if args.html:  # before any work
        require("plotly", "the interactive HTML view", "view")
    _check_picture(args.plot, args.object)
    obj = load_object(args.object, allow_open=args.allow_open, part=args.part,
                      allow_outside_meshes=args.allow_outside_meshes)
    if obj.dim == 3 and args.vertices:
        raise InputError("--vertices is for polygons; on a polyhedron every finger is on a face")
    if args.vertices and args.contact == "frictionless":
        raise InputError("--vertices puts soft fingers, with friction, on vertices; it "
                         "does not go with --contact frictionless")
    defaulted = args.fingers is None
    result = synthesize(obj, args.fingers, args.contact, args.mu, top=args.top,
                        margin=args.margin, construction=args.construction,
                        method=args.method, samples=args.samples, seed=args.seed)
    args.fingers = result.fingers  # the default filled in (the API's and dataset's)
    if defaulted and not args.json:
        from ..synthesis.best import default_fingers_reason

        print(f"{obj.name}: by default {default_fingers_reason(obj.dim, args.contact)} "
              "(--fingers N to choose)")
    found, mu, method = result.found, result.mu, result.method
    corners = []
    if args.vertices:  # the table's vertex construction, two fingers
        corners = synthesize(obj, 2, "soft", mu, top=args.top, margin=args.margin,
                             construction="vertices").found
    if args.json:
        record = {"object": obj.name, "fingers": args.fingers, "contact": args.contact,
                  "mu": mu, "size": obj.size, "units": getattr(obj, "units", None),
                  "method": method,
                  "construction": {"name": result.construction.name,
                                   "paper": result.construction.paper,
                                   "searched": result.searched},
                  "complete": result.complete, "undecided": result.undecided,
                  "grasps": [r.to_dict() for r in found]}
        if args.vertices:
            record["vertex_grasps"] = [g.to_dict() for g in corners]
        json.dump(record, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        _print_found(args, obj, result)
        if args.vertices:
            print(f"  with a soft finger on a convex vertex ({len(corners)} best):")
            for rank, g in enumerate(corners, start=1):
                vertex, where = g.describe()
                print(f"  {rank}. {vertex} with {where}; certified: {g.certify().holds}")
    _save_views(args, found, corners)
    return 0


#: ``--fingers`` of synthesize and dataset: one default (synthesis.best.default_fingers).
FINGERS_HELP = ("number of fingers (default: the fewest that can hold the object: 2 with "
                "friction in the plane, 4 frictionless; in space 2 soft, 3 hard, 7 frictionless)")


def _print_found(args: argparse.Namespace, obj, result) -> None:
    """The region sets found, best first, for people (``--json`` has every number)."""
    from ..objects.polygon import in_units

    found, c = result.found, result.construction
    friction = ("frictionless" if args.contact == "frictionless"
                else f"{args.contact} fingers, mu {result.mu:g}")
    how = {"edges": "", "faces": f", regions on faces ({c.paper})",
           "mesh": ", regions grown on the mesh around sampled prototypes"}[result.method]
    units = getattr(obj, "units", None)
    ranked = "the shortest independent segment" if obj.dim == 2 else "the smallest region"
    print(f"{obj.name}: {len(found)} best {args.fingers}-finger grasps ({friction}){how}, "
          f"ranked by {ranked}" + (f"; coordinates in {units}" if units and " " not in units
                                   else f"; coordinates in units of {units}" if units else ""))
    if not found:
        more = f" (of {args.samples:,} random grasps: try --samples)" if \
            result.method == "mesh" or result.construction.name == "grown" else ""
        print(f"  no force-closure grasp found; searched {result.searched}{more}")
    elif result.undecided:
        print(f"  searched {result.searched}")
    for rank, r in enumerate(found, start=1):
        print(f"  {rank}. {'; '.join(r.describe())}")
        cert = r.certify()
        if obj.dim == 2:
            size = (f"shortest segment {r.min_size:.4g}{in_units(units)} "
                    f"({r.relative_min_size:.1%} of the object's size)")
        else:
            size = (f"region areas {', '.join(f'{a:.4g}' for a in r.sizes)} (smallest "
                    f"{r.relative_min_size:.2%} of size^2)")
        notes = "".join(f"; {n}" for n in r.notes())
        proof = f" ({cert.method})" if obj.dim == 3 else ""
        print(f"     {size}{notes}; certified: {cert.holds}{proof}")


def _check_picture(path: str | None, source: str) -> None:
    """``--plot`` of a format the pictures are not saved in, or where nothing can be
    written (or onto the input file): refused before any work."""
    if path:
        from ..files.atomic import check_output
        from ..pictures.plot import check_plot_path

        check_plot_path(path)
        check_output(path, inputs=[source])


def _save_views(args: argparse.Namespace, found: list, corners: list = ()) -> None:
    """The PNG still (``--plot``) and the interactive page (``--html``) of the grasps found
    and those with a soft finger on a vertex (``--vertices``), whatever their kind; a mesh
    file's object upright by its format's convention
    (:func:`forceclosure.pictures.plot.upright_axis`)."""
    say = sys.stderr if args.json else sys.stdout
    drawn = [*found, *corners]
    if not drawn or not (args.plot or args.html):
        return
    from ..pictures.plot import upright_axis

    up = upright_axis(args.object, drawn[0].object)
    if args.plot:
        from ..pictures.plot import plot_found

        plot_found(drawn, args.plot, up=up)
        print(f"  picture: {args.plot}", file=say)
    if args.html:
        from ..pictures.view import write_html

        write_html(drawn, args.html, up=up)
        print(f"  interactive view: {args.html}", file=say)


def _dataset_job(args: argparse.Namespace):
    """The dataset's job: regions (synthesis or analysis; options not given take Job's
    defaults, those of synthesize) or, with --gripper, labelled jaw poses."""
    from .dataset import Job
    from .dataset_gripper import GripperJob
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
                          **grasps_job_options(args, _robust_settings(args),
                                               _task_settings(args)), **common)
    given = [flag for flag, value in gripper.items() if value is not None]
    given += given_grasps_options(args)
    if given:
        raise InputError(f"{given[0]} is for --gripper parallel-jaw")
    options = {"fingers": args.fingers, "contact": args.contact, "mu": args.mu,
               "top": args.top, "margin": args.margin, "construction": args.construction,
               "method": args.method, "samples": args.samples}
    return Job(mode="analyze" if args.analyze else "synthesize", grasps=args.grasps,
               **{k: v for k, v in options.items() if v is not None}, **common)


def _cmd_dataset(args: argparse.Namespace) -> int:
    from .dataset import run_dataset

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
        extra = {"grasps_table": str(table)} if table else {}
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
    from .dataset_options import EXPORTS_FILE

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


def _robust_settings(args: argparse.Namespace) -> dict[str, Any] | None:
    """The ``grasps --robust`` settings, checked (None without ``--robust``)."""
    import math

    given = [f for f, v in (("--robust-samples", args.robust_samples),
                            ("--pose-sigma", args.pose_sigma), ("--angle-sigma", args.angle_sigma),
                            ("--mu-sigma", args.mu_sigma), ("--normal-sigma", args.normal_sigma),
                            ("--robust-confidence", args.robust_confidence))
             if v is not None] + (["--no-robust-epsilon"] if args.no_robust_epsilon else [])
    if not args.robust:
        if given:
            raise InputError(f"{given[0]} needs --robust")
        return None
    settings = {"samples": 100 if args.robust_samples is None else args.robust_samples,
                "pose_sigma": args.pose_sigma,  # None: 1 % of the opening, once the hand is known
                "angle_sigma": 0.05 if args.angle_sigma is None else args.angle_sigma,
                "mu_sigma": 0.05 if args.mu_sigma is None else args.mu_sigma,
                "normal_sigma": 0.0 if args.normal_sigma is None else args.normal_sigma,
                "confidence": 0.95 if args.robust_confidence is None else args.robust_confidence}
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


def _robust_stage(obj: Any, labels: Any, gripper: Any, args: argparse.Namespace,
                  settings: dict[str, Any]) -> tuple[Any, dict[str, Any]]:
    """``grasps --robust``: the labels with robustness, and the summary's ``robust`` entry."""
    import time

    import numpy as np
    from tqdm import tqdm

    from ..gripper.robust import robust_labels

    samples = settings["samples"]
    start = time.perf_counter()
    with tqdm(total=len(labels) * samples, unit=" samples", unit_scale=True, file=sys.stderr,
              disable=None, **bar_size(), desc="robustness") as bar:
        r = robust_labels(obj, labels, gripper, args.mu, samples=samples, seed=args.seed,
                          pose_sigma=settings["pose_sigma"], angle_sigma=settings["angle_sigma"],
                          mu_sigma=settings["mu_sigma"], normal_sigma=settings["normal_sigma"],
                          contact=args.contact, confidence=settings["confidence"],
                          epsilon=not args.no_robust_epsilon, progress=bar.update)
    seconds = time.perf_counter() - start
    median = (lambda a: float(np.median(a)) if len(a) and np.all(np.isfinite(a))  # noqa: E731
              else None)
    total = len(labels) * samples
    entry = {**settings, "probability_mean": float(np.mean(r.probability)) if len(r) else None,
             "probability_median": median(r.probability), "epsilon_median": median(r.epsilon),
             "missed_fraction": float(r.missed.sum() / total) if total else None,
             "seconds": round(seconds, 3),
             "samples_per_second": round(total / seconds) if seconds > 0 else None}
    return labels.with_robustness(r), entry


def _collision_summary(labels) -> dict:
    """The summary's collision counts: colliding grasps, by verdict, and the closed clear
    ones (all None when the check did not run)."""
    import numpy as np

    keys = ("collides", "collides_closure", "collides_marginal", "collides_none",
            "closure_clear")
    if labels.collides is None:
        return dict.fromkeys(keys)
    hit = labels.collides
    return {"collides": int(hit.sum()),
            **{f"collides_{v}": int(np.sum(hit & (labels.code == c)))
               for c, v in enumerate(VERDICT_WORDS)},
            "closure_clear": int(np.sum(~hit & (labels.code == VerdictCode.CLOSURE)))}


#: ``grasps --f-max`` default: each jaw's normal force, N (a Franka Emika hand's
#: continuous grip force, 70 N).
DEFAULT_F_MAX = 70.0


def _task_settings(args: argparse.Namespace) -> dict[str, Any] | None:
    """The ``grasps --task-mass`` settings, checked (None without ``--task-mass``)."""
    import math

    if args.task_mass is None:
        for flag, value in (("--gravity", args.gravity), ("--f-max", args.f_max)):
            if value is not None:
                raise InputError(f"{flag} needs --task-mass")
        return None
    if not (math.isfinite(args.task_mass) and args.task_mass > 0):
        raise InputError(f"--task-mass must be a finite positive mass, got {args.task_mass}")
    gravity = [0.0, 0.0, -9.81]
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
    return {"mass": args.task_mass, "gravity": gravity, "f_max": f_max, "edges": 8}


def _task_stage(obj: Any, labels: Any, settings: dict[str, Any]) -> tuple[Any, dict[str, Any]]:
    """``grasps --task-mass``: the labels with the task arrays, and the summary's ``task``
    entry. The weight acts at the mesh's centre of mass (trimesh, uniform density)."""
    import time

    import numpy as np
    from tqdm import tqdm

    from ..analysis.task import gravity_wrench
    from ..gripper.jaw import surface_mesh
    from ..gripper.labels import TASK_VERDICTS, label_task

    com = [float(x) for x in surface_mesh(obj)[1].center_mass]
    settings = {**settings, "center_of_mass": com}
    wrench = gravity_wrench(settings["mass"], com, settings["gravity"])
    start = time.perf_counter()
    with tqdm(total=len(labels), unit=" grasps", unit_scale=True, file=sys.stderr,
              disable=None, **bar_size(), desc="task wrench") as bar:
        code, spare, upper = label_task(labels, wrench, settings["f_max"], settings["edges"],
                                        progress=bar.update)
    seconds = time.perf_counter() - start
    finite = spare[np.isfinite(spare)]
    entry = {**settings, **{v: int(np.sum(code == c)) for c, v in enumerate(TASK_VERDICTS)},
             "spare_median": float(np.median(finite)) if len(finite) == len(spare)
             and len(spare) else None,
             "seconds": round(seconds, 3),
             "grasps_per_second": round(len(labels) / seconds) if seconds > 0 else None}
    return labels.with_task(code, spare, upper, settings), entry


def _metrics_stage(labels: Any) -> tuple[Any, dict[str, Any]]:
    """``grasps --metrics``: the labels with the metric arrays, and the summary's medians."""
    import time

    import numpy as np
    from tqdm import tqdm

    from ..gripper.labels import METRIC_ARRAYS, label_metrics

    start = time.perf_counter()
    with tqdm(total=len(labels), unit=" grasps", unit_scale=True, file=sys.stderr,
              disable=None, **bar_size(), desc="metrics") as bar:
        labels = labels.with_metrics(label_metrics(labels, progress=bar.update))
    seconds = time.perf_counter() - start
    entry = {f"{name}_median": float(np.median(getattr(labels, name))) if len(labels) else None
             for name in METRIC_ARRAYS}
    entry["seconds"] = round(seconds, 3)
    return labels, entry


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


def _cmd_grasps(args: argparse.Namespace) -> int:
    """Sample parallel-jaw grasps on a mesh and label them: verdict, least friction, epsilon."""
    import math
    import time

    import numpy as np
    from tqdm import tqdm

    from ..gripper.hand_poses import APPROACHES, DEPTHS, units_warning
    from ..gripper.labels import grasp_labels
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
    robust = _robust_settings(args)
    task = _task_settings(args)
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
    if robust is not None and robust["pose_sigma"] is None:
        robust["pose_sigma"] = 0.01 * gripper.width_max
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

            beside = _shared_js(args.html)
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
    for warning in obj.warnings:
        print(f"forceclosure: warning: {obj.name}: {warning}", file=sys.stderr)
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
    start = time.perf_counter()
    with tqdm(total=args.count, unit=" grasps", unit_scale=True, file=sys.stderr, disable=None,
              **bar_size(),
              desc="labelling") as bar:
        labels = grasp_labels(obj, gripper, args.mu, args.count, args.seed,
                              args.contact, progress=bar.update,
                              least_friction=not args.no_least_friction,
                              collision=not args.no_collision, clearance=args.clearance,
                              approaches=APPROACHES if args.approaches is None
                              else args.approaches, epsilon=not args.no_epsilon,
                              depths=DEPTHS if args.depths is None else args.depths,
                              tilt=args.tilt, support=support)
    seconds = time.perf_counter() - start
    if robust is not None:
        labels, robust = _robust_stage(obj, labels, gripper, args, robust)
    metrics = _metrics_stage(labels) if args.metrics else None
    if metrics is not None:
        labels, metrics = metrics
    if task is not None:
        labels, task = _task_stage(obj, labels, task)
    if args.out:
        from .export_cmd import with_source

        with_source(labels, args).save(args.out)
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
    counts = labels.counts()
    mu_star = (float(np.median(labels.least_friction))
               if len(labels) and not args.no_least_friction else math.nan)
    closed = (labels.epsilon[labels.code == VerdictCode.CLOSURE] if not args.no_epsilon
              else np.zeros(0))
    summary = {"object": args.object, "candidates": len(labels), "requested": args.count,
               "attempts": labels.meta["attempts"], "rejected": labels.meta["rejected"],
               "contact": args.contact, "mu": args.mu, "width": gripper.width_max,
               "gripper": gripper.name, **counts,
               "least_friction_median": mu_star if math.isfinite(mu_star) else None,
               "epsilon_median": float(np.median(closed)) if len(closed) else None,
               **_collision_summary(labels),
               "exports": [{"kind": kind, "file": path} for kind, path in args.export],
               "plot": args.plot, "html": args.html,
               "html_plotly_js": _shared_js(args.html) if args.html_shared else None,
               "approaches": labels.meta["approaches"], "depths": labels.meta["depths"],
               "hand_poses_tried": labels.meta["tried"],
               "support_plane": None if support is None else support.to_dict(),
               "seconds": round(seconds, 3),
               "grasps_per_second": round(len(labels) / seconds) if seconds > 0 else None,
               "out": args.out}
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
                                  else "median: none closes" if not math.isfinite(mu_star)
                                  else f"median {mu_star:.4g}")
          + (f"; epsilon (L1) of the closed: median {summary['epsilon_median']:.4g}"
             if closed.size else "; epsilon not computed" if args.no_epsilon else ""))
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
    print(f"  {seconds:.2f} s ({summary['grasps_per_second'] or 0:,} grasps/s)"
          + (f"; labels in {printable(args.out)}" if args.out else ""))
    for kind, path in args.export:
        print(f"  {kind} export in {printable(path)}")
    if args.plot:
        print(f"  picture of the {min(args.plot_top, len(labels))} best: {printable(args.plot)}")
    if args.html:
        print(f"  interactive view of the {min(args.plot_top, len(labels))} best: "
              f"{printable(args.html)}"
              + (f" (loads {printable(_shared_js(args.html))})" if args.html_shared else ""))
    return 0


def _shared_js(page: str) -> str:
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


def _cmd_warmup(args: argparse.Namespace) -> int:
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
    from ..kernels import compiling_announced

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


def _outside_meshes_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--allow-outside-meshes", action="store_true",
                   help="let a URDF name meshes outside its folder (or its package's "
                        "folder); refused by default")


def _synthesis_options(p: argparse.ArgumentParser) -> None:
    """The hand and the construction: options shared by ``synthesize`` and ``dataset``."""
    p.add_argument("--contact", choices=("hard", "soft", "frictionless"), default="hard",
                   help="contact model (in the plane a soft finger acts as a hard one)")
    p.add_argument("--mu", type=float, default=0.3, help="friction coefficient (default 0.3)")
    p.add_argument("--top", type=int, default=5, help="how many grasps (default 5)")
    p.add_argument("--margin", type=float, default=1e-3,
                   help="radians: the regions stay force-closure when every contact normal "
                        "turns by up to this angle (default 1e-3; cones narrowed by it)")
    p.add_argument("--construction", choices=names(), default=DEFAULT,
                   help="a name in the table of constructions (forceclosure constructions): "
                        "maximal regions (an exact LP), the paper's two-sided cone "
                        "constructions (nguyen: §5.1, §5.2, §5.4), a soft finger on a vertex "
                        "(vertices: polygons), segments grown around sampled grasps (grown: "
                        "polygons, any hand), regions grown on the mesh (mesh: polyhedra)")
    p.add_argument("--method", choices=("auto", "faces", "mesh"), default="auto",
                   help="polyhedra: the paper's constructions on faces (two soft, three hard, "
                        "seven frictionless fingers), or regions grown over a mesh around "
                        "sampled prototype grasps (any hand); auto: faces unless the object "
                        "is curved")
    p.add_argument("--samples", type=int, default=20_000,
                   help="random grasps sampled for prototypes (polyhedra, and hands on a "
                        "polygon no paper construction serves; default 20000)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the sampling")
    p.add_argument("--allow-open", action="store_true",
                   help="accept open or non-manifold meshes (scans, single-sided surfaces), "
                        "with a warning, instead of refusing them")


class _Parser(argparse.ArgumentParser):
    """argparse, with a bad command line answered in one line (and where to look) instead
    of the usage block, exit status 2 as before."""

    def error(self, message: str) -> NoReturn:
        _error(f"{message} (see '{self.prog} --help')")
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``forceclosure`` command."""
    parser = _Parser(
        prog="forceclosure",
        description="Analyse force-closure grasps (V.-D. Nguyen, IJRR 1988).")
    parser.add_argument("--version", action="version", version=f"forceclosure {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
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
    p.set_defaults(run=_cmd_analyze)
    d = sub.add_parser("demo", help="analyse the bundled example grasps")
    d.set_defaults(run=_cmd_demo)
    w = sub.add_parser("warmup", help="compile the batch kernels now (once per installation; "
                                      "otherwise on first use)")
    w.set_defaults(run=_cmd_warmup)
    o = sub.add_parser("objects", help="list the bundled example objects")
    o.set_defaults(run=_cmd_objects)
    k = sub.add_parser("constructions", help="list the constructions of independent regions "
                                             "(the table synthesize chooses from)")
    k.add_argument("--json", action="store_true", help="print the table as JSON")
    k.set_defaults(run=_cmd_constructions)
    i = sub.add_parser("inspect", help="summarise an object: polygon or polyhedron",
                       description="Load an object (a file or a bundled name), check it, and "
                                   "summarise it: edges, or planar faces found in a mesh.")
    i.add_argument("object", metavar="OBJECT",
                   help="a file (.json .geojson .svg .csv .stl .obj .ply .off .glb .gltf .urdf) "
                        "or a bundled name")
    i.add_argument("--plot", metavar="OUT", help="save a picture (.png or .svg)")
    i.add_argument("--json", action="store_true", help="print the summary as JSON")
    i.add_argument("--allow-open", action="store_true",
                   help="open or non-manifold meshes are described either way; with this "
                        "flag, without the reminder that synthesize needs it")
    i.add_argument("--part", metavar="NAME", help="the URDF link (or SVG element id) to read")
    _outside_meshes_option(i)
    i.set_defaults(run=_cmd_inspect)
    y = sub.add_parser("synthesize", help="where to put the fingers: independent regions",
                       description="Find the best force-closure grasps on an object and the "
                                   "independent regions of contact around them (Nguyen 1988, "
                                   "§5): every choice of one point per region is "
                                   "force-closure.")
    y.add_argument("object", metavar="OBJECT",
                   help="a polygon or mesh file, or a bundled name")
    y.add_argument("--fingers", type=int, default=None, help=FINGERS_HELP)
    y.add_argument("--part", metavar="NAME", help="the URDF link (or SVG element id) to read")
    _outside_meshes_option(y)
    _synthesis_options(y)
    y.add_argument("--vertices", action="store_true",
                   help="also grasp with a soft finger on a convex vertex (a wider cone)")
    y.add_argument("--json", action="store_true", help="print JSON for machines")
    y.add_argument("--plot", metavar="OUT", help="save a picture (.png or .svg)")
    y.add_argument("--html", metavar="OUT",
                   help="save an interactive view (.html, self-contained, works offline)")
    y.set_defaults(run=_cmd_synthesize)
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
    _synthesis_options(t)
    t.add_argument("--analyze", action="store_true",
                   help="analyse the grasps given per object instead of synthesizing")
    t.add_argument("--grasps", default="", metavar="PATTERN",
                   help="with --analyze: each object's grasp file, with {dir}, {stem} and "
                        "{name} filled in, plain names only (default {dir}/{stem}.grasps.npz "
                        "or .json)")
    _outside_meshes_option(t)
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
    t.set_defaults(run=_cmd_dataset, mu=None, contact=None, top=None, margin=None,
                   construction=None, method=None, samples=None)
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
    _outside_meshes_option(g)
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
    # robustness (issue 17): Monte Carlo over pose, friction and normal noise
    g.add_argument("--robust", action="store_true",
                   help="also the probability of force closure and the expected epsilon "
                        "under noise, with confidence intervals (saved as robust_* arrays)")
    g.add_argument("--robust-samples", type=int, metavar="K",
                   help="noise samples per grasp (default 100; at least 2)")
    g.add_argument("--pose-sigma", type=float, metavar="S",
                   help="jaw translation noise per axis, object units (default 1%% of --width)")
    g.add_argument("--angle-sigma", type=float, metavar="RAD",
                   help="closing-axis rotation noise about each perpendicular axis, radians "
                        "(default 0.05)")
    g.add_argument("--mu-sigma", type=float, metavar="S",
                   help="friction noise, absolute, clipped at 0 (default 0.05)")
    g.add_argument("--normal-sigma", type=float, metavar="RAD",
                   help="contact normal noise per tangent axis, radians (default 0)")
    g.add_argument("--robust-confidence", type=float, metavar="C",
                   help="confidence of the intervals (default 0.95)")
    g.add_argument("--no-robust-epsilon", action="store_true",
                   help="skip the expected epsilon (saved as NaN): the probability alone, "
                        "about ten times faster")
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
    g.set_defaults(run=_cmd_grasps)
    from .export_cmd import add_parser as add_export_parser  # forceclosure export

    add_export_parser(sub)
    parser.epilog = f"Verdicts within {TOLERANCE:g} of the boundary are 'marginal'."
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command; returns the exit status."""
    args = build_parser().parse_args(argv)
    try:
        from .limits import check_options

        check_options(args)  # every option's range, before any work (app/limits.py)
        from .interrupt import run_interruptible

        # the command in a thread: Ctrl-C ends it within seconds, even in compiled code
        return run_interruptible(lambda: args.run(args))
    except InputError as e:
        _error(as_flags(str(e)))
        return 2
    except KeyboardInterrupt:
        print("forceclosure: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader (e.g. `head`) closed the pipe: stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except Exception as e:  # an internal error: one line unless debugging
        if os.environ.get("FORCECLOSURE_DEBUG"):
            raise
        print(f"forceclosure: internal error: {type(e).__name__}: {printable(clip(str(e)))} "
              "(set FORCECLOSURE_DEBUG=1 for the traceback)", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
