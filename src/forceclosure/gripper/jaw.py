"""A parallel-jaw gripper: jaw poses and the contacts they make on a mesh.

A :class:`JawPose` is where the two jaws are: a centre, the closing axis
(from the first jaw to the second), an approach axis perpendicular to it,
and the opening ``width``; the jaws' pads sit at ``centre ∓ width/2 ·
closing``. :func:`contacts_of` closes the jaws onto an object by casting a
ray from each jaw towards the other (trimesh's ray queries, embree when it
is installed) and takes the first surface each one meets: the contact pair,
with the outward normals of the faces hit — or the reason there is none
(a ray misses the object between the jaws, a jaw starts inside it, the pose
is wider than the gripper opens). :func:`pose_from_contacts` is the way
back, from a contact pair to the pose whose jaws touch it.

Hit points are recomputed in double precision from the plane of the
triangle hit (embree reports distances in single precision), so a contact
lies on its face to rounding.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass, fields
from numbers import Real
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..contacts import MAX_COORDINATE
from ..errors import InputError, shown

__all__ = ["JAW_CONTACTS", "JawContacts", "JawPose", "ParallelJaw", "check_jaw_contact",
           "contacts_of", "pose_from_contacts"]

#: The contact models of a parallel jaw's pads: soft (a pad's torsional friction) or hard.
JAW_CONTACTS = ("soft", "hard")

#: Reasons a jaw pose makes no contact pair (``JawContacts.reason``).
MISSES = "misses: a jaw's ray meets no surface between the jaws"
INSIDE = "a jaw starts inside the object: it is wider than the opening along this line"
TOO_WIDE = "wider than the opening: the pose's width exceeds the gripper's width_max"

#: How far behind its pad each jaw's ray starts, relative to the object's size, so that a
#: surface touching the pad (a pose from :func:`pose_from_contacts`) is met.
BACKOFF = 1e-6


def _unit(v: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        a = np.asarray(v, dtype=float).reshape(3)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"'{name}' must be 3 numbers, got {v!r}") from None
    length = float(np.linalg.norm(a))
    if not np.isfinite(length) or length <= 1e-12:
        raise InputError(f"'{name}' must be a finite nonzero vector, got {a.tolist()}")
    return a / length


def _point(v: ArrayLike, name: str) -> NDArray[np.float64]:
    """3 finite numbers within the library's coordinates, or one line naming ``name``."""
    try:
        a = np.asarray(v, dtype=float).reshape(3)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"'{name}' must be 3 numbers, got {shown(v, 80)}") from None
    if not np.all(np.isfinite(a)) or np.abs(a).max() > MAX_COORDINATE:
        raise InputError(f"'{name}' must be 3 finite numbers of at most {MAX_COORDINATE:g}, "
                         f"got {a.tolist()}")
    return a


def default_approach(closing: NDArray[np.float64]) -> NDArray[np.float64]:
    """A unit vector perpendicular to ``closing``: the world axis least aligned with it,
    with its ``closing`` component removed (deterministic).

    Examples
    --------
    >>> default_approach(np.array([1.0, 0, 0])).tolist()
    [0.0, 1.0, 0.0]
    """
    axis = np.eye(3)[int(np.argmin(np.abs(closing)))]
    a = axis - (axis @ closing) * closing
    return a / np.linalg.norm(a)


#: The hand's box dimensions (:class:`ParallelJaw`) and their defaults, shares of ``width_max``.
_SHAPE = {"depth": 0.2, "finger_length": 0.5, "finger_thickness": 0.1, "finger_height": 0.2,
          "palm_thickness": 0.1}

#: The optional sizes whose defaults follow from the others (:class:`ParallelJaw`).
_DERIVED = ("pad_length", "pad_height", "palm_width", "palm_height", "tip_offset",
            "pad_compliance")


def _digits(x: float) -> float:
    """``x`` to 15 significant digits (0.002, not 0.0020000000000000005), at any size."""
    return float(f"{x:.15g}")


