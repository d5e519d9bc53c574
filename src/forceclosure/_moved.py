"""Old module paths, kept working: ``forceclosure.closure`` is ``forceclosure.analysis.closure``.

The package was laid out by layer (issue 16); a module's old dotted name is an
alias of its new one. :class:`MovedFinder`, on :data:`sys.meta_path` from
``import forceclosure``, answers an import of an old name with the very module
object of the new name (``sys.modules`` holds it under both names), so
``from forceclosure.closure import analyze``, ``import forceclosure.batch as b``
and pickles whose classes name an old module all work, and nothing is loaded
twice. Three old modules became packages that forward every name to the module
they were (``forceclosure.gripper`` → :mod:`~forceclosure.gripper.jaw`,
``forceclosure.synthesis.planar`` → :mod:`~forceclosure.synthesis.planar.two_fingers`,
``forceclosure.synthesis.mesh`` → :mod:`~forceclosure.synthesis.mesh.grown_regions`),
so they are not in :data:`MOVED`. Importing this module loads no numpy.

Examples
--------
>>> import forceclosure.closure, forceclosure.analysis.closure
>>> forceclosure.closure is forceclosure.analysis.closure
True
>>> forceclosure.analysis.closure.__spec__.name
'forceclosure.analysis.closure'
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from importlib.machinery import ModuleSpec
from types import ModuleType

__all__ = ["MOVED", "MovedFinder", "forward", "install", "moved_attribute"]

#: Old dotted module name -> the module's name now.
MOVED: dict[str, str] = {
    "forceclosure.antipodal": "forceclosure.gripper.antipodal",
    "forceclosure.atomic": "forceclosure.io.atomic",
    "forceclosure.batch": "forceclosure.analysis.batch",
    "forceclosure.batch_analysis": "forceclosure.analysis.batch_analysis",
    "forceclosure.cli": "forceclosure.app.cli",
    "forceclosure.closure": "forceclosure.analysis.closure",
    "forceclosure.collision": "forceclosure.gripper.collision",
    "forceclosure.dataset": "forceclosure.app.dataset",
    "forceclosure.dataset_gripper": "forceclosure.app.dataset_gripper",
    "forceclosure.equilibrium": "forceclosure.analysis.equilibrium",
    "forceclosure.export": "forceclosure.io.export",
    "forceclosure.files": "forceclosure.io.files",
    "forceclosure.friction": "forceclosure.analysis.friction",
    "forceclosure.grasp_arrays": "forceclosure.io.grasp_arrays",
    "forceclosure.grasp_file": "forceclosure.io.grasp_file",
    "forceclosure.grasp_plot": "forceclosure.pictures.grasp_plot",
    "forceclosure.labels": "forceclosure.gripper.labels",
    "forceclosure.metrics": "forceclosure.analysis.metrics",
    "forceclosure.motion": "forceclosure.analysis.motion",
    "forceclosure.outdir": "forceclosure.io.outdir",
    "forceclosure.plot": "forceclosure.pictures.plot",
    "forceclosure.quality": "forceclosure.analysis.quality",
    "forceclosure.robust": "forceclosure.gripper.robust",
    "forceclosure.synthesis.edge_pair": "forceclosure.synthesis.planar.edge_pair",
    "forceclosure.synthesis.edge_sites": "forceclosure.synthesis.planar.edge_sites",
    "forceclosure.synthesis.frictionless": "forceclosure.synthesis.planar.four_frictionless",
    "forceclosure.synthesis.nguyen": "forceclosure.synthesis.planar.two_sided_cone",
    "forceclosure.synthesis.patches": "forceclosure.synthesis.spatial.patches",
    "forceclosure.synthesis.seven": "forceclosure.synthesis.spatial.seven_frictionless",
    "forceclosure.synthesis.soft_pair": "forceclosure.synthesis.spatial.two_soft",
    "forceclosure.synthesis.three_fingers": "forceclosure.synthesis.planar.three_fingers",
    "forceclosure.synthesis.three_hard": "forceclosure.synthesis.spatial.three_hard",
    "forceclosure.synthesis.vertices": "forceclosure.synthesis.planar.vertex_grasps",
    "forceclosure.synthesis.zones": "forceclosure.synthesis.spatial.zones",
    "forceclosure.task": "forceclosure.analysis.task",
    "forceclosure.two_finger": "forceclosure.analysis.two_finger",
    "forceclosure.view": "forceclosure.pictures.view",
    "forceclosure.workers": "forceclosure.app.workers",
}


class _AliasLoader:
    """Loads an old name as the module of its new name (imported first, if need be)."""

    def __init__(self, new: str) -> None:
        self.new = new
        self.spec: ModuleSpec | None = None

    def create_module(self, spec: ModuleSpec) -> ModuleType:
        module = importlib.import_module(self.new)
        self.spec = module.__spec__
        return module

    def exec_module(self, module: ModuleType) -> None:
        # the import system has set the module's __spec__ to the alias's: give it back its own
        module.__spec__ = self.spec


class MovedFinder:
    """A :data:`sys.meta_path` finder for the names in :data:`MOVED`."""

    @staticmethod
    def find_spec(fullname: str, path: object = None, target: object = None) -> ModuleSpec | None:
        new = MOVED.get(fullname)
        if new is None:
            return None
        return importlib.util.spec_from_loader(fullname, _AliasLoader(new))


def install() -> None:
    """Put :class:`MovedFinder` on :data:`sys.meta_path` (once)."""
    if not any(isinstance(f, MovedFinder) for f in sys.meta_path):
        sys.meta_path.append(MovedFinder())


def moved_attribute(package: str, name: str) -> ModuleType:
    """``package.name`` for a module that moved away from ``package`` (a module
    ``__getattr__`` calls this); :class:`AttributeError` otherwise."""
    if f"{package}.{name}" in MOVED:
        return importlib.import_module(f"{package}.{name}")
    raise AttributeError(f"module {package!r} has no attribute {name!r}")


def forward(package: str, module: str, name: str) -> object:
    """``name`` of the module an old module's package forwards to (its ``__getattr__``)."""
    found = importlib.import_module(module)
    try:
        return getattr(found, name)
    except AttributeError:
        raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
