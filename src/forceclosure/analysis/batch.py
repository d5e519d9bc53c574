"""Many grasps at once: arrays in, arrays out.

:func:`analyze_batch` takes ``N`` grasps of ``k`` point contacts as arrays
and returns arrays of verdicts, ranks, margins and unresisted twists, with
the same meaning as :func:`forceclosure.analyze` (it lives in
:mod:`forceclosure.analysis.batch_analysis`). :func:`least_friction_batch` gives
each grasp's least friction in one compiled pass (from
:mod:`forceclosure.analysis.friction`), and :func:`epsilon_batch` the Ferrari–Canny
epsilon of those that are closed.

For two-finger grasps, :func:`forceclosure.analysis.two_finger.two_finger_closure`
is faster still.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..contacts import ORIENTATIONS, Cone, Orientation, model_codes
from ..errors import InputError
from .batch_analysis import (
    CHUNK,
    BatchAnalysis,
    Engine,
    analyze_batch,
    check_engine,
    extreme_grasps,
    kernel_inputs,
    validate_grasps,
)
from .closure import TOLERANCE, check_tolerance
from .friction import least_friction_batch
from .quality import epsilon

__all__ = ["CHUNK", "BatchAnalysis", "Engine", "analyze_batch", "epsilon_batch",
           "least_friction_batch"]


def epsilon_batch(points: ArrayLike, normals: ArrayLike, *, mu: ArrayLike = 0.0,
                  model: str | Sequence[str] = "hard", torsion: ArrayLike | None = None,
                  norm: Literal["L1", "Linf"] = "L1", edges: int = 8, tol: float = TOLERANCE,
                  engine: Engine = "compiled",
                  progress: Callable[[int], object] | None = None,
                  orientation: Orientation = "grasp") -> NDArray[np.float64]:
    """Ferrari–Canny epsilon of each of ``N`` grasps (0 where not force-closure).

    The batch form of :func:`forceclosure.analysis.quality.epsilon`, in its default
    frame (torques about the contacts' centroid, divided by their largest
    distance from it) and with the same ``norm``, inscribed ``edges``-edge
    pyramids and ``orientation`` (by default each pyramid oriented by the grasp
    itself, :func:`forceclosure.geometry.cones.fill_frame`, so a turned, moved,
    scaled or reordered grasp has the same epsilon). Compiled, each closed
    grasp's wrench hull is built and checked in the kernel
    (:mod:`forceclosure.kernels.hull`) and the few grasps it
    cannot settle go to the reference (Qhull); values agree with the
    reference to about 1e-9. ``Linf`` always takes the reference path: its
    hulls, of every sum of one wrench per finger, have hundreds of points,
    where Qhull is as fast as the kernel.

    Parameters
    ----------
    points, normals, mu, model, torsion :
        As in :func:`analyze_batch`.
    norm : {"L1", "Linf"}
        Bound on the sum of the fingers' normal forces, or on each.
    edges : int
        Edges of the inscribed pyramid standing in for spatial cones.
    engine, progress :
        As in :func:`analyze_batch`.
    orientation : {"grasp", "axes"}
        Pyramids oriented by the grasp (default) or, as before, by the
        coordinate axes (:func:`forceclosure.analysis.quality.epsilon`).

    Examples
    --------
    Two fingers pinching head-on with friction 0.5 (the nearest facet of the
    tetrahedron of their four wrenches is 1/3 from the origin), and the same
    fingers 1.0 apart along the jaw, which friction 0.5 does not close:

    >>> import numpy as np
    >>> P = np.array([[[-1, 0], [1, 0]], [[-1, 0], [1, 1.0]]])
    >>> N = np.array([[[-1, 0], [1, 0]]] * 2)
    >>> epsilon_batch(P, N, mu=0.5).round(6).tolist()
    [0.333333, 0.0]
    """
    check_engine(engine)
    if norm not in ("L1", "Linf"):
        raise InputError(f"norm must be 'L1' or 'Linf', got {norm!r}")
    if orientation not in ORIENTATIONS:
        raise InputError(f"orientation must be 'grasp' or 'axes', got {orientation!r}")
    cone = Cone(edges, "inscribed")
    tol = check_tolerance(tol)
    grasps = validate_grasps(points, normals, mu, model, torsion)
    n, k, d = grasps.points.shape
    out = np.zeros(n)
    reference = engine == "reference" or norm == "Linf"
    if reference or n == 0:
        todo = np.arange(n)
    else:
        from ..kernels import announce_compiling, kernel_array, pool_for, theorem1
        from ..kernels.quality import epsilon_kernel

        maxm = theorem1.columns_per_grasp(k, d, max(cone.edges, 256))
        kinds = model_codes(grasps.models)
        deferred = np.zeros(n, dtype=np.bool_)
        extreme = extreme_grasps(grasps)
        announce_compiling(epsilon_kernel)
        for lo in range(0, n, CHUNK):
            part = slice(lo, min(n, lo + CHUNK))
            P, M = kernel_inputs(grasps, part, extreme)
            with pool_for(part.stop - part.start):
                epsilon_kernel(P, kernel_array(grasps.normals[part]), M,
                               kernel_array(grasps.torsion[part]), kinds, cone.edges,
                               float(tol), maxm, out[part], deferred[part],
                               orientation == "grasp")
            if progress is not None:
                progress(part.stop - part.start)
        todo = np.flatnonzero(deferred | extreme)
    for g in todo:
        out[g] = epsilon(grasps.contacts(g), norm, edges=cone.edges, tol=tol,
                         orientation=orientation).value
        if reference and progress is not None:
            progress(1)
    return out