def rectangle_mean_radius(length: float, height: float) -> float:
    """The mean distance from the centre of a ``length`` × ``height`` rectangle to its
    points: the torsional friction of a uniformly pressed rectangular pad is ``μ`` times
    it times the normal force.

    With half-sides ``p``, ``q`` and ``d = sqrt(p² + q²)`` the integral of the distance
    over a quarter is ``(2pqd + p³ ln((q + d)/p) + q³ ln((p + d)/q)) / 6``.

    Examples
    --------
    >>> round(rectangle_mean_radius(2.0, 2.0), 6)  # (sqrt 2 + ln(1 + sqrt 2)) / 3
    0.765196
    >>> rectangle_mean_radius(1.0, 0.0)  # a segment: a quarter of its length
    0.25
    """
    p, q = 0.5 * float(length), 0.5 * float(height)
    if p <= 0 or q <= 0:
        return 0.5 * max(p, q)
    unit = max(p, q)  # the radius scales with the sides: computed on sides at most 1
    p, q = p / unit, q / unit
    d = math.hypot(p, q)
    quarter = (2 * p * q * d + p**3 * math.log((q + d) / p) + q**3 * math.log((p + d) / q)) / 6
    return float(quarter / (p * q)) * unit


def check_jaw_contact(contact: Any) -> str:
    """``contact`` if it is one of :data:`JAW_CONTACTS`, else a one-line
    :class:`~forceclosure.errors.InputError`.

    Examples
    --------
    >>> check_jaw_contact("soft")
    'soft'
    """
    if contact not in JAW_CONTACTS:
        raise InputError(f"contact must be 'soft' or 'hard', got {contact!r}")
    return contact


