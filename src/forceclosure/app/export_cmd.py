"""``forceclosure export LABELS``: saved labels as files trainers load.

``LABELS`` is a label file (``forceclosure grasps --out FILE.npz``,
:meth:`~forceclosure.gripper.labels.GraspLabels.save`) or the folder of a
``forceclosure dataset --gripper parallel-jaw`` run (one file per object
record done). ``--graspnet`` writes graspnetAPI's GraspGroup array
(:func:`~forceclosure.io.export.save_graspnet`), ``--acronym`` ACRONYM's
HDF5 (:func:`~forceclosure.io.export.save_acronym`): for a folder both name
output folders, each object's files named after its labels file. The
object an ACRONYM file names (``object/file``, ``object/scale``, relative to
``--mesh-root``) is the one the labels were made on: a ``grasps --out``
file records it in ``meta["object_source"]``
(:func:`forceclosure.io.export.with_object_source`), a dataset's record holds its
path; ``--object FILE`` names it where neither does (a label file written before, or
moved from another machine).

Every option is checked before anything is written; files are written
atomically; bad input is one line and exit status 2. In a folder, an
object whose files cannot be made (its labels file missing or changed, its
object gone) is reported in one line and skipped; the others are written,
and the exit status is 2.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from pathlib import Path
from typing import Any

from ..errors import InputError, printable

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``export`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    e = sub.add_parser("export", help="turn saved labels into GraspNet and ACRONYM files",
                       description="Write the labels of a 'grasps --out' file, or of every "
                                   "object of a 'dataset --gripper parallel-jaw' folder, as "
                                   "graspnetAPI's GraspGroup array (.npy) and ACRONYM's HDF5 "
                                   "(.h5), atomically (docs/gripper.md).")
    e.add_argument("labels", metavar="LABELS",
                   help="a label file (.npz from 'grasps --out') or a dataset folder")
    e.add_argument("--graspnet", metavar="F.npy",
                   help="graspnetAPI's GraspGroup array (a folder for a dataset)")
    e.add_argument("--acronym", metavar="F.h5",
                   help="ACRONYM's HDF5 layout, needs the 'export' extra (a folder for a "
                        "dataset); an object that is not one mesh file is written as an "
                        ".obj beside it")
    e.add_argument("--graspnet-score", choices=("friction", "epsilon"), default="friction",
                   help="the GraspGroup score: 1.1 - least friction (default) or epsilon")
    e.add_argument("--mesh-root", metavar="DIR",
                   help="ACRONYM's mesh root: object/file is written relative to it, as "
                        "load_mesh(filename, mesh_root_dir) joins them (default: the .h5's "
                        "folder)")
    e.add_argument("--object", metavar="FILE",
                   help="the object the labels were made on (mesh, URDF or bundled name), "
                        "where the labels' meta does not locate it, or to override it")
    e.add_argument("--part", metavar="NAME", help="with --object: the URDF link")
    e.add_argument("--allow-outside-meshes", action="store_true",
                   help="with --object: let a URDF name meshes outside its folder")
    e.add_argument("--json", action="store_true", help="print the summary as JSON")
    e.set_defaults(run=run)


def _check_folder_out(path: str, flag: str, labels: Path) -> None:
    """An output folder: an existing, writable folder, or one whose parent is (made later)."""
    from ..files.atomic import check_output

    if os.path.exists(path) and not os.path.isdir(path):
        raise InputError(f"{flag} {path}: for a dataset folder, an output folder (this is a "
                         "file)")
    if os.path.abspath(path) in (str(labels.resolve()), str((labels / "objects").resolve())):
        raise InputError(f"{flag} {path}: the dataset's own folder; write elsewhere")
    probe = os.path.join(path if os.path.isdir(path) else os.path.dirname(
        os.path.abspath(path)), "probe")
    check_output(probe)


def _check_file_out(path: str, kind: str, flag: str, labels: str) -> None:
    from ..files.atomic import check_output
    from ..io.export import KINDS

    if not path.lower().endswith(KINDS[kind]):
        raise InputError(f"{flag} {path}: written as {' or '.join(KINDS[kind])}")
    check_output(path, inputs=[labels])


def run(args: argparse.Namespace) -> int:
    """Run ``forceclosure export``; the exit status."""
    if not args.graspnet and not args.acronym:
        raise InputError("nothing to write: give --graspnet and/or --acronym")
    labels = Path(args.labels)
    if not labels.exists():
        raise InputError(f"{args.labels}: no such label file or dataset folder")
    if args.mesh_root is not None and not os.path.isdir(args.mesh_root):
        raise InputError(f"--mesh-root {args.mesh_root}: not a folder")
    if (args.part or args.allow_outside_meshes) and not args.object:
        raise InputError("--part and --allow-outside-meshes go with --object")
    if args.object is not None:
        from ..objects.examples import POLYHEDRA

        if labels.is_dir():
            raise InputError("--object names one object; a dataset folder's records name "
                             "theirs")
        if not os.path.isfile(args.object) and args.object not in POLYHEDRA:
            raise InputError(f"--object {args.object}: no such file, and no bundled "
                             "polyhedron of that name")
    if args.acronym:
        from ..io.export import require_h5py

        require_h5py()
    if labels.is_dir():
        return _run_folder(args, labels)
    outputs = [p for p in (args.graspnet, args.acronym) if p]
    if len(set(map(os.path.abspath, outputs))) < len(outputs):
        raise InputError("--graspnet and --acronym: each needs its own file")
    if args.graspnet:
        _check_file_out(args.graspnet, "graspnet", "--graspnet", args.labels)
    if args.acronym:
        _check_file_out(args.acronym, "acronym", "--acronym", args.labels)
    entry = export_one(args, str(labels), args.graspnet, args.acronym, None)
    return _report(args, [entry], failed=0)


def export_one(args: argparse.Namespace, labels_file: str, graspnet: str | None,
               acronym: str | None, record: dict[str, Any] | None,
               job: dict[str, Any] | None = None) -> dict[str, Any]:
    """:func:`~forceclosure.io.label_files.export_labels_file` with the command's options."""
    from ..io.label_files import export_labels_file

    return export_labels_file(labels_file, graspnet, acronym, score=args.graspnet_score,
                              mesh_root=args.mesh_root, obj=args.object, part=args.part,
                              allow_outside_meshes=args.allow_outside_meshes, record=record,
                              job=job)


