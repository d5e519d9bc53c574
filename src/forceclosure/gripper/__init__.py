"""Parallel-jaw grippers: jaw poses to contacts (:mod:`.jaw`), collisions, antipodal
sampling, labels and robust labels for grasp datasets.

An adapter at the synthesis level (geometry → contacts → analysis →
synthesis/gripper → pictures/io → app): it turns what a user has, a jaw pose,
into contacts and labels them with the analysis; it may import the analysis,
objects and synthesis (antipodal sampling uses its patches), never pictures,
the exports or the app. It was the module :mod:`.jaw` before (issue 16), whose
names it still gives: ``from forceclosure.gripper import ParallelJaw`` works.

Examples
--------
>>> from forceclosure.gripper import ParallelJaw, jaw
>>> ParallelJaw is jaw.ParallelJaw
True
"""

from typing import Any

from .._moved import forward

__all__ = ["JawContacts", "JawPose", "ParallelJaw", "contacts_of", "pose_from_contacts"]


def __getattr__(name: str) -> Any:
    return forward(__name__, f"{__name__}.jaw", name)