@dataclass(frozen=True, init=False)
class ParallelJaw:
    """A parallel-jaw gripper.

    Parameters
    ----------
    width_max : float
        The widest opening (same units as the object).
    pad_radius : float, optional
        How the soft pads resist twisting about their normal. None (the
        default): by the region each pad presses, ``|τ| ≤ μ l f_n`` with ``l``
        the region's mean lever about the contact's normal, from below
        (:mod:`forceclosure.gripper.pads`; per contact, in the labels'
        ``torsion``). A positive radius ``a``: a disc, ``|τ| ≤ (2/3) μ a f_n``.
        0: the paper's soft finger (uncoupled, unlimited torque), only when
        asked for.
    depth, finger_length, finger_thickness, finger_height, palm_thickness : float, optional
        The hand's boxes, for collision checks (:mod:`forceclosure.gripper.collision`),
        in the jaw frame (x the approach axis, y the closing axis, origin the
        jaw centre): each finger is a box ``finger_length`` long along x, from
        ``depth - finger_length`` to its tip at ``depth`` (how far the tips
        reach past the jaw centre, graspnetAPI's ``depth``),
        ``finger_thickness`` thick along y, outside the opening, and
        ``finger_height`` high along z (graspnetAPI's ``height``); the palm
        joins the fingers' bases, ``palm_thickness`` thick along x behind
        them (0: no palm). Defaults, from ``width_max = w``: depth ``0.2 w``,
        finger length ``0.5 w``, thickness ``0.1 w``, height ``0.2 w``, palm
        ``0.1 w`` (graspnetAPI's collision model at ``w = 0.1``: height
        0.02, finger width 0.01, palm 0.02 behind the centre for a depth of
        0.02, not its thickness).
    name : str
        What the hand is called (a built-in's name, see
        :mod:`forceclosure.gripper.grippers`).
    pad_length, pad_height : float, optional
        The flat pad at each fingertip, along x from the tip and along z
        (default: the finger's whole inner face, ``finger_length`` ×
        ``finger_height``). The jaws touch where their pads first meet the
        object (:mod:`forceclosure.gripper.pads`).
    palm_width, palm_height : float, optional
        The palm's size along y and z (default ``width_max + 2
        finger_thickness`` and ``finger_height``).
    tip_offset : float, optional
        From the hand's base frame (its mounting flange; ACRONYM's gripper
        frame) to the fingertips, along the approach axis (default
        ``finger_length + palm_thickness``: the palm's back face).
    pad_compliance : float, optional
        How deep a pad presses into its contact past the first touch (default
        ``0.01 width_max``): the contact is the pressed point nearest the pad's
        centre (:mod:`forceclosure.gripper.pads`); 0: rigid pads.

    Examples
    --------
    >>> ParallelJaw(0.08, pad_radius=0.01).torsion(0.3)
    0.002
    >>> ParallelJaw(0.1).finger_length, ParallelJaw(0.1, depth=0.03).depth
    (0.05, 0.03)
    >>> ParallelJaw(0.1).pad_length, ParallelJaw(0.1, pad_radius=0).torsion(0.5) is None
    (0.05, True)
    """

    # every size is a float once made (a size left None gets its default); only pad_radius
    # keeps None, which means something (the pressed region's lever)
    width_max: float
    pad_radius: float | None
    depth: float
    finger_length: float
    finger_thickness: float
    finger_height: float
    palm_thickness: float
    name: str
    pad_length: float
    pad_height: float
    palm_width: float
    palm_height: float
    tip_offset: float
    pad_compliance: float

    def __init__(self, width_max: float, pad_radius: float | None = None,
                 depth: float | None = None, finger_length: float | None = None,
                 finger_thickness: float | None = None, finger_height: float | None = None,
                 palm_thickness: float | None = None, name: str = "parallel-jaw",
                 pad_length: float | None = None, pad_height: float | None = None,
                 palm_width: float | None = None, palm_height: float | None = None,
                 tip_offset: float | None = None, pad_compliance: float | None = None) -> None:
        given = locals()  # the arguments, one per field, checked and completed below
        for f in fields(self):
            object.__setattr__(self, f.name, given[f.name])
        for name in ("width_max", "pad_radius", *_SHAPE, *_DERIVED):
            value = getattr(self, name)
            if value is None and name != "width_max":
                continue
            try:  # an int past float's range (10**400) is not finite either
                number = float(value) if isinstance(value, Real) else math.nan
            except OverflowError:
                number = math.inf
            if (isinstance(value, bool) or not isinstance(value, Real)
                    or not math.isfinite(number) or number < 0 or number > 1e150):
                raise InputError(f"ParallelJaw: '{name}' must be a finite number >= 0 (at "
                                 f"most 1e150), got {shown(value, 80)}")
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError(f"ParallelJaw: 'name' must be a non-empty string, got {self.name!r}")
        if self.width_max <= 0:
            raise InputError(f"ParallelJaw: 'width_max' must be positive, got {self.width_max}")
        for name, share in _SHAPE.items():
            if getattr(self, name) is None:
                object.__setattr__(self, name, round(share * float(self.width_max), 15))
            else:
                object.__setattr__(self, name, float(getattr(self, name)))
        defaults = {"pad_length": self.finger_length, "pad_height": self.finger_height,
                    "palm_width": round(self.width_max + 2 * self.finger_thickness, 15),
                    "palm_height": self.finger_height,
                    "tip_offset": round(self.finger_length + self.palm_thickness, 15),
                    "pad_compliance": round(0.01 * self.width_max, 15)}
        for name in _DERIVED:
            value = getattr(self, name)
            object.__setattr__(self, name, float(defaults[name] if value is None else value))
        if self.pad_radius is not None:
            object.__setattr__(self, "pad_radius", float(self.pad_radius))
        for name in ("finger_length", "finger_thickness", "finger_height", "pad_length",
                     "pad_height"):
            if getattr(self, name) <= 0:
                raise InputError(f"ParallelJaw: '{name}' must be positive, got "
                                 f"{getattr(self, name)}")
        if self.depth > self.finger_length:
            raise InputError(f"ParallelJaw: 'depth' ({self.depth}) must not exceed "
                             f"'finger_length' ({self.finger_length}): the tips reach past the "
                             "jaw centre by at most the fingers' length")
        if self.pad_length > self.finger_length:
            raise InputError(f"ParallelJaw: 'pad_length' ({self.pad_length}) must not exceed "
                             f"'finger_length' ({self.finger_length})")

    def torsion(self, mu: float) -> float | None:
        """The soft pads' coupled torsional coefficient at friction ``mu`` (the bound on
        the twisting torque per unit normal force), or None (uncoupled: ``pad_radius``
        0). With ``pad_radius`` None it is the most a pad gives, pressed flat over its
        whole rectangle (μ times :func:`rectangle_mean_radius`): an upper bound, never
        what a label relies on (labels take the pressed region's lever, from below)."""
        if self.pad_radius is None:
            return _digits(mu * rectangle_mean_radius(self.pad_length, self.pad_height))
        return None if self.pad_radius == 0 else _digits(2.0 / 3.0 * mu * self.pad_radius)

    def shape(self) -> dict[str, Any]:
        """Every size of the hand, by field name (what ``ParallelJaw(**shape)`` rebuilds)."""
        return {name: getattr(self, name) for name in (
            "width_max", "pad_radius", *_SHAPE, "name", *_DERIVED)}


