"""Theorem 1 on many grasps at once: arrays in, arrays out.

:func:`analyze_batch` takes ``N`` grasps of ``k`` point contacts as arrays
and returns arrays of verdicts, ranks, margins and unresisted twists, with
the same meaning as :func:`forceclosure.analyze`. Contacts in one slot share
a contact model. The compiled engine (:mod:`forceclosure.kernels`) decides
grasps in parallel and hands the few it cannot settle with a clear margin to
the reference path; ``engine="reference"`` runs the reference path on every
grasp. Both give the same verdicts. Work proceeds in chunks, so memory stays
bounded however many grasps there are.

This module is the bottom of the batch layer: the checks of grasp arrays and
the verdicts. Corollary 3's closed form (:mod:`forceclosure.analysis.two_finger`),
least friction (:mod:`forceclosure.analysis.friction`) and epsilon
(:mod:`forceclosure.analysis.batch`) build on it; :mod:`forceclosure.analysis.batch` is where
users find all three.

Examples
--------
>>> import numpy as np
>>> p = np.array([[[-1, 0], [1, 0.2]]])
>>> analyze_batch(p, np.array([[[-1, 0], [1, 0]]]), mu=0.3).verdict.tolist()
['closure']
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..contacts import (
    MAX_CONTACTS,
    MAX_COORDINATE,
    MODELS,
    Cone,
    Contact,
    Model,
    fixed_cone,
    model_codes,
    unit_rows,
)
from ..errors import InputError
from ..verdicts import VerdictCode, verdict_words
from .closure import (
    FRICTION_CAP,
    TOLERANCE,
    TORSION_MAX,
    check_tolerance,
    decide,
    force_direction_closure,
    torque_closure,
)
from .motion import motion_of, shift_twist

__all__ = ["CHUNK", "BatchAnalysis", "Engine", "analyze_batch"]

#: The two ways every batch function can run: compiled kernels, or the reference path.
Engine = Literal["compiled", "reference"]

#: Grasps handed to the kernel at a time: bounds the memory of the outputs in flight.
CHUNK = 65_536


class VerdictCodes:
    """Verdicts kept as a ``code`` array (0 ``none``, 1 ``marginal``, 2 ``closure``), read as
    words or as a mask on use."""

    code: NDArray[np.int8]

    @property
    def verdict(self) -> NDArray[np.str_]:
        """``"closure"``, ``"marginal"`` or ``"none"`` for each."""
        return verdict_words(self.code)

    @property
    def force_closure(self) -> NDArray[np.bool_]:
        """True where the verdict is ``closure``."""
        return self.code == VerdictCode.CLOSURE


@dataclass(frozen=True, eq=False)
class BatchAnalysis(VerdictCodes):
    """Verdicts for ``N`` grasps, as arrays (see :class:`forceclosure.Analysis`).

    ``code`` is the verdict as 0 ``none``, 1 ``marginal``, 2 ``closure``;
    ``margin`` is NaN where undefined; ``twist`` rows (the unresisted motion,
    ``(omega, v)`` about the origin as in :class:`forceclosure.Motion`) are NaN
    for grasps that are force-closure; ``force_direction_closure`` and
    ``torque_closure`` are filled only when asked for (``explain=True``).
    """

    code: NDArray[np.int8]
    rank: NDArray[np.int64]
    margin: NDArray[np.float64]
    twist: NDArray[np.float64]
    force_direction_closure: NDArray[np.bool_] | None
    torque_closure: NDArray[np.bool_] | None

    def __len__(self) -> int:
        return len(self.code)


@dataclass(frozen=True, eq=False)
class _Grasps:
    """Validated arrays: points, unit normals, per-contact mu and torsion, slot models."""

    points: NDArray[np.float64]
    normals: NDArray[np.float64]
    mu: NDArray[np.float64]
    torsion: NDArray[np.float64]
    models: list[Model]

    def contacts(self, g: int | np.integer, mu: float | None = None) -> list[Contact]:
        """Grasp ``g`` as contacts for the reference path (with all friction ``mu``, if given)."""
        return [Contact(self.points[g, i][None], self.normals[g, i][None], self.models[i],
                        float(np.nan_to_num(self.mu[g, i] if mu is None else mu)),
                        None if np.isnan(self.torsion[g, i]) else float(self.torsion[g, i]))
                for i in range(self.points.shape[1])]


def _per_contact(value: ArrayLike | None, shape: tuple[int, int], name: str) -> NDArray:
    try:
        a = np.asarray(np.nan if value is None else value, dtype=float)
        a = np.broadcast_to(a, shape)
    except (TypeError, ValueError, OverflowError):  # 10**400: an int no float holds
        raise InputError(f"'{name}' must be a number or an array broadcastable to {shape} "
                         "(grasps, contacts)") from None
    # NaN is a soft finger's "no coupled torsion"; a friction coefficient must be a number
    bad = np.argwhere(((a < 0) | ~np.isfinite(a)) if name == "mu"
                      else ~np.isnan(a) & ((a < 0) | ~np.isfinite(a)))
    if len(bad):
        g, c = bad[0]
        raise InputError(f"grasp {g + 1}, contact {c + 1}: '{name}' must be finite and >= 0, "
                         f"got {a[g, c]}")
    return a


def validate_grasps(points: ArrayLike, normals: ArrayLike, mu: ArrayLike,
                    model: str | Sequence[str], torsion: ArrayLike | None) -> _Grasps:
    """A batch of grasps checked and read as arrays (shape ``(N, k, 2 or 3)``, finite, bounded
    coordinates; friction, models and torsion broadcast per contact), or one
    :class:`~forceclosure.errors.InputError` line naming the first bad grasp and contact."""
    try:
        if np.iscomplexobj(points) or np.iscomplexobj(normals):
            raise TypeError
        P = np.asarray(points, dtype=float)
        N_ = np.asarray(normals, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError("points and normals must be arrays of numbers") from None
    if P.ndim != 3 or P.shape != N_.shape or P.shape[2] not in (2, 3):
        raise InputError(f"points and normals must both have shape (N, k, 2 or 3); got "
                         f"{P.shape} and {N_.shape}")
    n, k, _ = P.shape
    if k == 0:
        raise InputError(f"points and normals have shape {P.shape}: a grasp needs at least "
                         "one contact")
    if k > MAX_CONTACTS:
        raise InputError(f"points and normals have shape {P.shape}: {k:,} contacts a grasp; "
                         f"at most {MAX_CONTACTS:,} are analysed")
    for name, arr in (("point", P), ("normal", N_)):
        bad = np.argwhere(~np.all(np.isfinite(arr), axis=2))
        if len(bad):
            raise InputError(f"grasp {bad[0][0] + 1}, contact {bad[0][1] + 1}: '{name}' has a "
                             "non-finite coordinate")
    bad = np.argwhere(np.max(np.abs(P), axis=2) > MAX_COORDINATE)
    if len(bad):
        g, c = bad[0]
        raise InputError(f"grasp {g + 1}, contact {c + 1}: 'point' has a coordinate beyond "
                         f"{MAX_COORDINATE:g}, too large to compute with")
    unit, length = unit_rows(N_)
    bad = np.argwhere(length <= 1e-12)
    if len(bad):
        raise InputError(f"grasp {bad[0][0] + 1}, contact {bad[0][1] + 1}: 'normal' is a zero "
                         "vector")
    if isinstance(model, str):
        models = [model] * k
    else:
        try:
            models = [str(m) for m in model]
        except TypeError:
            models = []
    if len(models) != k or any(m not in MODELS for m in models):
        raise InputError(f"model must be one of {', '.join(MODELS)}, or a list of {k} of them")
    grasps = _Grasps(P, unit, _per_contact(mu, (n, k), "mu"),
                     _per_contact(torsion, (n, k), "torsion"),
                     cast(list[Model], models))  # each one of MODELS, checked above
    if not np.all(np.isnan(grasps.torsion)):
        _check_torsion(grasps)
    return grasps


def _sizes(P: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each grasp's own length scale (``contacts.own_frame``, physical units), without overflow."""
    big = np.max(np.abs(P), axis=(1, 2))
    unit = np.where((big == 0) | ((big >= 2.0**-64) & (big <= 2.0**64)), 1.0,
                    np.ldexp(1.0, np.minimum(np.frexp(big)[1], 1023)))
    scaled = P / unit[:, None, None]
    spread = np.max(unit_rows(scaled - scaled.mean(axis=1, keepdims=True))[1], axis=1)
    one_point = np.where(unit == 1.0, spread <= 1e-12 * np.maximum(1.0, big),
                         (unit < 1.0) | (spread <= 1e-12 * np.max(np.abs(scaled), axis=(1, 2))))
    with np.errstate(over="ignore"):
        return np.where(one_point, np.where(unit > 1.0, big, 1.0), spread * unit)


