"""Labelled jaw poses in the formats grasp-learning trainers read.

**graspnetAPI's** ``GraspGroup`` (:func:`graspnet_array`, saved as ``.npy``
by :func:`save_graspnet`; ``GraspGroup().from_npy(path)`` reads it): an
``(N, 17)`` float64 array, one row per grasp, columns ``[score, width,
height, depth, R (9, row-major), translation (3), object_id]`` (graspnetAPI
``graspnetAPI/grasp.py``: ``GRASP_ARRAY_LEN = 17``, ``Grasp.rotation_matrix``
is ``grasp_array[4:13].reshape((3, 3))``, ``translation`` ``[13:16]``). The
gripper frame there (``plot_gripper_pro_max`` in ``graspnetAPI/utils/
utils.py``, and the collision masks of ``utils/eval_utils.py``): the
columns of ``R`` are x the approach axis (the fingers run along +x, their
tips at ``x = depth``), y the closing axis (the fingers at ``y = ∓(width/2
+ finger width)``), z = x × y (``height`` is the fingers' size along it);
the translation is the point between the fingers, ``depth`` behind their
tips. Here: ``R = JawPose.rotation`` (columns approach, closing, approach ×
closing), the translation the jaw centre (midpoint of the contacts),
``width`` the contacts' distance, ``height`` and ``depth`` the gripper's
``finger_height`` and ``depth``.

The score: GraspNet scores a grasp ``1.1 - μ`` with ``μ`` the least
friction coefficient (on its grid 0.1, 0.2, …, 1.0) at which the grasp is
in force closure, and keeps only grasps that close and do not collide
(``graspnetAPI/graspnet.py``, ``loadGrasp``: ``scores = (1.1 -
fric_coefs)``, ``mask1 = (fric_coefs <= thresh) & (fric_coefs > 0) &
~collision``). ``score="friction"`` is ``1.1 - μ*`` with our exact least
friction μ*, not a grid value; ``score="epsilon"`` is the Ferrari–Canny ε.
Every grasp is written, in the labels' order (row ``i`` is grasp ``i``);
those that do not close at the labels' μ, or collide, score ``-1`` (as
graspnetAPI's evaluation scores colliding grasps), so ``array[array[:, 0]
>= 0]`` is GraspNet's selection.

**ACRONYM's** HDF5 layout (:func:`save_acronym`; h5py, the ``export``
extra), as its ``acronym_tools/acronym.py`` (``load_grasps``,
``load_mesh``) and its example files read it: ``grasps/transforms`` ``(N,
4, 4)`` gripper poses, ``grasps/qualities/flex/object_in_gripper`` ``(N,)``
int64 0/1, ``object/file`` (a string), ``object/scale`` (a float). The
gripper frame there is the Panda's (``data/franka_gripper_collision_mesh.stl``
and ``create_gripper_marker``): z the approach axis, x the closing axis (the
fingers at ``x = ±0.041``), y = z × x, the origin at the hand's base, behind
the palm: the fingertips are 0.112 ahead of it. Here the transform's
rotation is ``(closing, approach × closing, approach)`` and its origin lies
``offset`` behind the jaw centre along the approach axis (default: our
hand's base, the palm's back face, ``finger_length - depth +
palm_thickness``; for ACRONYM's Panda pass its fingertips' 0.112 less the
depth at which its pads hold the contacts). ``object_in_gripper`` is 1
where the verdict is closure and the hand does not collide (collision not
checked: closure alone). Our labels are under the group ``forceclosure``
(every array of :data:`~forceclosure.gripper.labels.ARRAYS`, the verdict names, and
``meta`` as JSON text in its attributes); ``object/friction`` is the
labels' μ.
"""

from __future__ import annotations

import io
import json
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError
from ..gripper.jaw import ParallelJaw

__all__ = ["KINDS", "acronym_transforms", "graspnet_array", "save_acronym", "save_graspnet"]