@dataclass(frozen=True, eq=False)
class JawPose:
    """Where the jaws are: ``center``, unit ``closing_axis`` (jaw 1 → jaw 2), unit
    ``approach_axis`` (perpendicular to it; made so if given otherwise), ``width``.

    Examples
    --------
    >>> pose = JawPose([0, 0, 0], [2, 0, 0], [0, 0, 1], 3.0)
    >>> pose.closing_axis.tolist(), pose.jaws.tolist()
    ([1.0, 0.0, 0.0], [[-1.5, 0.0, 0.0], [1.5, 0.0, 0.0]])
    """

    center: NDArray[np.float64]
    closing_axis: NDArray[np.float64]
    approach_axis: NDArray[np.float64]
    width: float

    def __post_init__(self) -> None:
        try:
            center = np.asarray(self.center, dtype=float).reshape(3)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"JawPose: 'center' must be 3 numbers, got {self.center!r}") from None
        if not np.all(np.isfinite(center)):
            raise InputError(f"JawPose: 'center' must be finite, got {center.tolist()}")
        closing = _unit(self.closing_axis, "closing_axis")
        approach = _unit(self.approach_axis, "approach_axis")
        approach = approach - (approach @ closing) * closing
        if np.linalg.norm(approach) <= 1e-9:
            raise InputError("JawPose: 'approach_axis' is parallel to 'closing_axis'")
        approach = approach / np.linalg.norm(approach)
        try:
            width = float(self.width)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"JawPose: 'width' must be a number, got {shown(self.width, 80)}"
                             ) from None
        if not np.isfinite(width) or width <= 0:
            raise InputError(f"JawPose: 'width' must be finite and positive, got {width}")
        object.__setattr__(self, "center", center)
        object.__setattr__(self, "closing_axis", closing)
        object.__setattr__(self, "approach_axis", approach)
        object.__setattr__(self, "width", width)

    @property
    def jaws(self) -> NDArray[np.float64]:
        """The two pads' centres, ``(2, 3)``: ``center ∓ width/2 · closing_axis``."""
        half = 0.5 * self.width * self.closing_axis
        return np.array([self.center - half, self.center + half])

    @property
    def rotation(self) -> NDArray[np.float64]:
        """The gripper frame as a rotation matrix, columns ``(approach, closing, approach ×
        closing)``: graspnetAPI's order (x approach, y the jaws' axis)."""
        a, c = self.approach_axis, self.closing_axis
        return np.column_stack([a, c, np.cross(a, c)])


