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
analysed. Before anything is allocated, every array's size is checked
against the bytes actually in the file, so a small file cannot claim
millions of grasps.

Ctrl-C during :func:`analyze_npz` raises :class:`AnalysisInterrupted`, which
carries the results of the grasps done so far; :meth:`NpzResults.save` marks
them ``partial``, and ``analyze_npz(..., resume=...)`` goes on from there.
"""

from __future__ import annotations

import os
import zipfile
import zlib
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import IO, Any

import numpy as np
from numpy.lib import format as npy
from numpy.typing import NDArray

from ..analysis.batch import CHUNK, analyze_batch, epsilon_batch
from ..contacts import MAX_CONTACTS, MAX_QUALITY_CONTACTS, MODELS, Cone, parse_cone
from ..errors import InputError, clip
from ..files.atomic import atomic_write
from ..files.read import regular_file
from ..verdicts import ERROR, VERDICT_WORDS, VerdictCode, verdict_counts
from .grasp_file import MAX_COORDINATE

__all__ = ["ERROR", "AnalysisInterrupted", "GraspArrays", "NpzResults", "analyze_npz",
           "iter_chunks", "load_results", "open_npz", "resumable"]

#: The most a deflated zip member expands (deflate's limit is about 1032 to 1).
_DEFLATE_RATIO = 1100

#: The most bytes of per-grasp arrays read at a time, whatever ``chunk`` asks.
_CHUNK_BYTES = 2**28

#: A truncated array (its header claims more rows than it holds) is read up to where it ends;
#: it may claim this many rows whatever it holds, and no more than it holds beyond that.
_CLAIM_ROWS = 2**22


def _member_bytes(archive: zipfile.ZipFile, name: str, path: str, file_size: int) -> int:
    """The most bytes a member can hold, from the bytes really in the file: a member
    stored (as ``numpy.savez`` writes) holds what it occupies, a deflated one (as
    ``savez_compressed`` writes) at most ``_DEFLATE_RATIO`` times that."""
    info = archive.getinfo(name + ".npy")
    if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
        raise InputError(f"{path}: array '{name}' is compressed with a method numpy does not "
                         "write (save with numpy.savez or savez_compressed)")
    stored = min(info.compress_size, file_size)
    most = stored if info.compress_type == zipfile.ZIP_STORED else stored * _DEFLATE_RATIO
    return min(info.file_size, most)


#: What reading a damaged zip archive raises (zipfile's own errors and those beneath it).
_ZIP_ERRORS = (zipfile.BadZipFile, zlib.error, EOFError, OSError, ValueError,
               NotImplementedError, RuntimeError)


def _member(archive: zipfile.ZipFile, name: str, path: str) -> IO[bytes]:
    try:
        return archive.open(name + ".npy")
    except _ZIP_ERRORS as e:  # a bad local header, an encrypted or unsupported member
        raise InputError(f"{path}: array '{name}' is damaged: {clip(str(e))}") from None


def _open_member(archive: zipfile.ZipFile, name: str, path: str, whole: bool = True,
                 ) -> tuple[IO[bytes], tuple[int, ...], bool, np.dtype, int]:
    """A member opened past its ``.npy`` header, the header's shape, order and dtype, and the
    most bytes of data it can hold. With ``whole`` (an array read at once), refused unless
    it can hold the bytes its shape claims."""
    f = _member(archive, name, path)
    try:
        version = npy.read_magic(f)
        read = npy.read_array_header_1_0 if version == (1, 0) else npy.read_array_header_2_0
        shape, fortran, dtype = read(f)
    except _ZIP_ERRORS as e:
        f.close()
        raise InputError(f"{path}: array '{name}' is not a valid .npy array: "
                         f"{clip(str(e))}") from None
    claimed = int(np.prod(shape, dtype=object)) * dtype.itemsize
    most = max(0, _member_bytes(archive, name, path, regular_file(path)) - f.tell())
    if whole and claimed > most:
        f.close()
        raise InputError(f"{path}: array '{name}' claims shape {clip(str(shape), 80)} "
                         f"({claimed:,} bytes) but the file holds at most {most:,} bytes of it")
    return f, shape, fortran, dtype, most


class _Rows:
    """One ``.npy`` member of a zip archive, read a block of leading rows at a time."""

    def __init__(self, archive: zipfile.ZipFile, name: str, path: str) -> None:
        self.name = name
        self._file, self.shape, fortran, self.dtype, most = _open_member(archive, name, path,
                                                                         whole=False)
        if fortran and len(self.shape) > 1:
            raise InputError(f"{path}: array '{name}' is stored in Fortran order; save it with "
                             "numpy.ascontiguousarray first")
        if self.dtype.hasobject or self.dtype.kind not in "fiu":
            raise InputError(f"{path}: array '{name}' must hold numbers, not {self.dtype}")
        self._row = int(np.prod(self.shape[1:], dtype=object)) * self.dtype.itemsize
        #: how many rows the bytes in the file can hold, whatever the header claims
        self.held = most // self._row if self._row else 0

    def read(self, rows: int) -> NDArray[np.float64]:
        try:
            data = self._file.read(rows * self._row)
        except _ZIP_ERRORS as e:
            raise InputError(f"array '{self.name}' is damaged ({clip(str(e))})") from None
        got = len(data) // self._row if self._row else rows
        if len(data) != got * self._row:
            raise InputError(f"array '{self.name}' is truncated")
        return np.frombuffer(data, dtype=self.dtype).reshape(got, *self.shape[1:]).astype(float)


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
    _open_member(archive, name, path)[0].close()  # its size checked first
    with _member(archive, name, path) as f:
        try:
            return npy.read_array(f, allow_pickle=False)
        except _ZIP_ERRORS as e:
            raise InputError(f"{path}: array '{name}' cannot be read: {clip(str(e))}") from None


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
    regular_file(path)  # not a FIFO, a device or a symlink loop
    try:
        archive = zipfile.ZipFile(path)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except _ZIP_ERRORS:
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
        members = {n: _Rows(archive, n, path) for n in ("points", "normals")}
        shapes = {n: r.shape for n, r in members.items()}
        shape = shapes["points"]
        if len(shape) != 3 or shape[2] not in (2, 3) or shapes["normals"] != shape:
            raise InputError(f"{path}: 'points' and 'normals' must both have shape (N, k, 2 or "
                             f"3); got {shape} and {shapes['normals']}")
        n, k, d = shape
        if k == 0:
            raise InputError(f"{path}: 'points' has shape {shape}: every grasp needs at least "
                             "one contact")
        if k > MAX_CONTACTS:  # before any list or array of k is made
            raise InputError(f"{path}: 'points' has shape {shape}: {k:,} contacts a grasp; "
                             f"at most {MAX_CONTACTS:,} are analysed")
        held = min(r.held for r in members.values())
        if n > max(held, _CLAIM_ROWS):
            raise InputError(f"{path}: 'points' and 'normals' claim {n:,} grasps but the file "
                             f"holds at most {held:,}")
        models = ["hard"] * k
        if "model" in names:
            m = _small(archive, "model", path)
            models = [str(m)] * k if m.ndim == 0 else [str(x) for x in m]
            if len(models) != k or any(x not in MODELS for x in models):
                raise InputError(f"{path}: 'model' must be one of {', '.join(MODELS)}, or {k} "
                                 f"of them; got {m.tolist()}")
        cone: str | Cone = "exact"
        if "cone" in names:
            cone = parse_cone(str(_small(archive, "cone", path)))
        streamed = ["points", "normals"]
        constant: dict[str, NDArray[np.float64]] = {}
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


def iter_chunks(info: GraspArrays, size: int = CHUNK, start: int = 0,
                ) -> Iterator[dict[str, NDArray]]:
    """The per-grasp arrays, ``size`` rows at a time (fewer when a chunk would pass 256 MiB),
    as dicts keyed like the file, from row ``start`` on."""
    row_bytes = 8 * info.contacts * (2 * info.dim + len(info.streamed) - 2)
    size = max(1, min(size, _CHUNK_BYTES // row_bytes))
    with zipfile.ZipFile(info.path) as archive:
        readers = [_Rows(archive, name, info.path) for name in info.streamed]
        for lo in range(0, start, size):  # a zip member is read in order: skip the done rows
            rows = min(size, start - lo)
            if any(len(r.read(rows)) != rows for r in readers):
                raise InputError(f"{info.path}: an array is truncated: it ends before row "
                                 f"{lo + rows}")
        for lo in range(start, info.count, size):
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
    with np.errstate(over="ignore", invalid="ignore"):
        tests = [("'point' has a non-finite coordinate", ~np.all(np.isfinite(P), axis=2)),
                 ("'normal' has a non-finite coordinate", ~np.all(np.isfinite(N), axis=2)),
                 (f"'point' has a coordinate beyond {MAX_COORDINATE:g} in magnitude",
                  np.any(np.abs(P) > MAX_COORDINATE, axis=2)),
                 (f"'normal' has a coordinate beyond {MAX_COORDINATE:g} in magnitude",
                  np.any(np.abs(N) > MAX_COORDINATE, axis=2)),
                 ("'normal' is a zero vector",
                  np.linalg.norm(np.nan_to_num(N), axis=2) <= 1e-12)]
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
    ``done`` is how many grasps, from the first, were analysed: all of them
    (``None``) unless the run was interrupted; ``input`` the fingerprint of
    the grasp file (:func:`forceclosure.files.read.fingerprint`), when known.
    """

    code: NDArray[np.int8]
    rank: NDArray[np.int8]
    margin: NDArray[np.float64]
    errors: list[str]
    epsilon: NDArray[np.float64] | None = None
    done: int | None = None
    input: str | None = None

    @property
    def partial(self) -> bool:
        """Whether only the first :attr:`done` grasps were analysed (an interrupted run)."""
        return self.done is not None and self.done < len(self.code)

    def counts(self) -> dict[str, int]:
        """How many grasps got each verdict, and how many were refused."""
        return verdict_counts(self.code[:self.done], errors=True)

    def save(self, path: str) -> None:
        """Write the results as an ``.npz`` at exactly ``path`` (no ``.npz`` added),
        atomically: ``verdict`` codes, ``rank``, ``margin``, ``names``, if computed
        ``epsilon``, and ``done`` (grasps analysed), ``partial`` (whether that is fewer than
        all) and, when known, ``input`` (the grasp file's fingerprint).

        Examples
        --------
        >>> import os, tempfile
        >>> path = os.path.join(tempfile.mkdtemp(), "results")
        >>> NpzResults(np.array([2, -1], np.int8), np.array([3, 0], np.int8),
        ...            np.array([0.5, np.nan]), [], done=1).save(path)
        >>> saved = np.load(path)
        >>> saved["verdict"].tolist(), int(saved["done"]), bool(saved["partial"])
        ([2, -1], 1, True)
        """
        # Any: np.savez's stubs take a keyword argument for a flag of its own
        extra: dict[str, Any] = {} if self.epsilon is None else {"epsilon": self.epsilon}
        if self.input is not None:
            extra["input"] = np.array(self.input)
        done = len(self.code) if self.done is None else self.done
        with atomic_write(path) as f:
            np.savez(f, verdict=self.code, rank=self.rank, margin=self.margin,
                     names=np.array(VERDICT_WORDS), done=np.int64(done),
                     partial=np.bool_(self.partial), **extra)


