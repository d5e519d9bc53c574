"""Fuzzing the gripper and task helpers: a result or an InputError (one line), nothing else.

The helpers a user calls with their own numbers (``pose_from_contacts``, ``ParallelJaw``,
``JawPose``, ``make_gripper``, ``gravity_wrench``, ``resist_wrench`` and its batch) get
what a careless or hostile caller passes: ints past float's range (``10**400``), NaN and
infinities, subnormals, strings, None, booleans, vectors of the wrong length, nested
lists. Where a call returns, its result is checked against the closed form written here
(a pose's centre and width, the weight's force and torque).
"""

from __future__ import annotations

import math
import os

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from forceclosure.analysis.task import gravity_wrench, resist_wrench, resist_wrench_batch
from forceclosure.errors import InputError
from forceclosure.gripper.grippers import make_gripper
from forceclosure.gripper.jaw import JawPose, ParallelJaw, pose_from_contacts

#: 120 examples a test, the same every run; FORCECLOSURE_FUZZ_EXAMPLES for a longer, random
#: search (as tests/test_fuzz_api.py).
_EXAMPLES = os.environ.get("FORCECLOSURE_FUZZ_EXAMPLES")
LIGHT = settings(max_examples=int(_EXAMPLES or 120), deadline=None, derandomize=not _EXAMPLES,
                 suppress_health_check=list(HealthCheck))

NUMBER = st.one_of(
    st.sampled_from([0, 1, -1, 0.5, 10**400, -(10**400), 2**64, 1e300, -1e300, 1.7e308,
                     5e-324, math.nan, math.inf, -math.inf, 1e150, 1e151, True]),
    st.floats(-10, 10), st.integers(-5, 5))
JUNK = st.one_of(NUMBER, st.none(), st.sampled_from(["x", "", "1", b"1", 1j, object()]))
VECTOR = st.one_of(st.lists(NUMBER, min_size=0, max_size=5),
                   st.lists(st.lists(NUMBER, max_size=3), max_size=3), JUNK)


def _only_input_errors(call):
    try:
        return call()
    except InputError as e:
        assert str(e) and "\n" not in str(e), repr(str(e))
        return None


def _as3(v):
    """``v`` as 3 finite floats by plain Python, or None."""
    try:
        if isinstance(v, (str, bytes)) or len(v) != 3:
            return None
        out = [float(x) for x in v]
    except (TypeError, ValueError, OverflowError):
        return None
    return out if all(math.isfinite(x) for x in out) else None


@LIGHT
@given(VECTOR, VECTOR, st.one_of(st.none(), VECTOR))
def test_pose_from_contacts(p, q, approach):
    pose = _only_input_errors(lambda: pose_from_contacts(p, q, approach))
    if pose is None:
        return
    p3, q3 = _as3(p), _as3(q)
    assert p3 is not None and q3 is not None  # only 3 finite numbers each make a pose
    assert np.allclose(pose.center, [(a + b) / 2 for a, b in zip(p3, q3, strict=True)])
    assert math.isclose(pose.width, math.dist(p3, q3), rel_tol=1e-9)


@LIGHT
@given(JUNK, VECTOR, VECTOR, st.one_of(st.none(), VECTOR))
def test_gravity_wrench(mass, center, g, reference):
    w = _only_input_errors(lambda: gravity_wrench(mass, center, g, reference))
    if w is None:
        return
    c, g3 = _as3(center), _as3(g)
    r = [0.0, 0.0, 0.0] if reference is None else _as3(reference)
    f = [float(mass) * x for x in g3]
    arm = [a - b for a, b in zip(c, r, strict=True)]
    torque = [arm[1] * f[2] - arm[2] * f[1], arm[2] * f[0] - arm[0] * f[2],
              arm[0] * f[1] - arm[1] * f[0]]
    assert np.all(np.isfinite(w))
    assert np.allclose(w, f + torque, rtol=1e-9, atol=1e-300)


PINCH_P = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
PINCH_N = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]


@LIGHT
@given(st.one_of(NUMBER, st.lists(NUMBER, min_size=2, max_size=2), JUNK), JUNK,
       st.one_of(st.just([0, 0, -4, 0, 0, 0]), VECTOR), st.one_of(st.just(1.0), JUNK),
       st.one_of(st.none(), VECTOR), st.one_of(st.just(8), JUNK),
       st.sampled_from(["soft", "hard", "frictionless", "glue", ["soft"] * 2]))
def test_resist_wrench(mu, torsion, wrench, f_max, reference, edges, model):
    """The squeeze of resist_wrench's example, with every other argument fuzzed; where it
    answers, spare <= spare_upper (the inscribed pyramids' LP is a lower bound)."""
    t = _only_input_errors(lambda: resist_wrench(
        PINCH_P, PINCH_N, wrench, mu=mu, model=model, torsion=torsion, f_max=f_max,
        reference=reference, edges=edges))
    if t is not None:
        assert t.verdict in ("resists", "undecided", "fails")
        assert t.spare <= t.spare_upper * (1 + 1e-9) + 1e-12
    batch = _only_input_errors(lambda: resist_wrench_batch(
        [PINCH_P], [PINCH_N], wrench, mu=mu, model=model, torsion=torsion, f_max=f_max,
        reference=reference, edges=edges))
    if batch is not None and t is not None:
        assert batch[0][0] == {"fails": 0, "undecided": 1, "resists": 2}[t.verdict]


@LIGHT
@given(JUNK, st.one_of(st.none(), JUNK), st.sampled_from([None, "parallel-jaw", "panda",
                                                          "nope", 3]))
def test_grippers(width, pad_radius, name):
    hand = _only_input_errors(lambda: ParallelJaw(width, pad_radius))
    if hand is not None:
        assert 0 < hand.width_max <= 1e150 and hand.finger_length > 0
        t = hand.torsion(0.5)  # the coupled torsion of a disk pad: (2/3) mu r
        if hand.pad_radius == 0:
            assert t is None
        elif hand.pad_radius is not None:
            assert math.isclose(t, 2 / 3 * 0.5 * hand.pad_radius, rel_tol=1e-12)
    _only_input_errors(lambda: make_gripper(name, width, pad_radius))


@LIGHT
@given(VECTOR, VECTOR, VECTOR, JUNK)
def test_jaw_pose(center, closing, approach, width):
    pose = _only_input_errors(lambda: JawPose(center, closing, approach, width))
    if pose is not None:
        R = pose.rotation
        assert np.allclose(R.T @ R, np.eye(3), atol=1e-9)
        assert pose.width > 0 and math.isfinite(pose.width)
