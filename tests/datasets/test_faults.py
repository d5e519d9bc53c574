"""Datasets under real faults: damaged, foreign and stale records, a second run on the same
folder, a driver killed alone, a worker stuck in compiled code or stopped, a full disk, URDFs
naming meshes outside their folder or a symbolic link loop, and --grasps templates."""

from __future__ import annotations

import errno
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from contextlib import suppress
from pathlib import Path

import numpy as np
import pandas as pd
import psutil
import pybullet_data
import pytest

from forceclosure.app.cli import main
from forceclosure.datasets import Job, pool, process_object, record_name, run_dataset
from forceclosure.errors import InputError
from forceclosure.objects.io import load_object

DATA = Path(pybullet_data.getDataPath())
URDFS = DATA / "random_urdfs"
BUNDLED = ["cube", "l-prism", "hexagon", "square", "triangle"]
SOFT = Job(contact="soft", mu=0.5, top=1, samples=500)
SOFT_ARGS = ["--contact", "soft", "--mu", "0.5", "--top", "1", "--samples", "500"]
HARD = Job(fingers=3, contact="hard", mu=0.5, top=1, samples=1000)
HARD_ARGS = ["--fingers", "3", "--contact", "hard", "--mu", "0.5", "--top", "1",
             "--samples", "1000"]
#: What differs between two computations of one object: where, how fast, and the stamps.
VOLATILE = ("seconds", "load_seconds", "worker", "job", "input")
CLI = [sys.executable, "-m", "forceclosure", "dataset"]


def _urdfs(count: int) -> list[Path]:
    return [URDFS / f"{i:03d}" / f"{i:03d}.urdf" for i in range(count)]


def _strip(record: dict) -> dict:
    return {k: v for k, v in record.items() if k not in VOLATILE}


def _records(out: Path) -> dict[str, dict]:
    return {f.name: json.loads(f.read_text()) for f in (out / "objects").glob("*.json")}


def _truth(paths, job: Job) -> dict[str, dict]:
    """Each object computed alone, in this process: what every record must say."""
    return {record_name(Path(p)): _strip(process_object(p, job)) for p in paths}


@pytest.fixture(scope="module")
def bundled_truth():
    return _truth(BUNDLED, SOFT)


@pytest.fixture(scope="module")
def urdf_truth():
    return _truth(_urdfs(8), HARD)


def _tmp_files(out: Path) -> list[Path]:
    return [*out.glob(".*.tmp"), *(out / "objects").glob(".*.tmp")]


# -- records -------------------------------------------------------------------------------

def test_damaged_foreign_and_stale_records_are_redone(tmp_path, bundled_truth):
    out = tmp_path / "out"
    lines: list[str] = []
    first = run_dataset(BUNDLED, out, SOFT, workers=1, progress=False)
    assert first.done == 5
    files = {name: out / "objects" / record_name(Path(name)) for name in BUNDLED}
    files["cube"].write_text("[]")
    files["l-prism"].write_text("null")
    hexagon = json.loads(files["hexagon"].read_text())
    del hexagon["status"]
    files["hexagon"].write_text(json.dumps(hexagon))
    shutil.copy(files["triangle"], files["square"])  # a record copied over another's
    triangle = json.loads(files["triangle"].read_text())
    files["triangle"].write_text(json.dumps({**triangle, "seconds": "slow"}))  # wrong type
    again = run_dataset(BUNDLED, out, SOFT, workers=1, progress=False, log=lines.append)
    assert (again.computed, again.skipped, again.done) == (5, 0, 5)
    reasons = "\n".join(lines)
    for why in ("not a record (a JSON list)", "not a record (a JSON NoneType)",
                "fields missing (status)", "the record of another object",
                "a field of the wrong type"):
        assert why in reasons
    assert all(line.startswith("forceclosure: warning: ") for line in lines)
    assert {n: _strip(r) for n, r in _records(out).items()} == bundled_truth
    table = pd.read_parquet(out / "results.parquet")
    assert len(table) == 5 and table["path"].is_unique and (table["status"] == "done").all()
    # invalid JSON (a half-written file from another tool): redone, not a crash
    files["cube"].write_text('{"path": "cube", "sta')
    lines.clear()
    assert run_dataset(BUNDLED, out, SOFT, workers=1, progress=False,
                       log=lines.append).computed == 1
    assert "not readable JSON" in lines[0]
    # job.json deleted, then another friction coefficient: every record is stale
    (out / "job.json").unlink()
    other = Job(contact="soft", mu=0.9, top=1, samples=500)
    lines.clear()
    third = run_dataset(BUNDLED, out, other, workers=1, progress=False, log=lines.append)
    assert third.computed == 5 and len(lines) == 5
    assert all("made by another job" in line for line in lines)
    assert {r["mu"] for r in _records(out).values()} == {0.9}
    assert json.loads((out / "job.json").read_text())["mu"] == 0.9


