"""Signals and process ends seen from outside: Ctrl-C (a real SIGINT) stops a command
busy in compiled code, progress goes to a terminal standard error whatever standard
output is, and a pool worker ended without its exit handlers leaks no semaphore."""

from __future__ import annotations

import os
import pty
import signal
import subprocess
import sys
from pathlib import Path

import psutil
import pytest

#: The imports and the compiled kernel both scripts below run: ``spin(n, returned)`` loops
#: ``n`` times without the GIL, then writes 1 in ``returned``.
SPIN = """
import math, sys
import numba
import numpy as np
from forceclosure.app import cli, cmd_demo

@numba.njit(nogil=True, cache=False)
def spin(n, returned):
    s = 0.0
    for i in range(n):
        s += math.sin(i * 1e-3)
    returned[0] = 1
    return s
"""

#: A command whose work is one call of a compiled kernel, a minute long here (seconds on a
#: fast machine: far more than the time Ctrl-C takes): "started" before; the kernel itself
#: writes 1 in the file argv[1] (mapped in memory) as it returns.
BUSY = SPIN + """
def busy(args):
    returned = np.asarray(np.memmap(sys.argv[1], dtype=np.int64, mode="r+", shape=(1,)))
    spin(10, np.zeros(1, np.int64))  # compiled before it says it started
    print("started", flush=True)
    spin(3 * 10**9, returned)
    return 0

cmd_demo.run = busy
sys.exit(cli.main(["demo"]))
"""


def _started(proc: subprocess.Popen) -> None:
    """Read the command's standard output until it says it started."""
    line = proc.stdout.readline()
    assert line == "started\n", (line, proc.stderr.read() if line == "" else "")


