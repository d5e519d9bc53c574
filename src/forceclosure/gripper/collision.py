"""Gripper–object collision: does the opened hand of a jaw pose meet the object?

The hand of a :class:`~forceclosure.gripper.jaw.ParallelJaw` is three boxes in
the jaw frame (x the approach axis, y the closing axis, z = x × y, origin
the jaw centre; the frame of ``JawPose.rotation``): two fingers and the
palm joining their bases (:func:`hand_boxes`; their sizes are the
gripper's optional shape fields). At each pose the fingers are opened to
the grasp's width plus a clearance on each side, ``width + 2 clearance``:
the pads stand ``clearance`` off their contacts, so that touching the
contact faces is not a collision, and the check is of the hand as it
arrives before closing. The default clearance is :data:`CLEARANCE` times
``width_max``. A user's hand mesh (``hand=``, a ``trimesh.Trimesh`` in the
jaw frame, as it arrives) replaces the boxes; it is checked as given, not
opened per grasp.

The check is FCL's (python-fcl) through trimesh's ``CollisionManager``:
the object's mesh in one manager, the hand's parts in another, moved to
each pose. FCL tests surfaces against surfaces, so a part wholly inside
the object, or an object wholly inside a part, meets no surface; both are
caught too: a vertex of each part's connected pieces is tested inside the
object (``trimesh``'s ``contains``, ray parity: meaningful on closed
meshes) and a vertex of each of the object's pieces inside each part.
"""

from __future__ import annotations

import weakref
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from .jaw import JawPose, ParallelJaw

__all__ = ["APPROACHES", "CLEARANCE", "approach_axes", "choose_approach", "collides",
           "hand_boxes", "jaw_frames"]

#: Default clearance of each pad off its contact, as a share of ``width_max``.
CLEARANCE = 0.01

#: Approach axes tried per contact pair by default (:func:`choose_approach`).
APPROACHES = 8


def hand_boxes(gripper: ParallelJaw, width: float, clearance: float | None = None
               ) -> list[tuple[str, NDArray[np.float64], NDArray[np.float64]]]:
    """The hand's boxes at an opening: ``(name, extents, centre)`` in the jaw frame.

    The fingers' inner faces are at ``y = ∓(width/2 + clearance)``; they run
    along x from ``depth - finger_length`` to ``depth``. The palm (absent
    when ``palm_thickness`` is 0) lies behind them, ``palm_width`` wide and
    ``palm_height`` high.

    Examples
    --------
    >>> for name, ext, c in hand_boxes(ParallelJaw(1.0), 0.5, clearance=0.0):
    ...     print(name, ext.round(3).tolist(), c.round(3).tolist())
    jaw1 [0.5, 0.1, 0.2] [-0.05, -0.3, 0.0]
    jaw2 [0.5, 0.1, 0.2] [-0.05, 0.3, 0.0]
    palm [0.1, 1.2, 0.2] [-0.35, 0.0, 0.0]
    """
    g = gripper
    c = CLEARANCE * g.width_max if clearance is None else float(clearance)
    if not np.isfinite(c) or c < 0:
        raise InputError(f"clearance must be a finite number >= 0, got {clearance!r}")
    length, t, h = g.finger_length, g.finger_thickness, g.finger_height
    finger = np.array([length, t, h])
    x = g.depth - 0.5 * length
    y = 0.5 * width + c + 0.5 * t
    boxes = [("jaw1", finger, np.array([x, -y, 0.0])), ("jaw2", finger, np.array([x, y, 0.0]))]
    if g.palm_thickness > 0:
        boxes.append(("palm", np.array([g.palm_thickness, g.palm_width, g.palm_height]),
                      np.array([g.depth - length - 0.5 * g.palm_thickness, 0.0, 0.0])))
    return boxes


def jaw_frames(center: ArrayLike, closing_axis: ArrayLike, approach_axis: ArrayLike
               ) -> NDArray[np.float64]:
    """``(N, 4, 4)`` transforms from the jaw frame to the world: rotation columns
    ``(approach, closing, approach × closing)``, translation the jaw centre.

    The approach axis is made perpendicular to the closing axis (as
    :class:`~forceclosure.gripper.jaw.JawPose` does); both are normalised.

    Examples
    --------
    >>> jaw_frames([[0, 0, 1]], [[1, 0, 0]], [[0, 0, -1]])[0].tolist()
    [[0.0, 1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0], [-1.0, 0.0, 0.0, 1.0], [0.0, 0.0, 0.0, 1.0]]
    """
    center = np.asarray(center, dtype=float).reshape(-1, 3)
    c = np.asarray(closing_axis, dtype=float).reshape(-1, 3)
    a = np.asarray(approach_axis, dtype=float).reshape(-1, 3)
    c = c / np.linalg.norm(c, axis=1, keepdims=True)
    a = a - np.einsum("ij,ij->i", a, c)[:, None] * c
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    frames = np.zeros((len(center), 4, 4))
    frames[:, :3, 0], frames[:, :3, 1], frames[:, :3, 2] = a, c, np.cross(a, c)
    frames[:, :3, 3] = center
    frames[:, 3, 3] = 1.0
    return frames


