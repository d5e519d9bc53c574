"""File safety, at the bottom of the layers: reading a user's file, writing results atomically.

Four modules that import nothing of the package but :mod:`forceclosure.errors`, so that
every layer (objects, the gripper, the formats of :mod:`forceclosure.io`, pictures,
datasets, the app) may use them: :mod:`.read` (read a regular file, capped, and its
fingerprint), :mod:`.atomic` (write one file atomically, after checking its place),
:mod:`.outdir` (a run's results folder: atomic files and one run at a time) and
:mod:`.saves` (saves that Ctrl-C never cuts short). The package itself loads nothing.
"""

__all__: list[str] = []
