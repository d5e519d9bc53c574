"""Every command-line option checked up front, by its own name and range.

:func:`check_options` runs before any file is read or any array made: a
number out of its range, a path spelled so that the results could not be
written (``""``, ``-``, a trailing ``/``), a scheduler that is not an address,
or a job whose arrays would not fit in memory is refused in one line naming
the option (exit status 2), never found out after the work, nor as a
``MemoryError``, ``OverflowError`` or numpy's ``ValueError``.

The ranges (above them an option is refused; below them, each command's own
checks answer, as before):

* ``--seed``: a whole number from 0 to 2**63 - 1 (numpy's generators take no
  negative seed; results files keep it as a 64-bit integer);
* ``--width`` from :data:`MIN_WIDTH` (1e-6) to :data:`MAX_LENGTH` (1e6 object
  units), ``--pad-radius``, ``--clearance``, ``--pose-sigma`` at most 1e6:
  beyond them the hand's derived sizes (fingers, pads, compliance, kept to 15
  decimals) vanish or their squares overflow;
* ``--mu`` and ``--mu-sigma`` at most :data:`MAX_MU` (1e6: a cone within 1e-6
  rad of a half-space); ``--angle-sigma``, ``--normal-sigma`` at most pi;
* ``--approaches`` at most :data:`MAX_APPROACHES` (3600: 0.1 degree steps),
  ``--depths`` at most :data:`MAX_DEPTHS` (1000);
* ``--robust-samples`` at most :data:`MAX_ROBUST_SAMPLES` (one chunk of the
  noise sampler, 262,144 a grasp);
* ``--samples`` at most :data:`MAX_SAMPLES` (10,000,000), ``--top`` and
  ``--plot-top`` at most :data:`MAX_TOP`, ``--chunk`` at most 2**24;
* ``--task-mass`` and ``--f-max`` at most 1e100 (their products stay finite);
* ``--count`` (``grasps``, and per object in ``dataset --gripper``, times the
  local workers labelling at once): the labels' memory, estimated as
  :data:`BYTES_PER_GRASP` (4 KiB) a grasp (measured: about 1.7 KiB on the
  cube, doubled for objects where more closing lines miss) plus 8 bytes a
  robust sample, at most
  :func:`memory_budget` (half the machine's memory);
* output paths (``--out``, ``--plot``, ``--html``, ``--export``, ``--graspnet``,
  ``--acronym``): not empty,
  not ``-`` (refused: results are files, never standard output; ``./-``
  names a file called ``-``), and a file's not ending in ``/``;
* ``dataset --scheduler``: ``[tcp|tls|ws|wss|ucx://]HOST:PORT`` or
  ``inproc://NAME``.
"""

from __future__ import annotations

import argparse
import math
import os
import re
from typing import Any

from ..errors import InputError, printable

__all__ = ["BYTES_PER_GRASP", "MAX_APPROACHES", "MAX_DEPTHS", "MAX_LENGTH", "MAX_MU",
           "MAX_ROBUST_SAMPLES", "MAX_SAMPLES", "MAX_SEED", "MAX_TOP", "MIN_WIDTH",
           "check_options", "check_path_spelling", "check_scheduler", "memory_budget"]

MAX_SEED = 2**63 - 1
MIN_WIDTH = 1e-6
MAX_LENGTH = 1e6
MAX_MU = 1e6
MAX_APPROACHES = 3600
MAX_DEPTHS = 1000
MAX_ROBUST_SAMPLES = 1 << 18  # gripper.robust.CHUNK_SAMPLES, not imported (numpy-free here)
MAX_SAMPLES = 10_000_000
MAX_TOP = 1_000_000
MAX_CHUNK = 1 << 24
#: Memory a labelled grasp takes while ``grasps`` runs (measured ~1.7 KiB, doubled).
BYTES_PER_GRASP = 4096
#: Memory one noise sample of ``--robust`` keeps per grasp (its epsilon, a float64).
BYTES_PER_ROBUST_SAMPLE = 8
#: Largest bound on a physical quantity (mass, force, gravity): products stay finite.
MAX_QUANTITY = 1e100

