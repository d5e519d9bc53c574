"""The batch benchmark stays runnable by a new user (its smoke mode, small sizes)."""

import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).parents[1] / "benchmarks" / "bench_batch.py"


@pytest.mark.long
def test_batch_benchmark_runs(tmp_path):
    png = tmp_path / "bench.png"
    run = subprocess.run([sys.executable, str(BENCH), "--quick", "--plot", str(png)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    out = run.stdout
    assert "planar pairs, Corollary 3" in out and "linprog" in out
    assert "streamed 200,000 grasps" in out
    assert png.stat().st_size > 10_000


@pytest.mark.long
def test_gripper_benchmark_runs():
    """The labelling benchmark against GraspNet's and Dex-Net's labellers, on a few poses."""
    pytest.importorskip("cvxopt")
    bench = Path(__file__).parents[1] / "benchmarks" / "bench_gripper.py"
    run = subprocess.run([sys.executable, str(bench), "--poses", "300", "--baseline", "20"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "bunny.obj" in run.stdout and "GraspNet" in run.stdout
    assert "ferrari_canny_L1" in run.stdout and "closes every pair GraspNet's passes: True" \
        in run.stdout


@pytest.mark.long
def test_calls_benchmark_runs():
    """The benchmark of the calls a person makes (issue 26), on a few grasps: every row is
    printed, and the vectorised NumPy baseline agrees with the pairs' verdicts."""
    bench = Path(__file__).parents[1] / "benchmarks" / "bench_calls.py"
    run = subprocess.run([sys.executable, str(bench), "--grasps", "3", "--repeats", "1"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    out = run.stdout
    for row in ("`analyze()`", "HiGHS reused", "`least_friction()`, 2 soft fingers",
                "`epsilon()`", "| 1,000,000 | its kernel alone", "public / kernel (CPU)"):
        assert row in out
    assert "disagrees" not in out and "load average after" in out


@pytest.mark.long
def test_robust_benchmark_runs():
    """The robust-labels benchmark on a few poses: both objects, CPU time and load printed."""
    bench = Path(__file__).parents[1] / "benchmarks" / "bench_robust.py"
    run = subprocess.run([sys.executable, str(bench), "--grasps", "10", "--samples", "4"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    for text in ("duck_vhacd.urdf (panda", "bunny.obj", "per CPU-second", "load ",
                 "pad_contacts", "pair_codes"):
        assert text in run.stdout


@pytest.mark.long
def test_adversarial_benchmark_runs():
    """The adversarial benchmark on two placements of each case, truths checked exactly: every
    row printed, ours without a wrong closure (it exits 1 and names the case otherwise)."""
    pytest.importorskip("cvxopt")
    bench = Path(__file__).parents[1] / "benchmarks" / "bench_adversarial.py"
    run = subprocess.run([sys.executable, str(bench), "--copies", "2", "--check"],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:] + run.stdout[-2000:]
    out = run.stdout
    assert "every truth checked exactly" in out and "load average after" in out
    for row in ("| ours: `analyze` (one at a time) | 76 | **0** |",
                "| ours: `analyze_batch` | 76 | **0** |",
                "| ours: `two_finger_closure` | 44 | **0** |", "Dex-Net QP", "GraspIt!-style",
                "Qhull with joggle", "Dex-Net pair", "GraspNet pair"):
        assert row in out
    assert "WRONG CLOSURE OF OURS" not in out


def _regenerate():
    import importlib.util

    path = Path(__file__).parents[1] / "benchmarks" / "regenerate.py"
    spec = importlib.util.spec_from_file_location("regenerate", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_table_of_the_benchmarks_page_has_its_script():
    """Each table marker of docs/benchmarks.md names a script regenerate.py runs (or the
    gripper's, written by hand), so no table there is left without a command."""
    regenerate = _regenerate()
    page = (Path(__file__).parents[1] / "docs" / "benchmarks.md").read_text()
    names = [m["name"] for m in regenerate.BLOCK.finditer(page)]
    assert "targets" in names and "calls.pairs" in names
    for name in names:
        assert name.split(".")[0] in regenerate.SCRIPTS, name
        assert (BENCH.parent / f"bench_{name.split('.')[0]}.py").exists()


def test_regenerate_replaces_tables_and_refuses_stale_or_unknown_ones():
    regenerate = _regenerate()
    page = ("intro\n<!-- table: calls.single -->\n| old | 1 s |\n<!-- /table -->\nmiddle\n"
            "<!-- table: calls.pairs -->\n| old |\n<!-- /table -->\n"
            "<!-- table: calling -->\n| kept |\n<!-- /table -->\n")
    new = regenerate.replace(page, "calls", {"calls.single": "| new |", "calls.pairs": "| p |"},
                             "*stamp*")
    assert "old" not in new and "| kept |" in new and new.count("*stamp*") == 2
    assert new.startswith("intro\n") and "middle\n" in new
    with pytest.raises(regenerate.RegenerateError, match=r"no longer prints.*calls\.pairs"):
        regenerate.replace(page, "calls", {"calls.single": "| new |"}, "*stamp*")
    with pytest.raises(regenerate.RegenerateError, match=r"no marker.*calls\.extra"):
        regenerate.replace(page, "calls", {"calls.single": "x", "calls.pairs": "y",
                                           "calls.extra": "z"}, "*stamp*")


@pytest.mark.long
@pytest.mark.parametrize("script", list(_regenerate().SCRIPTS))  # one each: the workers share
def test_regenerate_quick_rewrites_every_table(tmp_path, script):
    """``regenerate.py --quick`` runs every script at small sizes and stamps every table it
    owns: no table of the page keeps its old rows."""
    regenerate = _regenerate()
    page = tmp_path / "benchmarks.md"
    original = (Path(__file__).parents[1] / "docs" / "benchmarks.md").read_text()
    page.write_text(original)
    run = subprocess.run([sys.executable, str(BENCH.parent / "regenerate.py"), "--quick",
                          "--only", script, "--docs", str(page)], capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-2000:]
    blocks = [b for b in regenerate.BLOCK.finditer(page.read_text())
              if b["name"].split(".")[0] == script]
    assert blocks, script
    for block in blocks:
        assert "(--quick)" in block[0] and "load average" in block[0], block["name"]
        assert block[0].count("\n|") >= 3, block["name"]  # header, rule, a row at least
