"""Start-up loads only what a command needs (issue 18): `forceclosure --help`, `--version`
and `import forceclosure` load no numpy, scipy or numba; the public names still arrive on
first use. (Times are measured in benchmarks/bench_startup.py, not asserted here.)"""

from __future__ import annotations

import subprocess
import sys

import pytest

HEAVY = ("numpy", "scipy", "numba", "trimesh", "shapely", "matplotlib")

PROBE = """
import sys
{code}
heavy = sorted({{m.split('.')[0] for m in sys.modules}} & set({heavy!r}))
print('HEAVY:' + ','.join(heavy))
"""


def loaded_after(code: str) -> list[str]:
    out = subprocess.run([sys.executable, "-c", PROBE.format(code=code, heavy=HEAVY)],
                         capture_output=True, text=True, check=True).stdout
    line = next(x for x in out.splitlines() if x.startswith("HEAVY:"))
    return [m for m in line.removeprefix("HEAVY:").split(",") if m]


@pytest.mark.parametrize("argv", [["--help"], ["--version"], ["analyze", "--help"],
                                  ["synthesize", "--help"], ["dataset", "--help"],
                                  ["grasps", "--help"]])
def test_help_and_version_load_nothing_heavy(argv):
    code = ("from forceclosure.app.cli import main\n"
            f"try:\n    main({argv!r})\nexcept SystemExit as e:\n    assert e.code == 0")
    assert loaded_after(code) == []


def test_import_forceclosure_loads_names_on_first_use():
    assert loaded_after("import forceclosure") == []
    assert "numpy" in loaded_after("from forceclosure import analyze")
    import forceclosure

    assert set(forceclosure.__all__) <= set(dir(forceclosure))
    for name in forceclosure.__all__:
        assert getattr(forceclosure, name) is not None
    with pytest.raises(AttributeError, match="no attribute 'nonsense'"):
        forceclosure.nonsense  # noqa: B018


def test_warmup_compiles_every_kernel_with_a_line_each(capsys):
    from forceclosure.app.cli import main

    assert main(["warmup"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert [line.split(" ...")[0] for line in err if line.startswith("[")] == [
        "[1/5] verdicts, Theorem 1 (one grasp, and batches)", "[2/5] least friction",
        "[3/5] Ferrari-Canny epsilon", "[4/5] two-finger pairs, Corollary 3",
        "[5/5] parallel-jaw pads and labels"]
    assert err[-1].startswith("forceclosure: kernels ready in")


def test_compiling_is_announced_once_when_nothing_is_cached(tmp_path, caplog, monkeypatch):
    """A kernel whose numba cache index is missing on disk gets one warning per process;
    one whose index exists gets none."""
    from types import SimpleNamespace

    from forceclosure import kernels

    def kernel(index):
        return SimpleNamespace(_cache=SimpleNamespace(_cache_file=SimpleNamespace(
            _index_path=str(index))))

    (tmp_path / "cached.nbi").write_bytes(b"")
    monkeypatch.setattr(kernels, "_announced", False)
    kernels.announce_compiling(kernel(tmp_path / "cached.nbi"))
    assert not caplog.records
    kernels.announce_compiling(kernel(tmp_path / "cached.nbi"), kernel(tmp_path / "no.nbi"))
    kernels.announce_compiling(kernel(tmp_path / "no.nbi"))
    assert [r.getMessage().split(",")[0] for r in caplog.records] == [
        "forceclosure: warning: compiling the batch kernels for this machine"]


def test_single_grasps_take_the_reference_path_until_the_kernels_are_compiled(tmp_path, caplog,
                                                                             monkeypatch):
    """On a machine with nothing compiled, the first COMPILE_AFTER single-grasp calls of a
    process get their answer from the reference path at once; the next one compiles, with
    the notice. A compiled kernel is used from the first call."""
    from types import SimpleNamespace

    from forceclosure import kernels

    def kernel(index):
        return SimpleNamespace(_cache=SimpleNamespace(_cache_file=SimpleNamespace(
            _index_path=str(index))))

    (tmp_path / "cached.nbi").write_bytes(b"")
    monkeypatch.setattr(kernels, "_announced", False)
    monkeypatch.setattr(kernels, "_uncompiled_uses", 0)
    assert kernels.use_compiled(kernel(tmp_path / "cached.nbi"))
    missing = kernel(tmp_path / "no.nbi")
    assert not any(kernels.use_compiled(missing) for _ in range(kernels.COMPILE_AFTER))
    assert not caplog.records
    assert kernels.use_compiled(missing)
    assert [r.getMessage().split(",")[0] for r in caplog.records] == [
        "forceclosure: warning: compiling the batch kernels for this machine"]


def test_a_small_first_batch_takes_the_reference_path_until_the_kernel_is_compiled(monkeypatch):
    """On a machine where the batch kernel is not compiled, analyze_batch answers the first
    COMPILE_AFTER grasps of a process from the reference path (the same answers as
    engine="reference", and the kernel is not called); a batch past that budget runs the
    kernel. A compiled kernel is used from the first grasp."""
    import numpy as np

    from forceclosure import kernels
    from forceclosure.analysis.batch_analysis import analyze_batch
    from forceclosure.kernels import theorem1

    calls = []
    real = theorem1.closure_serial

    def spy(*args):
        calls.append(len(args[0]))
        return real(*args)

    rng = np.random.default_rng(0)
    p = rng.normal(size=(40, 3, 3))
    n = p + 0.2 * rng.normal(size=p.shape)
    want = analyze_batch(p, n, mu=0.5, engine="reference")
    monkeypatch.setattr(theorem1, "closure_serial", spy)
    monkeypatch.setattr(kernels, "COMPILE_AFTER", 100)
    monkeypatch.setattr(kernels, "_uncompiled_uses", 0)
    monkeypatch.setattr(kernels, "_announced", True)  # no notice in the test's output
    monkeypatch.setattr(kernels, "cached", lambda kernel: False)
    for _ in range(2):  # 80 grasps: within the budget
        got = analyze_batch(p, n, mu=0.5)
        assert not calls
        assert got.code.tolist() == want.code.tolist()
        assert got.rank.tolist() == want.rank.tolist()
        np.testing.assert_array_equal(got.margin, want.margin)
    assert len(set(want.code.tolist())) >= 2  # closed grasps and others
    got = analyze_batch(p, n, mu=0.5)  # 120: past it
    assert calls == [40]
    assert got.code.tolist() == want.code.tolist()
    monkeypatch.setattr(kernels, "cached", lambda kernel: True)
    monkeypatch.setattr(kernels, "_uncompiled_uses", 0)
    analyze_batch(p[:1], n[:1], mu=0.5)
    assert calls == [40, 1]
