"""forceclosure: analyse and construct force-closure grasps (Nguyen, IJRR 1988).

Examples
--------
>>> from forceclosure import analyze, point_contact
>>> grasp = [point_contact([-1, 0], [-1, 0], "hard", mu=0.3),
...          point_contact([1, 0], [1, 0], "hard", mu=0.3)]
>>> analyze(grasp).verdict.value
'closure'
"""

from importlib.metadata import PackageNotFoundError, version

from .closure import (
    TOLERANCE,
    Analysis,
    VectorClosure,
    Verdict,
    analyze,
    force_direction_closure,
    torque_closure,
    vector_closure,
)
from .contacts import (
    Cone,
    Contact,
    WrenchSet,
    edge_contact,
    face_contact,
    generating_wrenches,
    point_contact,
    vertex_contact,
)
from .errors import ForceClosureError, InputError
from .motion import Motion, motion_of

try:
    __version__ = version("forceclosure")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

__all__ = [
    "TOLERANCE",
    "Analysis",
    "Cone",
    "Contact",
    "ForceClosureError",
    "InputError",
    "Motion",
    "VectorClosure",
    "Verdict",
    "WrenchSet",
    "__version__",
    "analyze",
    "edge_contact",
    "face_contact",
    "force_direction_closure",
    "generating_wrenches",
    "motion_of",
    "point_contact",
    "torque_closure",
    "vector_closure",
    "vertex_contact",
]
