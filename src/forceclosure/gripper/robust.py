"""Robust labels: the probability of force closure, and the expected epsilon, under noise.

:func:`robust_labels` perturbs each parallel-jaw pose many times (Monte
Carlo, seeded) and labels every perturbed grasp with the batch kernels:

* **pose**: the jaws' centre moves by a Gaussian of standard deviation
  ``pose_sigma`` along each axis; the closing axis turns about the
  approach axis by a Gaussian angle of standard deviation
  ``angle_sigma[0]`` and about ``approach × closing`` by one of
  ``angle_sigma[1]`` (one rotation, by the vector of the two angles). A
  single number is both, and the approach axis turns with it. The pads then
  close again along the turned line through the moved centre, as for the
  labels (:func:`forceclosure.gripper.pads.pad_contacts`: where they first
  meet the object and press; each pad twists as the region it presses
  allows); a shift along the closing axis changes nothing, since the hand
  closes about the object wherever it starts;
* **friction**: ``mu + mu_sigma · z`` with ``z`` standard normal, clipped at
  0, one value per sample shared by both contacts (the pair of materials is
  uncertain, not each pad);
* **normals**: each contact's normal turns by a random small rotation about
  an axis in its tangent plane, of Gaussian components ``normal_sigma``
  (radians).

A sample counts as force-closure only when its verdict is ``closure`` (exact
cones, at the sample's friction); ``marginal`` counts as not. **A sample
whose pads hold nothing** (no surface under them, or the object wider than
the opening under them) **counts as not force-closure**, with epsilon 0; how many did is in
``missed``. The probability comes with a Wilson score interval, the mean
epsilon (0 for samples not closed) with a Student-t interval, both at
``confidence``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from numbers import Real
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..verdicts import VerdictCode
from .jaw import JawPose, ParallelJaw, check_jaw_contact, surface_mesh
from .settings import ROBUST_DEFAULTS

__all__ = ["Noise", "Robustness", "robust_labels", "wilson_interval"]

#: Perturbed grasps cast and labelled at a time (whole grasps; bounds the memory).
CHUNK_SAMPLES = 1 << 18


@dataclass(frozen=True)
class Noise:
    """Standard deviations of the noise :func:`robust_labels` draws.

    Attributes
    ----------
    pose_sigma : float
        Translation of the jaws' centre, per axis (object units).
    angle_sigma : (float, float)
        Rotation of the closing axis (radians) about the approach axis, and
        about ``approach × closing``.
    mu_sigma : float
        Friction coefficient (absolute; the draw is clipped at 0).
    normal_sigma : float
        Turn of each contact normal, per tangent axis (radians).
    """

    pose_sigma: float = 0.0
    angle_sigma: tuple[float, float] = (0.0, 0.0)
    mu_sigma: float = 0.0
    normal_sigma: float = 0.0

    def __post_init__(self) -> None:
        angle: Any = self.angle_sigma  # as given: one number or two, checked here
        if isinstance(angle, Real) and not isinstance(angle, bool):
            angle = (angle, angle)
        try:
            angle = tuple(angle)
        except TypeError:
            raise InputError(f"angle_sigma must be a number or two numbers, got "
                             f"{self.angle_sigma!r}") from None
        if len(angle) != 2:
            raise InputError(f"angle_sigma must be a number or two numbers, got {angle!r}")
        for name, value in (("pose_sigma", self.pose_sigma), ("angle_sigma", angle[0]),
                            ("angle_sigma", angle[1]), ("mu_sigma", self.mu_sigma),
                            ("normal_sigma", self.normal_sigma)):
            if (isinstance(value, bool) or not isinstance(value, Real)
                    or not math.isfinite(value) or value < 0):
                raise InputError(f"{name} must be a finite number >= 0, got {value!r}")
        object.__setattr__(self, "angle_sigma", (float(angle[0]), float(angle[1])))
        for name in ("pose_sigma", "mu_sigma", "normal_sigma"):
            object.__setattr__(self, name, float(getattr(self, name)))

    def to_dict(self) -> dict[str, Any]:
        """The four standard deviations, JSON-ready."""
        return {"pose_sigma": self.pose_sigma, "angle_sigma": list(self.angle_sigma),
                "mu_sigma": self.mu_sigma, "normal_sigma": self.normal_sigma}


@dataclass(frozen=True, eq=False)
class Robustness:
    """Per-grasp robustness of ``N`` jaw poses (:func:`robust_labels`).

    Attributes
    ----------
    probability : (N,) array
        Fraction of the samples that are force-closure (``closed / samples``).
    probability_low, probability_high : (N,) arrays
        Wilson score interval of the probability, at ``confidence``.
    epsilon : (N,) array
        Mean Ferrari–Canny epsilon (L1, as :func:`forceclosure.analysis.batch.epsilon_batch`)
        over the samples, 0 for those not closed; NaN when not computed.
    epsilon_low, epsilon_high : (N,) arrays
        Student-t interval of the mean epsilon at ``confidence`` (the low end
        clipped at 0, which the mean cannot be below).
    closed, missed : (N,) int arrays
        Samples that are force-closure, and that made no contact pair.
    samples, seed : int
    confidence : float
    noise : Noise
    """

    probability: NDArray[np.float64]
    probability_low: NDArray[np.float64]
    probability_high: NDArray[np.float64]
    epsilon: NDArray[np.float64]
    epsilon_low: NDArray[np.float64]
    epsilon_high: NDArray[np.float64]
    closed: NDArray[np.int64]
    missed: NDArray[np.int64]
    samples: int
    seed: int
    confidence: float
    noise: Noise

    def __len__(self) -> int:
        return len(self.probability)


def wilson_interval(closed: NDArray, n: int, confidence: float
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Wilson score interval of a binomial proportion ``closed / n`` at ``confidence``.

    Examples
    --------
    >>> low, high = wilson_interval(np.array([50]), 100, 0.95)
    >>> round(float(low[0]), 4), round(float(high[0]), 4)
    (0.4038, 0.5962)
    """
    from scipy.special import ndtri

    z = float(ndtri(0.5 + 0.5 * confidence))
    p = np.asarray(closed, dtype=float) / n
    z2n = z * z / n
    centre = (p + 0.5 * z2n) / (1 + z2n)
    half = z / (1 + z2n) * np.sqrt(p * (1 - p) / n + z2n / (4 * n))
    return np.clip(centre - half, 0.0, 1.0), np.clip(centre + half, 0.0, 1.0)


