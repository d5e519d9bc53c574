"""Two fingers with friction in closed form (Nguyen 1988, Corollary 3).

Two contacts with friction at ``P`` and ``Q`` are force-closure — planar
hard fingers, or spatial soft fingers — iff the segment ``PQ``, or ``QP``,
points strictly out of the friction cone at ``P`` and into the one at ``Q``:
the fingers squeeze the object,

    angle(Q - P, -n_P) < atan(mu_P)   and   angle(P - Q, -n_Q) < atan(mu_Q),

or spread apart inside it (both angles measured from ``P - Q`` and ``Q -
P`` instead). In the plane that is exact (iff) for any friction, costs
O(1), and gives the least friction that closes the pair, ``mu* =
tan(max(angle_P, angle_Q))`` (the smaller of the two ways). Two *hard*
fingers in space are never force-closure: nothing resists rotation about
the line ``PQ`` (the wrenches have rank 5).

**In space the condition is sufficient, and necessary only when the two
normals are antiparallel.** The paper states it as iff, but a soft finger's
torques about two non-parallel normals span a plane of torques on their
own, so a squeeze whose direction lies in both cones but off ``PQ`` can
complete torque closure (docs/analysis.md works an example). Such pairs are
decided exactly all the same, in closed form: with ``beta`` the angle between
``n_Q`` and ``-n_P`` and ``psi`` the angle between the line of ``n_Q - n_P``
and that of ``PQ`` projected on the plane of the two normals, the pair closes
iff the cones' half-angle exceeds ``beta / 2 + psi`` (docs/analysis.md
derives it, for unequal friction too). The compiled engine uses it (and the
general test, Theorem 1, where it is ill-conditioned); the reference engine
uses Theorem 1, so the two check each other.

Everything here is vectorised over any number of pairs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..contacts import MAX_COORDINATE, point_contact, unit_rows
from ..errors import InputError
from ..geometry.cones import angle_between as _angle
from ..verdicts import VerdictCode
from .batch_analysis import Engine, VerdictCodes, analyze_batch
from .closure import TOLERANCE, analyze, check_tolerance

__all__ = ["SERIAL_BELOW", "PairClosure", "pair_codes", "pair_labels", "pair_least_friction",
           "two_finger_closure"]



@dataclass(frozen=True, eq=False)
class PairClosure(VerdictCodes):
    """Corollary 3 for ``N`` pairs.

    Attributes
    ----------
    code : (N,) int8 array
        0 ``none``, 1 ``marginal``, 2 ``closure``: the verdict, compactly.
    least_friction : (N,) array
        The least friction coefficient, the same at both fingers, above which
        the pair closes: ``tan(max(angle_p, angle_q))`` for antiparallel
        normals (and in the plane), the closed form above for other
        spatial soft pairs; ``inf`` when no friction can close it (an angle
        of 90 degrees or more either way, coincident points, parallel
        normals, or hard fingers in space).
    verdict : (N,) array of str
        ``"closure"``, ``"marginal"`` or ``"none"`` (made from ``code`` on use).
    angle_p, angle_q : (N,) arrays
        Angles (radians) between ``PQ`` and ``-n_P``, and ``QP`` and ``-n_Q``
        (computed on use; a spreading pair has both above 90 degrees).
    """

    code: NDArray[np.int8]
    least_friction: NDArray[np.float64]
    _pairs: tuple[NDArray[np.float64], ...] = field(repr=False)
    #: ``_pairs`` as given, to be conditioned on use (the angles)
    _raw: bool = field(default=False, repr=False)

    def _conditioned_pairs(self) -> tuple[NDArray[np.float64], ...]:
        return _conditioned(*self._pairs) if self._raw else self._pairs

    @property
    def angle_p(self) -> NDArray[np.float64]:
        """Angle between ``Q - P`` and ``-n_P``."""
        p, n_p, q, _ = self._conditioned_pairs()
        return _angle(q - p, -n_p)

    @property
    def angle_q(self) -> NDArray[np.float64]:
        """Angle between ``P - Q`` and ``-n_Q``."""
        p, _, q, n_q = self._conditioned_pairs()
        return _angle(p - q, -n_q)


def _check_pair_model(model: Any) -> None:
    """Corollary 3 is for point contacts with friction: soft or hard fingers."""
    if model not in ("soft", "hard"):
        raise InputError(f"model must be 'soft' or 'hard' for Corollary 3, got {model!r}")


def _array(value: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"'{name}' must be an array of numbers") from None


def two_finger_closure(p: ArrayLike, n_p: ArrayLike, q: ArrayLike, n_q: ArrayLike,
                       mu_p: ArrayLike, mu_q: ArrayLike | None = None, *,
                       model: str = "soft", tol: float = TOLERANCE,
                       engine: Engine = "compiled") -> PairClosure:
    """Corollary 3: are two frictional contacts force-closure? Vectorised.

    Parameters
    ----------
    p, q : (..., d) arrays
        Contact points, ``d`` = 2 or 3.
    n_p, n_q : (..., d) arrays
        Outward normals there (any length but zero).
    mu_p, mu_q : arrays broadcastable to ``(...)``
        Friction coefficients (``mu_q`` defaults to ``mu_p``).
    model : {"soft", "hard"}
        In the plane both mean the same. In space the corollary needs soft
        fingers (the paper's uncoupled torque); ``"hard"`` pairs are never
        force-closure (rank 5).
    tol : float
        Angles within ``tol`` radians of the cone's half-angle are
        ``marginal``.
    engine : {"compiled", "reference"}
        The compiled kernel (:mod:`forceclosure.kernels.pairs`, on slices in
        threads from :data:`SERIAL_BELOW` pairs; spatial soft pairs in closed
        form) or the NumPy reference computing the angles (spatial soft pairs
        failing Corollary 3 by Theorem 1). They return the
        same verdicts, but within the tolerance band of the boundary, where one
        may say ``marginal`` and the other not.

    Returns
    -------
    PairClosure

    Examples
    --------
    >>> r = two_finger_closure([-1, 0], [-1, 0], [1, 0.2], [1, 0], 0.3)
    >>> str(r.verdict), round(float(r.least_friction), 3)
    ('closure', 0.1)
    """
    p, q, n_p, n_q = (_array(v, name) for v, name in
                      ((p, "p"), (q, "q"), (n_p, "n_p"), (n_q, "n_q")))
    d = p.shape[-1] if p.ndim else 0
    if d not in (2, 3) or any(a.ndim == 0 or a.shape[-1] != d for a in (q, n_p, n_q)):
        raise InputError("p, n_p, q, n_q must all have 2 or all have 3 coordinates")
    mu_p = _array(mu_p, "mu_p")
    mu_q = mu_p if mu_q is None else _array(mu_q, "mu_q")
    for name, mu in (("mu_p", mu_p), ("mu_q", mu_q)):
        if not (math.isfinite(one := float(mu.flat[0])) and one >= 0 if mu.size == 1
                else np.all(np.isfinite(mu)) and not np.any(mu < 0)):
            raise InputError(f"'{name}' must be finite and >= 0")
    _check_pair_model(model)
    tol = check_tolerance(tol)
    if engine not in ("compiled", "reference"):
        raise InputError(f"engine must be 'compiled' or 'reference', got {engine!r}")
    try:
        shape = p.shape[:-1]
        if not (p.shape == q.shape == n_p.shape == n_q.shape and mu_p.ndim == mu_q.ndim == 0):
            shape = np.broadcast_shapes(shape, q.shape[:-1], n_p.shape[:-1], n_q.shape[:-1],
                                        mu_p.shape, mu_q.shape)
    except ValueError:
        raise InputError("p, n_p, q, n_q, mu_p and mu_q do not broadcast to one shape") from None
    if engine == "reference":
        _check_coordinates(p, q)
        p, n_p, q, n_q = _conditioned(p, n_p, q, n_q)
        code, least = _reference(p, n_p, q, n_q, mu_p, mu_q, model, tol)
    else:
        code, least = _compiled(p, n_p, q, n_q, mu_p, mu_q, model, tol, shape)
    return PairClosure(np.asarray(code, dtype=np.int8).reshape(shape),
                       np.asarray(least, dtype=float).reshape(shape), (p, n_p, q, n_q),
                       _raw=engine != "reference")


def _check_coordinates(p, q) -> None:
    """Raise if a finite coordinate of ``p`` or ``q`` is too large to compute with."""
    for name, a in (("p", p), ("q", q)):
        with np.errstate(invalid="ignore"):
            if np.any(np.isfinite(a) & (np.abs(a) > MAX_COORDINATE)):  # non-finite: later
                raise InputError(f"'{name}' has a coordinate beyond {MAX_COORDINATE:g}, too "
                                 "large to compute with")


def _conditioned(p: NDArray[np.float64], n_p: NDArray[np.float64], q: NDArray[np.float64],
                 n_q: NDArray[np.float64]) -> tuple[NDArray[np.float64], ...]:
    """Unit normals (without overflow), and pairs with coordinates beyond ``2**64`` divided by
    a power of two (exact; the verdict does not depend on units). Zero, tiny and non-finite
    values are left for the checks that name them."""
    if not all(np.all(np.isfinite(a)) for a in (p, q, n_p, n_q)):
        return p, n_p, q, n_q
    normals = []
    for n in (n_p, n_q):
        unit, length = unit_rows(n)
        normals.append(np.where(length[..., None] > 1e-12, unit, n))
    big = np.maximum(np.max(np.abs(p), axis=-1), np.max(np.abs(q), axis=-1))
    if np.any(big > 2.0**64):
        scale = np.where(big > 2.0**64, np.ldexp(1.0, np.minimum(np.frexp(big)[1], 1023)), 1.0)
        p, q = p / scale[..., None], q / scale[..., None]
    return p, normals[0], q, normals[1]


def pair_codes(points: ArrayLike, normals: ArrayLike, mu: ArrayLike, model: str = "soft",
               torsion: ArrayLike | None = None) -> NDArray[np.int8]:
    """Verdict codes (0 none, 1 marginal, 2 closure; exact cones) of ``(N, 2, d)`` pairs.

    Spatial soft pairs with the paper's uncoupled torque (``torsion`` None)
    and planar pairs are decided in closed form (:func:`two_finger_closure`,
    Theorem 1 only where that is ill-conditioned); other pairs by
    :func:`forceclosure.analysis.batch.analyze_batch`. ``mu`` is one value, or one
    per pair, or ``(N, 2)``.

    Examples
    --------
    >>> P = np.array([[[-1, 0, 0], [1, 0.5, 0.3]]])
    >>> N = np.array([[[-1, 0.2, 0], [1, 0, 0.1]]])
    >>> pair_codes(P, N, 0.5).tolist(), pair_codes(P, N, 0.5, "hard").tolist()
    ([2], [0])
    """
    points = np.asarray(points, dtype=float)
    normals = np.asarray(normals, dtype=float)
    if points.ndim != 3 or points.shape[1] != 2:
        raise InputError(f"points must have shape (N, 2, 2 or 3); got {points.shape}")
    try:
        mu = np.asarray(mu, dtype=float)
        mu = np.broadcast_to(mu if mu.ndim == 2 else mu.reshape(-1, 1), (len(points), 2))
    except (TypeError, ValueError):
        raise InputError(f"'mu' of shape {np.shape(mu)} does not fit {len(points)} pairs: "
                         "give one value, one per pair, or (N, 2)") from None
    if torsion is None and model in ("soft", "hard") and (model == "soft"
                                                            or points.shape[2] == 2):
        return two_finger_closure(points[:, 0], normals[:, 0], points[:, 1], normals[:, 1],
                                  mu[:, 0], mu[:, 1], model=model).code
    return analyze_batch(points, normals, mu=mu, model=model, torsion=torsion).code


#: Largest friction coefficient tried; beyond it cones are numerically half-spaces
#: (:func:`forceclosure.analysis.friction.least_friction` and the μ* here: ``inf`` above it).
MU_MAX = 1e4

#: Pairs below which :func:`pair_labels` and the pair kernel run on the calling thread (about
#: 3 ms of work); at and above it, one slice per thread, in threads that sleep between calls.
SERIAL_BELOW = 1 << 14


def pair_labels(points: ArrayLike, normals: ArrayLike, mu: float, model: str = "soft",
                tol: float = TOLERANCE) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
    """Verdict codes and least friction of ``(N, 2, d)`` contact pairs, in one compiled pass.

    The verdict (0 none, 1 marginal, 2 closure; exact cones) at friction ``mu`` and
    μ*, the least friction closing each pair (``inf``: none up to
    :data:`~forceclosure.analysis.friction.MU_MAX` does), of soft fingers with the
    paper's uncoupled torque (spatial) or of any two fingers in the plane, in closed
    form (Corollary 3, and its exact spatial form); ``model="hard"`` spatial pairs are
    never closed (rank 5). The same answers as :func:`pair_codes` and
    :func:`~forceclosure.analysis.batch.least_friction_batch` give, but validation and
    conditioning (unit normals, huge coordinates in units of a power of two) run inside
    the kernel: a row that cannot be decided raises one
    :class:`~forceclosure.errors.InputError` naming the first such pair. Below
    :data:`SERIAL_BELOW` pairs it runs on the calling thread, above it on one slice
    per thread (numba's thread count). The few spatial pairs whose closed form is
    ill-conditioned (nearly parallel normals) are decided by Theorem 1.

    Examples
    --------
    >>> P = np.array([[[-1, 0, 0], [1, 0.2, 0]], [[-1, 0, 0], [1, 0.5, 0.3]]])
    >>> N = np.array([[[-1.0, 0, 0], [1, 0, 0]], [[-1, 0.2, 0], [1, 0, 0.1]]])
    >>> code, least = pair_labels(P, N, 0.3)
    >>> code.tolist(), least.round(4).tolist()
    ([2, 0], [0.1, 0.4951])
    >>> pair_labels(P, N, 0.3, "hard")[0].tolist()
    [0, 0]
    """
    from ..kernels import announce_compiling, kernel_array
    from ..kernels import pairs as kernel

    points = kernel_array(_array(points, "points"))
    normals = kernel_array(_array(normals, "normals"))
    if points.ndim != 3 or points.shape[1] != 2 or points.shape[2] not in (2, 3):
        raise InputError(f"points must have shape (N, 2, 2 or 3); got {points.shape}")
    if normals.shape != points.shape:
        raise InputError(f"normals must have the shape of points, {points.shape}; got "
                         f"{normals.shape}")
    try:
        mu = float(mu)
    except (TypeError, ValueError):
        raise InputError(f"'mu' must be one number, got {mu!r}") from None
    if not math.isfinite(mu) or mu < 0:
        raise InputError(f"'mu' must be finite and >= 0, got {mu!r}")
    _check_pair_model(model)
    tol = check_tolerance(tol)
    n = len(points)
    code = np.empty(n, dtype=np.int8)
    least = np.empty(n)
    if n == 0:
        return code, least
    announce_compiling(kernel.pair_labels_kernel)
    flagged = kernel.pair_labels(points, normals, mu, float(tol), model == "hard", MU_MAX,
                                 MAX_COORDINATE, code, least, SERIAL_BELOW)
    if not flagged:
        return code, least
    bad = np.flatnonzero(code >= kernel.ZERO_NORMAL)
    if len(bad):
        i = int(bad[0])
        what = {kernel.ZERO_NORMAL: "a normal is a zero vector",
                kernel.TOO_LARGE: f"a point has a coordinate beyond {MAX_COORDINATE:g}, too "
                                  "large to compute with"}.get(
            int(code[i]), "a point or normal has a non-finite coordinate")
        raise InputError(f"pair at index {i}: {what}")
    undecided = np.flatnonzero(code == kernel.UNDECIDED)
    if len(undecided):  # spatial soft pairs beyond the closed form: Theorem 1, compiled
        code[undecided] = analyze_batch(points[undecided], normals[undecided], mu=mu,
                                        model="soft", tol=tol).code
    return code, least


def pair_least_friction(p: NDArray[np.float64], n_p: NDArray[np.float64],
                        q: NDArray[np.float64], n_q: NDArray[np.float64]
                        ) -> NDArray[np.float64]:
    """The least friction of ``(N, d)`` pairs of soft fingers (planar: any fingers), compiled
    (the pair kernel, whose verdicts at friction 1 are dropped). Inputs as
    :func:`two_finger_closure` checks them; exact cones."""
    from ..kernels import announce_compiling, kernel_array
    from ..kernels import pairs as kernel

    code = np.empty(len(p), dtype=np.int8)
    least = np.empty(len(p))
    one = np.ones(1)
    announce_compiling(kernel.pair_verdict_kernel)
    kernel.pair_verdicts(kernel_array(p), kernel_array(n_p), kernel_array(q), kernel_array(n_q),
                         one, one, 0.0, False, MAX_COORDINATE, code, least, SERIAL_BELOW)
    return least


def _compiled(p, n_p, q, n_q, mu_p, mu_q, model, tol, shape):
    """The pairs in one compiled pass that also validates and conditions each row
    (:func:`forceclosure.kernels.pairs.pair_verdict_kernel`); rows it flags as bad input are
    reported as before (:func:`_compiled_checked`)."""
    from ..kernels import announce_compiling, kernel_array
    from ..kernels import pairs as kernel

    def rows(a: NDArray[np.float64], tail: tuple[int, ...]) -> NDArray[np.float64]:
        if a.shape[: len(a.shape) - len(tail)] != shape:  # broadcast only when needed
            a = np.broadcast_to(a, (*shape, *tail))
        return kernel_array(a.reshape(-1, *tail))

    flat = [rows(a, (a.shape[-1],)) for a in (p, n_p, q, n_q)]
    # one friction value for all pairs stays one value (the kernel reads it for each)
    mus = [kernel_array(m.reshape(1)) if m.size == 1 else rows(m, ()) for m in (mu_p, mu_q)]
    n = flat[0].shape[0]
    code = np.empty(n, dtype=np.int8)
    least = np.empty(n)
    hard = p.shape[-1] == 3 and model == "hard"
    announce_compiling(kernel.pair_verdict_kernel)
    flagged = kernel.pair_verdicts(*flat, *mus, float(tol), hard, MAX_COORDINATE, code, least,
                                   SERIAL_BELOW)
    if not flagged:
        return code, least
    if np.any(code >= kernel.ZERO_NORMAL):  # bad input: named as the checks name it
        _compiled_checked(p, n_p, q, n_q, shape, code)
    undecided = np.flatnonzero(code == kernel.UNDECIDED)
    if len(undecided):  # spatial soft pairs beyond Corollary 3: Theorem 1, compiled
        _theorem1(flat, mus, undecided, n, tol, code)
    return code, least


def _theorem1(flat, mus, undecided, n, tol, code) -> None:
    """Decide the ``undecided`` spatial soft pairs by Theorem 1 (compiled) into ``code``."""
    P = np.stack([flat[0][undecided], flat[2][undecided]], axis=1)
    N = np.stack([flat[1][undecided], flat[3][undecided]], axis=1)
    mu = np.stack([np.broadcast_to(m, (n,))[undecided] for m in mus], axis=1)
    code[undecided] = analyze_batch(P, N, mu=mu, model="soft", tol=tol).code


def _compiled_checked(p, n_p, q, n_q, shape, code) -> None:
    """Raise the one-line error naming the bad input the kernel flagged in ``code``, as the
    checks before the compiled pass always named it: a coordinate too large (``p``, then
    ``q``), else the first pair whose normal is a zero vector or whose values are not finite
    (with non-finite values anywhere, pairs are read unconditioned, as the checks did)."""
    from ..kernels import pairs as kernel

    _check_coordinates(p, q)
    p, n_p, q, n_q = _conditioned(p, n_p, q, n_q)
    d = p.shape[-1]
    p, n_p, q, n_q = (np.broadcast_to(a, (*shape, d)).reshape(-1, d) for a in (p, n_p, q, n_q))
    v = q - p
    with np.errstate(over="ignore", invalid="ignore"):
        pq2, np2, nq2, cp, cq = (sum(x[:, k] * y[:, k] for k in range(d))
                                 for x, y in ((v, v), (n_p, n_p), (n_q, n_q), (v, -n_p),
                                              (v, n_q)))
        non_finite = ~np.isfinite(pq2 + np2 + nq2 + cp + cq)
    zero = (np2 <= 1e-24) | (nq2 <= 1e-24)
    bad = np.flatnonzero(non_finite | zero)
    i = int(bad[0]) if len(bad) else int(np.flatnonzero(code >= kernel.ZERO_NORMAL)[0])
    index = tuple(int(k) for k in np.unravel_index(i, shape)) if len(shape) > 1 else i
    where = f"pair at index {index}" if shape else "the pair"
    what = ("a point or normal has a non-finite coordinate"
            if non_finite[i] or code[i] == kernel.NON_FINITE else "a normal is a zero vector")
    raise InputError(f"{where}: {what}")


def _soft_least(pq, a, b, antiparallel_least):
    """The least friction of spatial soft pairs (unit normals ``a``, ``b``), in NumPy:
    ``tan(beta / 2 + psi)`` (see the module's text), Corollary 3's value for antiparallel
    normals, ``inf`` for parallel ones or ``PQ`` along ``a x b``."""
    m = np.cross(a, b)
    sin_b = np.linalg.norm(m, axis=-1)
    antiparallel = np.sum((a + b) ** 2, axis=-1) <= 1e-18
    parallel = np.sum((a - b) ** 2, axis=-1) <= 1e-18
    general = ~(antiparallel | parallel)
    with np.errstate(invalid="ignore", divide="ignore"):
        m = m / sin_b[..., None]
        beta = np.arctan2(sin_b, -np.sum(a * b, axis=-1))
        w = pq - np.sum(pq * m, axis=-1)[..., None] * m
        off_plane = np.sum(w * w, axis=-1) <= 1e-24 * np.sum(pq * pq, axis=-1)
        c = b - a
        psi = np.arctan2(np.linalg.norm(np.cross(w, c), axis=-1),
                         np.abs(np.sum(w * c, axis=-1)))
        angle = 0.5 * beta + psi
        exact = np.where(off_plane | (angle >= np.pi / 2), np.inf,
                         np.tan(np.minimum(angle, np.pi / 2)))
    return np.where(antiparallel, antiparallel_least,
                    np.where(general, exact, np.inf))


def _reference(p, n_p, q, n_q, mu_p, mu_q, model, tol):
    """The angles of Corollary 3, in NumPy; spatial pairs it cannot settle by ``analyze``."""
    if not all(np.all(np.isfinite(a)) for a in (p, q, n_p, n_q)):
        raise InputError("a point or normal has a non-finite coordinate")
    d = p.shape[-1]
    norm_p = np.linalg.norm(n_p, axis=-1, keepdims=True)
    norm_q = np.linalg.norm(n_q, axis=-1, keepdims=True)
    if np.any(norm_p <= 1e-12) or np.any(norm_q <= 1e-12):
        raise InputError("a normal is a zero vector")
    pq = q - p
    angle_p = _angle(pq, -n_p / norm_p)
    angle_q = _angle(-pq, -n_q / norm_q)
    code = np.zeros(np.shape(angle_p), dtype=np.int8)
    worst = np.full(np.shape(angle_p), np.pi)
    for a_p, a_q in ((angle_p, angle_q), (np.pi - angle_p, np.pi - angle_q)):  # PQ, or QP
        gap = np.maximum(a_p - np.arctan(mu_p), a_q - np.arctan(mu_q))
        code = np.maximum(code, np.where(gap < -tol, 2, np.where(gap > tol, 0, 1)))
        worst = np.minimum(worst, np.maximum(a_p, a_q))
    scale = np.maximum(np.max(np.abs(p), axis=-1), np.max(np.abs(q), axis=-1))
    apart = np.linalg.norm(pq, axis=-1) > 1e-12 * np.maximum(scale, 1.0)
    code = np.where(apart, code, 0)
    least = np.where(apart & (worst < np.pi / 2), np.tan(np.minimum(worst, np.pi / 2)), np.inf)
    if d == 3 and model != "hard":
        unit_p, unit_q = n_p / norm_p, n_q / norm_q
        least = np.where(apart, _soft_least(pq, unit_p, unit_q, least), np.inf)
    if d == 3 and model == "hard":
        code = np.zeros_like(code)
        least = np.full_like(least, np.inf)
    elif d == 3:
        unit_p, unit_q = n_p / norm_p, n_q / norm_q
        antiparallel = np.linalg.norm(unit_p + unit_q, axis=-1) <= 1e-9
        code = np.array(code)
        open_ = np.argwhere((code != VerdictCode.CLOSURE) & apart & ~antiparallel)
        if len(open_):
            shape = code.shape
            P, Q, NP, NQ = (np.broadcast_to(a, (*shape, 3)) for a in (p, q, unit_p, unit_q))
            MP, MQ = np.broadcast_to(mu_p, shape), np.broadcast_to(mu_q, shape)
            for idx in map(tuple, open_):
                grasp = [point_contact(P[idx], NP[idx], "soft", float(MP[idx])),
                         point_contact(Q[idx], NQ[idx], "soft", float(MQ[idx]))]
                code[idx] = analyze(grasp, tol=tol).verdict.code
    return code, least
