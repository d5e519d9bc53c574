"""Parallel-jaw grippers: jaw poses to contacts (:mod:`.jaw`), collisions, antipodal
sampling, labels and robust labels for grasp datasets.

An adapter at the synthesis level (geometry → contacts → analysis →
synthesis/gripper → pictures/io → app): it turns what a user has, a jaw pose,
into contacts and labels them with the analysis; it may import the analysis,
objects and synthesis (antipodal sampling uses its patches), never pictures,
the exports or the app. Its names are in its modules
(``from forceclosure.gripper.jaw import ParallelJaw``,
``from forceclosure.gripper.labels import grasp_labels``), and the most used at the top
level (``from forceclosure import ParallelJaw, grasp_labels``).

Examples
--------
>>> from forceclosure.gripper.jaw import ParallelJaw
>>> from forceclosure import ParallelJaw as same
>>> ParallelJaw is same
True
"""

__all__: list[str] = []