def _pose_arrays(poses: Any) -> tuple[NDArray, NDArray, NDArray]:
    """Centres, closing and approach axes ``(N, 3)`` of a JawPose, a sequence of them, or
    anything with those arrays (:class:`~forceclosure.gripper.labels.GraspLabels`,
    :class:`~forceclosure.gripper.antipodal.AntipodalSamples`)."""
    if isinstance(poses, JawPose):
        poses = [poses]
    if all(hasattr(poses, a) for a in ("center", "closing_axis", "approach_axis")):
        arrays = [np.asarray(getattr(poses, a), dtype=float)
                  for a in ("center", "closing_axis", "approach_axis")]
        if any(a.ndim != 2 or a.shape[1:] != (3,) or len(a) != len(arrays[0])
               for a in arrays):
            raise InputError("poses: 'center', 'closing_axis' and 'approach_axis' must be "
                             "(N, 3) arrays of one length")
        if not all(np.all(np.isfinite(a)) for a in arrays):
            raise InputError("poses: a centre or axis has a non-finite coordinate")
        c, a = arrays[1], arrays[2]
        cn = np.linalg.norm(c, axis=1)
        if np.any(cn <= 1e-12):
            raise InputError(f"poses: pose {int(np.argmin(cn)) + 1} has a zero closing axis")
        c = c / cn[:, None]
        a = a - np.einsum("ij,ij->i", a, c)[:, None] * c
        an = np.linalg.norm(a, axis=1)
        if np.any(an <= 1e-9):
            raise InputError(f"poses: pose {int(np.argmin(an)) + 1}'s approach axis is "
                             "parallel to its closing axis")
        return arrays[0], c, a / an[:, None]
    if isinstance(poses, Sequence) and all(isinstance(p, JawPose) for p in poses):
        if not poses:
            return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3))
        return (np.array([p.center for p in poses]), np.array([p.closing_axis for p in poses]),
                np.array([p.approach_axis for p in poses]))
    raise InputError(f"poses must be a JawPose, a sequence of them, or GraspLabels, got "
                     f"{type(poses).__name__}")


