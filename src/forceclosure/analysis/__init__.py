"""The forward problem (Nguyen 1988, §2-§3): is a given grasp force-closure, and how well.

Theorem 1's verdict with its certificates (:mod:`.closure`), the motion a grasp
does not resist (:mod:`.motion`), equilibrium, two-finger pairs (Corollary 3),
the least friction, quality and metrics, task wrenches, and the batch paths
over the compiled kernels. A layer of its own: it imports only the core
(:mod:`forceclosure.errors`, :mod:`~forceclosure.tolerance`,
:mod:`~forceclosure.contacts`), :mod:`forceclosure.geometry` and
:mod:`forceclosure.kernels`; never synthesis, the gripper, pictures, io or the
app, which are built on it (data flows one way: geometry → contacts →
analysis → synthesis/gripper → pictures/io → app). The public names are in
:mod:`forceclosure` itself; the modules load on first import.
"""

__all__: list[str] = []
