"""Nonmarginal equilibrium implies force closure (Nguyen 1988, Corollary 4).

A planar grasp with at least two distinct contacts with friction is
force-closure if its contact forces are in equilibrium and each points
strictly inside its friction cone. In space the same holds with at least two
distinct soft fingers, or three hard fingers not on one line. This gives a
certificate of closure from any equilibrium a user already has (from a
simulator, a force sensor or a grasp planner) with no linear program.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..contacts import Contact, check_grasp, frame
from ..errors import InputError
from .closure import TOLERANCE

__all__ = ["EQUILIBRIUM_RTOL", "EquilibriumCertificate", "nonmarginal_equilibrium"]

#: Relative size of the net force and torque accepted as equilibrium.
EQUILIBRIUM_RTOL = 1e-9


@dataclass(frozen=True)
class EquilibriumCertificate:
    """Whether Corollary 4 certifies force closure, and why (not).

    Attributes
    ----------
    certified : bool
        True: the grasp is force-closure (Corollary 4).
    reason : str
        One sentence.
    residual : float
        Net wrench (force, torque / length scale) over the total force.
    cone_gap : float
        Smallest ``atan(mu) - angle(f_i, -n_i)`` over the contacts (radians);
        positive when every force is strictly inside its cone.
    """

    certified: bool
    reason: str
    residual: float
    cone_gap: float


def _collinear(points: np.ndarray, scale: float) -> bool:
    centred = points - points.mean(axis=0)
    sv = np.linalg.svd(centred, compute_uv=False)
    return len(sv) < 2 or sv[1] <= 1e-9 * scale


def nonmarginal_equilibrium(contacts: Sequence[Contact], forces: ArrayLike,
                            tol: float = TOLERANCE) -> EquilibriumCertificate:
    """Certify force closure from contact forces in nonmarginal equilibrium (Corollary 4).

    Parameters
    ----------
    contacts : sequence of Contact
        Point contacts with friction (hard or soft fingers, one point and one
        normal each).
    forces : (k, d) array
        The force each finger applies to the object.
    tol : float
        How far (radians) inside its cone each force must be.

    Examples
    --------
    >>> from forceclosure import point_contact
    >>> grasp = [point_contact([-1, 0], [-1, 0], "hard", 0.3),
    ...          point_contact([1, 0], [1, 0], "hard", 0.3)]
    >>> nonmarginal_equilibrium(grasp, [[1, 0], [-1, 0]]).certified
    True
    """
    contacts = check_grasp(contacts)
    f = np.asarray(forces, dtype=float)
    d = contacts[0].dim
    if f.shape != (len(contacts), d):
        raise InputError(f"forces must have shape ({len(contacts)}, {d}), got {f.shape}")
    if not np.all(np.isfinite(f)):
        raise InputError("forces have a non-finite entry")
    for i, c in enumerate(contacts):
        if len(c.points) != 1 or len(c.normals) != 1:
            raise InputError(f"contact {i + 1}: Corollary 4 takes point contacts only")
    ref, scale = frame(contacts)
    pts = np.array([c.point for c in contacts])
    normals = np.array([c.normal for c in contacts])
    total = float(np.sum(np.linalg.norm(f, axis=1)))
    if total == 0.0:
        return EquilibriumCertificate(False, "all contact forces are zero", 0.0, -math.inf)
    arm = pts - ref
    torque = (arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0]) if d == 2 else np.cross(arm, f)
    net = np.concatenate([f.sum(axis=0), np.atleast_1d(torque.sum(axis=0)) / scale])
    residual = float(np.linalg.norm(net) / total)
    dot = np.sum(f * -normals, axis=1)
    norm = np.linalg.norm(f, axis=1)
    angles = np.arccos(np.clip(dot / np.maximum(norm, 1e-300), -1.0, 1.0))
    alphas = np.array([math.atan(c.mu) if c.frictional else 0.0 for c in contacts])
    gap = float(np.min(np.where(norm > 0, alphas - angles, -math.inf)))
    if residual > EQUILIBRIUM_RTOL:
        return EquilibriumCertificate(False, f"not in equilibrium (net wrench {residual:.3g} "
                                             "of the total force)", residual, gap)
    if gap <= tol:
        worst = int(np.argmin(np.where(norm > 0, alphas - angles, -math.inf)))
        return EquilibriumCertificate(False, f"contact {worst + 1}: its force is not strictly "
                                             "inside its friction cone (marginal)", residual, gap)
    distinct = np.unique(np.round(pts / (scale * 1e-9)), axis=0)
    soft = sum(c.model == "soft" for c in contacts)
    if d == 2 and len(distinct) < 2:
        why = "needs two distinct contacts with friction"
    elif d == 3 and not (soft >= 2 and len(distinct) >= 2) and _collinear(pts, scale):
        why = ("needs two distinct soft fingers or three hard fingers not on one line "
               "(nothing resists rotation about the line through the contacts)")
    else:
        return EquilibriumCertificate(True, "nonmarginal equilibrium with distinct contacts "
                                            "(Corollary 4)", residual, gap)
    return EquilibriumCertificate(False, why, residual, gap)