#: The collision manager of the last few meshes checked, by identity (building one costs
#: milliseconds per thousand triangles).
_WORLDS: dict[int, tuple[Any, Any]] = {}


def _world(mesh):
    """A collision manager holding ``mesh`` alone (kept for the mesh's next checks)."""
    from trimesh.collision import CollisionManager

    kept = _WORLDS.get(id(mesh))
    if kept is not None and kept[0]() is mesh:
        return kept[1]
    world = CollisionManager()
    world.add_object("object", mesh)
    if len(_WORLDS) >= 8:
        _WORLDS.pop(next(iter(_WORLDS)))
    _WORLDS[id(mesh)] = (weakref.ref(mesh), world)
    return world


def _anchors(mesh) -> NDArray[np.float64]:
    """One vertex of each connected piece of a mesh (by shared edges)."""
    import trimesh

    labels = trimesh.graph.connected_component_labels(mesh.face_adjacency, len(mesh.faces))
    _, first = np.unique(labels, return_index=True)
    return mesh.vertices[mesh.faces[first, 0]]


def _poses(poses: Any) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    if isinstance(poses, JawPose):
        poses = [poses]
    if isinstance(poses, (list, tuple)):
        if not all(isinstance(p, JawPose) for p in poses):
            raise InputError("poses must be JawPose objects (or arrays of jaw poses, such as "
                             "GraspLabels)")
        if not poses:
            return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0)
        return (np.array([p.center for p in poses]), np.array([p.closing_axis for p in poses]),
                np.array([p.approach_axis for p in poses]), np.array([p.width for p in poses]))
    try:
        arrays = [np.asarray(getattr(poses, name), dtype=float)
                  for name in ("center", "closing_axis", "approach_axis", "width")]
    except AttributeError:
        raise InputError("poses must be a JawPose, a list of them, or an object with arrays "
                         "center, closing_axis, approach_axis, width (GraspLabels), got "
                         f"{type(poses).__name__}") from None
    center, closing, approach, width = (arrays[0].reshape(-1, 3), arrays[1].reshape(-1, 3),
                                        arrays[2].reshape(-1, 3), arrays[3].reshape(-1))
    if not (len(closing) == len(approach) == len(width) == len(center)):
        raise InputError(f"poses: center, closing_axis, approach_axis and width must have "
                         f"the same length, got {len(center)}, {len(closing)}, "
                         f"{len(approach)}, {len(width)}")
    return center, closing, approach, width