_SCHEMES = ("tcp", "tls", "ws", "wss", "ucx", "inproc")
_HOST_PORT = re.compile(r"(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9_.-]+):(\d{1,5})/?")


def memory_budget() -> int:
    """Bytes a command may plan to hold: half the machine's physical memory (8 GiB when the
    system does not say)."""
    try:
        total = os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):  # pragma: no cover - not POSIX
        total = 16 << 30
    return max(total, 1 << 30) // 2


def _size(n: float) -> str:
    for unit, scale in (("TiB", 1 << 40), ("GiB", 1 << 30), ("MiB", 1 << 20)):
        if n >= scale:
            return f"{n / scale:,.1f} {unit}"
    return f"{n / 1024:,.1f} KiB"


def _at_most(flag: str, value: Any, high: float, what: str = "", why: str = "") -> None:
    """Refuse ``value`` above ``high`` (values below the range, and non-numbers, are the
    commands' own checks, with their own messages)."""
    if value is not None and value > high:
        shown = f"{value:,}" if isinstance(value, int) and value < 10**30 else f"{value:g}" \
            if isinstance(value, float) else printable(str(value), 40) + "..."
        limit = f"{high:,}" if isinstance(high, int) else f"{high:g}"
        raise InputError(f"{flag} must be at most {limit}{what}{why}, got {shown}")


def _at_least(flag: str, value: Any, low: float, why: str = "") -> None:
    """Refuse a positive ``value`` below ``low`` (zero and negatives are the commands' own
    checks)."""
    if value is not None and 0 < value < low:
        raise InputError(f"{flag} must be at least {low:g}{why}, got {value:g}")


def check_path_spelling(flag: str, path: str | None, *, folder: bool = False) -> None:
    """Refuse an output path that cannot be what is meant: empty, ``-`` (standard output is
    not a results file: refused, not a file named ``-``), or, for a file, ending in ``/``.

    Examples
    --------
    >>> check_path_spelling("--out", "r.npz")
    >>> check_path_spelling("--out", "r.npz/")
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: --out 'r.npz/': ends with '/', a folder; give a file name
    """
    if path is None:
        return
    if path.strip() == "":
        raise InputError(f"{flag} is empty: give a {'folder' if folder else 'file'} name")
    if path == "-":
        raise InputError(f"{flag} -: results are not written to standard output; give a "
                         f"{'folder' if folder else 'file'} name (./- for a file named '-')")
    if not folder and path.endswith(("/", os.sep)):
        raise InputError(f"{flag} {printable(repr(path), 200)}: ends with '/', a folder; "
                         "give a file name")


def check_scheduler(address: str | None) -> None:
    """Refuse a ``--scheduler`` that is not a Dask address (``tcp://HOST:PORT``, or
    ``tls``, ``ws``, ``wss``, ``ucx``, ``inproc``) before any work.

    Examples
    --------
    >>> check_scheduler("tcp://127.0.0.1:8786")
    >>> check_scheduler("foo://x")
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: --scheduler 'foo://x': unknown scheme foo:// (tcp, ...)
    """
    if address is None:
        return
    shown = printable(repr(address), 200)
    scheme, sep, rest = address.partition("://")
    if not sep:
        scheme, rest = "tcp", address
    if scheme not in _SCHEMES:
        raise InputError(f"--scheduler {shown}: unknown scheme {printable(scheme, 40)}:// "
                         f"({', '.join(_SCHEMES)})")
    if scheme == "inproc":
        if not rest:
            raise InputError(f"--scheduler {shown}: no address after inproc://")
        return
    match = _HOST_PORT.fullmatch(rest)
    if not match or not 1 <= int(match.group(2)) <= 65535:
        raise InputError(f"--scheduler {shown}: not a scheduler address; give "
                         "tcp://HOST:PORT (e.g. tcp://127.0.0.1:8786)")


