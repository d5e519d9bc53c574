"""The job a dataset runs on every object: its options, and what decides its results.

A :class:`Job` finds each object's best grasps and their independent regions
(``forceclosure synthesize``, §5) or analyses the grasps given per object
(Theorem 1); any other job that labels objects itself (the parallel-jaw
:class:`forceclosure.datasets.gripper_job.GripperJob`) follows :class:`LabelJob`.
"""

from __future__ import annotations

import math
import string
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any, Literal, Protocol

from ..errors import InputError

__all__ = ["PLACEHOLDERS", "Job", "LabelJob"]

#: The placeholders a ``--grasps`` pattern may use, as plain names.
PLACEHOLDERS = ("dir", "stem", "name")


@dataclass(frozen=True)
class Job:
    """What to do with every object.

    Attributes
    ----------
    mode : {"synthesize", "analyze"}
        Find the best grasps and their regions (the options below, as for
        ``forceclosure synthesize``), or analyse the grasps given for each
        object in a grasp file (``grasps``).
    fingers : int or None
        None: the fewest that hold the object (2 on polygons; on polyhedra 2
        soft, 3 hard, 7 frictionless).
    contact, mu, top, margin, construction, method, samples, seed
        As for :func:`forceclosure.synthesis.best.synthesize`.
    grasps : str
        Analysis: where each object's grasp file is, with ``{dir}`` (the
        object's folder), ``{stem}`` and ``{name}`` filled in; ``.npz`` or
        JSON grasp files. Default: ``{dir}/{stem}.grasps.npz``, else
        ``{dir}/{stem}.grasps.json``.
    timeout : float or None
        Seconds one object may take; None (or ``inf``) for no limit.
    allow_open : bool
        Accept open and non-manifold meshes (``load_object(..., allow_open=True)``);
        part of the job's identity, since it changes which objects load and how.
    allow_outside_meshes : bool
        Let a URDF name meshes outside its folder (or its package's); refused
        by default (:func:`forceclosure.objects.urdf.check_mesh_inside`).
    """

    mode: Literal["synthesize", "analyze"] = "synthesize"
    fingers: int | None = None
    contact: str = "hard"
    mu: float = 0.3
    top: int = 5
    margin: float = 1e-3
    construction: str = "maximal"
    method: str = "auto"
    samples: int = 20_000
    seed: int = 0
    grasps: str = ""
    timeout: float | None = None
    allow_open: bool = False
    allow_outside_meshes: bool = False

    def __post_init__(self) -> None:
        if self.mode not in ("synthesize", "analyze"):
            raise InputError(f"mode must be synthesize or analyze, got {self.mode!r}")
        if self.timeout is not None and not self.timeout > 0:
            raise InputError(f"--timeout must be a positive number of seconds, got "
                             f"{self.timeout:g}")
        if self.timeout is not None and math.isinf(self.timeout):
            object.__setattr__(self, "timeout", None)  # inf: no limit
        if self.samples < 1:
            raise InputError(f"--samples must be at least 1, got {self.samples}")
        if self.fingers is not None and self.fingers < 1:
            raise InputError(f"--fingers must be at least 1, got {self.fingers}")
        _check_pattern(self.grasps)

    def identity(self) -> dict[str, Any]:
        """The options that decide the results (the time limit does not)."""
        if self.mode == "analyze":
            return {"mode": "analyze", "grasps": self.grasps, "allow_open": self.allow_open,
                    "allow_outside_meshes": self.allow_outside_meshes}
        record = asdict(self)
        record.pop("timeout")
        return record


class LabelJob(Protocol):
    """A job that labels each object itself, as
    :class:`forceclosure.datasets.gripper_job.GripperJob` does: what
    :func:`~forceclosure.datasets.run.run_dataset` asks of a job other than a
    :class:`Job` (its optional ``store``, ``write_tables``, ``check`` and
    ``output_folders`` are looked up when there)."""

    @property
    def mode(self) -> Literal["gripper"]:
        """The dispatch key of :func:`process_object`."""
        ...

    @property
    def timeout(self) -> float | None:
        """Seconds one object may take; None for no limit."""
        ...

    @property
    def allow_open(self) -> bool:
        """Accept open and non-manifold meshes (as :class:`Job`'s)."""
        ...

    @property
    def allow_outside_meshes(self) -> bool:
        """Let a URDF name meshes outside its folder (as :class:`Job`'s)."""
        ...

    def identity(self) -> dict[str, Any]:
        """The options that decide the results (``job.json``'s content)."""
        ...

    def label(self, obj: Any, path: Path) -> dict[str, Any]:
        """The record's fields for one loaded object."""
        ...

    def warm_up(self) -> None:
        """Run its compiled kernels once (a pool worker, before its first object)."""
        ...


def _check_pattern(pattern: str) -> None:
    """A ``--grasps`` pattern may use :data:`PLACEHOLDERS`, as plain names: no attribute or
    index (``{dir.__class__}``), no nested field, since ``str.format`` would evaluate them."""
    def refuse(why: str) -> InputError:
        return InputError(f"--grasps {pattern[:200]!r}: {why}; {{dir}}, {{stem}} and {{name}} "
                          "are the placeholders it may use, as plain names")

    try:
        parsed = list(string.Formatter().parse(pattern))
    except ValueError as e:
        raise refuse(str(e)) from None
    for _, field_name, spec, _ in parsed:
        if field_name is None:
            continue
        if field_name not in PLACEHOLDERS:
            raise refuse(f"{{{field_name[:60]}}} is not one")
        if spec and ("{" in spec or "}" in spec):
            raise refuse(f"{{{field_name}:{spec[:60]}}} nests a field")
    try:
        pattern.format(dir="", stem="", name="")
    except (KeyError, IndexError, ValueError) as e:
        raise refuse(f"{type(e).__name__}: {e}") from None

