"""The pad kernels' pressed polygons against shapely's: random triangles under a pad.

A pad pressing a triangle presses the part of it under the pad's rectangle
(``x`` in ``[depth - length, depth]``, ``|z| <= h/2``) and within the pressed
layer (``y <= level`` for jaw 0, ``y >= level`` for jaw 1). ``y`` is affine on
the triangle, so that part is a convex polygon in the x-z plane: here the
triangle's projection intersected with the rectangle and the half-plane where
the layer holds, by shapely; the penetration is affine on it, so its integral
is the polygon's area times the penetration at its centroid.
:func:`forceclosure.kernels.pads.pad_pressure` must give the same integral.
"""

from __future__ import annotations

import numpy as np
import pytest
from shapely.geometry import LineString, Polygon, box
from shapely.ops import split

from forceclosure.kernels.pads import pad_nearest, pad_pressure

DEPTH, LENGTH, H = 0.3, 0.8, 0.6


def _truth(tri: np.ndarray, level: float, jaw: int) -> float:
    """The integral of the penetration past ``level`` over the pressed part, by shapely."""
    (x0, y0, z0), (x1, y1, z1), (x2, y2, z2) = tri
    # y = y0 + a (x - x0) + b (z - z0) on the triangle
    det = (x1 - x0) * (z2 - z0) - (x2 - x0) * (z1 - z0)
    a = ((y1 - y0) * (z2 - z0) - (y2 - y0) * (z1 - z0)) / det
    b = ((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)) / det

    def y(x, z):
        return y0 + a * (x - x0) + b * (z - z0)

    region = Polygon(tri[:, [0, 2]]).intersection(box(DEPTH - LENGTH, -H / 2, DEPTH, H / 2))
    if region.is_empty or region.area == 0:
        return 0.0
    # split by the line y(x, z) = level; each piece lies on one side of it
    if abs(b) > abs(a):  # z as a function of x on the line
        line = LineString([(x, z0 + (level - y0 - a * (x - x0)) / b) for x in (-50.0, 50.0)])
    else:
        line = LineString([(x0 + (level - y0 - b * (z - z0)) / a, z) for z in (-50.0, 50.0)])
    total = 0.0
    for piece in split(region, line).geoms:
        c = piece.centroid
        pen = (level - y(c.x, c.y)) if jaw == 0 else (y(c.x, c.y) - level)
        if pen > 0:
            total += piece.area * pen
    return total


@pytest.mark.parametrize("seed", range(4))
def test_pressure_integral_matches_shapely(seed):
    rng = np.random.default_rng(seed)
    checked = 0
    for _ in range(60):
        tri = rng.uniform(-0.8, 0.8, (3, 3))
        jaw = int(rng.integers(2))
        level = float(rng.uniform(tri[:, 1].min(), tri[:, 1].max()))
        V, F = tri, np.array([[0, 1, 2]])
        args = (V, F, np.array([0]), np.array([0]), np.zeros((1, 3)), np.eye(3)[None],
                np.array([DEPTH]), LENGTH, H, np.array([level]), jaw)
        got = pad_pressure(*args)[0, 0]
        want = _truth(tri, level, jaw)
        assert got == pytest.approx(want, rel=1e-7, abs=1e-12)
        if want > 0:  # a pressed region: its point nearest the pad's middle is found
            dist, _ = pad_nearest(*args, np.array([[DEPTH - LENGTH / 2, 0.0]]))
            assert np.isfinite(dist[0])
            checked += 1
    assert checked >= 10  # the check is not empty
