"""Many grasps at once: arrays in, arrays out.

:func:`analyze_batch` takes ``N`` grasps of ``k`` point contacts as arrays
and returns arrays of verdicts, ranks, margins and unresisted twists, with
the same meaning (and the same code path per grasp) as
:func:`forceclosure.analyze`. Contacts in one slot share a contact model.
For two-finger grasps, :func:`forceclosure.two_finger.two_finger_closure`
is fully vectorised and far faster.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .closure import TOLERANCE, Verdict, decide, force_direction_closure, torque_closure
from .contacts import MODELS, Cone, Contact
from .errors import InputError
from .motion import motion_of, shift_twist


@dataclass(frozen=True, eq=False)
class BatchAnalysis:
    """Verdicts for ``N`` grasps, as arrays (see :class:`forceclosure.Analysis`).

    ``margin`` is NaN where undefined; ``twist`` rows are NaN for grasps that
    are force-closure; ``force_direction_closure`` and ``torque_closure`` are
    filled only when asked for (``explain=True``).
    """

    verdict: NDArray[np.str_]
    rank: NDArray[np.int64]
    margin: NDArray[np.float64]
    twist: NDArray[np.float64]
    force_direction_closure: NDArray[np.bool_] | None
    torque_closure: NDArray[np.bool_] | None

    @property
    def force_closure(self) -> NDArray[np.bool_]:
        """True where the verdict is ``closure``."""
        return self.verdict == Verdict.CLOSURE.value

    def __len__(self) -> int:
        return len(self.verdict)


def _per_contact(value: ArrayLike | None, shape: tuple[int, int], name: str) -> NDArray:
    a = np.broadcast_to(np.asarray(np.nan if value is None else value, dtype=float), shape)
    bad = np.argwhere(~np.isnan(a) & ((a < 0) | ~np.isfinite(a)))
    if len(bad):
        g, c = bad[0]
        raise InputError(f"grasp {g + 1}, contact {c + 1}: '{name}' must be finite and >= 0, "
                         f"got {a[g, c]}")
    return a


def analyze_batch(points: ArrayLike, normals: ArrayLike, *, mu: ArrayLike = 0.0,
                  model: str | Sequence[str] = "hard", torsion: ArrayLike | None = None,
                  cone: str | Cone = "exact", tol: float = TOLERANCE,
                  explain: bool = False) -> BatchAnalysis:
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
        Also fill ``force_direction_closure`` and ``torque_closure``.

    Examples
    --------
    >>> import numpy as np
    >>> p = np.array([[[-1, 0], [1, 0.2]], [[-1, 0], [1, 1.0]]])
    >>> n = np.array([[[-1, 0], [1, 0]]] * 2)
    >>> analyze_batch(p, n, mu=0.3).verdict.tolist()
    ['closure', 'none']
    """
    P = np.asarray(points, dtype=float)
    N_ = np.asarray(normals, dtype=float)
    if P.ndim != 3 or P.shape != N_.shape or P.shape[2] not in (2, 3):
        raise InputError(f"points and normals must both have shape (N, k, 2 or 3); got "
                         f"{P.shape} and {N_.shape}")
    n, k, d = P.shape
    for name, arr in (("point", P), ("normal", N_)):
        bad = np.argwhere(~np.all(np.isfinite(arr), axis=2))
        if len(bad):
            raise InputError(f"grasp {bad[0][0] + 1}, contact {bad[0][1] + 1}: '{name}' has a "
                             "non-finite coordinate")
    length = np.linalg.norm(N_, axis=2)
    bad = np.argwhere(length <= 1e-12)
    if len(bad):
        raise InputError(f"grasp {bad[0][0] + 1}, contact {bad[0][1] + 1}: 'normal' is a zero "
                         "vector")
    mus = _per_contact(mu, (n, k), "mu")
    tors = _per_contact(torsion, (n, k), "torsion")
    models = [model] * k if isinstance(model, str) else list(model)
    if len(models) != k or any(m not in MODELS for m in models):
        raise InputError(f"model must be one of {', '.join(MODELS)}, or a list of {k} of them")
    verdict = np.empty(n, dtype="<U8")
    rank = np.zeros(n, dtype=np.int64)
    margin = np.full(n, np.nan)
    twist = np.full((n, 3 if d == 2 else 6), np.nan)
    fd = np.zeros(n, dtype=bool) if explain else None
    tc = np.zeros(n, dtype=bool) if explain else None
    for g in range(n):
        grasp = [Contact(P[g, i][None], (N_[g, i] / length[g, i])[None], models[i],
                         float(np.nan_to_num(mus[g, i])),
                         None if np.isnan(tors[g, i]) else float(tors[g, i]))
                 for i in range(k)]
        vc, ws, _ = decide(grasp, cone, tol)
        verdict[g] = vc.verdict.value
        rank[g] = vc.rank
        margin[g] = np.nan if vc.margin is None else vc.margin
        if vc.twist is not None:
            physical = shift_twist(vc.twist, ws.reference, ws.length_scale)
            twist[g] = motion_of(physical, length_scale=ws.length_scale).twist
        if explain:
            closed = vc.verdict is Verdict.CLOSURE
            fd[g] = closed or force_direction_closure(ws.wrenches, tol)
            tc[g] = closed or (not fd[g] and torque_closure(ws.wrenches))
    return BatchAnalysis(verdict, rank, margin, twist, fd, tc)
