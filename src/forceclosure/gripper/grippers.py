"""Real parallel-jaw hands, by name: their opening, fingers, pads, palm and base frame.

Each built-in is a :class:`~forceclosure.gripper.jaw.ParallelJaw` whose sizes
come from a source a user can check (metres, the jaw frame of
:mod:`forceclosure.gripper.collision`: x the approach axis, y the closing
axis):

``panda``
    The Franka Emika Panda hand, as its description ships with
    ``pybullet_data`` (``franka_panda/panda.urdf`` and its collision meshes
    ``hand.obj`` and ``finger.obj``): each finger slides 0 to 0.04 m
    (opening up to 0.08); the fingers are mounted 0.0584 in front of the
    hand's frame and are 0.0538 long, so the fingertips are 0.1122 in
    front of it (the ACRONYM gripper frame is this hand frame); the
    hand's body reaches 0.066 forward, so 0.0462 of each finger stands
    free of it; the finger is 0.021 across (z) and up to 0.0266 thick (y);
    its flat pad is the last 0.0175 of the inner face, 0.0175 across; the
    hand's body is 0.2044 wide (y, from -0.104 to 0.1004: off the jaws'
    line, so the palm box centred on it is 0.208 wide to hold it) and 0.0632
    high (z), and reaches 0.0259 behind the frame. Its pads are taken to press 1 mm (a rubber
    fingertip; an assumption, not a datum).
``graspnet``
    GraspNet-1Billion's collision model (graspnetAPI
    ``utils/eval_utils.py``: ``height = 0.02``, ``depth_base = 0.02``,
    ``finger_width = 0.01``; widths up to 0.1 as its evaluation clips
    them): fingers 0.01 thick and 0.02 high reaching from the palm, 0.02
    behind the grasp point, to the tips (depths up to 0.04: 0.06 long), the
    palm 0.01 thick; the pad is the last 0.04 of the fingers' inner faces
    (GraspNet's depths reach 0.04 past the grasp point), pressing 1 mm (an
    assumption; GraspNet's labels take point contacts).

``robotiq-2f85``
    The Robotiq 2F-85 Adaptive Gripper. Its fingers move on a four-bar
    linkage, not a slide: at the fingertips it acts as a parallel jaw (the pads
    stay parallel) whose pads advance up to 0.014 along the approach axis as they
    close; it is modelled as that parallel jaw at its full opening. Sources: the
    stroke, 85 mm, from Robotiq's 2F-85 & 2F-140 Instruction Manual (section
    6.1, Specifications; also ``gripper_max_force 235`` N and speeds 0.02–0.15
    m/s in Robotiq's own ROS description, ``robotiq/ros``,
    ``robotiq_2f_85_macro.urdf.xacro``); the rest from Robotiq's description as
    ROS-Industrial ships it (``robotiq_2f_85_gripper_visualization``,
    ``robotiq_arg2f_85_model_macro.xacro``: the pad a 0.022 × 0.00635 × 0.0375
    box; the linkage's joints; its collision meshes, measured here at full
    opening): the pads 0.086 apart at full opening (the stroke, 0.085, is the
    opening used), each pad 0.0375 long along the approach axis and 0.022 across;
    the fingertips 0.1491 in front of the gripper's mounting face (its base
    link's origin, without Robotiq's coupling); everything between the pads
    deeper than 0.0969 from that face is the linkage or the body (the palm
    here), the fingers reaching 0.0522 past it, 0.0312 thick outside the opening
    and 0.034 high (the linkage at the palm's front; 0.027 past 0.1); the body
    and linkage 0.0996 deep, 0.1484 wide (the knuckles outside, ±0.0742) and
    0.075 high. The pads' 1 mm press is an assumption (rubber pads), as for
    the Panda.

A built-in's boxes enclose the real hand's parts (never smaller), so a pose
called clear of the object is clear for the real hand.

A user's hand is read from its URDF (a name ending in ``.urdf``):
:func:`~forceclosure.gripper.urdf_hand.gripper_from_urdf` measures the same
sizes from the file's finger joints and geometry (the Panda's URDF gives the
``panda`` hand above, to the rounding of its sizes and with boxes that enclose
its meshes exactly).
"""

from __future__ import annotations

from functools import lru_cache

from ..errors import InputError
from .jaw import ParallelJaw

__all__ = ["GENERIC", "GRIPPERS", "gripper_named", "make_gripper", "parse_links"]

#: The name of the generic hand, whose sizes follow from its opening (:class:`ParallelJaw`).
GENERIC = "parallel-jaw"

#: The built-in hands, by name (module text gives each one's sources).
GRIPPERS: dict[str, ParallelJaw] = {
    "panda": ParallelJaw(
        0.08, name="panda", finger_length=0.0462, finger_thickness=0.0266,
        finger_height=0.021, depth=0.00875, pad_length=0.0175, pad_height=0.0175,
        palm_thickness=0.0919, palm_width=0.208, palm_height=0.0632, tip_offset=0.1122,
        pad_compliance=0.001),
    "graspnet": ParallelJaw(
        0.1, name="graspnet", finger_length=0.06, finger_thickness=0.01, finger_height=0.02,
        depth=0.02, palm_thickness=0.01, palm_width=0.12, palm_height=0.02, pad_length=0.04,
        pad_compliance=0.001),
    "robotiq-2f85": ParallelJaw(
        0.085, name="robotiq-2f85", finger_length=0.0522, finger_thickness=0.0312,
        finger_height=0.034, depth=0.01875, pad_length=0.0375, pad_height=0.022,
        palm_thickness=0.0996, palm_width=0.1484, palm_height=0.075, tip_offset=0.1491,
        pad_compliance=0.001),
}


