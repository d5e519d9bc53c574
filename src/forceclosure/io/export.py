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
closing), the translation the jaw centre (on the closing line between the
pads as they first touch the object), ``width`` the pads' distance then,
``height`` the gripper's ``finger_height`` and ``depth`` the pose's own
(:func:`pose_depths`).

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
int64 0/1, ``object/file`` (a string), ``object/scale`` (a float).
``load_mesh(filename, mesh_root_dir)`` does ``trimesh.load(os.path.join(
mesh_root_dir, object/file)).apply_scale(object/scale)``: ``object/file``
names a mesh relative to a mesh root and ``object/scale`` the scale that
makes it the labels' object (:func:`acronym_object`: a mesh file as it is;
a URDF link of one uniformly scaled mesh at the identity origin, that mesh
and its scale; anything else, the surface written as an ``.obj`` beside
the ``.h5``). The gripper frame there is the Panda's
(``data/franka_gripper_collision_mesh.stl`` and ``create_gripper_marker``:
the fingers at ``x = ±0.041`` from ``z = 0.066`` to their tips at ``z =
0.112``): z the approach axis, x the closing axis, y = z × x, the origin
the hand's base frame. Here the transform's rotation is ``(closing,
approach × closing, approach)`` and its origin lies ``tip_offset - depth``
behind the jaw centre along the approach axis (:func:`tip_offset`: the
gripper's distance from its base frame to its fingertips, 0.112 for the
Panda, by default our box hand's palm back face; :func:`pose_depths`: the
pose's depth, by default the gripper's), so the contacts sit on the
fingers' pads: ``x = ∓width/2`` (up to the pads' press inside it), ``|y|``
within half the pad's height, ``z`` within the pad's length of the
fingertips at ``z = tip_offset``.
``object_in_gripper`` is 1 where the verdict is closure and the hand does
not collide (collision not checked: closure alone). Our labels are under
the group ``forceclosure`` (every array of
:data:`~forceclosure.gripper.labels.ARRAYS` and a per-pose ``depth``, the
verdict names, and ``meta`` as JSON text in its attributes);
``object/friction`` is the labels' μ, ``gripper/type`` the gripper's name.