def collides(obj: Any, poses: Any, gripper: ParallelJaw, clearance: float | None = None,
             hand: Any = None, depths: Any = None) -> NDArray[np.bool_] | bool:
    """Whether the hand, opened at each jaw pose, meets the object.

    Parameters
    ----------
    obj : file, bundled name, trimesh.Trimesh or Polyhedron
        Loaded as :func:`~forceclosure.gripper.jaw.contacts_of` loads it.
    poses : JawPose, list of JawPose, or arrays
        Any object with arrays ``center``, ``closing_axis``,
        ``approach_axis`` (``(N, 3)``) and ``width`` (``(N,)``), such as
        :class:`~forceclosure.gripper.labels.GraspLabels`.
    gripper : ParallelJaw
        Its shape fields size the boxes (:func:`hand_boxes`).
    clearance : float, optional
        Each pad's distance off its contact; default :data:`CLEARANCE` ×
        ``width_max``.
    hand : trimesh.Trimesh, optional
        A hand mesh in the jaw frame, instead of the boxes (checked as given).
    depths : (N,) array, optional
        How far each pose's fingertips reach past its jaw centre (default the
        gripper's ``depth``): the hand moves along its approach axis by the
        difference.

    Returns
    -------
    bool for one JawPose, else an ``(N,)`` bool array.

    References
    ----------
    .. [1] J. Pan, S. Chitta and D. Manocha, "FCL: A general purpose library for
       collision and proximity queries", *Proc. IEEE ICRA*, 2012

    Examples
    --------
    The 2-unit cube pinched across its x faces 0.8 above its middle: coming
    from above the hand is clear; coming from below, its palm is in the cube.

    >>> hand = ParallelJaw(3.0)
    >>> collides("cube", JawPose([0, 0, 0.8], [1, 0, 0], [0, 0, -1], 2.0), hand)
    False
    >>> collides("cube", JawPose([0, 0, 0.8], [1, 0, 0], [0, 0, 1], 2.0), hand)
    True
    """
    import trimesh
    from trimesh.collision import CollisionManager

    from .jaw import surface_mesh

    if not isinstance(gripper, ParallelJaw):
        raise InputError(f"gripper must be a ParallelJaw, got {type(gripper).__name__}")
    single = isinstance(poses, JawPose)
    center, closing, approach, width = _poses(poses)
    n = len(center)
    if hand is not None and not isinstance(hand, trimesh.Trimesh):
        raise InputError(f"hand must be a trimesh.Trimesh, got {type(hand).__name__}")
    _, mesh = surface_mesh(obj)
    frames = jaw_frames(center, closing, approach) if n else np.zeros((0, 4, 4))
    if depths is not None:
        try:
            depths = np.asarray(depths, dtype=float).reshape(n)
        except (TypeError, ValueError, OverflowError):
            raise InputError(f"depths must be {n} numbers, one a pose") from None
        if not np.all(np.isfinite(depths)):
            raise InputError("depths must be finite")
        if hand is not None:  # the given hand moves back as the fingertips reach less far
            frames[:, :3, 3] += (depths - gripper.depth)[:, None] * frames[:, :3, 0]
    if hand is None:
        template = hand_boxes(gripper, 0.0, clearance)
        names = [name for name, _, _ in template]
        extents = [ext for _, ext, _ in template]
        parts = {name: trimesh.creation.box(extents=ext) for name, ext, _ in template}
        # the boxes at each opening: the fingers move out by half the width, the palm stays
        side = np.array([-1.0 if name == "jaw1" else 1.0 if name == "jaw2" else 0.0
                         for name in names])
        offsets = np.repeat(np.array([c for _, _, c in template])[None], n, axis=0)
        offsets[:, :, 1] += 0.5 * width[:, None] * side[None]
        if depths is not None:
            offsets[:, :, 0] += (depths - gripper.depth)[:, None]
    else:
        names, parts = ["hand"], {"hand": hand}
        offsets = np.zeros((n, 1, 3))
    world = _world(mesh)
    gripper_parts = CollisionManager()
    for name in names:
        gripper_parts.add_object(name, parts[name])
    # each part's pose: the jaw frame, then the part's offset in it
    part_frames = np.repeat(frames[:, None], len(names), axis=1)
    part_frames[:, :, :3, 3] += np.einsum("nij,nkj->nki", frames[:, :3, :3], offsets)
    hit = np.zeros(n, dtype=bool)
    for i in range(n):
        for k, name in enumerate(names):
            gripper_parts.set_transform(name, part_frames[i, k])
        hit[i] = world.in_collision_other(gripper_parts)
    # a part wholly inside the object: one vertex of each of its pieces is inside
    rest = np.flatnonzero(~hit)
    if len(rest):
        for k, name in enumerate(names):
            local = _anchors(parts[name])
            R, t = part_frames[rest, k, :3, :3], part_frames[rest, k, :3, 3]
            points = np.einsum("nij,mj->nmi", R, local) + t[:, None]
            inside = mesh.contains(points.reshape(-1, 3)).reshape(len(rest), -1)
            hit[rest] |= inside.any(axis=1)
    # the object wholly inside a part: one vertex of each of its pieces is inside the part
    rest = np.flatnonzero(~hit)
    if len(rest):
        anchors = _anchors(mesh)
        for k in range(len(names)):
            R, t = part_frames[rest, k, :3, :3], part_frames[rest, k, :3, 3]
            local = np.einsum("nji,nmj->nmi", R, anchors[None] - t[:, None])
            if hand is None:
                half = 0.5 * extents[k]
                inside = np.all(np.abs(local) < half, axis=2)
            else:
                inside = hand.contains(local.reshape(-1, 3)).reshape(len(rest), -1)
            hit[rest] |= inside.any(axis=1)
    return bool(hit[0]) if single else hit