#: Export kinds and the file extensions each is written to.
KINDS = {"graspnet": (".npy",), "acronym": (".h5", ".hdf5")}

#: The score of a grasp that does not close, or collides, in the GraspGroup array.
REJECTED = -1.0


def labels_gripper(labels: Any) -> ParallelJaw:
    """The gripper the labels were made with, from their ``meta`` (the hand's boxes when
    the collision check ran, else the defaults from ``width_max``)."""
    meta = labels.meta
    shape = dict(meta.get("collision") or {})
    shape.pop("clearance", None)
    return ParallelJaw(meta["width_max"], meta.get("pad_radius", 0.0), **shape)


def _accepted(labels: Any) -> NDArray[np.bool_]:
    ok = np.asarray(labels.code) == 2
    if labels.collides is not None:
        ok &= ~np.asarray(labels.collides, dtype=bool)
    return ok


def graspnet_array(labels: Any, gripper: ParallelJaw | None = None, score: str = "friction",
                   object_id: int = -1) -> NDArray[np.float64]:
    """The ``(N, 17)`` GraspGroup array of labelled jaw poses (layout in the module's text).

    Parameters
    ----------
    labels : GraspLabels
    gripper : ParallelJaw, optional
        Its ``finger_height`` and ``depth`` fill the height and depth columns
        (default: the labels' gripper, from their ``meta``).
    score : ``"friction"`` or ``"epsilon"``
        ``1.1 - μ*`` (GraspNet's score on the exact least friction) or ε;
        ``-1`` where the grasp does not close or collides.
    object_id : int
        The last column (graspnetAPI's default for no object is -1).

    Examples
    --------
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=4, collision=False)
    >>> a = graspnet_array(labels, score="epsilon")
    >>> a.shape, bool(np.allclose(a[:, 13:16], labels.center))
    ((4, 17), True)
    """
    if score not in ("friction", "epsilon"):
        raise InputError(f"score must be 'friction' or 'epsilon', got {score!r}")
    gripper = labels_gripper(labels) if gripper is None else gripper
    n = len(labels.code)
    ok = _accepted(labels)
    if score == "friction":
        mu_star = np.asarray(labels.least_friction, dtype=float)
        if np.any(np.isnan(mu_star[ok])):
            raise InputError("the GraspNet friction score needs the least friction, which was "
                             "not computed (least_friction=False): use the epsilon score")
        if float(labels.meta.get("mu", 0.0)) >= 2.1:
            raise InputError(f"mu {labels.meta['mu']} >= 2.1: the friction score 1.1 - mu* "
                             "could reach the rejected grasps' -1; use the epsilon score")
        values = 1.1 - mu_star
    else:
        values = np.asarray(labels.epsilon, dtype=float)
        if np.any(np.isnan(values[ok])):
            raise InputError("the GraspNet epsilon score needs the epsilon, which was not "
                             "computed (epsilon=False): use the friction score")
    a = np.empty((n, 17))
    a[:, 0] = np.where(ok, values, REJECTED)
    a[:, 1] = labels.width
    a[:, 2] = gripper.finger_height
    a[:, 3] = gripper.depth
    from ..gripper.collision import jaw_frames

    R = jaw_frames(labels.center, labels.closing_axis, labels.approach_axis)[:, :3, :3]
    a[:, 4:13] = R.reshape(n, 9)  # row-major; columns (approach, closing, approach x closing)
    a[:, 13:16] = labels.center
    a[:, 16] = object_id
    return a


def save_graspnet(path: str, labels: Any, gripper: ParallelJaw | None = None,
                  score: str = "friction", object_id: int = -1) -> None:
    """Write :func:`graspnet_array` to ``path`` (``.npy``), atomically."""
    from .atomic import atomic_write

    array = graspnet_array(labels, gripper, score, object_id)
    with atomic_write(path) as f:
        np.save(f, array)


