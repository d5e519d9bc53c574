"""Contacts from simulators: a pybullet or MuJoCo scene's contacts on an object,
as :class:`forceclosure.Contact` objects ready for :func:`forceclosure.analyze`.

Neither simulator is required by the library: each adapter imports its
simulator when called.
"""

from .mujoco import contacts_from_mujoco
from .pybullet import contacts_from_pybullet

__all__ = ["contacts_from_mujoco", "contacts_from_pybullet"]
