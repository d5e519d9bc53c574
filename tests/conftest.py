import os
import sys

sys.path.insert(0, os.path.dirname(__file__))

# A dataset run whose standard error is not a terminal (captured, as here) prints a progress
# line every 10 s; tests that count stderr lines must not depend on how long a run takes.
# tests/datasets/test_progress.py sets its own intervals.
os.environ.setdefault("FORCECLOSURE_PROGRESS_SECONDS", "inf")

from hypothesis import HealthCheck, settings

from forceclosure import kernels

# The compiled kernels from the first call, so that the tests that compare them with the
# reference path compare two paths on any machine (its default, 100, lets the first grasps
# of an uncompiled machine take the reference path; tests/test_startup.py sets it to test
# that).
kernels.COMPILE_AFTER = 0

settings.register_profile("ci", max_examples=60, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("thorough", max_examples=1000, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
