"""Grasp formats: grasp files and arrays, exports.

Above analysis and the gripper, beside pictures (geometry → contacts →
analysis → synthesis/gripper → pictures/io → app): the grasp-file formats
(:mod:`.grasp_file`, :mod:`.grasp_arrays`) and the exports (:mod:`.export`)
import the analysis and the gripper, never synthesis's internals, pictures or
the app. Reading a user's file safely and writing one atomically live below
every layer, in :mod:`forceclosure.files`. The package itself loads nothing.
"""

__all__: list[str] = []
