"""Datasets: the input set, one record per object whatever happens (killed runs, killed
workers, bad files, time limits), Parquet that pandas reads, and a real local Dask cluster."""

from __future__ import annotations

import json
import os
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
from forceclosure.datasets import (
    Job,
    ObjectTimeout,
    deadline,
    expand_inputs,
    process_object,
    record_name,
    run_dataset,
)
from forceclosure.errors import InputError
from forceclosure.objects.io import load_object

URDFS = Path(pybullet_data.getDataPath()) / "random_urdfs"
JOB = Job(fingers=3, contact="hard", mu=0.5, top=1, samples=1000)
#: Fields that say where and how fast, not what: they differ between runs.
RUN_FIELDS = ("seconds", "load_seconds", "worker")


def _objects(count: int) -> list[Path]:
    return [URDFS / f"{i:03d}" / f"{i:03d}.urdf" for i in range(count)]


@pytest.fixture(scope="module")
def corrupt(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("bad") / "corrupt.stl"
    path.write_bytes(b"solid nothing\n  facet normal 0 0 1\n  garbage \x00\x01\x02\n")
    return path


@pytest.fixture(scope="module")
def reference(tmp_path_factory, corrupt):
    """The single-process run of 24 objects and a corrupt file: the ground truth."""
    out = tmp_path_factory.mktemp("single")
    summary = run_dataset([*map(str, _objects(24)), str(corrupt)], out, JOB, workers=1,
                          progress=False, log=lambda line: None)
    return out, summary


def _records(out: Path) -> dict[str, dict]:
    records = {}
    for f in (out / "objects").glob("*.json"):
        record = json.loads(f.read_text())
        records[f.name] = {k: v for k, v in record.items() if k not in RUN_FIELDS}
    return records


def test_inputs_folders_globs_and_urdfs(tmp_path):
    found = expand_inputs([URDFS])
    assert len(found) == 1000 and all(p.suffix == ".urdf" for p in found)  # not their .obj
    assert expand_inputs([str(URDFS / "00[0-4]" / "*.obj")]) == [
        URDFS / f"00{i}" / f"00{i}.obj" for i in range(5)]
    (tmp_path / "a.grasps.json").write_text("{}")
    (tmp_path / "notes.txt").write_text("")
    (tmp_path / "sq.json").write_text("[[0, 0], [1, 0], [1, 1], [0, 1]]")
    assert expand_inputs(["cube", tmp_path, tmp_path / "sq.json"]) == [tmp_path / "sq.json",
                                                                       Path("cube")]
    with pytest.raises(InputError, match="no files match"):
        expand_inputs([tmp_path / "*.stl"])


def test_a_urdf_stands_for_every_mesh_it_names(tmp_path):
    """A link of two collision meshes and a visual one: the folder gives the URDF alone (the
    old listing left out only the first collision mesh, so the others ran as objects)."""
    cube = Path(pybullet_data.getDataPath()) / "cube.obj"
    for name in ("a.obj", "b.obj", "look.obj", "other.obj"):
        (tmp_path / name).write_bytes(cube.read_bytes())
    (tmp_path / "r.urdf").write_text(
        '<robot name="r"><link name="l">'
        '<visual><geometry><mesh filename="look.obj"/></geometry></visual>'
        '<collision><geometry><mesh filename="a.obj"/></geometry></collision>'
        '<collision><origin xyz="3 0 0"/><geometry><mesh filename="package://r/b.obj"/>'
        '</geometry></collision></link></robot>')
    assert expand_inputs([tmp_path]) == [tmp_path / "other.obj", tmp_path / "r.urdf"]


def test_urdf_scale():
    """A URDF stands for its collision mesh with the scale it gives (0.015 here)."""
    urdf = load_object(URDFS / "000" / "000.urdf")
    mesh = load_object(URDFS / "000" / "000.obj")
    assert urdf.size == pytest.approx(0.015 * mesh.size, rel=1e-12)
    assert np.allclose(urdf.vertices, 0.015 * mesh.vertices)


def test_single_process_run(reference, corrupt):
    out, summary = reference
    assert (summary.objects, summary.done, summary.failed, summary.computed) == (25, 24, 1, 25)
    table = pd.read_parquet(out / "results.parquet")
    assert len(table) == 25 and table["path"].is_unique
    bad = table[table["status"] == "failed"]
    assert list(bad["name"]) == ["corrupt"]
    error = bad["error"].iloc[0]
    assert error.startswith("corrupt.stl: ") and "\n" not in error
    good = table[table["status"] == "done"]
    assert good["all_certified"].all() and (good["grasps"] == 1).all()
    assert (good["best_min_region"] > 0).all() and (good["kind"] == "polyhedron").all()
    # the table is the records, flattened
    record = json.loads((out / "objects" / record_name(_objects(1)[0])).read_text())
    row = table[table["path"] == record["path"]].iloc[0]
    assert row["best_min_region"] == record["grasps"][0]["min_area"]
    assert list(row["best_region_sizes"]) == record["grasps"][0]["areas"]
    # every region set certified again here, from the record alone (sampling, exact cones)
    from forceclosure.analysis.batch import analyze_batch

    polyhedron = load_object(_objects(1)[0])
    rng = np.random.default_rng(0)
    for patches in record["grasps"][0]["regions"]:
        for patch in patches:
            corners = np.array(patch["polygon"])
            assert np.allclose(np.array([polyhedron.locate(c)[2] for c in corners]), 0,
                               atol=1e-9 * polyhedron.size)
    corners = [[(c, polyhedron.faces[p["face"]].normal) for p in patches for c in p["polygon"]]
               for patches in record["grasps"][0]["regions"]]  # each finger's region corners
    picks = [[c[i] for i in rng.integers(len(c), size=500)] for c in corners]
    P = np.stack([np.array([p for p, _ in pick]) for pick in picks], axis=1)
    N = np.stack([np.array([n for _, n in pick]) for pick in picks], axis=1)
    assert np.all(analyze_batch(P, N, mu=0.5, model="hard").code == 2)


def test_rerun_skips_everything(reference, corrupt):
    out, _ = reference
    before = _records(out)
    again = run_dataset([*map(str, _objects(24)), str(corrupt)], out, JOB, workers=1,
                        progress=False)
    assert (again.computed, again.skipped) == (0, 25)
    assert _records(out) == before
    # failed objects are computed again only when asked
    retry = run_dataset([*map(str, _objects(24)), str(corrupt)], out, JOB, workers=1,
                        progress=False, retry_failed=True, log=lambda line: None)
    assert (retry.computed, retry.failed) == (1, 1)
    with pytest.raises(InputError, match="another job"):
        run_dataset([str(corrupt)], out, Job(fingers=3, mu=0.4), workers=1)


@pytest.mark.long
def test_dask_cluster_with_a_worker_killed(reference, corrupt, tmp_path):
    """Two workers on a real LocalCluster; one is killed mid-run. The run completes, a
    re-run computes nothing, and every record equals the single-process one."""
    from distributed import Client, LocalCluster

    out = tmp_path / "dask"
    inputs = [*map(str, _objects(24)), str(corrupt)]
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        pids = list(client.run(os.getpid).values())
        killed = []

        def kill_one() -> None:
            while len(list((out / "objects").glob("*.json"))) < 5:
                time.sleep(0.05)
            os.kill(pids[0], signal.SIGKILL)
            killed.append(pids[0])

        killer = threading.Thread(target=kill_one, daemon=True)
        killer.start()
        summary = run_dataset(inputs, out, JOB, executor=client.get_executor(), workers=2,
                              progress=False, log=lambda line: None)
        killer.join(timeout=60)
        assert killed, "no worker was killed"
        assert pids[0] not in client.run(os.getpid).values()  # the nanny started another
        assert (summary.done, summary.failed) == (24, 1)
        again = run_dataset(inputs, out, JOB, executor=client.get_executor(),
                            progress=False)
        # the command on the same cluster, by its address
        cli_out = tmp_path / "cli"
        assert main(["dataset", *inputs[:3], "--out", str(cli_out), "--fingers", "3",
                     "--mu", "0.5", "--top", "1", "--samples", "1000", "--scheduler",
                     cluster.scheduler_address]) == 0
    assert again.computed == 0
    assert _records(out) == _records(reference[0])
    assert len(pd.read_parquet(out / "results.parquet")) == 25
    truth = _records(reference[0])
    assert _records(cli_out) == {k: truth[k] for k in _records(cli_out)}
    assert len(_records(cli_out)) == 3


@pytest.mark.long
def test_local_pool_with_a_worker_killed(reference, tmp_path):
    out = tmp_path / "pool"
    inputs = [*map(str, _objects(12))]
    me = psutil.Process()

    killed = []

    def kill_one() -> None:
        while len(list((out / "objects").glob("*.json"))) < 3:
            time.sleep(0.05)
        server = next(p for p in me.children() if "forkserver" in " ".join(p.cmdline()))
        worker = server.children()[0]  # the pool's workers are forked by the server
        worker.kill()
        killed.append(worker.pid)

    killer = threading.Thread(target=kill_one, daemon=True)
    killer.start()
    summary = run_dataset(inputs, out, JOB, workers=2, progress=False)
    killer.join(timeout=60)
    assert killed, "no worker was killed"
    assert (summary.done, summary.computed) == (12, 12)
    truth = _records(reference[0])
    assert _records(out) == {k: truth[k] for k in _records(out)}


@pytest.mark.long
def test_killed_run_resumes(reference, tmp_path):
    """The command killed mid-way (SIGKILL, with its pool) and run again: exactly one
    record per object, the same as the single-process run."""
    out = tmp_path / "killed"
    argv = [sys.executable, "-m", "forceclosure", "dataset", *map(str, _objects(12)),
            "--out", str(out), "--fingers", "3", "--contact", "hard", "--mu", "0.5",
            "--top", "1", "--samples", "1000", "--workers", "2"]
    run = subprocess.Popen(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                           start_new_session=True)
    deadline_ = time.monotonic() + 240
    while len(list((out / "objects").glob("*.json"))) < 3 and time.monotonic() < deadline_:
        time.sleep(0.05)
    os.killpg(run.pid, signal.SIGKILL)
    run.wait()
    partial = len(list((out / "objects").glob("*.json")))
    assert 3 <= partial < 12
    done = subprocess.run(argv, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert f"{12 - partial} in" in done.stdout and f"{partial} skipped" in done.stdout
    truth = _records(reference[0])
    assert _records(out) == {k: truth[k] for k in _records(out)}
    assert len(_records(out)) == 12


def test_a_time_limit_inside_compiled_code_is_a_timeout(monkeypatch):
    """The limit landing inside a numba dispatcher's own C code comes out as CPython's
    ``SystemError: ... returned a result with an exception set``, caused by the
    ObjectTimeout (seen on the pool with the compiled pad kernels): the record says
    'timeout', as for the limit anywhere else, not 'internal error'."""
    from forceclosure.datasets import one_object

    def compiled_call(obj, job):
        try:
            raise ObjectTimeout
        except ObjectTimeout as limit:
            raise SystemError("CPUDispatcher(<function line_pairs>) returned a result with "
                              "an exception set") from limit

    monkeypatch.setattr(one_object, "_synthesize", compiled_call)
    record = process_object("cube", Job(mu=0.5, top=1, timeout=60))
    assert record["status"] == "timeout" and "time limit of 60 s" in record["error"]
    monkeypatch.setattr(one_object, "_synthesize", lambda obj, job: 1 / 0)
    record = process_object("cube", Job(mu=0.5, top=1, timeout=60))
    assert record["status"] == "failed" and "internal error: ZeroDivisionError" in \
        record["error"]


def test_time_limit(tmp_path):
    """Over the limit: recorded as 'timeout', in the main thread (signal) and in another
    thread (as on a Dask worker); the run goes on. No clock decides the test: the work timed
    out is far beyond any limit (or never ends), the limits end blocks that would not."""
    from forceclosure.objects.io import load_object

    # loaded once first: the modules trimesh imports on first use are in, so the limit lands
    # in the computation (trimesh's import guards catch BaseException: a limit firing inside
    # one of those imports is swallowed, and the object runs to its end)
    load_object(_objects(1)[0])
    # (without a limit this object takes 0.6 s here: twelve times the limit)
    slow = Job(fingers=3, contact="hard", mu=0.5, top=1, samples=30_000, timeout=0.05)
    record = process_object(_objects(1)[0], slow)
    assert record["status"] == "timeout" and "0.05 s" in record["error"]
    assert record["seconds"] >= 0.05  # stopped by the limit, not before it
    box = []
    thread = threading.Thread(target=lambda: box.append(process_object(_objects(1)[0], slow)))
    thread.start()
    thread.join()
    assert box[0]["status"] == "timeout"
    with deadline(60):  # a block that ends in time is left alone, and so is what follows
        pass
    # no `except Exception` on the way (a file reader's, say) swallows the time limit
    with pytest.raises(ObjectTimeout), deadline(0.05), suppress(Exception):
        while True:  # ends by the limit alone
            time.sleep(0.01)
    escaped = []

    def busy() -> None:
        try:
            with deadline(0.05):
                while True:
                    with suppress(Exception):
                        sum(range(1000))
        except ObjectTimeout:
            escaped.append(True)

    worker = threading.Thread(target=busy)
    worker.start()
    worker.join()  # the busy loop ends by the limit alone
    assert escaped == [True]
    time.sleep(0.01)
    # a reader that swallows even BaseException (trimesh's optional imports do) once: the
    # limit comes again, in the main thread and in another
    def swallowing() -> None:
        with deadline(0.05):
            swallowed = False
            for _ in range(100_000):  # a limit that came only once would let this end
                try:
                    time.sleep(0.01)
                except BaseException:  # the reader this test stands for
                    if swallowed:
                        raise
                    swallowed = True

    with pytest.raises(ObjectTimeout):
        swallowing()
    escaped.clear()

    def in_thread() -> None:
        try:
            swallowing()
        except ObjectTimeout:
            escaped.append(True)

    worker = threading.Thread(target=in_thread)
    worker.start()
    worker.join()
    assert escaped == [True]
    # on the pool, with a limit: every object gets its record, done or over the limit (which
    # of the two is the clock's to say, not this test's: a worker stuck past its limit is the
    # long profile's test_worker_stuck_in_compiled_code), and a done one is complete
    summary = run_dataset([str(_objects(1)[0]), "cube"], tmp_path,
                          Job(contact="soft", mu=0.5, top=1, samples=200_000, timeout=0.5),
                          workers=1, progress=False, log=lambda line: None)
    records = {r["name"]: r for r in _records(tmp_path).values()}
    assert sorted(records) == ["000", "cube"] and summary.computed == 2
    assert summary.done + summary.timeout == 2 and summary.failed == 0
    for record in records.values():
        assert record["status"] in ("done", "timeout")
        assert (len(record["grasps"]) == 1) if record["status"] == "done" else (
            "over the time limit of 0.5 s" in record["error"])


@pytest.mark.parametrize("where", ["main", "thread"])
def test_a_limit_never_lands_inside_an_import(tmp_path, monkeypatch, where):
    """A limit that passes while a module is being imported comes right after the import,
    never inside it: the module is whole for the objects after it (numba imports its type
    modules on first use; one left half initialised failed every later object of its
    process with "partially initialized module 'numba.core.types'")."""
    name = f"slow_import_{where}"
    (tmp_path / f"{name}.py").write_text("import time\ntime.sleep(0.5)\nWHOLE = True\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, name, raising=False)
    outcome: list = []

    def run() -> None:
        try:
            with deadline(0.05):
                outcome.append(__import__(name).WHOLE)
                for _ in range(6000):  # ends by the limit (a minute at most, if it never came)
                    time.sleep(0.01)
        except ObjectTimeout:
            outcome.append("timeout")

    if where == "main":
        run()
    else:
        worker = threading.Thread(target=run, daemon=True)
        worker.start()
        worker.join(timeout=120)
    assert outcome == [True, "timeout"]
    assert sys.modules[name].WHOLE
    monkeypatch.delitem(sys.modules, name)


def test_analyze_mode(tmp_path):
    """Grasps given per object: two fingers on opposite sides of a square with mu 0.3 hold
    exactly when the line between them is within the cones, |y1 - y2| / 2 < 0.3."""
    (tmp_path / "square.json").write_text("[[-1, -1], [1, -1], [1, 1], [-1, 1]]")
    rng = np.random.default_rng(1)
    y = rng.uniform(-1, 1, (40, 2))
    y = y[np.abs(np.abs(y[:, 0] - y[:, 1]) / 2 - 0.3) > 1e-3]  # away from the boundary
    P = np.stack([np.column_stack([-np.ones(len(y)), y[:, 0]]),
                  np.column_stack([np.ones(len(y)), y[:, 1]])], axis=1)
    N = np.broadcast_to(np.array([[-1.0, 0.0], [1.0, 0.0]]), P.shape).copy()
    P[0, 0] = [-1.5, 0.0]  # one contact off the surface
    np.savez(tmp_path / "square.grasps.npz", points=P, normals=N, mu=0.3)
    summary = run_dataset([tmp_path / "square.json"], tmp_path / "out", Job(mode="analyze"),
                          workers=1, progress=False)
    assert summary.done == 1
    row = pd.read_parquet(tmp_path / "out" / "results.parquet").iloc[0]
    expected = np.abs(y[:, 0] - y[:, 1]) / 2 < 0.3
    assert row["closure"] == expected.sum() and row["none"] == (~expected).sum()
    assert row["off_surface"] == 1 and row["grasps"] == len(y)
    # a JSON grasp file: head-on (closure) and offset past the cones (none), and 3-D
    # contacts for a polygon, refused by name
    (tmp_path / "sq2.json").write_text("[[-1, -1], [1, -1], [1, 1], [-1, 1]]")
    pair = [{"contacts": [{"point": [-1, a], "normal": [-1, 0], "mu": 0.3},
                          {"point": [1, b], "normal": [1, 0], "mu": 0.3}]}
            for a, b in ((0.1, 0.2), (-0.5, 0.5))]
    (tmp_path / "sq2.grasps.json").write_text(json.dumps({"grasps": pair}))
    (tmp_path / "sq3.json").write_text("[[-1, -1], [1, -1], [1, 1], [-1, 1]]")
    flat = [{"contacts": [{"point": [-1, 0, 0], "normal": [-1, 0, 0]},
                          {"point": [1, 0, 0], "normal": [1, 0, 0]}]}]
    (tmp_path / "sq3.grasps.json").write_text(json.dumps({"grasps": flat}))
    run_dataset([tmp_path / "sq2.json", tmp_path / "sq3.json"], tmp_path / "json",
                Job(mode="analyze"), workers=1, progress=False, log=lambda line: None)
    table = pd.read_parquet(tmp_path / "json" / "results.parquet").set_index("name")
    assert table.loc["sq2", ["closure", "none", "off_surface"]].tolist() == [1, 1, 0]
    assert table.loc["sq3", "status"] == "failed"
    assert "grasp 1: 3-D contacts for a 2-D object" in table.loc["sq3", "error"]
    (tmp_path / "other.json").write_text("[[0, 0], [1, 0], [0, 1]]")
    missing = run_dataset([tmp_path / "other.json"], tmp_path / "out2", Job(mode="analyze"),
                          workers=1, progress=False, log=lambda line: None)
    assert missing.failed == 1


def test_cli(tmp_path, capsys, corrupt):
    out = tmp_path / "cli"
    assert main(["dataset", "cube", "hexagon", str(corrupt), "--out", str(out), "--contact",
                 "soft", "--mu", "0.5", "--top", "1", "--workers", "1", "--json"]) == 2
    captured = capsys.readouterr()
    summary = json.loads(captured.out)
    assert (summary["objects"], summary["done"], summary["failed"]) == (3, 2, 1)
    assert "forceclosure: failed: corrupt.stl: " in captured.err
    assert main(["dataset", "cube", "--out", str(tmp_path / "x"), "--fingers", "2"]) == 2
    assert "at least 3 hard fingers" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()  # refused before any work
    for argv, message in ((["--workers", "0"], "--workers must be at least 1"),
                          (["--timeout", "-1"], "--timeout must be a positive")):
        assert main(["dataset", "cube", "--out", str(tmp_path / "y"), *argv]) == 2
        assert message in capsys.readouterr().err


@pytest.mark.parametrize("urdf,message", [
    ("<robot><link/>", "not a URDF file"),
    ("<robot><link name='a'><inertial/></link></robot>",
     "no link has collision or visual geometry"),
    ("<robot><link><collision><geometry><mesh filename='gone.obj'/></geometry></collision>"
     "</link></robot>", "its mesh gone.obj is missing"),
    ("<robot><link><collision><geometry><mesh filename='m.obj' scale='1 -1 1'/></geometry>"
     "</collision></link></robot>", "is not three positive numbers"),
    ("<robot><link><collision><geometry><mesh filename='m.obj' scale='1 x 1'/></geometry>"
     "</collision></link></robot>", "is not three numbers"),
    ("<robot><link><collision><geometry><mesh filename='m.txt'/></geometry></collision>"
     "</link></robot>", "its mesh m.txt is not a mesh file"),
])
def test_bad_urdfs_one_line(tmp_path, capsys, urdf, message):
    (tmp_path / "m.obj").write_text((URDFS / "000" / "000.obj").read_text())
    (tmp_path / "m.txt").write_text("")
    (tmp_path / "r.urdf").write_text(urdf)
    assert main(["inspect", str(tmp_path / "r.urdf")]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_grasps_pattern_and_outer_alarm():
    with pytest.raises(InputError, match="placeholders"):
        Job(mode="analyze", grasps="{folder}/{stem}.npz")
    # an alarm set around a deadline (pytest-timeout's, say) survives it
    signal.setitimer(signal.ITIMER_REAL, 50)
    try:
        with deadline(100):  # longer than the outer one: what is left after it is the outer's
            pass
        remaining, _ = signal.getitimer(signal.ITIMER_REAL)
        assert 0 < remaining <= 50
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