@dataclass(frozen=True, eq=False)
class JawContacts:
    """The contact pair a jaw pose makes, or why it makes none.

    ``points`` and ``normals`` are ``(2, 3)`` (the contact met by jaw 1, then
    jaw 2; outward unit normals of the faces hit), ``triangles`` the
    triangles hit (indices into the loaded object's ``triangles``, which may
    differ from a given trimesh's: vertices are merged and faces oriented);
    all None when ``reason`` says why there is no pair.
    """

    points: NDArray[np.float64] | None
    normals: NDArray[np.float64] | None
    triangles: NDArray[np.int64] | None
    reason: str | None = None

    @property
    def ok(self) -> bool:
        """True when the jaws meet the object in a contact pair."""
        return self.reason is None


def surface_mesh(obj: Any):
    """``(polyhedron, trimesh)`` of an object (a file, a bundled name, a ``trimesh.Trimesh``
    or a :class:`~forceclosure.objects.Polyhedron`): the mesh validated and oriented
    outward by :func:`~forceclosure.objects.io.load_object`."""
    from ..objects.io import load_object
    from ..objects.polyhedron import Polyhedron

    poly = load_object(obj)
    if not isinstance(poly, Polyhedron):
        raise InputError(f"{poly.name}: a parallel-jaw gripper grasps a mesh (a polyhedron), "
                         "not a polygon")
    cached = _MESHES.get(id(poly))
    if cached is not None and cached[0]() is poly:
        return poly, cached[1]
    mesh = poly.to_trimesh()
    if len(_MESHES) >= 8:
        _MESHES.pop(next(iter(_MESHES)))
    _MESHES[id(poly)] = (weakref.ref(poly), mesh)
    return poly, mesh


#: The trimesh (and its ray accelerator) of the last few polyhedra used, by identity.
_MESHES: dict[int, tuple[weakref.ref, Any]] = {}


def cast_first(mesh, origins: NDArray[np.float64], directions: NDArray[np.float64]
               ) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]:
    """The first triangle each ray meets (-1 for none), the distance along the ray
    (double precision, from the triangle's plane; inf for none), and the hit points.

    One batched ray query (``mesh.ray.intersects_id``, embree when installed).
    """
    n = len(origins)
    tri = np.full(n, -1, dtype=np.int64)
    t = np.full(n, np.inf)
    if n:
        index_tri, index_ray = mesh.ray.intersects_id(origins, directions, multiple_hits=False)
        tri[np.asarray(index_ray, dtype=np.int64)] = index_tri
    hit = tri >= 0
    normal = mesh.face_normals[tri[hit]]
    anchor = mesh.vertices[mesh.faces[tri[hit], 0]]
    denom = np.einsum("ij,ij->i", normal, directions[hit])
    with np.errstate(divide="ignore", invalid="ignore"):
        t[hit] = np.einsum("ij,ij->i", normal, anchor - origins[hit]) / denom
    t[hit] = np.where(np.isfinite(t[hit]), t[hit], 0.0)  # a ray grazing its face
    points = origins + np.where(hit, t, 0.0)[:, None] * directions
    return tri, t, points


def jaw_contacts(mesh, size: float, centers: NDArray, closing: NDArray, widths: NDArray
                 ) -> tuple[NDArray, NDArray, NDArray, NDArray[np.object_]]:
    """Vectorised :func:`contacts_of` for ``N`` poses on a trimesh (outward faces):
    points ``(N, 2, 3)``, normals ``(N, 2, 3)``, triangles ``(N, 2)`` and reasons (None
    where the pose makes a pair)."""
    n = len(centers)
    back = BACKOFF * size
    half = (0.5 * widths + back)[:, None] * closing
    origins = np.concatenate([centers - half, centers + half])
    directions = np.concatenate([closing, -closing])
    tri, t, points = cast_first(mesh, origins, directions)
    reach = np.concatenate([widths, widths]) + 2 * back
    met = tri >= 0
    normals = np.zeros((2 * n, 3))
    normals[met] = mesh.face_normals[tri[met]]
    # the first face met, however far, faces away from the jaw: the jaw is inside
    inside = met & (np.einsum("ij,ij->i", normals, directions) > 0)
    hit = met & (t <= reach)
    reasons = np.full(n, None, dtype=object)
    miss = ~(hit[:n] & hit[n:])
    reasons[miss] = MISSES
    reasons[inside[:n] | inside[n:]] = INSIDE
    pair = lambda a: np.stack([a[:n], a[n:]], axis=1)  # noqa: E731
    return pair(points), pair(normals), pair(np.where(hit, tri, -1)), reasons


