"""Reading a mesh file's triangles as the file stores them.

trimesh reads the formats (``.stl``, ``.obj``, ``.ply``, ``.off``,
``.glb``, ``.gltf``; scenes flattened into one mesh) without its own
processing, so vertices and triangles keep the file's order: the checks of
:class:`~forceclosure.objects.polyhedron.Polyhedron` then name vertices
and triangles as the file numbers them.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError, first_line

__all__ = ["MESH_SUFFIXES", "read_mesh_arrays"]

MESH_SUFFIXES = (".stl", ".obj", ".ply", ".off", ".glb", ".gltf")


def read_mesh_arrays(path: Path) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The vertices ``(n, 3)`` and triangles ``(m, 3)`` of a mesh file, unprocessed.

    Examples
    --------
    >>> import pybullet_data
    >>> V, T = read_mesh_arrays(Path(pybullet_data.getDataPath()) / "cube.obj")
    >>> V.shape[1], T.shape[1], float(V.min()), float(V.max())
    (3, 3, -0.5, 0.5)
    """
    import trimesh

    if path.stat().st_size == 0:
        raise InputError(f"{path.name}: the file is empty")
    suffix = path.suffix.lower()
    try:
        loaded = trimesh.load(str(path), file_type=suffix[1:], force="mesh", process=False)
    except Exception as e:  # trimesh raises many types on malformed files
        raise InputError(f"{path.name}: cannot read the {suffix[1:].upper()} file: "
                         f"{first_line(e)}") from None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise InputError(f"{path.name}: the file holds no triangles")
    return np.asarray(loaded.vertices, dtype=float), np.asarray(loaded.faces, dtype=np.int64)