def _run_folder(args: argparse.Namespace, folder: Path) -> int:
    """A ``dataset --gripper`` folder: one GraspNet and ACRONYM file per object done."""
    from ..datasets.gripper_job import export_dataset, read_records

    try:
        job = json.loads((folder / "job.json").read_text(encoding="utf-8"))
    except (OSError, ValueError, UnicodeDecodeError):
        job = None
    if not isinstance(job, dict) or job.get("mode") != "gripper":
        raise InputError(f"{args.labels}: a folder, but not the output of 'dataset --gripper "
                         "parallel-jaw' (no job.json of a gripper job)")
    for path, flag in ((args.graspnet, "--graspnet"), (args.acronym, "--acronym")):
        if path:
            _check_folder_out(path, flag, folder)
    records = read_records(folder)
    entries, errors = export_dataset(folder, records, args.graspnet, args.acronym,
                                     score=args.graspnet_score, mesh_root=args.mesh_root)
    for _, why in errors:  # this object's: said, the others done
        print(f"forceclosure: error: {printable(why)}", file=sys.stderr)
    # every record done with a labels file gave an entry or an error; the rest were skipped
    return _report(args, entries, len(errors), len(records) - len(entries) - len(errors))


def _report(args: argparse.Namespace, entries: list[dict[str, Any]], failed: int,
            skipped: int = 0) -> int:
    if args.json:
        json.dump({"labels": args.labels, "exported": entries, "failed": failed,
                   "skipped": skipped}, sys.stdout, indent=2, allow_nan=False)
        sys.stdout.write("\n")
    else:
        for entry in entries:
            parts = [f"{printable(entry['labels'])}: {entry['poses']:,} poses"]
            if "graspnet" in entry:
                g = entry["graspnet"]
                parts.append(f"graspnet {printable(g['file'])} ({g['scored']:,} scored)")
            if "acronym" in entry:
                a = entry["acronym"]
                parts.append(f"acronym {printable(a['file'])} (object/file "
                             f"{printable(a['object_file'])}, scale {a['scale']:g})")
            print("; ".join(parts))
        if skipped:
            print(f"{skipped:,} records not done (failed or timed out): no labels to export")
    for entry in entries:
        note = entry.get("acronym", {}).get("note")
        if note:
            print(f"forceclosure: warning: {printable(entry['acronym']['file'])}: {note}",
                  file=sys.stderr)
    return 2 if failed else 0