def contacts_of(obj: Any, pose: JawPose, gripper: ParallelJaw | None = None) -> JawContacts:
    """The contact pair the jaws of ``pose`` make on ``obj``, closing along its axis.

    Each jaw casts a ray from its pad (``pose.jaws``) towards the other jaw;
    its contact is the first surface met within the opening, with that
    face's outward normal. There is no pair, and ``reason`` says so, when
    the pose is wider than ``gripper.width_max``, when a ray meets nothing
    before the other jaw (misses), or when the first face a ray meets faces
    away from the jaw (the jaw starts inside the object).

    Parameters
    ----------
    obj : file, bundled name, trimesh.Trimesh or Polyhedron
    pose : JawPose
    gripper : ParallelJaw, optional
        Checks the pose's width against ``width_max``.

    A file is read again at each call; for many poses load it once
    (:func:`~forceclosure.objects.io.load_object`): a loaded object's ray
    accelerator is kept between calls.

    Examples
    --------
    The 2 × 2 × 2 cube, pinched across its x faces 0.5 above its middle:

    >>> c = contacts_of("cube", JawPose([0, 0.5, 0], [1, 0, 0], [0, 0, 1], 3.0))
    >>> c.points.round(9).tolist(), c.normals.tolist()
    ([[-1.0, 0.5, 0.0], [1.0, 0.5, 0.0]], [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    >>> contacts_of("cube", JawPose([0, 0, 0], [1, 0, 0], [0, 0, 1], 3.0),
    ...             ParallelJaw(2.5)).reason
    "wider than the opening: the pose's width exceeds the gripper's width_max"
    >>> contacts_of("cube", JawPose([0, 3, 0], [1, 0, 0], [0, 0, 1], 3.0)).reason
    "misses: a jaw's ray meets no surface between the jaws"
    """
    if not isinstance(pose, JawPose):
        raise InputError(f"pose must be a JawPose, got {type(pose).__name__}")
    if gripper is not None and pose.width > gripper.width_max:
        return JawContacts(None, None, None, TOO_WIDE)
    poly, mesh = surface_mesh(obj)
    points, normals, tris, reasons = jaw_contacts(
        mesh, poly.size, pose.center[None], pose.closing_axis[None], np.array([pose.width]))
    if reasons[0] is not None:
        return JawContacts(None, None, None, reasons[0])
    return JawContacts(points[0], normals[0], tris[0])


def pose_from_contacts(p: ArrayLike, q: ArrayLike, approach: ArrayLike | None = None
                       ) -> JawPose:
    """The jaw pose whose pads touch ``p`` (jaw 1) and ``q`` (jaw 2): centred between
    them, closing from ``p`` to ``q``, as wide as they are apart; the approach axis is
    ``approach`` made perpendicular to the closing axis (default
    :func:`default_approach`).

    Examples
    --------
    >>> pose = pose_from_contacts([-1, 0.5, 0], [1, 0.5, 0], approach=[0, 1, 1])
    >>> pose.center.tolist(), pose.width, pose.approach_axis.round(6).tolist()
    ([0.0, 0.5, 0.0], 2.0, [0.0, 0.707107, 0.707107])
    """
    p, q = _point(p, "p"), _point(q, "q")
    closing = _unit(q - p, "q - p")
    axis = default_approach(closing) if approach is None else _unit(approach, "approach_axis")
    return JawPose(0.5 * (p + q), closing, axis, float(np.linalg.norm(q - p)))
