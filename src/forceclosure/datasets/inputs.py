"""A dataset's input set: the object files found in files, folders and patterns, what
identifies each object, and the fingerprint of everything its result is computed from."""

from __future__ import annotations

import glob
import hashlib
import re
from collections.abc import Callable, Iterable
from contextlib import suppress
from pathlib import Path

from ..errors import InputError
from ..objects.io import MESH_SUFFIXES, POLYGON_SUFFIXES, ROBOT_SUFFIXES
from ..objects.urdf import mesh_files
from .job import Job, LabelJob

__all__ = ["EXPORTS_FILE", "GRASP_SUFFIXES", "OBJECT_SUFFIXES", "expand_inputs", "fingerprint",
           "grasp_file_of", "object_key", "record_name"]

#: Files a folder contributes: polygons, meshes, robot descriptions.
OBJECT_SUFFIXES = POLYGON_SUFFIXES + MESH_SUFFIXES + ROBOT_SUFFIXES
#: Grasp files given per object (analysis mode), not objects themselves.
GRASP_SUFFIXES = (".grasps.json", ".grasps.npz")
#: The report of a gripper dataset's exports (``--export``), in its folder.
EXPORTS_FILE = "exports.json"


# -- the input set --------------------------------------------------------------------------

def expand_inputs(inputs: Iterable[str | Path], exclude: str | Path | None = None,
                  folders: Iterable[str | Path] = ()) -> list[Path]:
    """Object files from files, folders (searched recursively) and glob patterns.

    A folder contributes its polygon, mesh and URDF files, but not the mesh
    files its URDFs name (the URDF stands for them, with its scale) nor
    grasp files (``*.grasps.json``). A file named directly is always taken.
    The own files of the dataset whose results folder is ``exclude`` (its
    ``job.json``, ``exports.json``, ``*.parquet`` and the records folder
    ``objects/``: JSON too) and files inside ``folders`` (the job's pictures
    and exports) are left out of folders and glob patterns; the rest of
    ``exclude`` (an input folder inside it, say) is searched as any folder.

    Examples
    --------
    >>> import pybullet_data, os
    >>> urdfs = os.path.join(pybullet_data.getDataPath(), "random_urdfs")
    >>> found = expand_inputs([urdfs])
    >>> len(found), found[0].name
    (1000, '000.urdf')
    """
    from ..objects import POLYGONS, POLYHEDRA

    named: list[Path] = []
    walked: list[Path] = []
    skip = _own_output(exclude, folders)
    for item in inputs:
        path = Path(item)
        if path.is_file() or (not path.exists() and str(item) in {*POLYGONS, *POLYHEDRA}):
            named.append(path)  # a file, or a bundled object's name
        elif path.is_dir():
            walked += [p for p in sorted(path.rglob("*"))
                       if p.is_file() and p.suffix.lower() in OBJECT_SUFFIXES
                       and not p.name.lower().endswith(GRASP_SUFFIXES) and not skip(p)]
        else:
            matches = sorted(Path(m) for m in glob.glob(str(item), recursive=True))
            matches = [m for m in matches if m.is_file()]
            if not matches:
                raise InputError(f"{item}: no such file or folder, and no files match it")
            matches = [m for m in matches if not skip(m)]
            named += matches
    meshes_of_urdfs = set()
    for p in walked:
        if p.suffix.lower() in ROBOT_SUFFIXES:
            # a bad URDF (or one naming a symbolic link loop) is recorded as failed in its turn
            with suppress(InputError, OSError, RuntimeError):
                for m in mesh_files(p):
                    with suppress(OSError, RuntimeError):
                        meshes_of_urdfs.add(str(m.resolve()))
    walked = [p for p in walked if object_key(p) not in meshes_of_urdfs]
    unique: dict[str, Path] = {}
    for p in named + walked:
        unique.setdefault(object_key(p), p)
    return sorted(unique.values(), key=lambda p: str(p))


