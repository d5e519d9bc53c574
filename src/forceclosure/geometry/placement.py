"""Object-centred, scaled coordinates: the one rule by which far-away or very small or large
objects are computed on as if they stood at the origin about 1 across.

``local = (x - centre) / scale``, with ``centre`` the centre of the object's bounding box and
``scale`` a power of two within a factor of 1.5 of its size, in any dimension. A power of two
divides and multiplies exactly, so a length found locally maps back exactly (times the scale),
and a point of the object maps there and back to itself wherever its coordinates are large
beside its size (the subtraction of the centre is then exact). Polygons are searched in these
coordinates (:mod:`forceclosure.synthesis.frame`), polyhedra too, and the outer surface of a
decomposition is united in them (:mod:`forceclosure.objects.outer`).

Examples
--------
>>> import numpy as np
>>> p = Placement.of(np.array([[1e8, 0.0, 0.0], [1e8 + 2, 2.0, 1.0]]))
>>> p.centre.tolist(), p.scale
([100000001.0, 1.0, 0.5], 4.0)
>>> p.to_user_points(p.to_local_points([[1e8 + 2, 2.0, 1.0]])).tolist()
[[100000002.0, 2.0, 1.0]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Self

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["Placement"]


@dataclass(frozen=True)
class Placement:
    """The map from the user's coordinates to object-centred, scaled ones.

    Attributes
    ----------
    centre : (d,) array
        The centre of the object's bounding box.
    scale : float
        A power of two within a factor of 1.5 of the object's size (its bounding box's
        diagonal).
    """

    centre: NDArray[np.float64]
    scale: float

    @classmethod
    def of(cls, points: ArrayLike, size: float | None = None) -> Self:
        """The placement of an object with these points (or its bounding box's two corners);
        ``size`` defaults to the bounding box's diagonal."""
        pts = np.asarray(points, dtype=float)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        if size is None:
            size = float(np.linalg.norm(hi - lo))
        centre = 0.5 * lo + 0.5 * hi
        centre.setflags(write=False)
        return cls(centre, math.ldexp(1.0, round(math.log2(size))))

    def to_local_points(self, x: ArrayLike) -> NDArray[np.float64]:
        """Points in object-centred, scaled coordinates."""
        return (np.asarray(x, dtype=float) - self.centre) / self.scale

    def to_user_points(self, x: ArrayLike) -> NDArray[np.float64]:
        """Points in the user's coordinates (``-0.0`` made ``0.0``)."""
        return np.asarray(x, dtype=float) * self.scale + self.centre + 0.0