def _turn(v: NDArray, e1: NDArray, e2: NDArray, a1: NDArray, a2: NDArray) -> NDArray:
    """Rotate unit rows ``v`` by the rotation vectors ``a1 e1 + a2 e2`` (Rodrigues; the
    vectors are perpendicular to ``v``, so ``v`` turns by their length)."""
    omega = a1[:, None] * e1 + a2[:, None] * e2
    rho = np.linalg.norm(omega, axis=1)
    sinc = np.sinc(rho / np.pi)  # sin(rho) / rho, 1 at 0
    out = np.cos(rho)[:, None] * v + sinc[:, None] * np.cross(omega, v)
    return out / np.linalg.norm(out, axis=1)[:, None]


#: (pose, triangle) pairs handed to the pad kernel at a time.
PAIRS = 1 << 23


def _pads_closed(poly, mesh, gripper: ParallelJaw, origin, closing, approach, depth,
                 levers: bool = True):
    """The pads' contacts (:func:`~forceclosure.gripper.pads.pad_contacts`) at the perturbed
    poses, their torsional levers (zeros unless ``levers``), and whether they hold the
    object within the opening; in blocks of at most :data:`PAIRS` (pose, triangle) pairs."""
    from .pads import line_candidates, pad_contacts, pad_reach

    m = len(origin)
    reach = pad_reach(depth, gripper.pad_length, gripper.pad_height)
    line_of, tri_of = line_candidates(mesh, origin, closing, reach)
    points, normals, lever = np.zeros((m, 2, 3)), np.zeros((m, 2, 3)), np.zeros((m, 2))
    held = np.zeros(m, bool)
    bounds = np.searchsorted(line_of, np.arange(0, m + 1))
    step = max(1, int(PAIRS // max(1.0, len(line_of) / max(m, 1))))
    for start in range(0, m, step):
        stop = min(m, start + step)
        sl = slice(bounds[start], bounds[stop])
        pc = pad_contacts(mesh, origin[start:stop], closing[start:stop],
                          approach[start:stop], depth[start:stop], gripper.pad_length,
                          gripper.pad_height, line_of[sl] - start, tri_of[sl], poly.size,
                          gripper.pad_compliance, levers)
        held[start:stop] = pc.holds(gripper.width_max, poly.size)
        points[start:stop], normals[start:stop] = pc.points, pc.normals
        lever[start:stop] = pc.lever
    return points, normals, lever, held


def robust_labels(obj: Any, poses: Any, gripper: ParallelJaw, mu: float, *,
                  samples: int = ROBUST_DEFAULTS["samples"], seed: int = 0,
                  pose_sigma: float | None = ROBUST_DEFAULTS["pose_sigma"],
                  angle_sigma: float | tuple[float, float] = ROBUST_DEFAULTS["angle_sigma"],
                  mu_sigma: float = ROBUST_DEFAULTS["mu_sigma"],
                  normal_sigma: float = ROBUST_DEFAULTS["normal_sigma"], contact: str = "soft",
                  confidence: float = ROBUST_DEFAULTS["confidence"],
                  epsilon: bool = ROBUST_DEFAULTS["epsilon"],
                  progress: Callable[[int], object] | None = None) -> Robustness:
    """The probability of force closure and the expected epsilon of jaw poses under noise.

    Each pose is perturbed ``samples`` times (the noise of the module's
    docstring), its jaws opened to ``gripper.width_max`` about the moved
    centre and closed along the turned axis onto ``obj`` (all poses' samples
    in one ray query per :data:`CHUNK_SAMPLES`), and every sample labelled
    by the batch kernels in one call: the verdict with exact cones at the
    sample's friction (:func:`~forceclosure.analysis.two_finger.pair_codes`) and, for
    the closed samples, the epsilon (:func:`~forceclosure.analysis.batch.epsilon_batch`,
    L1, 8-edge inscribed pyramids, torques about the pair's midpoint per its
    half-width). **A sample whose jaws make no contact pair** (they miss the
    object, or a jaw starts inside it: the opening about the moved centre
    does not clear it) **counts as not force-closure**, with epsilon 0; so
    does a ``marginal`` verdict.

    Parameters
    ----------
    obj : file, bundled name, trimesh.Trimesh or Polyhedron
        The object the poses were made on.
    poses : JawPose, sequence of JawPose, or GraspLabels / AntipodalSamples
    gripper : ParallelJaw
        Its ``width_max`` is the opening the jaws close from; soft pads couple their
        torsion to each sample's friction (:meth:`~forceclosure.gripper.jaw.ParallelJaw.torsion`).
    mu : float
        Nominal friction coefficient.
    samples : int
        Noise samples per pose (at least 2).
    seed : int
        The same seed, poses (in the same order) and noise give the same result.
    pose_sigma : float, optional
        Translation per axis, in object units (default: 1% of ``gripper.width_max``).
    angle_sigma : float or (float, float)
        Rotation of the closing axis in radians, about the approach axis and
        about ``approach × closing`` (one number: both; default 0.05).
    mu_sigma : float
        Friction noise, absolute (default 0.05); draws are clipped at 0.
    normal_sigma : float
        Normal noise in radians, per tangent axis (default 0).
    contact : {"soft", "hard"}
    confidence : float
        Of both intervals, in (0, 1).
    epsilon : bool
        Compute the expected epsilon (the costlier part: about 10k closed
        samples a second, against 200k+ verdicts); False leaves it NaN.
    progress : callable, optional
        Called with the number of samples just labelled.

    References
    ----------
    .. [1] J. Weisz and P. K. Allen, "Pose error robust grasping from contact wrench
       space metrics", *Proc. IEEE ICRA*, 2012
    .. [2] J. Mahler et al., "Dex-Net 2.0: Deep learning to plan robust grasps with
       synthetic point clouds and analytic grasp metrics", *Robotics: Science and
       Systems*, 2017

    Examples
    --------
    A head-on pinch across the 2-unit cube with small pads stays closed under
    small noise; a pose beside the cube never meets it:

    >>> poses = [JawPose([0, 0, 0], [1, 0, 0], [0, 0, 1], 2.0),
    ...          JawPose([0, 5, 0], [1, 0, 0], [0, 0, 1], 2.0)]
    >>> hand = ParallelJaw(3.0, pad_length=0.2, pad_height=0.2, depth=0.1)
    >>> r = robust_labels("cube", poses, hand, mu=0.5, samples=50, angle_sigma=0.05,
    ...                   mu_sigma=0.02)
    >>> r.probability.tolist(), r.missed.tolist(), bool(r.epsilon[0] > 0)
    ([1.0, 0.0], [0, 50], True)
    """
    from ..analysis.batch import epsilon_batch
    from ..analysis.two_finger import pair_codes
    from ..contacts import tangent_basis

    if not isinstance(gripper, ParallelJaw):
        raise InputError(f"gripper must be a ParallelJaw, got {type(gripper).__name__}")
    check_jaw_contact(contact)
    if isinstance(mu, bool) or not isinstance(mu, Real) or not math.isfinite(mu) or mu < 0:
        raise InputError(f"mu must be a finite number >= 0, got {mu!r}")
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples < 2:
        raise InputError(f"samples must be a whole number >= 2 (an interval needs two), "
                         f"got {samples!r}")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer):
        raise InputError(f"seed must be a whole number, got {seed!r}")
    if (isinstance(confidence, bool) or not isinstance(confidence, Real)
            or not 0 < confidence < 1):
        raise InputError(f"confidence must be a number strictly between 0 and 1, got "
                         f"{confidence!r}")
    if pose_sigma is None:
        pose_sigma = 0.01 * gripper.width_max
    noise = Noise(pose_sigma, angle_sigma, mu_sigma, normal_sigma)
    center, closing, approach = _pose_arrays(poses)
    depth = getattr(poses, "depth", None)
    depth = (np.full(len(center), gripper.depth) if depth is None
             else np.asarray(depth, dtype=float).reshape(len(center)))
    binormal = np.cross(approach, closing)
    poly, mesh = surface_mesh(obj)
    n, s = len(center), int(samples)
    closed = np.zeros(n, dtype=np.int64)
    missed = np.zeros(n, dtype=np.int64)
    eps = np.zeros((n, s)) if epsilon else None
    rng = np.random.default_rng(seed)
    sa, sb = noise.angle_sigma
    step = max(1, CHUNK_SAMPLES // s)
    for lo in range(0, n, step):
        part = slice(lo, min(n, lo + step))
        m = (part.stop - part.start) * s
        z_t = rng.standard_normal((m, 3))
        z_a = rng.standard_normal((m, 2))
        z_mu = rng.standard_normal(m)
        z_n = rng.standard_normal((m, 2, 2))
        c, a, b, centres = (np.repeat(v[part], s, axis=0)
                            for v in (closing, approach, binormal, center))
        shift = noise.pose_sigma * z_t
        axes = _turn(c, a, b, sa * z_a[:, 0], sb * z_a[:, 1])
        turned = a - np.einsum("ij,ij->i", a, axes)[:, None] * axes
        turned /= np.linalg.norm(turned, axis=1)[:, None]
        friction = np.maximum(0.0, mu + noise.mu_sigma * z_mu)
        # the pads' levers bound soft pads' torsion unless the hand gives its own radius
        points, normals, lever, held = _pads_closed(
            poly, mesh, gripper, centres + shift, axes, turned, np.repeat(depth[part], s),
            levers=contact == "soft" and gripper.pad_radius is None)
        ok = np.flatnonzero(held)
        P, N = points[ok], normals[ok]
        if noise.normal_sigma > 0 and len(ok):
            flat = N.reshape(-1, 3)
            t1, t2 = tangent_basis(flat)
            z = noise.normal_sigma * z_n[ok].reshape(-1, 2)
            N = _turn(flat, t1, t2, z[:, 0], z[:, 1]).reshape(-1, 2, 3)
        f = friction[ok][:, None]
        # soft pads twist as the region they press allows, or as the hand says
        per_mu = (lever[ok] if gripper.pad_radius is None else gripper.torsion(1.0)
                  ) if contact == "soft" else None
        torsion = None if per_mu is None else per_mu * f
        code = np.zeros(m, dtype=np.int8)
        if len(ok):
            code[ok] = pair_codes(P, N, f, contact, torsion)
        won = code == VerdictCode.CLOSURE
        closed[part] = won.reshape(-1, s).sum(axis=1)
        missed[part] = (~held).reshape(-1, s).sum(axis=1)
        if eps is not None:
            values = np.zeros(m)
            sel = np.flatnonzero(won[ok])
            if len(sel):
                values[ok[sel]] = epsilon_batch(
                    P[sel], N[sel], mu=f[sel], model=contact,
                    torsion=None if torsion is None else torsion[sel])
            eps[part] = values.reshape(-1, s)
        if progress is not None:
            progress(m)
    low, high = wilson_interval(closed, s, confidence)
    if eps is not None:
        from scipy.stats import t as student

        mean = eps.mean(axis=1)
        half = float(student.ppf(0.5 + 0.5 * confidence, s - 1)) * eps.std(axis=1, ddof=1) \
            / math.sqrt(s)
        e_low, e_high = np.maximum(0.0, mean - half), mean + half
    else:
        mean = e_low = e_high = np.full(n, np.nan)
    return Robustness(closed / s, low, high, mean, e_low, e_high, closed, missed, s,
                      int(seed), float(confidence), noise)