def _own_output(out: str | Path | None, folders: Iterable[str | Path] = ()
                ) -> Callable[[Path], bool]:
    """Whether a path is one of the files a dataset writes (symbolic links followed): in its
    results folder ``out`` (None: none), ``job.json``, ``exports.json``, ``*.parquet`` and
    the records folder ``objects/``; anything inside ``folders``."""
    tops: list[Path] = []
    files: set[Path] = set()
    top: Path | None = None
    try:
        if out is not None:
            top = Path(out).resolve()
            files = {top / "job.json", top / EXPORTS_FILE}
            tops.append(top / "objects")
        tops += [Path(f).resolve() for f in folders]
    except (OSError, RuntimeError):
        pass

    def own(path: Path) -> bool:
        try:
            where = path.resolve()
        except (OSError, RuntimeError):
            return False
        return (where in files or (where.parent == top and where.suffix.lower() == ".parquet")
                or any(where.is_relative_to(t) for t in tops))
    return own


def object_key(path: Path) -> str:
    """What identifies an object: its absolute path (a bundled object: its name)."""
    try:
        return str(path.resolve()) if path.exists() else str(path)
    except (OSError, RuntimeError):  # a symbolic link loop: its path as given, made absolute
        return str(path.absolute())


def record_name(path: Path) -> str:
    """The file name of an object's record: readable, and unique per object."""
    key = object_key(path)
    stem = re.sub(r"[^A-Za-z0-9._-]+", "_", path.name)[:60]
    return f"{stem}-{hashlib.sha1(key.encode()).hexdigest()[:12]}.json"



def grasp_file_of(path: Path, pattern: str) -> Path:
    """The grasp file given for the object at ``path`` (analysis mode)."""
    fill = {"dir": str(path.parent), "stem": path.stem, "name": path.name}
    if pattern:
        return Path(pattern.format(**fill))
    for suffix in GRASP_SUFFIXES[::-1]:  # .npz first
        candidate = path.parent / f"{path.stem}{suffix}"
        if candidate.exists():
            return candidate
    raise InputError(f"{path.name}: no grasp file {path.stem}.grasps.npz or "
                     f"{path.stem}.grasps.json beside it (or give --grasps PATTERN)")


def fingerprint(path: str | Path, job: Job | LabelJob) -> str:
    """The SHA-256 of everything an object's result is computed from: the object file, the
    mesh files a URDF names, and in analysis the grasp file (or that it is missing).

    A record whose input's fingerprint differs is stale, and computed again.
    Files that are not regular files (devices, FIFOs, symbolic link loops)
    are not read: their kind stands for them.

    Examples
    --------
    >>> len(fingerprint("cube", Job())), fingerprint("cube", Job()) == fingerprint("hexagon", Job())
    (64, False)
    """
    from .. import __version__

    path = Path(path)
    digest = hashlib.sha256()

    def add(label: str, file: Path) -> None:
        digest.update(label.encode("utf-8", "surrogateescape") + b"\0")
        try:
            if not file.is_file():
                digest.update(b"missing or not a regular file")
                return
            with open(file, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    digest.update(block)
        except (OSError, RuntimeError) as e:
            digest.update(f"unreadable: {type(e).__name__}".encode())
        digest.update(b"\0")

    if not path.exists() and not path.is_symlink():  # a bundled object
        digest.update(f"bundled {path} {__version__}".encode("utf-8", "surrogateescape"))
    else:
        add("object", path)
    if path.suffix.lower() in ROBOT_SUFFIXES:
        with suppress(InputError, OSError, RuntimeError, ValueError):
            for mesh in mesh_files(path):
                add(f"mesh {mesh}", mesh)
    if job.mode == "analyze":
        try:
            add("grasps", grasp_file_of(path, job.grasps))
        except (InputError, OSError, RuntimeError):
            digest.update(b"no grasp file")
    return digest.hexdigest()