def load_results(path: str) -> NpzResults:
    """The results saved by :meth:`NpzResults.save` (a file from before ``done`` existed is
    taken as complete); :class:`~forceclosure.errors.InputError` if it is not one."""
    regular_file(path)
    try:
        with np.load(path, allow_pickle=False) as saved:
            arrays = {k: saved[k] for k in ("verdict", "rank", "margin", "epsilon", "done",
                                            "input") if k in saved.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, zlib.error) as e:
        raise InputError(f"{path}: not a results file: {clip(str(e))}") from None
    code = arrays.get("verdict")
    n = -1 if code is None or code.ndim != 1 else len(code)
    shapes_ok = n >= 0 and all(arrays[k].shape == (n,) for k in ("rank", "margin", "epsilon")
                               if k in arrays) and {"rank", "margin"} <= set(arrays)
    done = arrays.get("done", np.int64(n))
    if code is None or not shapes_ok or done.shape != () or not 0 <= int(done) <= n:
        raise InputError(f"{path}: not a results file of 'forceclosure analyze --out'")
    return NpzResults(code.astype(np.int8), arrays["rank"].astype(np.int8),
                      arrays["margin"].astype(float), [],
                      arrays["epsilon"].astype(float) if "epsilon" in arrays else None,
                      int(done) if int(done) < n else None,
                      str(arrays["input"]) if "input" in arrays else None)


class AnalysisInterrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`analyze_npz`; ``results`` holds the grasps analysed before it
    (``results.done`` of them; the later rows are ``-1``)."""

    def __init__(self, results: NpzResults) -> None:
        super().__init__(f"interrupted after {results.done:,} of {len(results.code):,} grasps")
        self.results = results



def resumable(path: str, source: str, epsilon: bool) -> NpzResults | None:
    """The partial results at ``path`` that a run on the grasp file whose fingerprint is
    ``source`` (:func:`forceclosure.files.read.fingerprint`) resumes (``analyze_npz(...,
    resume=)``), or None where there are none to resume (no file, not a results file, or
    complete results: a new run replaces them).

    Raises
    ------
    InputError
        The partial results are of another grasp file (or another version of it), or were
        computed with ``epsilon`` other than asked.
    """
    if not os.path.exists(path):
        return None
    try:
        saved = load_results(path)
    except InputError:
        return None  # not results of a partial run: replaced, as any complete file is
    if not saved.partial:
        return None
    if saved.input != source:
        raise InputError(f"{clip(path)}: holds the partial results of another grasp file (or "
                         "of an earlier version of this one); remove it to start again, or "
                         "write elsewhere")
    if (saved.epsilon is not None) != epsilon:
        flag = "with" if saved.epsilon is not None else "without"
        raise InputError(f"{clip(path)}: holds partial results computed {flag} epsilon; "
                         f"resume {flag} it, or remove the file to start again")
    return saved

def analyze_npz(path: str, *, chunk: int = CHUNK, tol: float | None = None,
                epsilon: bool = False,
                progress: Callable[[int], object] | None = None,
                resume: NpzResults | None = None) -> NpzResults:
    """Analyse every grasp of an ``.npz`` grasp file, a chunk at a time (Theorem 1).

    With ``epsilon``, also the Ferrari–Canny epsilon of the grasps found
    force-closure (:func:`forceclosure.analysis.batch.epsilon_batch`, L1, 8-edge
    inscribed pyramids). With ``resume`` (partial results of the same file
    and options, from :class:`AnalysisInterrupted` or :func:`load_results`),
    the grasps it has done are kept and skipped. Ctrl-C raises
    :class:`AnalysisInterrupted` with the grasps done so far.

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
    from ..analysis.closure import TOLERANCE

    tol = TOLERANCE if tol is None else tol
    info = open_npz(path)
    if epsilon and info.dim == 3 and info.contacts > MAX_QUALITY_CONTACTS:
        raise InputError(f"{path}: {info.contacts:,} spatial contacts a grasp: epsilon is "
                         f"computed for at most {MAX_QUALITY_CONTACTS} (minutes a grasp beyond); "
                         "the verdicts alone are not limited by it (analyse without epsilon)")
    if resume is not None:
        _check_resume(resume, info, epsilon)
    code = np.full(info.count, ERROR, dtype=np.int8)
    rank = np.zeros(info.count, dtype=np.int8)
    margin = np.full(info.count, np.nan)
    eps = np.full(info.count, np.nan) if epsilon else None
    lo = 0
    if resume is not None and resume.done is not None:
        lo = resume.done
        code[:lo], rank[:lo], margin[:lo] = resume.code[:lo], resume.rank[:lo], resume.margin[:lo]
        if eps is not None and resume.epsilon is not None:
            eps[:lo] = resume.epsilon[:lo]
    errors: list[str] = []
    parts = iter_chunks(info, chunk, start=lo)
    reported = 0
    try:
        while True:
            reported = len(errors)
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
                _analyse_rows(part, good, lo, info, tol, (code, rank, margin, eps))
            lo += rows
            reported = len(errors)
            if progress is not None:
                progress(rows)
    except KeyboardInterrupt:
        code[lo:], rank[lo:], margin[lo:] = ERROR, 0, np.nan
        if eps is not None:
            eps[lo:] = np.nan
        raise AnalysisInterrupted(NpzResults(code, rank, margin, errors[:reported], eps,
                                             done=lo)) from None
    return NpzResults(code, rank, margin, errors, eps)


