"""Signals and process ends seen from outside: Ctrl-C (a real SIGINT) stops a command
busy in compiled code, progress goes to a terminal standard error whatever standard
output is, and a pool worker ended without its exit handlers leaks no semaphore."""

from __future__ import annotations

import subprocess
import sys

WORKER_KILLED = """
import os, signal, sys
from forceclosure.app.dataset import Job, _context, _worker_init

def work():
    _worker_init(Job(), ())  # a pool worker's start: numba's threads, one of them
    os.kill(os.getpid(), signal.SIGKILL)  # then ended as a pool ends one: no exit handlers

if __name__ == "__main__":
    worker = _context().Process(target=work)
    worker.start()
    worker.join()
    print("worker exit", worker.exitcode, file=sys.stderr)
"""


def test_a_killed_pool_worker_leaks_no_semaphore(tmp_path):
    """The run's resource_tracker says nothing when a worker it started dies by SIGKILL
    (numba's start-up lock was a named semaphore only the worker's exit handlers freed:
    "There appear to be 1 leaked semaphore objects to clean up at shutdown")."""
    script = tmp_path / "run.py"
    script.write_text(WORKER_KILLED)
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert done.stderr.splitlines() == ["worker exit -9"], done.stderr