def gripper_named(name: str) -> ParallelJaw:
    """The built-in hand called ``name`` (:data:`GRIPPERS`).

    Examples
    --------
    >>> hand = gripper_named("panda")
    >>> hand.width_max, hand.tip_offset, hand.pad_length
    (0.08, 0.1122, 0.0175)
    >>> gripper_named("robotiq")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: unknown gripper 'robotiq'; the built-in grippers are ...
    """
    try:
        return GRIPPERS[name]
    except (KeyError, TypeError):
        raise InputError(f"unknown gripper {name!r}; the built-in grippers are "
                         + ", ".join(sorted(GRIPPERS)) + " (or give a hand's .urdf file)"
                         ) from None


def make_gripper(name: str | None = None, width: float | None = None,
                 pad_radius: float | None = None, links: str | None = None, *,
                 allow_outside_meshes: bool = False) -> ParallelJaw:
    """A hand from what a user names: a built-in by ``name`` (its opening is its own:
    ``width`` refused), a hand's URDF file (``name`` ending in ``.urdf``, read by
    :func:`~forceclosure.gripper.urdf_hand.gripper_from_urdf`; its opening is its own),
    or the generic hand (``name`` None or :data:`GENERIC`) opening
    ``width``; ``pad_radius`` replaces the pads' torsion model (0: the paper's
    unlimited torque; see :class:`~forceclosure.gripper.jaw.ParallelJaw`). ``links``
    names a URDF hand's links (:func:`parse_links`): ``"PALM"``, ``"PALM,FINGER1,FINGER2"``
    or ``",FINGER1,FINGER2"`` (the palm found). ``allow_outside_meshes`` lets a URDF hand
    name meshes outside its folder (or its package's); refused by default.

    Examples
    --------
    >>> make_gripper("panda").name, make_gripper(width=0.1).name
    ('panda', 'parallel-jaw')
    >>> make_gripper("panda", pad_radius=0).torsion(0.5) is None
    True
    >>> make_gripper("panda", width=0.1)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    forceclosure.errors.InputError: width: the panda gripper opens 0.08 (its own); give ...
    """
    from dataclasses import replace

    from .urdf_hand import is_urdf_name

    if links is not None and not is_urdf_name(name):
        raise InputError(f"links: name a URDF hand's links; {name or GENERIC!r} is not a "
                         ".urdf file")
    if name is None or name == GENERIC:
        if width is None:
            raise InputError(f"width: the {GENERIC} gripper needs its opening (or name a "
                             f"built-in gripper: {', '.join(sorted(GRIPPERS))})")
        return ParallelJaw(width, pad_radius)
    hand = (_urdf_hand(name, *parse_links(links), allow_outside_meshes=allow_outside_meshes)
            if is_urdf_name(name) else gripper_named(name))
    if width is not None:
        raise InputError(f"width: the {hand.name} gripper opens {hand.width_max:g} (its own); give "
                         "one or the other")
    return hand if pad_radius is None else replace(hand, pad_radius=pad_radius)


def parse_links(links: str | None) -> tuple[str | None, tuple[str, str] | None]:
    """The palm and finger links a ``--gripper-links`` value names: ``"PALM"``,
    ``"PALM,FINGER1,FINGER2"`` or ``",FINGER1,FINGER2"``; None: found in the URDF.

    Examples
    --------
    >>> parse_links("panda_hand"), parse_links(",a,b"), parse_links(None)
    (('panda_hand', None), (None, ('a', 'b')), (None, None))
    """
    if links is None:
        return None, None
    parts = [p.strip() for p in str(links).split(",")]
    if len(parts) not in (1, 3) or (len(parts) == 1 and not parts[0]) or (
            len(parts) == 3 and not (parts[1] and parts[2])):
        raise InputError(f"links {links!r}: give PALM, PALM,FINGER1,FINGER2 or "
                         ",FINGER1,FINGER2 (link names of the URDF)")
    return parts[0] or None, (parts[1], parts[2]) if len(parts) == 3 else None


def _urdf_hand(path: str, palm: str | None = None,
               fingers: tuple[str, str] | None = None, *,
               allow_outside_meshes: bool = False) -> ParallelJaw:
    """The hand of a URDF file, read once per version of the file (its path, size and time)."""
    import os

    try:
        stat = os.stat(path)
    except OSError:
        raise InputError(f"{path}: no such URDF file") from None
    return _read_urdf_hand(os.path.abspath(path), stat.st_size, stat.st_mtime_ns, palm,
                           fingers, bool(allow_outside_meshes))


@lru_cache(maxsize=8)
def _read_urdf_hand(path: str, size: int, mtime: int, palm: str | None,
                    fingers: tuple[str, str] | None, allow_outside_meshes: bool = False
                    ) -> ParallelJaw:
    from .urdf_hand import gripper_from_urdf

    return gripper_from_urdf(path, palm_link=palm, finger_links=fingers,
                             allow_outside_meshes=allow_outside_meshes)
