"""Label sampled grasps on a box the way a dataset builder does, with the batch engine.

Three hard fingers are dropped at random on the faces of a 2 x 1 x 0.5 box;
`analyze_batch` decides each grasp (Theorem 1, 8-edge friction pyramids) and
`least_friction_batch` says how much friction each one needs. Given a
file name, the grasps are also saved as an .npz for `forceclosure analyze`.

    uv run python examples/label_grasps.py [box_grasps.npz]
"""

import sys
import time

import numpy as np

from forceclosure import Cone
from forceclosure.analysis.batch import analyze_batch, least_friction_batch

HALF = np.array([1.0, 0.5, 0.25])  # half extents of the box


def sample_box_grasps(rng, n, fingers=3):
    """Points on the box's faces (by area) and the faces' outward normals."""
    areas = np.repeat([HALF[1] * HALF[2], HALF[0] * HALF[2], HALF[0] * HALF[1]], 2)
    face = rng.choice(6, size=(n, fingers), p=areas / areas.sum())
    axis, sign = face // 2, np.where(face % 2 == 0, 1.0, -1.0)
    points = rng.uniform(-1, 1, (n, fingers, 3)) * HALF
    np.put_along_axis(points, axis[..., None], (sign * HALF[axis])[..., None], axis=2)
    normals = np.zeros((n, fingers, 3))
    np.put_along_axis(normals, axis[..., None], sign[..., None], axis=2)
    return points, normals


def main():
    rng = np.random.default_rng(1)
    points, normals = sample_box_grasps(rng, 200_000)
    start = time.perf_counter()
    result = analyze_batch(points, normals, mu=0.4, model="hard", cone=Cone(8))
    seconds = time.perf_counter() - start
    counts = {v: int(np.sum(result.verdict == v)) for v in ("closure", "marginal", "none")}
    print(f"{len(points):,} grasps in {seconds:.2f} s: {counts}")
    print(f"force-closure share with mu = 0.4: {result.force_closure.mean():.1%}")

    needed = least_friction_batch(points[:5_000], normals[:5_000], cone=Cone(8))
    finite = needed[np.isfinite(needed)]
    print(f"least friction over 5,000 grasps: median {np.median(finite):.3f}; "
          f"{np.mean(needed <= 0.4):.1%} close with mu = 0.4; "
          f"{np.mean(~np.isfinite(needed)):.1%} close with no friction at all")

    if len(sys.argv) > 1:  # keep the grasp set for the command line
        np.savez_compressed(sys.argv[1], points=points, normals=normals, mu=0.4, model="hard",
                            cone="8-inscribed")
        print(f"wrote {sys.argv[1]}; label it with: forceclosure analyze {sys.argv[1]}")

if __name__ == "__main__":
    main()
