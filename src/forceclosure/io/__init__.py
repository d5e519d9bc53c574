"""Files in and out: reading a user's file safely, grasp files and arrays, exports.

Above analysis and the gripper, beside pictures (geometry → contacts →
analysis → synthesis/gripper → pictures/io → app): the grasp-file formats
(:mod:`.grasp_file`, :mod:`.grasp_arrays`) and the exports (:mod:`.export`)
import the analysis and the gripper, never synthesis's internals, pictures or
the app. Two modules are leaf primitives importing nothing but
:mod:`forceclosure.errors`, which any layer may use: :mod:`.files` (read a
regular file, capped) and :mod:`.atomic` (write a file atomically). The
package itself loads nothing.
"""

__all__: list[str] = []