def approach_axes(closing_axis: ArrayLike, approach_axis: ArrayLike, count: int
                  ) -> NDArray[np.float64]:
    """``count`` approach axes per pose, ``(count, N, 3)``: the given one turned about the
    closing axis by ``2 pi k / count``, ``k = 0 … count - 1``.

    Each axis is a unit vector perpendicular to the closing axis; ``k = 0``
    is the given axis (made perpendicular and normalised).

    Examples
    --------
    >>> (approach_axes([[1, 0, 0]], [[0, 0, -1]], 4)[:, 0].round(12) + 0.0).tolist()
    [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]]
    """
    c = np.asarray(closing_axis, dtype=float).reshape(-1, 3)
    a = np.asarray(approach_axis, dtype=float).reshape(-1, 3)
    c = c / np.linalg.norm(c, axis=1, keepdims=True)
    a = a - np.einsum("ij,ij->i", a, c)[:, None] * c
    a = a / np.linalg.norm(a, axis=1, keepdims=True)
    b = np.cross(c, a)
    angle = 2 * np.pi * np.arange(int(count)) / int(count)
    return np.cos(angle)[:, None, None] * a[None] + np.sin(angle)[:, None, None] * b[None]


class _Poses:
    """Arrays of jaw poses, as :func:`collides` reads them."""

    def __init__(self, center, closing_axis, approach_axis, width):
        self.center, self.closing_axis = center, closing_axis
        self.approach_axis, self.width = approach_axis, width


def choose_approach(obj: Any, poses: Any, gripper: ParallelJaw, approaches: int = APPROACHES,
                    clearance: float | None = None, hand: Any = None
                    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Per pose, the first of ``approaches`` approach axes at which the hand is clear.

    The approach axis of a parallel-jaw pose may be any direction
    perpendicular to its closing axis. The candidates are the pose's own
    axis turned about the closing axis in even steps of ``2 pi /
    approaches`` (:func:`approach_axes`); the first whose hand does not meet
    the object (:func:`collides`) is kept. Where every one collides, the
    pose's own axis is kept and marked colliding. The contacts, and so the
    verdict, μ* and ε, do not depend on the approach: only the hand moves.

    Two collision calls at most, over arrays: every pose's own axis, then
    the other ``approaches - 1`` axes of the poses that collided, all at once.

    Parameters
    ----------
    obj, poses, gripper, clearance, hand
        As for :func:`collides` (``poses`` as arrays or ``JawPose`` objects).
    approaches : int
        Axes tried per pose (at least 1; 1: the pose's own axis alone).

    Returns
    -------
    approach_axis : (N, 3) array
        The chosen unit axes, perpendicular to the closing axes.
    collides : (N,) bool array
        True where all ``approaches`` axes collide.

    Examples
    --------
    The 2-unit cube pinched across x, 0.8 above its middle; the given
    approach (+z, from below) puts the palm in the cube; turned half a
    turn (the third of 4 axes, -z) it is clear.

    >>> from forceclosure.gripper.jaw import JawPose
    >>> axis, hit = choose_approach("cube", [JawPose([0, 0, 0.8], [1, 0, 0], [0, 0, 1], 2.0)],
    ...                             ParallelJaw(3.0), approaches=4)
    >>> (axis.round(12) + 0.0).tolist(), hit.tolist()
    ([[0.0, 0.0, -1.0]], [False])
    """
    if isinstance(approaches, bool) or not isinstance(approaches, int | np.integer) \
            or approaches < 1:
        raise InputError(f"approaches must be a whole number >= 1, got {approaches!r}")
    center, closing, approach, width = _poses(poses)
    n = len(center)
    if n == 0:
        return np.zeros((0, 3)), np.zeros(0, dtype=bool)
    axes = approach_axes(closing, approach, approaches)
    hit = np.asarray(collides(obj, _Poses(center, closing, axes[0], width), gripper, clearance,
                              hand), dtype=bool)
    chosen = axes[0].copy()
    rest = np.flatnonzero(hit)
    if approaches > 1 and len(rest):
        k = approaches - 1
        more = np.asarray(collides(obj, _Poses(np.tile(center[rest], (k, 1)),
                                               np.tile(closing[rest], (k, 1)),
                                               axes[1:, rest].reshape(-1, 3),
                                               np.tile(width[rest], k)),
                                   gripper, clearance, hand), dtype=bool).reshape(k, len(rest))
        clear = ~more
        found = clear.any(axis=0)
        first = np.argmax(clear, axis=0)  # the first clear axis, where there is one
        chosen[rest[found]] = axes[1 + first[found], rest[found]]
        hit[rest[found]] = False
    return chosen, hit
