"""forceclosure: analyse and construct force-closure grasps (Nguyen, IJRR 1988).

Examples
--------
>>> from forceclosure import analyze, point_contact
>>> grasp = [point_contact([-1, 0], [-1, 0], "hard", mu=0.3),
...          point_contact([1, 0], [1, 0], "hard", mu=0.3)]
>>> analyze(grasp).verdict.value
'closure'

The reverse problem, where to put the fingers (§5), has one front door:

>>> from forceclosure import bundled, synthesize
>>> found = synthesize(bundled("square"), fingers=2, contact="hard", mu=0.3, top=1)
>>> found.method, found.found[0].certify().holds
('edges', True)
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version
from typing import TYPE_CHECKING

from .lazy import lazy_names

try:
    __version__ = version("forceclosure")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

#: Where each public name lives. They are imported on first use, so that ``import
#: forceclosure`` (and ``forceclosure --help``) does not load numpy and scipy.
_HOME = {
    **dict.fromkeys(["TOLERANCE", "Analysis", "VectorClosure", "Verdict", "analyze",
                     "force_direction_closure", "torque_closure", "vector_closure"],
                    "analysis.closure"),
    **dict.fromkeys(["Cone", "Contact", "WrenchSet", "edge_contact", "face_contact",
                     "generating_wrenches", "point_contact", "vertex_contact"], "contacts"),
    **dict.fromkeys(["ForceClosureError", "InputError"], "errors"),
    **dict.fromkeys(["Motion", "motion_of"], "analysis.motion"),
    **dict.fromkeys(["JawPose", "ParallelJaw", "contacts_of", "pose_from_contacts"], "gripper.jaw"),
    **dict.fromkeys(["sample_antipodal"], "gripper.antipodal"),
    **dict.fromkeys(["GraspLabels", "grasp_labels", "label_grasps"], "gripper.labels"),
    **dict.fromkeys(["contacts_from_mujoco", "contacts_from_pybullet"], "simulators"),
    **dict.fromkeys(["Noise", "Robustness", "robust_labels"], "gripper.robust"),
    **dict.fromkeys(["GraspMetrics", "grasp_matrix", "grasp_metrics"], "analysis.metrics"),
    **dict.fromkeys(["TaskWrench", "gravity_wrench", "resist_wrench"], "analysis.task"),
    **dict.fromkeys(["collides"], "gripper.collision"),
    **dict.fromkeys(["graspnet_array", "save_acronym", "save_graspnet"], "io.export"),
    **dict.fromkeys(["plot_grasps"], "pictures.grasp_plot"),
    **dict.fromkeys(["Synthesis", "synthesize"], "synthesis.best"),
    **dict.fromkeys(["Certificate", "Regions"], "synthesis"),
    **dict.fromkeys(["Polygon", "Polyhedron", "bundled", "glyph", "prism"], "objects"),
    **dict.fromkeys(["load_object"], "objects.io"),
}


__getattr__, __dir__ = lazy_names(__name__, _HOME)


if TYPE_CHECKING:  # for type checkers and editors: the same names, eagerly
    from .analysis.closure import (
        TOLERANCE,
        Analysis,
        VectorClosure,
        Verdict,
        analyze,
        force_direction_closure,
        torque_closure,
        vector_closure,
    )
    from .analysis.metrics import GraspMetrics, grasp_matrix, grasp_metrics
    from .analysis.motion import Motion, motion_of
    from .analysis.task import TaskWrench, gravity_wrench, resist_wrench
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
    from .gripper.antipodal import sample_antipodal
    from .gripper.collision import collides
    from .gripper.jaw import JawPose, ParallelJaw, contacts_of, pose_from_contacts
    from .gripper.labels import GraspLabels, grasp_labels, label_grasps
    from .gripper.robust import Noise, Robustness, robust_labels
    from .io.export import graspnet_array, save_acronym, save_graspnet
    from .objects import Polygon, Polyhedron, bundled, glyph, prism
    from .objects.io import load_object
    from .pictures.grasp_plot import plot_grasps
    from .simulators import contacts_from_mujoco, contacts_from_pybullet
    from .synthesis import Certificate, Regions
    from .synthesis.best import Synthesis, synthesize

__all__ = [
    "TOLERANCE",
    "Analysis",
    "Certificate",
    "Cone",
    "Contact",
    "ForceClosureError",
    "GraspLabels",
    "GraspMetrics",
    "InputError",
    "JawPose",
    "Motion",
    "Noise",
    "ParallelJaw",
    "Polygon",
    "Polyhedron",
    "Regions",
    "Robustness",
    "Synthesis",
    "TaskWrench",
    "VectorClosure",
    "Verdict",
    "WrenchSet",
    "__version__",
    "analyze",
    "bundled",
    "collides",
    "contacts_from_mujoco",
    "contacts_from_pybullet",
    "contacts_of",
    "edge_contact",
    "face_contact",
    "force_direction_closure",
    "generating_wrenches",
    "glyph",
    "grasp_labels",
    "grasp_matrix",
    "grasp_metrics",
    "graspnet_array",
    "gravity_wrench",
    "label_grasps",
    "load_object",
    "motion_of",
    "plot_grasps",
    "point_contact",
    "pose_from_contacts",
    "prism",
    "resist_wrench",
    "robust_labels",
    "sample_antipodal",
    "save_acronym",
    "save_graspnet",
    "synthesize",
    "torque_closure",
    "vector_closure",
    "vertex_contact",
]
