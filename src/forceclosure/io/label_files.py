"""A saved labels file (``GraspLabels.save``) written as the files other tools read: a
GraspNet ``.npy`` and an ACRONYM ``.h5`` (with the object's mesh it names), as
``forceclosure export`` and ``dataset --export`` write them."""

from __future__ import annotations

from typing import Any

from ..errors import InputError

__all__ = ["export_labels_file"]


def _source(labels: Any, obj: str | None, options: dict[str, Any],
            record: dict[str, Any] | None, job: dict[str, Any]) -> tuple[Any, dict[str, Any]]:
    """The object of ``labels`` and the options to read it with: ``obj`` when given, else
    the dataset record's path, else where the labels' meta says the object was read."""
    from .export import object_source

    if obj is not None:
        return obj, options
    if record is not None:
        return record.get("path"), {"allow_open": bool(job.get("allow_open", False)),
                                    "allow_outside_meshes":
                                        bool(job.get("allow_outside_meshes", False))}
    found = object_source(labels)
    where = labels.meta.get("object_source") or {}
    options = {k: where[k] for k in ("part", "allow_open", "allow_outside_meshes")
               if k in where} if found in (where.get("path"), where.get("name")) else {}
    return found, options


def export_labels_file(labels_file: str, graspnet: str | None = None,
                       acronym: str | None = None, *, score: str = "friction",
                       mesh_root: str | None = None, obj: str | None = None,
                       part: str | None = None, allow_outside_meshes: bool = False,
                       record: dict[str, Any] | None = None,
                       job: dict[str, Any] | None = None) -> dict[str, Any]:
    """Write one labels file as a GraspNet array and/or an ACRONYM file; everything is
    computed before either file is written (atomically).

    Parameters
    ----------
    labels_file : str
        A ``.npz`` of :meth:`forceclosure.gripper.labels.GraspLabels.save`.
    graspnet, acronym : str, optional
        The files to write (``.npy``; ``.h5``).
    score : {"friction", "epsilon"}
        The GraspNet score (:func:`forceclosure.io.export.graspnet_array`).
    mesh_root : str, optional
        Where ACRONYM's loader finds meshes (:func:`forceclosure.io.export.acronym_object`).
    obj : str, optional
        The object the labels were made on, with ``part`` and ``allow_outside_meshes``
        to read it; default: the dataset ``record``'s path (read with its ``job``'s
        options), else where the labels' meta says.

    Returns
    -------
    dict
        The summary entry of ``forceclosure export --json``: ``labels``, ``poses``, and
        per file written its details.

    Raises
    ------
    InputError
        The labels do not locate their object (name it with ``obj``), or a file cannot
        be read or written.

    Examples
    --------
    >>> import os, tempfile
    >>> from forceclosure import ParallelJaw, bundled, grasp_labels
    >>> folder = tempfile.mkdtemp()
    >>> labels = grasp_labels(bundled("cube"), ParallelJaw(width_max=2.0), 0.5, count=20,
    ...                       seed=1)
    >>> labels.save(os.path.join(folder, "cube.npz"))
    >>> entry = export_labels_file(os.path.join(folder, "cube.npz"),
    ...                            graspnet=os.path.join(folder, "cube.npy"))
    >>> entry["poses"] == len(labels), entry["graspnet"]["scored"] <= len(labels)
    (True, True)
    """
    import numpy as np

    from ..files.atomic import atomic_write
    from ..gripper.labels import GraspLabels
    from .export import acronym_object, graspnet_array, save_acronym

    labels = GraspLabels.load(labels_file)
    entry: dict[str, Any] = {"labels": labels_file, "poses": len(labels)}
    array = found = None
    if graspnet:
        array = graspnet_array(labels, score=score)
    if acronym:
        source, options = _source(labels, obj, {"part": part,
                                                "allow_outside_meshes": allow_outside_meshes},
                                  record, job or {})
        if source is None:
            raise InputError(f"{labels_file}: its meta does not locate the object the labels "
                             f"were made on (object {labels.meta.get('object')!r}); name it "
                             "with obj (the command line's --object FILE)")
        found = acronym_object(source, acronym, mesh_root, **options)
    if graspnet:
        assert array is not None  # computed above whenever graspnet is given
        with atomic_write(graspnet) as f:
            np.save(f, array)
        entry["graspnet"] = {"file": graspnet, "scored": int(np.sum(array[:, 0] >= 0))}
    if acronym:
        assert found is not None  # found above whenever acronym is given (or raised)
        save_acronym(acronym, labels, found)
        entry["acronym"] = {"file": acronym, "object_file": found.file, "scale": found.scale,
                            "mesh_root": found.mesh_root,
                            "surface_written": found.mesh if found.reason else None,
                            "note": found.note}
    return entry
