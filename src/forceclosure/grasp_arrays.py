"""Grasps as arrays on disk: ``.npz`` files read and analysed in chunks.

A dataset of sampled grasps is four arrays, saved with ``numpy.savez`` (or
``savez_compressed``):

* ``points``, ``normals``: ``(N, k, d)``, ``d`` = 2 or 3 — required;
* ``mu``: a number, ``(k,)`` per contact slot, or ``(N, k)`` (default 0);
* ``model``: a string, or ``(k,)`` strings, each ``frictionless``, ``hard``
  or ``soft`` (default ``hard``);
* ``torsion``: like ``mu``, NaN for the paper's uncoupled soft finger
  (optional);
* ``cone``: ``"exact"`` (default) or ``"8-inscribed"``, ``"16-circumscribed"``, ….

:func:`analyze_npz` reads the per-grasp arrays straight from the archive a
chunk of rows at a time, so memory stays bounded whatever ``N`` is (the
results, about 10 bytes a grasp, are the only thing that grows). Rows with
bad numbers are reported, one line each, and left out; the others are
analysed.
"""

from __future__ import annotations

import zipfile
import zlib
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import IO

import numpy as np
from numpy.lib import format as npy
from numpy.typing import NDArray

from .batch import CHUNK, analyze_batch, epsilon_batch
from .contacts import MODELS, Cone
from .errors import InputError

#: Verdict codes in the result arrays; -1 marks a grasp with bad input.
ERROR = -1


class _Rows:
    """One ``.npy`` member of a zip archive, read a block of leading rows at a time."""

    def __init__(self, archive: zipfile.ZipFile, name: str, path: str) -> None:
        self.name = name
        self._file: IO[bytes] = archive.open(name + ".npy")
        try:
            version = npy.read_magic(self._file)
            read = npy.read_array_header_1_0 if version == (1, 0) else npy.read_array_header_2_0
            self.shape, fortran, self.dtype = read(self._file)
        except ValueError as e:
            raise InputError(f"{path}: array '{name}' is not a valid .npy array: {e}") from None
        if fortran and len(self.shape) > 1:
            raise InputError(f"{path}: array '{name}' is stored in Fortran order; save it with "
                             "numpy.ascontiguousarray first")
        if self.dtype.hasobject or self.dtype.kind not in "fiu":
            raise InputError(f"{path}: array '{name}' must hold numbers, not {self.dtype}")
        self._row = int(np.prod(self.shape[1:], dtype=np.int64)) * self.dtype.itemsize

    def read(self, rows: int) -> NDArray[np.float64]:
        try:
            data = self._file.read(rows * self._row)
        except (zipfile.BadZipFile, zlib.error, EOFError) as e:
            raise InputError(f"array '{self.name}' is damaged ({e})") from None
        got = len(data) // self._row if self._row else rows
        if len(data) != got * self._row:
            raise InputError(f"array '{self.name}' is truncated")
        return np.frombuffer(data, dtype=self.dtype).reshape(got, *self.shape[1:]).astype(float)


def _parse_cone(spec: str) -> str | Cone:
    if spec == "exact":
        return "exact"
    edges, _, fit = spec.partition("-")
    if not edges.isdigit() or fit not in ("inscribed", "circumscribed"):
        raise InputError(f"'cone' must be \"exact\" or like \"8-inscribed\", got {spec!r}")
    return Cone(int(edges), fit)  # type: ignore[arg-type]


@dataclass(frozen=True)
class GraspArrays:
    """What an ``.npz`` grasp file holds, before its rows are read."""

    path: str
    count: int
    contacts: int
    dim: int
    models: list[str]
    cone: str | Cone
    streamed: tuple[str, ...]
    constant: dict[str, NDArray[np.float64]]


def _small(archive: zipfile.ZipFile, name: str, path: str) -> NDArray:
    with archive.open(name + ".npy") as f:
        try:
            return npy.read_array(f, allow_pickle=False)
        except ValueError as e:
            raise InputError(f"{path}: array '{name}' cannot be read: {e}") from None