def test_ctrl_c_stops_a_command_inside_a_compiled_call(tmp_path):
    """A real SIGINT while the command is inside one long nogil numba call: the process
    ends with status 130 and one line before the call returns (the kernel's own mark of
    its return is not in the file; Python alone saw the signal only after it)."""
    returned = tmp_path / "returned"
    returned.write_bytes(bytes(8))
    proc = subprocess.Popen([sys.executable, "-c", BUSY, str(returned)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _started(proc)
        os.kill(proc.pid, signal.SIGINT)
        out, err = proc.communicate()
    finally:
        proc.kill()
    assert proc.returncode == 130
    assert out == "" and err.splitlines() == ["forceclosure: interrupted"], (out, err)
    assert returned.read_bytes() == bytes(8)  # the call had not returned


#: A command that saves, then works on: inside holding(), one compiled call of seconds,
#: then the rest of the save (argv[2]); then one of a minute. Each call marks its return
#: in argv[1] (two numbers mapped in memory).
SAVING = """
import math, sys
import numba
import numpy as np
from forceclosure.app import cli, cmd_demo
from forceclosure.app import interrupt
from forceclosure.files.saves import holding

interrupt.GRACE = 0.1  # the save's call below outlasts it

@numba.njit(nogil=True, cache=False)
def spin(n, returned, k):
    s = 0.0
    for i in range(n):
        s += math.sin(i * 1e-3)
    returned[k] = 1
    return s

def save(args):
    returned = np.asarray(np.memmap(sys.argv[1], dtype=np.int64, mode="r+", shape=(2,)))
    spin(10, np.zeros(1, np.int64), 0)
    with holding():
        print("saving", flush=True)
        spin(2 * 10**8, returned, 0)
        with open(sys.argv[2], "w") as f:
            f.write("saved")
    spin(3 * 10**9, returned, 1)
    return 0

cmd_demo.run = save
sys.exit(cli.main(["demo"]))
"""


@pytest.mark.long  # 5 s of real processes
def test_ctrl_c_during_a_save_waits_for_it(tmp_path):
    """Ctrl-C while the command saves (inside holding(), in a compiled call longer than the
    grace): the save completes (its kernel returned, the file after it is written); the
    work after it is stopped inside its compiled call: status 130, one line."""
    returned, saved = tmp_path / "returned", tmp_path / "saved"
    returned.write_bytes(bytes(16))
    proc = subprocess.Popen([sys.executable, "-c", SAVING, str(returned), str(saved)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = proc.stdout.readline()
        assert line == "saving\n", (line, proc.stderr.read() if line == "" else "")
        os.kill(proc.pid, signal.SIGINT)
        out, err = proc.communicate()
    finally:
        proc.kill()
    assert out == "" and saved.read_text() == "saved"
    marks = returned.read_bytes()
    assert marks[:8] != bytes(8) and marks[8:] == bytes(8)  # the save's call returned only
    assert proc.returncode == 130 and err.splitlines() == ["forceclosure: interrupted"], err


#: A command that saves its work when interrupted (as analyze --out does): its compiled
#: call of seconds inside patient(), which marks its return in argv[1].
PATIENT = SPIN + """
from forceclosure.app import interrupt
from forceclosure.files.saves import patient

interrupt.GRACE = 0.1  # the call below outlasts it

def work(args):
    returned = np.asarray(np.memmap(sys.argv[1], dtype=np.int64, mode="r+", shape=(1,)))
    spin(10, np.zeros(1, np.int64))
    with patient():
        print("started", flush=True)
        spin(2 * 10**8, returned)
    return 0

cmd_demo.run = work
sys.exit(cli.main(["demo"]))
"""


@pytest.mark.long  # 5 s of real processes
def test_ctrl_c_waits_for_a_command_that_saves_its_work(tmp_path):
    """A command inside patient() (it saves what is done when interrupted) is waited for:
    one line says so, its compiled call returns, then it is interrupted (status 130)."""
    returned = tmp_path / "returned"
    returned.write_bytes(bytes(8))
    proc = subprocess.Popen([sys.executable, "-c", PATIENT, str(returned)],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        _started(proc)
        os.kill(proc.pid, signal.SIGINT)
        out, err = proc.communicate()
    finally:
        proc.kill()
    assert out == "" and returned.read_bytes() != bytes(8)
    assert proc.returncode == 130
    assert err.splitlines() == [
        "forceclosure: stopping when the current step returns, to save what is done "
        "(Ctrl-C again: quit without saving)", "forceclosure: interrupted"], err


@pytest.mark.long
def test_ctrl_c_on_a_pool_dataset_keeps_the_records_and_writes_the_table(tmp_path):
    """SIGINT to a dataset run on a local pool once two objects are recorded: exit 130,
    the summary says interrupted, results.parquet holds exactly the records written, no
    temporary is left and nothing from resource_tracker; the same command resumes them."""
    import json

    import pandas as pd
    import pybullet_data

    urdfs = Path(pybullet_data.getDataPath()) / "random_urdfs"
    out = tmp_path / "out"
    argv = [sys.executable, "-m", "forceclosure", "dataset",
            *(str(urdfs / f"{i:03d}" / f"{i:03d}.urdf") for i in range(12)),
            "--out", str(out), "--fingers", "3", "--contact", "hard", "--mu", "0.5",
            "--top", "1", "--samples", "1000", "--workers", "2", "--json"]
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        while len(list((out / "objects").glob("*.json"))) < 2:  # the event: two recorded
            assert proc.poll() is None, proc.stderr.read()
            psutil.wait_procs([psutil.Process(proc.pid)], timeout=0.05)
        os.kill(proc.pid, signal.SIGINT)
        out_text, err = proc.communicate()
    finally:
        proc.kill()
    assert proc.returncode == 130, err
    summary = json.loads(out_text)
    records = sorted(p.stem for p in (out / "objects").glob("*.json"))
    assert summary["interrupted"] and summary["done"] == len(records) < 12
    table = pd.read_parquet(out / "results.parquet")
    assert len(table) == len(records)
    assert [p for p in out.rglob("*") if p.name.endswith(".tmp")] == []
    assert "resource_tracker" not in err and "leaked" not in err
    again = subprocess.run(argv, capture_output=True, text=True)
    assert again.returncode == 0, again.stderr
    assert json.loads(again.stdout)["skipped"] == len(records)


@pytest.mark.long
def test_ctrl_c_stops_synthesize_within_seconds():
    """The real command: six soft fingers on the cube, about two minutes in its kernels;
    SIGINT once it has spent two seconds of processor time ends it within 30 s (it took
    100 s when only the kernel's return let Python see the signal)."""
    proc = subprocess.Popen([sys.executable, "-m", "forceclosure", "synthesize", "cube",
                             "--contact", "soft", "--fingers", "6"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        busy = psutil.Process(proc.pid)
        while sum(busy.cpu_times()[:2]) < 2.0:  # the event: deep in the work
            assert proc.poll() is None, proc.stderr.read()
            psutil.wait_procs([busy], timeout=0.1)
        os.kill(proc.pid, signal.SIGINT)
        out, err = proc.communicate(timeout=30)
    finally:
        proc.kill()
    assert proc.returncode == 130, err
    assert err.splitlines() == ["forceclosure: interrupted"] and out == "", (out, err)

WORKER_KILLED = """
import os, signal, sys
from forceclosure.datasets import Job
from forceclosure.datasets.pool import pool_context, worker_init

def work():
    worker_init(Job(), ())  # a pool worker's start: numba's threads, one of them
    os.kill(os.getpid(), signal.SIGKILL)  # then ended as a pool ends one: no exit handlers

if __name__ == "__main__":
    worker = pool_context().Process(target=work)
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


def _terminal_text(fd: int) -> str:
    """All a pseudo-terminal's reader gets until the writer closes it."""
    text = b""
    while True:
        try:
            chunk = os.read(fd, 4096)
        except OSError:  # the process closed the terminal
            chunk = b""
        if not chunk:
            return text.decode("utf-8", "replace")
        text += chunk


def test_progress_bar_on_a_terminal_stderr_when_stdout_is_a_pipe():
    """stdout a pipe, stderr a terminal nobody gave a size (0 columns, as a bare pty says):
    the bar is drawn on stderr, 80 wide, and stdout has the summary alone."""
    env = {k: v for k, v in os.environ.items() if k not in ("COLUMNS", "LINES")}
    master, slave = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "forceclosure", "grasps", "cube",
                             "--count", "200", "--width", "3"], stdout=subprocess.PIPE,
                            stderr=slave, env=env)
    os.close(slave)
    try:
        err = _terminal_text(master)
        out = proc.stdout.read().decode()
        assert proc.wait() == 0, err
    finally:
        proc.kill()
        os.close(master)
    bars = [line for line in err.replace("\r\n", "\r").split("\r") if "labelling" in line]
    assert bars and bars[-1].startswith("labelling: 100%|") and "200/200" in bars[-1], err
    assert max(len(line) for line in bars) <= 80
    assert "labelling" not in out and "cube: 200 jaw poses" in out