def _grasps_memory(args: argparse.Namespace) -> None:
    """Refuse a ``grasps`` run (or a ``dataset --gripper`` object) whose labels would not fit,
    before allocating them."""
    get = vars(args).get
    count = args.count
    per = BYTES_PER_GRASP
    robust = bool(get("robust"))
    samples = get("robust_samples") or 100
    if robust and not get("no_robust_epsilon"):
        per += BYTES_PER_ROBUST_SAMPLE * samples
    # dataset: each local worker labels an object at a time
    copies = (get("workers") or os.cpu_count() or 1) if (get("command") == "dataset"
                                                          and not get("scheduler")) else 1
    need = count * per * copies
    budget = memory_budget()
    if need > budget:
        what = (f"--count {count:,} x --robust-samples {samples:,}" if robust
                and per > BYTES_PER_GRASP else f"--count {count:,}")
        what += f" on {copies} workers at once" if copies > 1 else ""
        raise InputError(f"{what}: about {_size(need)} of labels ({_size(per)} a grasp), more "
                         f"than the {_size(budget)} this run may use (half this machine's "
                         "memory); sample in several runs with other --seed values")


def check_options(args: argparse.Namespace) -> None:
    """Check the numeric and path options of a parsed command line against their ranges,
    before any work.

    Raises
    ------
    InputError
        One line naming the option, its range and the value given.
    """
    get = vars(args).get
    command = get("command")
    seed = get("seed")
    if seed is not None and not 0 <= seed <= MAX_SEED:
        raise InputError(f"--seed must be a whole number from 0 to 2**63 - 1, got "
                         f"{printable(str(seed), 40)}")
    _at_most("--samples", get("samples"), MAX_SAMPLES)
    _at_most("--top", get("top"), MAX_TOP)
    _at_most("--chunk", get("chunk"), MAX_CHUNK)
    _at_most("--mu", get("mu"), MAX_MU)
    units = " (object units)"
    _at_least("--width", get("width"), MIN_WIDTH, units)
    for flag in ("width", "pad_radius", "clearance", "pose_sigma"):
        _at_most(f"--{flag.replace('_', '-')}", get(flag), MAX_LENGTH, why=units)
    for flag in ("angle_sigma", "normal_sigma"):
        _at_most(f"--{flag.replace('_', '-')}", get(flag), math.pi, why=" (radians)")
    _at_most("--mu-sigma", get("mu_sigma"), MAX_MU)
    _at_most("--task-mass", get("task_mass"), MAX_QUANTITY)
    _at_most("--f-max", get("f_max"), MAX_QUANTITY)
    _at_most("--approaches", get("approaches"), MAX_APPROACHES, why=" (0.1 degree steps)")
    _at_most("--depths", get("depths"), MAX_DEPTHS)
    _at_most("--robust-samples", get("robust_samples"), MAX_ROBUST_SAMPLES)
    _at_most("--plot-top", get("plot_top"), MAX_TOP)
    _at_most("--workers", get("workers"), 4096)
    if command == "dataset":
        for flag in ("out", "plot", "html"):  # folders: its results, pictures and pages
            check_path_spelling(f"--{flag}", get(flag), folder=True)
        for kind, path in get("export") or []:
            check_path_spelling(f"--export {printable(kind, 40)}", path, folder=True)
        check_scheduler(get("scheduler"))
    else:
        for flag in ("out", "plot", "html"):
            check_path_spelling(f"--{flag}", get(flag))
        for flag in ("graspnet", "acronym"):  # export: a file, or a folder for a dataset
            check_path_spelling(f"--{flag}", get(flag), folder=True)
        for kind, path in get("export") or []:
            check_path_spelling(f"--export {printable(kind, 40)}", path)
    count = get("count")
    if count is not None and count >= 0:
        _grasps_memory(args)
