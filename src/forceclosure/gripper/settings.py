"""The defaults of the labelling pipeline's optional stages
(:func:`forceclosure.gripper.pipeline.label_poses`): robustness under noise and the task
wrench. One home for them, read by the pipeline and by the command line's help and
checks; it imports nothing, so ``forceclosure --help`` stays free of numpy.

Examples
--------
>>> ROBUST_DEFAULTS["samples"], TASK_DEFAULTS["f_max"]
(100, 70.0)
"""

from __future__ import annotations

from typing import Any

__all__ = ["ROBUST_DEFAULTS", "TASK_DEFAULTS"]

#: The robustness settings :func:`~forceclosure.gripper.pipeline.label_poses` takes where
#: ``robust`` leaves them out (``pose_sigma`` None: 1 % of the hand's widest opening), as
#: :func:`~forceclosure.gripper.robust.robust_labels`'s defaults.
ROBUST_DEFAULTS: dict[str, Any] = {"samples": 100, "pose_sigma": None, "angle_sigma": 0.05,
                                   "mu_sigma": 0.05, "normal_sigma": 0.0, "confidence": 0.95,
                                   "epsilon": True}

#: The task wrench's settings where ``task`` leaves them out: gravity in the object's frame
#: (m/s^2, -z up), each jaw's largest normal force (a Franka Emika hand's continuous grip
#: force, 70 N) and the friction pyramid's edges.
TASK_DEFAULTS: dict[str, Any] = {"gravity": (0.0, 0.0, -9.81), "f_max": 70.0, "edges": 8}