def acronym_transforms(labels: Any, offset: float) -> NDArray[np.float64]:
    """``(N, 4, 4)`` gripper poses in ACRONYM's frame: rotation columns ``(closing,
    approach × closing, approach)``, origin ``offset`` behind the jaw centre along the
    approach axis.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> pose = SimpleNamespace(center=[[0, 0, 1.0]], closing_axis=[[1.0, 0, 0]],
    ...                        approach_axis=[[0, 0, -1.0]])
    >>> acronym_transforms(pose, 0.5)[0].tolist()
    [[1.0, 0.0, 0.0, 0.0], [0.0, -1.0, 0.0, 0.0], [0.0, 0.0, -1.0, 1.5], [0.0, 0.0, 0.0, 1.0]]
    """
    center = np.asarray(labels.center, dtype=float).reshape(-1, 3)
    closing = np.asarray(labels.closing_axis, dtype=float).reshape(-1, 3)
    approach = np.asarray(labels.approach_axis, dtype=float).reshape(-1, 3)
    T = np.zeros((len(center), 4, 4))
    T[:, :3, 0], T[:, :3, 1], T[:, :3, 2] = closing, np.cross(approach, closing), approach
    T[:, :3, 3] = center - offset * approach
    T[:, 3, 3] = 1.0
    return T


def require_h5py():
    """h5py, or one line naming the extra that installs it."""
    try:
        import h5py
    except ImportError:
        raise InputError("ACRONYM export needs h5py: install forceclosure's 'export' extra "
                         "(pip install 'forceclosure[export]')") from None
    return h5py


def save_acronym(path: str, labels: Any, object_file: str, scale: float = 1.0,
                 offset: float | None = None, gripper: ParallelJaw | None = None) -> None:
    """Write the labels in ACRONYM's HDF5 layout (module text) to ``path``, atomically.

    ``object_file`` is written as ``object/file`` as given (ACRONYM's loader
    joins it to a mesh root); ``offset`` defaults to the hand's base.

    Examples
    --------
    >>> import os, tempfile, h5py
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=3, collision=False,
    ...                       least_friction=False)
    >>> path = os.path.join(tempfile.mkdtemp(), "cube.h5")
    >>> save_acronym(path, labels, "cube.obj")
    >>> with h5py.File(path, "r") as f:
    ...     f["grasps/transforms"].shape, f["object/file"][()].decode()
    ((3, 4, 4), 'cube.obj')
    """
    from ..gripper.labels import _VERDICTS, ARRAYS
    from .atomic import atomic_write

    h5py = require_h5py()
    gripper = labels_gripper(labels) if gripper is None else gripper
    if offset is None:
        offset = gripper.finger_length - gripper.depth + gripper.palm_thickness
    buffer = io.BytesIO()
    with h5py.File(buffer, "w") as f:
        f.create_dataset("grasps/transforms", data=acronym_transforms(labels, offset))
        f.create_dataset("grasps/qualities/flex/object_in_gripper",
                         data=_accepted(labels).astype(np.int64))
        f.create_dataset("object/file", data=str(object_file), dtype=h5py.string_dtype())
        f.create_dataset("object/scale", data=float(scale))
        f.create_dataset("object/friction", data=float(labels.meta.get("mu", np.nan)))
        f.create_dataset("gripper/type", data="forceclosure parallel-jaw",
                         dtype=h5py.string_dtype())
        f.create_dataset("gripper/width_max", data=float(gripper.width_max))
        f.create_dataset("gripper/offset", data=float(offset))
        ours = f.create_group("forceclosure")
        for name in ARRAYS:
            value = getattr(labels, name)
            if value is not None:
                ours.create_dataset(name, data=np.asarray(value))
        ours.create_dataset("verdict", data=_VERDICTS[np.asarray(labels.code)].tolist(),
                            dtype=h5py.string_dtype())
        ours.attrs["meta"] = json.dumps(labels.meta)
    with atomic_write(path) as out:
        out.write(buffer.getvalue())
