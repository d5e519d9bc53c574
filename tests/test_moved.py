"""The old module paths keep working after the layout by layers (issue 16).

Every old dotted name in :data:`forceclosure._moved.MOVED` imports as the very module object
of its new name; the three old modules that became packages give their names; pickles written
before the move (whose classes name the old modules) load, in a fresh interpreter too. The list
of old names is checked against the files that were moved (``git mv``), not against the table
alone: the old layout is written out here by hand.
"""

from __future__ import annotations

import importlib
import pickle
import pkgutil
import subprocess
import sys

import pytest

from forceclosure._moved import MOVED

#: The modules of the flat layout before issue 16 (written out by hand, from ``git ls-tree``
#: of the commit before the move), and where each is now.
OLD_TOP = ["antipodal", "atomic", "batch", "batch_analysis", "cli", "closure", "collision",
           "dataset", "dataset_gripper", "equilibrium", "export", "files", "friction",
           "grasp_arrays", "grasp_file", "grasp_plot", "labels", "metrics", "motion", "outdir",
           "plot", "quality", "robust", "task", "two_finger", "view", "workers"]
OLD_SYNTHESIS = ["edge_pair", "edge_sites", "frictionless", "nguyen", "patches", "seven",
                 "soft_pair", "three_fingers", "three_hard", "vertices", "zones"]
#: Old modules whose name is a package now, forwarding to the module they were.
BECAME_PACKAGES = {"forceclosure.gripper": "forceclosure.gripper.jaw",
                   "forceclosure.synthesis.planar": "forceclosure.synthesis.planar.two_fingers",
                   "forceclosure.synthesis.mesh": "forceclosure.synthesis.mesh.grown_regions"}


def test_the_table_holds_every_old_module_and_nothing_else():
    old = {f"forceclosure.{m}" for m in OLD_TOP} | {f"forceclosure.synthesis.{m}"
                                                     for m in OLD_SYNTHESIS}
    assert set(MOVED) == old
    assert not set(MOVED) & set(BECAME_PACKAGES)


@pytest.mark.parametrize("old", sorted(MOVED))
def test_an_old_path_is_the_new_module(old):
    module = importlib.import_module(old)
    new = importlib.import_module(MOVED[old])
    assert module is new and sys.modules[old] is new
    assert new.__name__ == new.__spec__.name == MOVED[old]  # the alias did not rename it
    parent, _, leaf = old.rpartition(".")
    assert getattr(importlib.import_module(parent), leaf) is new
    for name in getattr(new, "__all__", []):
        assert getattr(module, name) is getattr(new, name)


def test_old_paths_as_attributes_and_from_imports():
    import forceclosure
    import forceclosure.analysis.batch
    import forceclosure.synthesis
    from forceclosure.synthesis.planar import best_regions
    from forceclosure.synthesis.planar.two_fingers import best_regions as new_best

    assert best_regions is new_best
    assert forceclosure.batch is forceclosure.analysis.batch
    assert forceclosure.synthesis.nguyen is importlib.import_module(
        "forceclosure.synthesis.planar.two_sided_cone")
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        forceclosure.synthesis.nonsense  # noqa: B018
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("forceclosure.nonsense")


@pytest.mark.parametrize("old, new", sorted(BECAME_PACKAGES.items()))
def test_an_old_module_now_a_package_gives_its_names(old, new):
    package, module = importlib.import_module(old), importlib.import_module(new)
    assert package is not module
    assert list(package.__all__) == list(module.__all__)
    # a name the module imported that is also a submodule of the package now is the submodule
    # (forceclosure.synthesis.planar.edge_pair: the function before, its module now)
    submodules = {m.name for m in pkgutil.iter_modules(package.__path__)}
    public = [n for n in vars(module) if not n.startswith("__") and n not in submodules]
    assert public and all(getattr(package, n) is getattr(module, n) for n in public)
    with pytest.raises(AttributeError, match=f"module '{old}' has no attribute 'nonsense'"):
        package.nonsense  # noqa: B018


def old_pickle(obj, old: str, new: str) -> bytes:
    """``obj`` pickled as before the move: protocol 0 names each class by ``module\\nname``,
    so the bytes differ from the new ones only in the module's name."""
    data = pickle.dumps(obj, protocol=0)
    tag = f"c{new}\n".encode()
    assert tag in data
    return data.replace(tag, f"c{old}\n".encode())


def objects_made_before():
    from forceclosure import Verdict, bundled
    from forceclosure.gripper import JawPose
    from forceclosure.synthesis.planar import maximal_regions

    regions = maximal_regions(bundled("square"), 0, 2, mu=0.3)
    # Verdict lives in forceclosure.verdicts now; pickles naming either earlier home load
    return [(Verdict.CLOSURE, "forceclosure.closure", "forceclosure.verdicts"),
            (Verdict.MARGINAL, "forceclosure.analysis.closure", "forceclosure.verdicts"),
            (JawPose([0, 0, 0], [1, 0, 0], [0, 0, 1], 1.0),
             "forceclosure.gripper", "forceclosure.gripper.jaw"),
            (regions, "forceclosure.synthesis.edge_pair",
             "forceclosure.synthesis.planar.edge_pair")]


def test_pickles_naming_old_modules_load():
    for obj, old, new in objects_made_before():
        data = old_pickle(obj, old, new)
        back = pickle.loads(data)
        assert type(back) is type(obj) and type(back).__module__ == new
        assert pickle.dumps(back, protocol=0) == pickle.dumps(obj, protocol=0)


def test_an_old_pickle_loads_in_a_fresh_interpreter():
    """The unpickler imports the old module by name before anything of the package is loaded."""
    obj, old, new = objects_made_before()[0]
    code = ("import pickle, sys\nv = pickle.loads(sys.stdin.buffer.read())\n"
            "print(type(v).__module__, v.value)")
    out = subprocess.run([sys.executable, "-c", code], input=old_pickle(obj, old, new),
                         capture_output=True, check=True).stdout.decode().split()
    assert out == ["forceclosure.verdicts", "closure"]