def _check_resume(resume: NpzResults, info: GraspArrays, epsilon: bool) -> None:
    if len(resume.code) != info.count or (resume.epsilon is not None) != epsilon:
        raise InputError(f"{info.path}: the results to resume are of {len(resume.code):,} "
                         f"grasps{' with' if resume.epsilon is not None else ' without'} "
                         f"epsilon; this run has {info.count:,} grasps"
                         f"{' with' if epsilon else ' without'} epsilon")


def _analyse_rows(part: dict[str, NDArray], good: NDArray[np.intp], lo: int,
                  info: GraspArrays, tol: float, out: tuple) -> None:
    """Verdicts (and epsilons) of a chunk's good rows, into the result arrays at ``lo``."""
    code, rank, margin, eps = out
    rows = len(part["points"])
    mu = np.broadcast_to(part.get("mu", 0.0), (rows, info.contacts))[good]
    torsion = part.get("torsion")
    if torsion is not None:
        torsion = np.broadcast_to(torsion, (rows, info.contacts))[good]
    P, N = part["points"][good], part["normals"][good]
    r = analyze_batch(P, N, mu=mu, model=info.models, torsion=torsion, cone=info.cone, tol=tol)
    code[lo + good] = r.code
    rank[lo + good] = r.rank
    margin[lo + good] = r.margin
    if eps is not None:
        eps[lo + good] = 0.0
        closed = np.flatnonzero(r.code == VerdictCode.CLOSURE)
        eps[lo + good[closed]] = epsilon_batch(
            P[closed], N[closed], mu=mu[closed], model=info.models,
            torsion=None if torsion is None else torsion[closed], tol=tol)
