"""The labelling pipeline of jaw poses (:mod:`forceclosure.gripper.pipeline`).

Expectations from outside the code: every antipodal pose on the cube's flat faces is
force-closure with soft pads (Corollary 3: the line between the contacts is along both
normals), so a weight small enough is resisted by every pose (force closure resists any
wrench, with forces in proportion) and a weight beyond what two pads can push
(each at most ``f_max`` along its normal and ``mu f_max`` across it) by none; without
noise a pose is closed in every noisy sample exactly when it is closed.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from forceclosure.errors import InputError
from forceclosure.gripper.jaw import ParallelJaw
from forceclosure.gripper.pipeline import label_poses

MU, F_MAX = 0.5, 70.0


def test_every_pose_on_the_cube_closes_and_the_summary_says_so():
    found = label_poses("cube", ParallelJaw(3.0), MU, 30, seed=1)
    s = found.summary
    assert s["candidates"] == s["requested"] == 30
    assert (s["closure"], s["marginal"], s["none"]) == (30, 0, 0)
    # antiparallel normals along the closing line: the least friction is 0 (within the
    # verdict's tolerance band), and a closed pose has a positive epsilon
    assert s["least_friction_median"] < 1e-3
    assert s["epsilon_median"] > 0
    assert s["collides"] == 0 and s["closure_clear"] == 30
    assert found.robust is found.metrics is found.task is None


def test_what_was_not_computed_is_none():
    found = label_poses("cube", ParallelJaw(3.0), MU, 10, seed=2, least_friction=False,
                        epsilon=False, collision=False)
    s = found.summary
    assert s["least_friction_median"] is None and s["epsilon_median"] is None
    assert s["collides"] is s["closure_clear"] is s["approaches"] is None


def test_the_task_against_a_tiny_weight_and_one_no_two_pads_can_carry():
    g = [0.0, 0.0, -9.81]
    light = label_poses("cube", ParallelJaw(3.0), MU, 20, seed=3,
                        task={"mass": 1e-6, "gravity": g, "f_max": F_MAX})
    assert light.summary["closure"] == 20
    assert light.task["resists"] == 20
    heavy_mass = 2 * F_MAX * math.hypot(1, MU) / 9.81 * 10  # ten times what the pads push
    heavy = label_poses("cube", ParallelJaw(3.0), MU, 20, seed=3,
                        task={"mass": heavy_mass, "gravity": g, "f_max": F_MAX})
    assert heavy.task["resists"] == 0
    assert heavy.task["center_of_mass"] == pytest.approx([0, 0, 0], abs=1e-9)
    assert len(heavy.labels.task_verdict) == 20


def test_without_noise_every_sample_of_a_closed_pose_closes():
    found = label_poses("cube", ParallelJaw(3.0), MU, 8, seed=4, metrics=True,
                        robust={"samples": 5, "pose_sigma": 0.0, "angle_sigma": 0.0,
                                "mu_sigma": 0.0, "epsilon": False})
    assert found.summary["closure"] == 8
    assert found.robust["probability_mean"] == 1.0
    assert found.robust["samples"] == 5 and "epsilon" not in found.robust
    assert np.all(found.labels.robust_probability == 1.0)
    # the isotropy is a ratio of singular values: in (0, 1]
    assert 0 < found.metrics["isotropy_median"] <= 1 + 1e-12


def test_the_default_pose_noise_is_a_hundredth_of_the_opening():
    found = label_poses("cube", ParallelJaw(3.0), MU, 2, seed=5,
                        robust={"samples": 2, "epsilon": False})
    assert found.robust["pose_sigma"] == pytest.approx(0.03)


def test_a_task_on_an_open_mesh_is_refused_before_any_work():
    # an open mesh as the loaders mark it (``watertight`` False): refused before its surface
    # is read, so nothing else of it is needed
    open_mesh = SimpleNamespace(name="scan", watertight=False)
    with pytest.raises(InputError, match=r"scan: .*closed mesh"):
        label_poses(open_mesh, ParallelJaw(3.0), MU, 5,
                    task={"mass": 1.0, "gravity": [0, 0, -9.81], "f_max": F_MAX})