Every function here takes the labels as a
:class:`~forceclosure.gripper.labels.GraspLabels`, a saved label file's
path, or what ``np.load`` returned for one (:func:`as_labels`).
"""

from __future__ import annotations

import dataclasses
import io
import json
import os
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..extras import require
from ..gripper.jaw import ParallelJaw
from ..verdicts import VerdictCode, verdict_words

__all__ = ["DIRECT_MESHES", "KINDS", "AcronymObject", "acronym_object", "acronym_transforms",
           "as_labels", "graspnet_array", "labels_gripper", "object_source", "pose_depths",
           "save_acronym", "save_graspnet", "tip_offset", "with_object_source",
           "write_acronym_object"]

#: Export kinds and the file extensions each is written to.
KINDS = {"graspnet": (".npy",), "acronym": (".h5", ".hdf5")}

#: The score of a grasp that does not close, or collides, in the GraspGroup array.
REJECTED = -1.0


def as_labels(labels: Any) -> Any:
    """Labels as the exports read them: a :class:`~forceclosure.gripper.labels.GraspLabels`
    as it is; a path to a saved label file (``.npz``), or what ``np.load`` returned for one,
    read by :meth:`~forceclosure.gripper.labels.GraspLabels.load`; anything else (an object
    with the arrays as attributes) as it is.

    Examples
    --------
    >>> import os, tempfile
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=3, collision=False)
    >>> path = os.path.join(tempfile.mkdtemp(), "l.npz")
    >>> labels.save(path)
    >>> bool(np.array_equal(as_labels(np.load(path)).center, labels.center))
    True
    """
    from ..gripper.labels import GraspLabels

    if isinstance(labels, GraspLabels):
        return labels
    if isinstance(labels, str | os.PathLike | Mapping | np.lib.npyio.NpzFile):
        return GraspLabels.load(labels)
    return labels


def labels_gripper(labels: Any) -> ParallelJaw:
    """The gripper the labels were made with, from their ``meta`` (every size under
    ``hand``; in older files the hand's boxes when the collision check ran, else the
    defaults from ``width_max``; its name and ``tip_offset`` when the labels know them)."""
    meta = as_labels(labels).meta
    if "width_max" not in meta:
        raise InputError("labels: their meta has no 'width_max' (the gripper's opening)")
    known = {f.name for f in dataclasses.fields(ParallelJaw)}
    sizes = meta.get("hand") or meta.get("collision") or {}
    shape = {k: v for k, v in dict(sizes).items()
             if k in known and k not in ("clearance", "width_max", "pad_radius")}
    if "name" in known and isinstance(meta.get("gripper"), str):
        shape["name"] = meta["gripper"]
    if "tip_offset" in known and meta.get("tip_offset") is not None:
        shape["tip_offset"] = float(meta["tip_offset"])
    return ParallelJaw(meta["width_max"], meta.get("pad_radius", 0.0), **shape)


def pose_depths(labels: Any, gripper: ParallelJaw) -> NDArray[np.float64]:
    """``(N,)`` how far each pose's fingertips reach past its jaw centre along the approach
    axis: the labels' per-pose ``depth`` where they have one, else the gripper's ``depth``.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> pose_depths(SimpleNamespace(code=[2, 0]), ParallelJaw(0.1)).tolist()
    [0.02, 0.02]
    >>> pose_depths(SimpleNamespace(code=[2, 0], depth=[0.01, 0.03]), ParallelJaw(0.1)).tolist()
    [0.01, 0.03]
    """
    n = len(labels.code)
    depth = getattr(labels, "depth", None)
    if depth is None:
        return np.full(n, float(gripper.depth))
    depth = np.asarray(depth, dtype=float)
    if depth.shape != (n,) or not np.all(np.isfinite(depth)):
        raise InputError(f"labels: 'depth' must be {n} finite numbers, one per pose; got an "
                         f"array of shape {depth.shape}")
    return depth


def tip_offset(labels: Any, gripper: ParallelJaw) -> float:
    """The distance along the approach axis from the hand's base frame to its fingertips:
    the gripper's ``tip_offset``, else the labels' ``meta["tip_offset"]``, else our box
    hand's (palm's back face to tips, ``finger_length + palm_thickness``).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> tip_offset(SimpleNamespace(meta={}), ParallelJaw(0.1))
    0.06
    >>> hand = SimpleNamespace(finger_length=0.05, palm_thickness=0.01)  # no tip_offset
    >>> tip_offset(SimpleNamespace(meta={"tip_offset": 0.1122}), hand)
    0.1122
    """
    tip = getattr(gripper, "tip_offset", None)
    if tip is None:
        tip = (getattr(labels, "meta", None) or {}).get("tip_offset")
    if tip is None:
        tip = gripper.finger_length + gripper.palm_thickness
    return round(float(tip), 15)


def _accepted(labels: Any) -> NDArray[np.bool_]:
    ok = np.asarray(labels.code) == VerdictCode.CLOSURE
    if labels.collides is not None:
        ok &= ~np.asarray(labels.collides, dtype=bool)
    return ok


def graspnet_array(labels: Any, gripper: ParallelJaw | None = None, score: str = "friction",
                   object_id: int = -1) -> NDArray[np.float64]:
    """The ``(N, 17)`` GraspGroup array of labelled jaw poses (layout in the module's text).

    Parameters
    ----------
    labels : GraspLabels, or a label file's path or ``np.load`` result (:func:`as_labels`)
    gripper : ParallelJaw, optional
        Its ``finger_height`` and ``depth`` fill the height and depth columns
        (default: the labels' gripper, from their ``meta``); a per-pose ``depth`` of the
        labels takes the place of the gripper's.
    score : ``"friction"`` or ``"epsilon"``
        ``1.1 - μ*`` (GraspNet's score on the exact least friction) or ε;
        ``-1`` where the grasp does not close or collides.
    object_id : int
        The last column (graspnetAPI's default for no object is -1).

    References
    ----------
    .. [1] H.-S. Fang, C. Wang, M. Gou and C. Lu, "GraspNet-1Billion: A large-scale
       benchmark for general object grasping", *Proc. IEEE/CVF CVPR*, 2020

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
    labels = as_labels(labels)
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
    a[:, 3] = pose_depths(labels, gripper)
    from ..gripper.collision import jaw_frames

    R = jaw_frames(labels.center, labels.closing_axis, labels.approach_axis)[:, :3, :3]
    a[:, 4:13] = R.reshape(n, 9)  # row-major; columns (approach, closing, approach x closing)
    a[:, 13:16] = labels.center
    a[:, 16] = object_id
    return a


def save_graspnet(path: str, labels: Any, gripper: ParallelJaw | None = None,
                  score: str = "friction", object_id: int = -1) -> None:
    """Write :func:`graspnet_array` to ``path`` (``.npy``), atomically.

    References
    ----------
    .. [1] H.-S. Fang, C. Wang, M. Gou and C. Lu, "GraspNet-1Billion: A large-scale
       benchmark for general object grasping", *Proc. IEEE/CVF CVPR*, 2020
    """
    from ..files.atomic import atomic_write

    array = graspnet_array(labels, gripper, score, object_id)
    with atomic_write(path) as f:
        np.save(f, array)


def acronym_transforms(labels: Any, offset: float | ArrayLike) -> NDArray[np.float64]:
    """``(N, 4, 4)`` gripper poses in ACRONYM's frame: rotation columns ``(closing,
    approach × closing, approach)``, origin ``offset`` (one number, or one per pose) behind
    the jaw centre along the approach axis.

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
    T[:, :3, 3] = center - np.broadcast_to(np.asarray(offset, dtype=float).reshape(-1),
                                           (len(center),))[:, None] * approach
    T[:, 3, 3] = 1.0
    return T


def require_h5py():
    """h5py, or one line naming the extra that installs it."""
    return require("h5py", "ACRONYM export", "export")


#: Mesh files that ``trimesh.load`` opens as one ``Trimesh`` (ACRONYM's ``load_mesh`` then
#: scales it); others (``.glb``, ``.gltf``: a ``Scene``) are written out as an ``.obj``.
DIRECT_MESHES = (".obj", ".stl", ".ply", ".off")


@dataclass(frozen=True, eq=False)
class AcronymObject:
    """The object of an ACRONYM file: what its ``load_mesh(filename, mesh_root_dir)`` reads.

    ``trimesh.load(os.path.join(mesh_root, file)).apply_scale(scale)`` is the object the
    labels were made on, in their frame.

    Attributes
    ----------
    file : str
        ``object/file``: the mesh's path relative to ``mesh_root``.
    scale : float
        ``object/scale``.
    mesh : str
        The mesh's absolute path.
    mesh_root : str
        The folder ``file`` is relative to (absolute).
    reason : str or None
        Why the object's surface is written as ``mesh`` (an ``.obj`` beside the ``.h5``)
        rather than an existing mesh named; None when an existing mesh is named.
    surface : (vertices, triangles) or None
        What is written to ``mesh`` (None: nothing, the mesh exists).
    """

    file: str
    scale: float
    mesh: str
    mesh_root: str
    reason: str | None = None
    surface: tuple[NDArray[np.float64], NDArray[np.int64]] | None = None

    @property
    def note(self) -> str | None:
        """One line saying that the surface was written, and why; None when not."""
        if self.reason is None:
            return None
        return (f"object/file is {self.file}, the object's surface written beside the .h5 "
                f"(scale 1): {self.reason}")


def _uniform_scale(placed: NDArray[np.float64], raw: NDArray[np.float64]) -> float | None:
    """``s`` when ``placed == s * raw`` vertex by vertex (to rounding), else None."""
    if placed.shape != raw.shape or not len(raw):
        return None
    s = float(np.sum(placed * raw) / np.sum(raw * raw))
    size = float(np.max(np.abs(placed)))
    return s if np.allclose(placed, s * raw, rtol=0.0, atol=1e-12 * max(size, 1e-300)) else None


def acronym_object(source: Any, path: str, mesh_root: str | None = None, *,
                   part: str | None = None, allow_outside_meshes: bool = False,
                   allow_open: bool = False, surface: Any = None,
                   load_surface: bool = True) -> AcronymObject:
    """Where ACRONYM's ``load_mesh`` finds the object of the ``.h5`` at ``path``.

    ``source`` is the object as the labels were made on it: a mesh file (``.obj``,
    ``.stl``, ``.ply``, ``.off``: named, scale 1); a URDF whose link (``part``) is one mesh
    with a uniform ``scale`` and the identity origin (that mesh named, with that scale:
    pybullet_data's ``duck_vhacd.urdf`` gives ``duck_vhacd.obj`` at 0.05); anything else
    (several pieces, primitives, an origin, a non-uniform scale, a ``.glb``/``.gltf``
    scene, a bundled name, a ``trimesh.Trimesh`` or polyhedron given in Python) has its
    surface written as an ``.obj`` beside the ``.h5`` (same name), scale 1. The mesh is
    named relative to ``mesh_root`` (default: the ``.h5``'s folder), as ``load_mesh``
    joins them. ``surface``: the object already loaded (saves loading it again when the
    surface is written; ``load_surface=False``: not loaded, ``surface`` left None, to
    check the place before any work). Nothing is written here
    (:func:`write_acronym_object` does).

    Examples
    --------
    >>> import os, tempfile, pybullet_data
    >>> folder = pybullet_data.getDataPath()
    >>> found = acronym_object(os.path.join(folder, "duck_vhacd.urdf"),
    ...                        os.path.join(folder, "duck.h5"))
    >>> found.file, found.scale, found.reason
    ('duck_vhacd.obj', 0.05, None)
    >>> cube = acronym_object("cube", os.path.join(tempfile.mkdtemp(), "cube.h5"))
    >>> cube.file, cube.scale, cube.reason
    ('cube.obj', 1.0, 'a bundled object, not a file')
    """
    from ..files.atomic import check_output
    from ..objects.io import ROBOT_SUFFIXES, load_object

    root = os.path.abspath(mesh_root if mesh_root is not None else
                           os.path.dirname(os.path.abspath(path)))
    if not os.path.isdir(root):
        raise InputError(f"mesh root {root}: not a folder")
    inputs: list[str] = []
    reason = None
    if isinstance(source, str | os.PathLike) and os.path.isfile(source):
        file = os.path.abspath(source)
        inputs.append(file)
        suffix = os.path.splitext(file)[1].lower()
        if suffix in DIRECT_MESHES:
            return AcronymObject(os.path.relpath(file, root), 1.0, file, root)
        if suffix in ROBOT_SUFFIXES:
            from pathlib import Path

            from ..objects.meshfile import read_mesh_arrays
            from ..objects.urdf import link_geometry

            _, pieces, _ = link_geometry(Path(file), part,
                                         allow_outside_meshes=allow_outside_meshes)
            inputs += [str(p.mesh_file) for p in pieces if p.mesh_file is not None]
            piece = pieces[0]
            mesh_file = piece.mesh_file  # set exactly for a mesh piece
            if len(pieces) > 1:
                reason = f"the URDF's link has {len(pieces)} pieces, not one mesh"
            elif piece.kind != "mesh" or mesh_file is None:
                reason = f"the URDF's link is a {piece.kind}, not a mesh"
            elif mesh_file.suffix.lower() not in DIRECT_MESHES:
                reason = (f"the URDF's mesh is a {mesh_file.suffix} scene, which "
                          "trimesh.load reads as a Scene")
            else:
                scale = _uniform_scale(piece.vertices, read_mesh_arrays(mesh_file)[0])
                if scale is None:
                    reason = ("the URDF places its mesh by an origin or scales it unevenly, "
                              "which object/scale cannot say")
                else:
                    mesh = str(mesh_file.resolve())
                    return AcronymObject(os.path.relpath(mesh, root), round(scale, 15), mesh,
                                         root)
        else:
            reason = f"a {suffix} file, which trimesh.load reads as a Scene, not one mesh"
    elif isinstance(source, str | os.PathLike):
        reason = "a bundled object, not a file"
    elif source is None:
        raise InputError("ACRONYM export: no object given, and the labels' meta does not "
                         "locate it")
    else:
        reason = f"a {type(source).__name__} given in Python, not a file"
    mesh = os.path.splitext(os.path.abspath(path))[0] + ".obj"
    check_output(mesh, inputs=inputs)
    if not load_surface:
        return AcronymObject(os.path.relpath(mesh, root), 1.0, mesh, root, reason)
    if surface is None:
        surface = source if type(source).__name__ == "Trimesh" else load_object(
            source, allow_open=allow_open, part=part,
            allow_outside_meshes=allow_outside_meshes)
    if type(surface).__name__ == "Trimesh":
        arrays = (np.asarray(surface.vertices, dtype=float),
                  np.asarray(surface.faces, dtype=np.int64))
    else:
        if getattr(surface, "dim", 3) != 3:
            raise InputError(f"ACRONYM export: {getattr(surface, 'name', 'the object')} is a "
                             "polygon; ACRONYM's objects are meshes")
        arrays = (np.asarray(surface.vertices, dtype=float),
                  np.asarray(surface.triangles, dtype=np.int64))
    return AcronymObject(os.path.relpath(mesh, root), 1.0, mesh, root, reason, arrays)


def write_acronym_object(found: AcronymObject) -> None:
    """Write the surface of ``found`` (when it has one) to its ``mesh``, an ``.obj``,
    atomically; exact to 17 decimals."""
    if found.surface is None:
        return
    import trimesh
    from trimesh.exchange.obj import export_obj

    from ..files.atomic import atomic_write

    text = export_obj(trimesh.Trimesh(*found.surface, process=False), include_normals=False,
                      include_color=False, include_texture=False, digits=17, header=None)
    with atomic_write(found.mesh) as f:
        f.write(text.encode("ascii"))


def with_object_source(labels: Any, obj: str, part: str | None = None,
                       allow_open: bool = False, allow_outside_meshes: bool = False) -> Any:
    """``labels`` with ``meta["object_source"]``: where their object was read (``path``,
    absolute, None for a bundled object; ``name`` as given; ``part``, ``allow_open``,
    ``allow_outside_meshes``), so that :func:`object_source` finds it again.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> found = with_object_source(SimpleNamespace(meta={}), "cube")
    >>> found.meta["object_source"]["name"], object_source(found)
    ('cube', 'cube')
    """
    source = {"path": os.path.abspath(obj) if os.path.isfile(obj) else None, "name": obj,
              "part": part, "allow_open": bool(allow_open),
              "allow_outside_meshes": bool(allow_outside_meshes)}
    meta = {**labels.meta, "object_source": source}
    if dataclasses.is_dataclass(labels) and not isinstance(labels, type):  # an instance
        return dataclasses.replace(labels, meta=meta)
    labels.meta = meta
    return labels


def object_source(labels: Any) -> Any:
    """The object of saved labels as their ``meta`` locates it: ``meta["object_source"]``'s
    path or bundled name (``forceclosure grasps --out`` records it), else ``meta["object"]``
    when it is an existing file or a bundled name; None when neither does.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> object_source(SimpleNamespace(meta={"object": "cube"}))
    'cube'
    >>> object_source(SimpleNamespace(meta={"object": "duck_vhacd"})) is None
    True
    """
    from ..objects.examples import POLYHEDRA

    meta = getattr(labels, "meta", None) or {}
    where = meta.get("object_source") or {}
    if isinstance(where.get("path"), str) and os.path.isfile(where["path"]):
        return where["path"]
    if where.get("path") is None and where.get("name") in POLYHEDRA:
        return where["name"]
    name = meta.get("object")
    if isinstance(name, str) and (os.path.isfile(name) or name in POLYHEDRA):
        return name
    return None


def save_acronym(path: str, labels: Any, object_file: Any = None, scale: float | None = None,
                 offset: float | None = None, gripper: ParallelJaw | None = None, *,
                 mesh_root: str | None = None, part: str | None = None,
                 allow_outside_meshes: bool = False, allow_open: bool = False,
                 surface: Any = None) -> AcronymObject:
    """Write the labels in ACRONYM's HDF5 layout (module text) to ``path``, atomically, and
    return where its ``object/file`` points (:class:`AcronymObject`).

    ``object_file`` is the object the labels were made on, found by
    :func:`acronym_object` (default: the labels' ``meta``, :func:`object_source`; or an
    :class:`AcronymObject` already found); when
    its surface has to be written, the ``.obj`` beside ``path`` is written first. With
    ``scale`` given, ``object_file`` is written as it is with that scale, unchecked (your
    mesh root, your mesh). The transforms' origin is the hand's base frame: per pose
    ``tip_offset - depth`` behind the jaw centre (:func:`tip_offset`, :func:`pose_depths`),
    or ``offset`` for every pose when given. ``labels`` may be a label file's path or
    ``np.load`` result.

    References
    ----------
    .. [1] C. Eppner, A. Mousavian and D. Fox, "ACRONYM: A large-scale grasp dataset
       based on simulation", *Proc. IEEE ICRA*, 2021

    Examples
    --------
    >>> import os, tempfile, h5py
    >>> from forceclosure.gripper.labels import grasp_labels
    >>> labels = grasp_labels("cube", ParallelJaw(3.0), mu=0.3, count=3, collision=False,
    ...                       least_friction=False)
    >>> path = os.path.join(tempfile.mkdtemp(), "cube.h5")
    >>> save_acronym(path, labels, "cube").file
    'cube.obj'
    >>> with h5py.File(path, "r") as f:
    ...     f["grasps/transforms"].shape, f["object/file"][()].decode(), f["object/scale"][()]
    ((3, 4, 4), 'cube.obj', np.float64(1.0))
    """
    from ..files.atomic import atomic_write
    from ..gripper.labels import ARRAYS

    h5py = require_h5py()
    labels = as_labels(labels)
    gripper = labels_gripper(labels) if gripper is None else gripper
    if object_file is None:
        object_file = object_source(labels)
    if isinstance(object_file, AcronymObject):
        found = object_file
    elif scale is not None:
        if not isinstance(object_file, str | os.PathLike):
            raise InputError("ACRONYM export: scale given: object_file must be the file name "
                             "to write")
        root = os.path.abspath(mesh_root or os.path.dirname(os.path.abspath(path)))
        found = AcronymObject(os.fspath(object_file), float(scale),
                              os.path.join(root, os.fspath(object_file)), root)
    else:
        found = acronym_object(object_file, path, mesh_root, part=part,
                               allow_outside_meshes=allow_outside_meshes,
                               allow_open=allow_open, surface=surface)
    tip = tip_offset(labels, gripper)
    offsets = (np.full(len(labels.code), float(offset)) if offset is not None
               else tip - pose_depths(labels, gripper))
    buffer = io.BytesIO()
    with h5py.File(buffer, "w") as f:
        f.create_dataset("grasps/transforms", data=acronym_transforms(labels, offsets))
        f.create_dataset("grasps/qualities/flex/object_in_gripper",
                         data=_accepted(labels).astype(np.int64))
        f.create_dataset("object/file", data=found.file, dtype=h5py.string_dtype())
        f.create_dataset("object/scale", data=found.scale)
        f.create_dataset("object/friction", data=float(labels.meta.get("mu", np.nan)))
        f.create_dataset("gripper/type", data=str(getattr(gripper, "name", "parallel-jaw")),
                         dtype=h5py.string_dtype())
        f.create_dataset("gripper/width_max", data=float(gripper.width_max))
        f.create_dataset("gripper/offset", data=float(offset) if offset is not None
                         else round(tip - gripper.depth, 15))
        f.create_dataset("gripper/tip_offset", data=tip)
        ours = f.create_group("forceclosure")
        for name in (*ARRAYS, "depth"):
            value = getattr(labels, name, None)
            if value is not None and name not in ours:
                ours.create_dataset(name, data=np.asarray(value))
        ours.create_dataset("verdict", data=verdict_words(labels.code).tolist(),
                            dtype=h5py.string_dtype())
        ours.attrs["meta"] = json.dumps(labels.meta)
    write_acronym_object(found)
    with atomic_write(path) as out:
        out.write(buffer.getvalue())
    return found