def test_changed_inputs_are_redone(tmp_path):
    """An object file edited, and a mesh a URDF names edited: each is computed again; the
    others are not."""
    (tmp_path / "sq.json").write_text("[[0, 0], [2, 0], [2, 2], [0, 2]]")
    shutil.copy(URDFS / "000" / "000.obj", tmp_path / "m.obj")
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="l"><collision><geometry><mesh filename="m.obj"/>'
        '</geometry></collision></link></robot>')
    shutil.copy(URDFS / "001" / "001.obj", tmp_path / "other.obj")
    out = tmp_path / "out"
    inputs = [tmp_path / "sq.json", tmp_path / "r.urdf", tmp_path / "other.obj"]
    assert run_dataset(inputs, out, HARD, workers=1, progress=False).computed == 3
    assert run_dataset(inputs, out, HARD, workers=1, progress=False).computed == 0
    (tmp_path / "sq.json").write_text("[[0, 0], [3, 0], [3, 3], [0, 3]]")  # side 3 now
    shutil.copy(URDFS / "002" / "002.obj", tmp_path / "m.obj")
    lines: list[str] = []
    again = run_dataset(inputs, out, HARD, workers=1, progress=False, log=lines.append)
    assert (again.computed, again.skipped) == (2, 1)
    assert sum("its input changed since" in line for line in lines) == 2
    records = {r["name"]: r for r in _records(out).values()}
    assert records["sq"]["size"] == pytest.approx(3 * np.sqrt(2))  # the new square's diagonal
    assert records["r"]["triangles"] == len(load_object(URDFS / "002" / "002.obj").triangles)