def open_npz(path: str) -> GraspArrays:
    """Check an ``.npz`` grasp file's arrays and shapes without reading its rows.

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> f = os.path.join(tempfile.mkdtemp(), "g.npz")
    >>> np.savez(f, points=np.zeros((5, 2, 3)), normals=np.ones((5, 2, 3)), mu=0.5,
    ...          model="soft")
    >>> info = open_npz(f)
    >>> info.count, info.contacts, info.dim, info.models
    (5, 2, 3, ['soft', 'soft'])
    """
    try:
        archive = zipfile.ZipFile(path)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (zipfile.BadZipFile, OSError):
        raise InputError(f"{path}: not an .npz archive") from None
    with archive:
        names = {n[:-4] for n in archive.namelist() if n.endswith(".npy")}
        missing = [n for n in ("points", "normals") if n not in names]
        if missing:
            raise InputError(f"{path}: missing array '{missing[0]}' (an .npz grasp file needs "
                             "'points' and 'normals', shape (N, k, 2 or 3))")
        unknown = sorted(names - {"points", "normals", "mu", "model", "torsion", "cone"})
        if unknown:
            raise InputError(f"{path}: unknown array '{unknown[0]}' (expected points, normals, "
                             "mu, model, torsion, cone)")
        shapes = {n: _Rows(archive, n, path).shape for n in ("points", "normals")}
        shape = shapes["points"]
        if len(shape) != 3 or shape[2] not in (2, 3) or shapes["normals"] != shape:
            raise InputError(f"{path}: 'points' and 'normals' must both have shape (N, k, 2 or "
                             f"3); got {shape} and {shapes['normals']}")
        n, k, d = shape
        models = ["hard"] * k
        if "model" in names:
            m = _small(archive, "model", path)
            models = [str(m)] * k if m.ndim == 0 else [str(x) for x in m]
            if len(models) != k or any(x not in MODELS for x in models):
                raise InputError(f"{path}: 'model' must be one of {', '.join(MODELS)}, or {k} "
                                 f"of them; got {m.tolist()}")
        cone: str | Cone = "exact"
        if "cone" in names:
            cone = _parse_cone(str(_small(archive, "cone", path)))
        streamed, constant = ["points", "normals"], {}
        for name in ("mu", "torsion"):
            if name not in names:
                continue
            rows = _Rows(archive, name, path)
            if rows.shape == (n, k):
                streamed.append(name)
            elif rows.shape in ((), (k,)):
                constant[name] = _small(archive, name, path).astype(float)
            else:
                raise InputError(f"{path}: '{name}' must be a number, shape ({k},) or ({n}, "
                                 f"{k}); got {rows.shape}")
    return GraspArrays(path, n, k, d, models, cone, tuple(streamed), constant)


def iter_chunks(info: GraspArrays, size: int = CHUNK) -> Iterator[dict[str, NDArray]]:
    """The per-grasp arrays, ``size`` rows at a time, as dicts keyed like the file."""
    with zipfile.ZipFile(info.path) as archive:
        readers = [_Rows(archive, name, info.path) for name in info.streamed]
        for lo in range(0, info.count, size):
            rows = min(size, info.count - lo)
            chunk = {r.name: r.read(rows) for r in readers}
            short = [name for name, v in chunk.items() if len(v) != rows]
            if short:
                raise InputError(f"{info.path}: array '{short[0]}' is truncated: it ends "
                                 f"before row {lo + rows}")
            chunk.update(info.constant)
            yield chunk


def _problems(chunk: dict[str, NDArray], offset: int) -> tuple[NDArray[np.bool_], list[str]]:
    """Rows with bad numbers, and a one-line message for each."""
    P, N = chunk["points"], chunk["normals"]
    n, k, _ = P.shape
    tests = [("'point' has a non-finite coordinate", ~np.all(np.isfinite(P), axis=2)),
             ("'normal' has a non-finite coordinate", ~np.all(np.isfinite(N), axis=2)),
             ("'normal' is a zero vector", np.linalg.norm(np.nan_to_num(N), axis=2) <= 1e-12)]
    for name in ("mu", "torsion"):
        if name in chunk:
            v = np.broadcast_to(chunk[name], (n, k))
            bad = (v < 0) | np.isinf(v) | (np.isnan(v) if name == "mu" else False)
            tests.append((f"'{name}' must be finite and >= 0", bad))
    bad_rows = np.zeros(n, dtype=bool)
    messages = []
    for what, flags in tests:
        rows = np.flatnonzero(flags.any(axis=1) & ~bad_rows)
        for g in rows:
            c = int(np.flatnonzero(flags[g])[0])
            messages.append((g, f"grasp {offset + g + 1}, contact {c + 1}: {what}"))
        bad_rows[rows] = True
    return bad_rows, [m for _, m in sorted(messages)]


