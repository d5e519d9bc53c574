"""Twists, and the motion they describe in words (§2.2: dual representation).

A twist ``t`` is an infinitesimal motion of the object: planar ``(omega, vx,
vy)``, spatial ``(omega, v)``, with ``v`` the velocity of the point at the
origin. A wrench ``w = (f, tau)`` does work ``f . v + tau . omega`` against
it; ``t`` is *repelling* to ``w`` when that is positive (the contact breaks)
and *reciprocal* when it is zero (the contact slides). A grasp that is not
force-closure leaves some twist ``t != 0`` with ``W^T t >= 0``: a motion
that no contact resists.

**In words.** A twist is told as a translation, a rotation or a screw by one
rule, with the one tolerance of :mod:`forceclosure.tolerance` (``rtol``,
:data:`~forceclosure.tolerance.TOLERANCE` = 1e-6 by default), at the
object's scale: ``L`` its size (``length_scale``) and ``v_c`` the velocity
of its centre ``c`` (``reference``), so that neither depends on where the
origin is.

* **translation** when the rotation is negligible: ``|omega| L <= rtol |v_c|``
  (over the object, the rotation moves no point by more than ``rtol`` times
  the translation);
* otherwise, with ``h = omega . v_c / |omega|^2`` the pitch (translation
  along the axis per radian), a **rotation** when that translation is
  negligible: ``|h| <= rtol (L + |v_c| / |omega|)`` (``|v_c| / |omega|`` being
  about the axis's distance from the object), and a **screw** otherwise.

The twist itself is kept whole (a translation keeps its negligible
rotation), so it stays the certificate it was.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..tolerance import TOLERANCE

__all__ = ["Motion", "motion_of", "shift_twist"]


def _fmt(values: ArrayLike, floor: float = 1e-12) -> str:
    """Coordinates to 3 significant digits, those below ``floor`` times the largest (or
    than ``floor``) shown as 0."""
    v = np.atleast_1d(np.asarray(values, dtype=float))
    v = np.where(np.abs(v) < floor * max(1.0, float(np.max(np.abs(v)))), 0.0, v)
    out = []
    for x in v:
        s = f"{x:.3g}"
        out.append("0" if s in ("-0", "0") else s)
    return "(" + ", ".join(out) + ")"


@dataclass(frozen=True)
class Motion:
    """A rigid motion of the object, decoded from a twist.

    Attributes
    ----------
    kind : {"translation", "rotation", "screw"}
    twist : array
        The twist about the origin, normalised (``|omega| = 1`` for a
        rotation or screw; for a translation, the velocity of the reference
        point has length 1).
    point : array or None
        Planar: the centre of rotation; spatial: the point of the axis
        nearest the origin.
    direction : array or None
        Translation direction, or spatial axis direction.
    pitch : float
        Screw pitch (translation per radian); 0 for a pure rotation.
    both_ways : bool
        True when the opposite motion is unresisted too (a reciprocal twist).
    """

    kind: Literal["translation", "rotation", "screw"]
    twist: NDArray[np.float64]
    point: NDArray[np.float64] | None
    direction: NDArray[np.float64] | None
    pitch: float
    both_ways: bool

    def describe(self) -> str:
        """The motion in words, e.g. ``rotation about the axis through (0, 0.3, 0.2) ...``.

        Examples
        --------
        >>> motion_of([1.0, 0.0, 0.0]).describe()
        'counter-clockwise rotation about the point (0, 0)'
        """
        either = " in either direction" if self.both_ways else ""
        if self.kind == "translation":
            assert self.direction is not None  # a translation has a direction, no point
            # a negligible rotation (up to TOLERANCE) tilts the direction by as little
            return f"translation{either} along {_fmt(self.direction, TOLERANCE)}"
        assert self.point is not None  # a rotation or screw has a point on its axis
        if self.direction is None:  # planar rotation
            sense = "counter-clockwise " if self.twist[0] > 0 else "clockwise "
            if self.both_ways:
                sense = ""
            return f"{sense}rotation{either} about the point {_fmt(self.point)}"
        axis = f"the axis through {_fmt(self.point)} with direction {_fmt(self.direction)}"
        if self.kind == "rotation":
            return f"rotation{either} about {axis}"
        return f"screw motion{either} about {axis}, pitch {self.pitch:.3g}"


def motion_of(twist: ArrayLike, *, both_ways: bool = False, length_scale: float = 1.0,
              reference: ArrayLike | None = None, rtol: float = TOLERANCE) -> Motion:
    """Decode a twist about the origin into a translation, rotation or screw.

    The rule and its tolerance are in the module's notes: a rotation that
    moves the object's points by at most ``rtol`` times its translation is
    a translation; a translation along the axis at most ``rtol`` times the
    motion's scale at the object is no screw.

    Parameters
    ----------
    twist : array
        Planar ``(omega, vx, vy)`` or spatial ``(wx, wy, wz, vx, vy, vz)``,
        ``v`` being the velocity of the point at the origin.
    both_ways : bool
        Whether ``-twist`` is unresisted too.
    length_scale : float
        Size of the object, ``L``.
    reference : array, optional
        The object's centre, ``c`` (default: the origin).
    rtol : float
        The tolerance of the rule (default: :data:`forceclosure.tolerance.TOLERANCE`).

    References
    ----------
    .. [1] V.-D. Nguyen, "Constructing force-closure grasps", *Int. J. Robotics
       Research* 7(3):3-16, 1988, §2.2 (twists
       reciprocal and repelling to the wrench convex)

    Examples
    --------
    >>> m = motion_of([1, 0, 0, 0, 0.2, -0.3])   # spin about x through (0, 0.3, 0.2)
    >>> m.describe()
    'rotation about the axis through (0, 0.3, 0.2) with direction (1, 0, 0)'

    Lifting an object of size 0.05 at (0, 0, 0.03) while turning it by 1e-9 rad per
    metre: the rotation moves its points by 5e-11 per metre lifted, a translation.

    >>> motion_of([1e-9, 0, 0, 0, 0, 1], length_scale=0.05, reference=[0, 0, 0.03]).describe()
    'translation along (0, 0, 1)'
    >>> motion_of([1e-3, 0, 0, 0, 0, 1], length_scale=0.05).describe()   # 5e-5 per metre
    'rotation about the axis through (0, -1e+03, 0) with direction (1, 0, 0)'
    """
    t = np.asarray(twist, dtype=float)
    k = 1 if t.shape[0] == 3 else 3
    omega, v = t[:k], t[k:]
    c = np.zeros(t.shape[0] - k) if reference is None else np.asarray(reference, dtype=float)
    # the velocity of the centre, v_0 + omega x c (planar: omega x c = omega (-cy, cx))
    v_c = v + (omega[0] * np.array([-c[1], c[0]]) if k == 1 else np.cross(omega, c))
    w_norm, vc_norm = float(np.linalg.norm(omega)), float(np.linalg.norm(v_c))
    if w_norm == 0.0 or w_norm * length_scale <= rtol * vc_norm:
        return Motion("translation", t / vc_norm, None, v_c / vc_norm, 0.0, both_ways)
    t = t / w_norm
    omega, v = t[:k], t[k:]
    if k == 1:
        # v_origin + omega x (c - 0) = 0  =>  c = (-vy, vx) / omega
        centre = np.array([-v[1], v[0]]) / omega[0]
        return Motion("rotation", t, centre, None, 0.0, both_ways)
    pitch = float(omega @ v)
    point = np.cross(omega, v)
    screw = abs(pitch) > rtol * (length_scale + vc_norm / w_norm)
    return Motion("screw" if screw else "rotation", t, point, omega.copy(),
                  pitch if screw else 0.0, both_ways)


def shift_twist(dual: NDArray[np.float64], reference: NDArray[np.float64],
                length_scale: float) -> NDArray[np.float64]:
    """A twist found in wrench space as a physical twist ``(omega, v)`` about the origin.

    The closure test finds a vector ``y`` laid out like the scaled wrenches
    ``(f, tau / length_scale)`` about ``reference``, with ``w . y`` the work
    done: its force slots hold the velocity ``v_ref`` of the reference point,
    its torque slots ``omega * length_scale``. The velocity then moves to the
    origin: ``v_0 = v_ref + omega x (0 - reference)``.

    Examples
    --------
    >>> shift_twist(np.array([0.0, 0.0, 2.0]), np.array([1.0, 0.0]), 2.0).tolist()
    [1.0, 0.0, -1.0]
    """
    y = np.asarray(dual, dtype=float)
    if y.shape[0] == 3:
        omega = y[2] / length_scale
        v = y[:2] + omega * np.array([reference[1], -reference[0]])
        return np.concatenate([[omega], v])
    omega = y[3:] / length_scale
    v = y[:3] - np.cross(omega, reference)
    return np.concatenate([omega, v])