def _check_torsion(grasps: _Grasps) -> None:
    """Refuse a torsional coefficient more than :data:`TORSION_MAX` times its grasp's size."""
    size = _sizes(grasps.points)
    with np.errstate(invalid="ignore", over="ignore"):
        soft = np.array([m == "soft" for m in grasps.models])
        bad = np.argwhere((grasps.torsion > TORSION_MAX * size[:, None]) & soft)
    if len(bad):
        g, c = bad[0]
        raise InputError(f"grasp {g + 1}, contact {c + 1}: 'torsion' {grasps.torsion[g, c]:g} "
                         f"is more than {TORSION_MAX:g} times the grasp's size {size[g]:.3g}")


def extreme_grasps(grasps: _Grasps) -> NDArray[np.bool_]:
    """Grasps the kernels leave to the reference path: coordinates beyond ``2**±64``
    (the reference computes them in units of a power of two)."""
    big = np.max(np.abs(grasps.points), axis=(1, 2))
    return (big != 0) & ((big < 2.0**-64) | (big > 2.0**64))


def kernel_inputs(grasps: _Grasps, part: slice,
                  extreme: NDArray[np.bool_]) -> tuple[NDArray, NDArray]:
    """Points and friction of ``part`` for the kernels: grasps with extreme coordinates
    zeroed (they are left to the reference), friction capped at :data:`FRICTION_CAP`."""
    from ..kernels import kernel_array

    P = grasps.points[part]
    extreme = extreme[part]
    if extreme.any():
        P = P.copy()
        P[extreme] = 0.0
    return kernel_array(P), kernel_array(np.minimum(grasps.mu[part], FRICTION_CAP))