@dataclass(frozen=True, eq=False)
class NpzResults:
    """Verdict codes (``-1`` bad input, 0 none, 1 marginal, 2 closure), ranks and margins.

    ``epsilon`` (when asked for) is each grasp's L1 Ferrari–Canny epsilon,
    0 where it is not force-closure and NaN where its input was bad.
    """

    code: NDArray[np.int8]
    rank: NDArray[np.int8]
    margin: NDArray[np.float64]
    errors: list[str]
    epsilon: NDArray[np.float64] | None = None

    def counts(self) -> dict[str, int]:
        """How many grasps got each verdict, and how many were refused."""
        return {name: int(np.sum(self.code == c))
                for name, c in (("closure", 2), ("marginal", 1), ("none", 0), ("errors", ERROR))}

    def save(self, path: str) -> None:
        """Write the results as an ``.npz``: ``verdict`` codes, ``rank``, ``margin``, ``names``
        and, if computed, ``epsilon``."""
        extra = {} if self.epsilon is None else {"epsilon": self.epsilon}
        np.savez(path, verdict=self.code, rank=self.rank, margin=self.margin,
                 names=np.array(["none", "marginal", "closure"]), **extra)


def analyze_npz(path: str, *, chunk: int = CHUNK, tol: float | None = None,
                epsilon: bool = False,
                progress: Callable[[int], object] | None = None) -> NpzResults:
    """Analyse every grasp of an ``.npz`` grasp file, a chunk at a time (Theorem 1).

    With ``epsilon``, also the Ferrari–Canny epsilon of the grasps found
    force-closure (:func:`forceclosure.batch.epsilon_batch`, L1, 8-edge
    inscribed pyramids).

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> f = os.path.join(tempfile.mkdtemp(), "g.npz")
    >>> P = np.array([[[-1, 0], [1, 0.2]], [[-1, 0], [1, 1.0]], [[-1, 0], [1, 0]]])
    >>> N = np.array([[[-1, 0], [1, 0]], [[-1, 0], [1, 0]], [[-1, 0], [0, 0]]])
    >>> np.savez(f, points=P, normals=N, mu=0.3)
    >>> r = analyze_npz(f)
    >>> r.code.tolist(), r.errors
    ([2, 0, -1], ["grasp 3, contact 2: 'normal' is a zero vector"])
    """
    from .closure import TOLERANCE

    tol = TOLERANCE if tol is None else tol
    info = open_npz(path)
    code = np.full(info.count, ERROR, dtype=np.int8)
    rank = np.zeros(info.count, dtype=np.int8)
    margin = np.full(info.count, np.nan)
    eps = np.full(info.count, np.nan) if epsilon else None
    errors: list[str] = []
    lo = 0
    parts = iter_chunks(info, chunk)
    while True:
        try:
            part = next(parts, None)
        except InputError as e:  # a truncated member: keep what was analysed before it
            errors.append(f"{e}; grasps {lo + 1} to {info.count} are not analysed")
            break
        if part is None:
            break
        rows = len(part["points"])
        bad, messages = _problems(part, lo)
        errors.extend(messages)
        good = np.flatnonzero(~bad)
        if len(good):
            mu = np.broadcast_to(part.get("mu", 0.0), (rows, info.contacts))[good]
            torsion = part.get("torsion")
            if torsion is not None:
                torsion = np.broadcast_to(torsion, (rows, info.contacts))[good]
            P, N = part["points"][good], part["normals"][good]
            r = analyze_batch(P, N, mu=mu, model=info.models, torsion=torsion, cone=info.cone,
                              tol=tol)
            code[lo + good] = r.code
            rank[lo + good] = r.rank
            margin[lo + good] = r.margin
            if eps is not None:
                eps[lo + good] = 0.0
                closed = np.flatnonzero(r.code == 2)
                eps[lo + good[closed]] = epsilon_batch(
                    P[closed], N[closed], mu=mu[closed], model=info.models,
                    torsion=None if torsion is None else torsion[closed], tol=tol)
        lo += rows
        if progress is not None:
            progress(rows)
    return NpzResults(code, rank, margin, errors, eps)
