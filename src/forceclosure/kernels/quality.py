"""Ferrari–Canny epsilon compiled, for many grasps at once (``quality.epsilon``).

A grasp's epsilon is 0 unless it is force-closure, both with exact cones and
with the inscribed pyramid the value is measured on (as the reference
decides it; the pyramid lies inside the exact cones, so its closure proves
theirs and is the one decided here); then it is the distance from the origin to the nearest facet of
the hull of the generating wrenches (:func:`.hull.hull_radius`; the ``L1``
epsilon). Spatial pyramids are oriented by the grasp itself
(:func:`forceclosure.geometry.cones.fill_frame`, compiled here from that one
source, so both paths build the same bits) or, with ``by_grasp`` False, by the
coordinate axes. Grasps whose verdict the kernel defers, or whose hull it cannot
build and check, are left to the reference path.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ..geometry import cones
from .hull import hull_radius
from .theorem1 import (
    BLOCK,
    CLOSURE,
    DEFER,
    EXACT_EDGES,
    contact_frame,
    decide_pyramid,
    work_arrays,
    wrenches,
)

__all__ = ["epsilon_kernel", "grasp_frames"]

#: Each contact's pyramid frame from the grasp (the reference's ``cones.fill_frame``, compiled).
grasp_frames = nb.njit(cache=True, nogil=True)(cones.fill_frame)


@nb.njit(parallel=True, cache=True, nogil=True)
def epsilon_kernel(points, normals, mu, tors, model, edges, tol, maxm,
                   out, deferred, by_grasp=True):  # pragma: no cover - compiled
    """Epsilon of ``(N, k, d)`` grasps into ``out``; ``deferred[g]`` where the kernel cannot say.

    ``by_grasp``: spatial pyramids oriented by the grasp (``cones.fill_frame``), else by
    the coordinate axes.
    """
    n_grasps, k, d = points.shape
    D = 3 if d == 2 else 6
    oriented = by_grasp and d == 3
    n_blocks = (n_grasps + BLOCK - 1) // BLOCK
    for blk in nb.prange(n_blocks):
        work = work_arrays(maxm, max(edges, EXACT_EDGES[-1]))
        ref = np.empty(d)
        y = np.empty(D)
        X = np.empty((maxm, D))
        frames = np.empty((k, 2, 3))
        for g in range(blk * BLOCK, min(n_grasps, (blk + 1) * BLOCK)):
            out[g] = 0.0
            deferred[g] = False
            P, N, M, T = points[g], normals[g], mu[g], tors[g]
            # closed with the inscribed pyramid epsilon is measured on: then with the exact
            # cones around it too (a proof for the pyramid is one for the larger cones);
            # only whether it closes is asked
            scale = contact_frame(P, ref)
            if oriented:
                grasp_frames(P, N, frames)
                c = decide_pyramid(P, N, M, T, model, edges, 1.0, ref, scale, tol, work, y,
                                   frames, True)[0]
            else:
                c = decide_pyramid(P, N, M, T, model, edges, 1.0, ref, scale, tol, work, y,
                                   None, True)[0]
            if c != CLOSURE:
                deferred[g] = c == DEFER
                continue
            if oriented:
                m = wrenches(P, N, M, T, model, edges, 1.0, ref, scale, work.W, work.two,
                             work.rim, frames)
            else:
                m = wrenches(P, N, M, T, model, edges, 1.0, ref, scale, work.W, work.two,
                             work.rim)
            for col in range(m):
                for j in range(D):
                    X[col, j] = work.W[j, col]
            radius = hull_radius(X, m)
            if np.isnan(radius):
                deferred[g] = True
            else:
                out[g] = max(0.0, radius)