def cone_args(cone: str | Cone) -> tuple[bool, int, int]:
    """``(exact, edges, fit)`` for the kernels (the cone read by
    :func:`forceclosure.contacts.parse_cone`)."""
    fixed = fixed_cone(cone)
    if fixed is None:
        return True, 8, 0
    return False, fixed.edges, int(fixed.fit == "circumscribed")


def check_engine(engine: str) -> None:
    """Refuse, in one line, an engine other than ``'compiled'`` or ``'reference'``."""
    if engine not in ("compiled", "reference"):
        raise InputError(f"engine must be 'compiled' or 'reference', got {engine!r}")


def analyze_batch(points: ArrayLike, normals: ArrayLike, *, mu: ArrayLike = 0.0,
                  model: str | Sequence[str] = "hard", torsion: ArrayLike | None = None,
                  cone: str | Cone = "exact", tol: float = TOLERANCE,
                  explain: bool = False, engine: Engine = "compiled",
                  progress: Callable[[int], object] | None = None) -> BatchAnalysis:
    """Analyse ``N`` grasps of ``k`` point contacts each (Theorem 1 per grasp).

    Parameters
    ----------
    points, normals : (N, k, d) arrays
        Contact points and outward normals (normalised here).
    mu, torsion : arrays broadcastable to (N, k)
        Friction and torsional coefficients (``torsion`` NaN or None: the
        paper's uncoupled soft-finger torque).
    model : str or sequence of k str
        Contact model of every contact, or of each contact slot.
    cone, tol :
        As in :func:`forceclosure.analyze`.
    explain : bool
        Also fill ``force_direction_closure`` and ``torque_closure`` (by the
        reference path, grasp by grasp, for those not force-closure).
    engine : {"compiled", "reference"}
        The compiled kernels (default), or the reference path for every grasp. On a machine
        where the kernel is not compiled yet, the first
        :data:`~forceclosure.kernels.COMPILE_AFTER` grasps of a process (in batches no
        larger) take the reference path too: a first answer in seconds, not after a minute
        of compiling (the same verdicts, ranks and margins).
    progress : callable, optional
        Called with the number of grasps just finished, after every chunk.

    Examples
    --------
    >>> import numpy as np
    >>> p = np.array([[[-1, 0], [1, 0.2]], [[-1, 0], [1, 1.0]]])
    >>> n = np.array([[[-1, 0], [1, 0]]] * 2)
    >>> analyze_batch(p, n, mu=0.3).verdict.tolist()
    ['closure', 'none']
    """
    check_engine(engine)
    tol = check_tolerance(tol)
    grasps = validate_grasps(points, normals, mu, model, torsion)
    exact, edges, fit = cone_args(cone)
    n, k, d = grasps.points.shape
    code = np.empty(n, dtype=np.int8)
    rank = np.zeros(n, dtype=np.int64)
    margin = np.full(n, np.nan)
    twist = np.full((n, 3 if d == 2 else 6), np.nan)
    from ..kernels import theorem1 as kernel
    from ..kernels import use_compiled

    run = kernel.closure_kernel if n > kernel.BLOCK else kernel.closure_serial
    # before the kernel is compiled on this machine, a few grasps go the reference path
    compiled = engine == "compiled" and n > 0 and use_compiled(run, grasps=n)
    if compiled:
        from ..kernels import kernel_array

        kinds = model_codes(grasps.models)
        maxm = kernel.columns_per_grasp(k, d, 256 if exact else edges)
        extreme = extreme_grasps(grasps)
        for lo in range(0, n, CHUNK):
            part = slice(lo, min(n, lo + CHUNK))
            P, M = kernel_inputs(grasps, part, extreme)
            run(
                P, kernel_array(grasps.normals[part]), M, kernel_array(grasps.torsion[part]),
                kinds, edges, fit, exact, float(tol), maxm,
                code[part], rank[part], margin[part], twist[part])
            # friction above the cap: the kernel's closure with the cap is a proof; the rest
            # is decided by the reference (closure.FRICTION_CAP), as are extreme coordinates
            above = (np.any(grasps.mu[part] > FRICTION_CAP, axis=1)
                     & (code[part] != VerdictCode.CLOSURE))
            code[part][above | extreme[part]] = kernel.DEFER
            if progress is not None:
                progress(part.stop - part.start)
        todo = np.flatnonzero(code == kernel.DEFER)
    else:
        todo = np.arange(n)
    for g in todo:
        vc, ws, _ = decide(grasps.contacts(g), cone, tol)
        code[g] = vc.verdict.code
        rank[g] = vc.rank
        margin[g] = np.nan if vc.margin is None else vc.margin
        twist[g] = np.nan
        if vc.twist is not None:
            physical = shift_twist(vc.twist, ws.reference, ws.length_scale)
            twist[g] = motion_of(physical, length_scale=ws.length_scale).twist
        if not compiled and progress is not None:
            progress(1)
    fd = tc = None
    if explain:
        fd = code == VerdictCode.CLOSURE
        tc = code == VerdictCode.CLOSURE
        for g in np.flatnonzero(code != VerdictCode.CLOSURE):
            vc, ws, _ = decide(grasps.contacts(g), cone, tol)
            fd[g] = force_direction_closure(ws.wrenches, tol)
            tc[g] = not fd[g] and torque_closure(ws.wrenches)
    return BatchAnalysis(code, rank, margin, twist, fd, tc)