def test_retry_failed_through_the_cli(tmp_path, capsys):
    """An object over the time limit stays so on a plain re-run, and is computed again with
    --retry-failed; a failed object whose file is fixed is computed again by itself."""
    (tmp_path / "bad.json").write_text("[[0, 0], [1, 0]]")  # two points: not a polygon
    out = str(tmp_path / "out")
    argv = ["dataset", "cube", str(tmp_path / "bad.json"), "--out", out, *SOFT_ARGS,
            "--workers", "1"]
    assert main([*argv, "--timeout", "0.001"]) == 2
    capsys.readouterr()
    statuses = {r["name"]: r["status"] for r in _records(Path(out)).values()}
    assert statuses["cube"] == "timeout" and statuses["bad"] != "done"
    assert main([*argv, "--json"]) == 2  # failed and timed out objects are kept
    assert json.loads(capsys.readouterr().out)["computed"] == 0
    (tmp_path / "bad.json").write_text("[[0, 0], [1, 0], [1, 1], [0, 1]]")  # fixed on disk
    assert main([*argv, "--json"]) == 2
    summary = json.loads(capsys.readouterr().out)
    assert (summary["computed"], summary["timeout"], summary["done"]) == (1, 1, 1)
    assert main([*argv, "--json", "--retry-failed"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["computed"], summary["done"]) == (1, 2)
    cube = next(r for r in _records(Path(out)).values() if r["name"] == "cube")
    assert _strip(cube) == _strip(process_object("cube", SOFT))


def test_timeout_inf_means_no_limit(tmp_path, capsys):
    assert Job(timeout=float("inf")).timeout is None
    assert main(["dataset", "cube", "--out", str(tmp_path), *SOFT_ARGS, "--workers", "1",
                 "--timeout", "inf", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["done"] == 1
    assert main(["dataset", "cube", "--out", str(tmp_path / "n"), "--timeout", "nan"]) == 2
    assert "--timeout must be a positive" in capsys.readouterr().err


# -- analysis --------------------------------------------------------------------------------

def _pinches(y: np.ndarray):
    """Two fingers on the sides x = -1 and x = 1 of the square of side 2, at heights y."""
    P = np.stack([np.column_stack([-np.ones(len(y)), y[:, 0]]),
                  np.column_stack([np.ones(len(y)), y[:, 1]])], axis=1)
    N = np.broadcast_to(np.array([[-1.0, 0.0], [1.0, 0.0]]), P.shape).copy()
    return P, N


def test_analyze_grasp_file_edited_and_truncated(tmp_path):
    """Editing the grasp file makes the object stale; a truncated .npz keeps the grasps
    before the cut, as 'forceclosure analyze' does. Truth: two fingers hold the square with
    mu 0.3 exactly when |y1 - y2| / 2 < 0.3 (the line between them inside both cones)."""
    import io
    import zipfile

    from numpy.lib import format as npy

    from forceclosure.io.grasp_arrays import CHUNK

    (tmp_path / "sq.json").write_text("[[-1, -1], [1, -1], [1, 1], [-1, 1]]")
    rng = np.random.default_rng(3)
    y = rng.uniform(-1, 1, (40, 2))
    y = y[np.abs(np.abs(y[:, 0] - y[:, 1]) / 2 - 0.3) > 1e-3]
    P, N = _pinches(y)
    np.savez(tmp_path / "sq.grasps.npz", points=P, normals=N, mu=0.3)
    out = tmp_path / "out"
    job = Job(mode="analyze")
    run_dataset([tmp_path / "sq.json"], out, job, workers=1, progress=False)
    row = pd.read_parquet(out / "results.parquet").iloc[0]
    assert row["closure"] == (np.abs(y[:, 0] - y[:, 1]) / 2 < 0.3).sum()
    # the grasp file edited: fingers head-on, all hold
    same = np.repeat(y[:, :1], 2, axis=1)
    P2, N2 = _pinches(same)
    np.savez(tmp_path / "sq.grasps.npz", points=P2, normals=N2, mu=0.3)
    lines: list[str] = []
    again = run_dataset([tmp_path / "sq.json"], out, job, workers=1, progress=False,
                        log=lines.append)
    assert again.computed == 1 and "its input changed since" in lines[0]
    row = pd.read_parquet(out / "results.parquet").iloc[0]
    assert (row["closure"], row["none"]) == (len(y), 0)
    # truncated: 'points' stops 10 rows into the second chunk
    n = CHUNK + 100
    y = rng.uniform(-1, 1, (n, 2))
    P, N = _pinches(y)
    with zipfile.ZipFile(tmp_path / "sq.grasps.npz", "w") as archive:
        for name, array, rows in (("points", P, CHUNK + 10), ("normals", N, n)):
            buffer = io.BytesIO()
            npy.write_array(buffer, array)
            raw = buffer.getvalue()
            archive.writestr(f"{name}.npy", raw[:len(raw) - array.nbytes
                                                + rows * array[0].nbytes])
        buffer = io.BytesIO()
        np.save(buffer, np.float64(0.3))
        archive.writestr("mu.npy", buffer.getvalue())
    run_dataset([tmp_path / "sq.json"], out, job, workers=1, progress=False,
                log=lines.append)
    record = next(iter(_records(out).values()))
    kept = y[:CHUNK]
    assert record["status"] == "done"
    assert record["closure"] == (np.abs(kept[:, 0] - kept[:, 1]) / 2 < 0.3).sum()
    assert record["closure"] + record["none"] + record["marginal"] == CHUNK
    assert record["errors"] == 100 and "truncated" in record["grasp_errors"][-1]


def test_grasps_placeholders_are_plain_names(tmp_path, capsys):
    for pattern in ("{dir.__class__}", "{name[0]}", "{stem:{dir}}", "{}", "{0}"):
        with pytest.raises(InputError, match="placeholders it may use, as plain names"):
            Job(mode="analyze", grasps=pattern)
    assert main(["dataset", "square", "--analyze", "--out", str(tmp_path / "o"), "--grasps",
                 "{dir.__class__.__mro__}"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "{dir.__class__.__mro__} is not one" in err
    assert "<class" not in err and not (tmp_path / "o").exists()
    assert Job(mode="analyze", grasps="{dir}/g/{stem!s}-{name:>5}.json").grasps


# -- URDF meshes -----------------------------------------------------------------------------

def test_urdf_meshes_outside_the_folder(tmp_path, capsys):
    """A URDF naming a mesh by '../', an absolute path or a link out of its folder is
    refused in one line; allowed, it reads the mesh (pybullet's cube.obj: volume 1)."""
    inside = tmp_path / "robot"
    (inside / "meshes").mkdir(parents=True)
    shutil.copy(DATA / "cube.obj", tmp_path / "cube.obj")
    shutil.copy(DATA / "cube.obj", inside / "meshes" / "cube.obj")
    (inside / "meshes" / "link.obj").symlink_to(tmp_path / "cube.obj")

    def urdf(name: str, filename: str) -> Path:
        path = inside / f"{name}.urdf"
        path.write_text(f'<robot name="r"><link name="l"><collision><geometry>'
                        f'<mesh filename="{filename}"/></geometry></collision></link></robot>')
        return path

    ok = urdf("ok", "meshes/cube.obj")
    up, absolute, linked = (urdf("up", "../cube.obj"),
                            urdf("abs", str(tmp_path / "cube.obj")),
                            urdf("link", "meshes/link.obj"))
    package = urdf("pkg", "package://robot/meshes/cube.obj")
    assert load_object(ok).volume == pytest.approx(1.0)
    assert load_object(package).volume == pytest.approx(1.0)
    for path in (up, absolute, linked):
        with pytest.raises(InputError, match="is outside the URDF's folder") as e:
            load_object(path)
        assert "\n" not in str(e.value) and "--allow-outside-meshes" in str(e.value)
        assert load_object(path, allow_outside_meshes=True).volume == pytest.approx(1.0)
    out = tmp_path / "out"
    argv = ["dataset", str(ok), str(up), "--out", str(out), *SOFT_ARGS, "--workers", "1",
            "--json"]
    assert main(argv) == 2
    assert json.loads(capsys.readouterr().out)["failed"] == 1
    with pytest.raises(InputError, match="another job"):  # the flag is part of the job
        run_dataset([up], out, Job(contact="soft", mu=0.5, top=1, samples=500,
                                   allow_outside_meshes=True), workers=1, progress=False)
    assert main([*argv[:3], "--out", str(tmp_path / "out2"), *argv[5:],
                 "--allow-outside-meshes"]) == 0
    assert json.loads(capsys.readouterr().out)["done"] == 2
    # inspect and synthesize take the same flag, and refuse without it
    for command in (["inspect", str(up), "--json"],
                    ["synthesize", str(up), *SOFT_ARGS, "--json"]):
        assert main(command) == 2
        assert "--allow-outside-meshes" in capsys.readouterr().err
        assert main([*command, "--allow-outside-meshes"]) == 0
        capsys.readouterr()


def test_a_symlink_loop_mesh_fails_only_its_urdf(tmp_path, capsys):
    shutil.copy(DATA / "cube.obj", tmp_path / "cube.obj")
    (tmp_path / "loop.obj").symlink_to(tmp_path / "loop.obj")
    (tmp_path / "bad.urdf").write_text(
        '<robot name="r"><link name="l"><collision><geometry><mesh filename="loop.obj"/>'
        '</geometry></collision></link></robot>')
    assert main(["dataset", str(tmp_path), "--out", str(tmp_path / "out"), *SOFT_ARGS,
                 "--workers", "1", "--json"]) == 2
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert (summary["objects"], summary["done"], summary["failed"]) == (2, 1, 1)
    assert "forceclosure: failed: bad.urdf: link 'l', collision 1: its mesh 'loop.obj' " \
           "cannot be followed" in captured.err


# -- a full disk -----------------------------------------------------------------------------

def test_full_disk(tmp_path, capsys, monkeypatch, bundled_truth):
    """ENOSPC from the second sync on: one line, the records written kept and correct, no
    temporary file left, the previous results.parquet intact; then the same command,
    with room again, completes with one record per object."""
    out = tmp_path / "out"
    argv = ["dataset", *BUNDLED[:2], "--out", str(out), *SOFT_ARGS, "--workers", "1"]
    assert main(argv) == 0
    capsys.readouterr()
    before = (out / "results.parquet").read_bytes()
    real_fsync, calls = os.fsync, []

    def fsync(fd: int) -> None:
        calls.append(fd)
        if len(calls) > 1:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        real_fsync(fd)

    monkeypatch.setattr(os, "fsync", fsync)
    argv = ["dataset", *BUNDLED, "--out", str(out), *SOFT_ARGS, "--workers", "1"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "No space left on device" in err
    assert "the 3 records written are kept; results.parquet is not updated" in err
    assert _tmp_files(out) == []
    assert (out / "results.parquet").read_bytes() == before
    assert {n: _strip(r) for n, r in _records(out).items()} == {
        n: bundled_truth[n] for n in _records(out)}
    monkeypatch.setattr(os, "fsync", real_fsync)
    assert main(argv) == 0
    assert {n: _strip(r) for n, r in _records(out).items()} == bundled_truth
    assert len(pd.read_parquet(out / "results.parquet")) == 5


# -- real processes --------------------------------------------------------------------------

def _wait_for(condition, seconds: float = 60) -> None:
    end = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < end, "timed out waiting"
        time.sleep(0.02)


def _hooked(tmp_path: Path) -> dict[str, str]:
    """The environment of a command whose workers get stuck on 'stuck.obj' (:data:`STUCK`)."""
    hook = tmp_path / "hook"
    hook.mkdir(exist_ok=True)
    (hook / "sitecustomize.py").write_text(STUCK)
    shutil.copy(URDFS / "000" / "000.obj", tmp_path / "stuck.obj")
    return {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(hook), *filter(None, [os.environ.get("PYTHONPATH")])])}


@pytest.mark.long
def test_concurrent_run_refused_and_killed_driver(tmp_path, urdf_truth, capsys):
    """A run in progress, one of its workers stuck (taking no signal, as in compiled code):
    a second run on the same --out is refused in one line. The first is killed alone
    (SIGKILL, not its process group): its workers vanish with it, the stuck one included,
    and so does the lock; the same command completes with exactly one correct record per
    object, leaving the earlier records as they were."""
    out = tmp_path / "out"
    env = _hooked(tmp_path)
    inputs = [str(tmp_path / "stuck.obj"), *map(str, _urdfs(8))]
    argv = [*CLI, *inputs, "--out", str(out), *HARD_ARGS, "--workers", "2"]
    run = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    try:
        _wait_for(lambda: len(list((out / "objects").glob("*.json"))) >= 2)
        assert main(["dataset", *inputs, "--out", str(out), *HARD_ARGS]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1
        assert f"another run (pid {run.pid} on " in err and "is writing there" in err
        descendants = psutil.Process(run.pid).children(recursive=True)
        assert len(descendants) >= 3  # the fork server and two workers at least
        run.kill()
        run.wait()
    finally:
        run.kill()
    _, alive = psutil.wait_procs(descendants, timeout=10)
    assert alive == []
    earlier = {f.name: f.read_bytes() for f in (out / "objects").glob("*.json")}
    assert 2 <= len(earlier) < 9 and record_name(tmp_path / "stuck.obj") not in earlier
    again = run_dataset(inputs, out, HARD, workers=2, progress=False)
    assert (again.skipped, again.done) == (len(earlier), 9)
    records = _records(out)
    truth = {**urdf_truth, **_truth([tmp_path / "stuck.obj"], HARD)}
    assert {n: _strip(r) for n, r in records.items()} == truth
    assert all((out / "objects" / n).read_bytes() == b for n, b in earlier.items())
    assert _tmp_files(out) == []


STUCK = '''
import itertools
import forceclosure.datasets.one_object as d

_original = d._synthesize


def _stuck(obj, job):
    """'stuck.obj' never returns: a sum over 10^13 ones, in C, holding the GIL and running
    no signal handler until it ends (hours), as a long call into compiled code does."""
    if obj.name == "stuck":
        sum(itertools.repeat(1, 10**13))
    return _original(obj, job)


d._synthesize = _stuck
'''


@pytest.mark.long
def test_worker_stuck_in_compiled_code(tmp_path):
    """A worker in a long C call that runs no signal handler (as in compiled code) is killed
    at the time limit and its object recorded as 'timeout' with the reason; the others
    complete."""
    env = _hooked(tmp_path)
    inputs = [str(tmp_path / "stuck.obj"), *map(str, _urdfs(3))]
    # (without the kill, the run would wait for the stuck worker for hours; a limit of 20 s
    # leaves the others, on a loaded machine beside a worker spinning on one core, time to
    # finish: 5 s did not, once)
    done = subprocess.run([*CLI, *inputs, "--out", str(tmp_path / "out"), *HARD_ARGS,
                           "--workers", "2", "--timeout", "20", "--json"], env=env,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 2, done.stderr
    summary = json.loads(done.stdout)
    assert (summary["done"], summary["timeout"]) == (3, 1)
    stuck = next(r for r in _records(tmp_path / "out").values() if r["name"] == "stuck")
    assert stuck["status"] == "timeout"
    assert stuck["error"] == ("stuck.obj: over the time limit of 20 s (its worker did not "
                              "stop, and was killed)")
    assert "forceclosure: timeout: stuck.obj: over the time limit" in done.stderr


@pytest.mark.long
def test_stopped_worker(tmp_path, monkeypatch):
    """Both workers stopped (SIGSTOP) once an object is done: the watchdog kills each after a
    second, the pool starts others, the objects they held are run again, and every object
    ends with its correct record.

    Objects of about half a second each, so that six or more are still to do when both
    workers stop, and the run cannot end without the watchdog (CI at stop 35, and a fresh
    clone's CI here: with objects of 0.1 s, the run could end before a loaded machine's stop
    came). Not before an
    object is done: workers that all die while starting break the pool (pebble:
    "BrokenProcessPool: All workers expired")."""
    monkeypatch.setattr(pool, "STALL_SECONDS", 1.0)
    job = Job(fingers=3, contact="hard", mu=0.5, top=1, samples=20_000)
    out = tmp_path / "out"
    me = psutil.Process()
    stopped: list[int] = []
    lines: list[str] = []

    def forked() -> list[psutil.Process]:
        """The fork server's children: pool workers."""
        try:
            return [w for p in me.children() if "forkserver" in " ".join(p.cmdline())
                    for w in p.children()]
        except psutil.Error:  # one ended while being looked at: look again
            return []

    earlier = {w.pid for w in forked()}  # an earlier test's, should one linger

    def workers() -> list[psutil.Process]:
        """This run's pool workers (not by their start times: psutil's are rounded to the
        boot time's whole second)."""
        return [w for w in forked() if w.pid not in earlier]

    def stop_all() -> None:
        _wait_for(lambda: len(list((out / "objects").glob("*.json"))) >= 1
                  and len(workers()) >= 2)
        for worker in workers():
            with suppress(psutil.NoSuchProcess):
                worker.send_signal(signal.SIGSTOP)
                stopped.append(worker.pid)

    thread = threading.Thread(target=stop_all, daemon=True)
    thread.start()
    summary = run_dataset(_urdfs(8), out, job, workers=2, progress=False, log=lines.append)
    thread.join(timeout=30)
    assert len(stopped) == 2 and not any(psutil.pid_exists(pid) for pid in stopped)
    assert (summary.done, summary.computed) == (8, 8)
    for pid in stopped:
        assert f"forceclosure: warning: worker {pid} stopped for 1 s" in "\n".join(lines)
    assert {n: _strip(r) for n, r in _records(out).items()} == _truth(_urdfs(8), job)


def test_names_cannot_forge_log_lines(tmp_path, capsys):
    """A file named with a newline and an ANSI escape: its failure is one plain line."""
    evil = tmp_path / "a\nforceclosure: done: all fine \x1b[32m.stl"
    evil.write_bytes(b"solid nothing\n garbage \x00\n")
    assert main(["dataset", str(evil), "cube", "--out", str(tmp_path / "out"), *SOFT_ARGS,
                 "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert "\x1b" not in err and err.count("\n") == 1
    assert err.startswith("forceclosure: failed: a\\nforceclosure: done: all fine \\x1b[32m.stl")
