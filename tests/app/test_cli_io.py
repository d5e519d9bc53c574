"""`forceclosure analyze`: nothing computed is lost, one bad input never spoils the rest.

Verdicts are checked against the closed form of planar pinches (Corollary 3:
two hard fingers at (-1, 0) and (1, y), normals along x, are force-closure iff
|y| / 2 < mu), files against their bytes, and outputs against what a strict
JSON reader and a UTF-8 terminal accept.
"""

import errno
import fcntl
import json
import os
import pty
import re
import signal
import struct
import subprocess
import sys
import termios
import time
import tracemalloc

import numpy as np
import pytest
from test_cli import _pinches

from forceclosure.app.cli import main

PINCH = {"contacts": [{"point": [-1, 0], "normal": [-1, 0], "mu": 0.3},
                      {"point": [1, 0], "normal": [1, 0], "mu": 0.3}]}
EPSILON_PINCH = 0.3 / np.sqrt(0.3 ** 2 + 2)  # head-on planar pinch, L1 epsilon (docs/analysis.md)


def _strict_json(text):
    """JSON as the standard has it: NaN and Infinity are not JSON."""
    def refuse(constant):
        raise AssertionError(f"{constant} in JSON output")
    return json.loads(text, parse_constant=refuse)


def _write_pinches(path, n, seed=4):
    P, N, mu, closed = _pinches(n, np.random.default_rng(seed))
    np.savez(path, points=P, normals=N, mu=mu)
    return np.where(closed, 2, 0)


# ---------------------------------------------------------------- JSON grasp files

def _three(tmp_path, middle, text=None):
    path = tmp_path / "g.json"
    path.write_text(text or json.dumps({"grasps": [PINCH, middle, PINCH]}))
    return str(path)


@pytest.mark.parametrize("flags", [[], ["--no-quality"]])
def test_an_overflowing_grasp_between_good_ones_is_reported_by_number(tmp_path, capsys, flags):
    bad = {"contacts": [{"point": [1e308, 0], "normal": [-1, 0], "mu": 0.3},
                        PINCH["contacts"][1]]}
    path = _three(tmp_path, bad)
    assert main(["analyze", path, *flags]) == 2
    out, err = capsys.readouterr()
    assert [line.split(":")[0] for line in out.splitlines() if line.startswith("grasp")] == [
        "grasp 1", "grasp 3"]
    assert err.count("\n") == 1 and err.startswith("forceclosure: error: grasp 2: contact 1: "
                                                   "field 'point' is too large")
    assert main(["analyze", path, "--json", *flags]) == 2
    results = _strict_json(capsys.readouterr().out)["results"]
    assert [r.get("verdict") for r in results] == ["closure", None, "closure"]
    assert results[1]["error"].startswith("grasp 2: contact 1")


def test_no_quality_says_so_instead_of_no_friction_closes_it(tmp_path, capsys):
    path = _three(tmp_path, PINCH)
    assert main(["analyze", path, "--no-quality"]) == 0
    out = capsys.readouterr().out
    assert "no friction coefficient closes it" not in out
    assert out.count("epsilon and least friction not computed (--no-quality)") == 3
    assert main(["analyze", path]) == 0  # with quality: the head-on pinch's closed forms
    assert out.count("closure: rank 3") == 3
    assert capsys.readouterr().out.count(f"epsilon {EPSILON_PINCH:.3g}") == 3
    assert main(["analyze", path, "--json", "--no-quality"]) == 0
    record = _strict_json(capsys.readouterr().out)["results"][0]
    assert record["verdict"] == "closure" and record["least_friction"] is None
    assert record["null_reasons"] == {"epsilon": "not computed (--no-quality)",
                                      "least_friction": "not computed (--no-quality)"}


@pytest.mark.parametrize("digits, message", [(400, "beyond the largest float"),
                                             (5000, "beyond the largest float")])
def test_huge_integers_are_a_grasp_error_not_an_internal_one(tmp_path, capsys, digits, message):
    text = json.dumps({"grasps": [PINCH, PINCH, PINCH]})
    text = text.replace('"mu": 0.3}', '"mu": 1' + "0" * digits + "}", 1)
    path = _three(tmp_path, None, text)
    assert main(["analyze", path, "--json"]) == 2
    captured = capsys.readouterr()
    results = _strict_json(captured.out)["results"]
    assert [r.get("verdict") for r in results] == [None, "closure", "closure"]
    assert captured.err.count("\n") == 1 and "grasp 1: contact 1: field 'mu'" in captured.err
    assert message in captured.err and len(captured.err) < 300


def _utf8_run(argv):
    """Run the command with standard output and error encoded as a terminal's, strict UTF-8."""
    proc = subprocess.run([sys.executable, "-m", "forceclosure", *argv], capture_output=True,
                          env={**os.environ, "PYTHONIOENCODING": "utf-8:strict"})
    return proc.returncode, proc.stdout.decode("utf-8"), proc.stderr.decode("utf-8")


def test_names_with_surrogates_newlines_and_ansi_escapes_are_escaped(tmp_path):
    names = ["\ud800", "evil\nforceclosure: error: forged", "\x1b[31mred\x1b[0m"]
    path = tmp_path / "g.json"
    path.write_text(json.dumps({"grasps": [dict(PINCH, name=n) for n in names]
                                + [{"name": "\x1b[2J", "contacts": []}]}))
    status, out, err = _utf8_run(["analyze", str(path)])
    assert status == 2, err
    assert "\x1b" not in out + err and "\ud800" not in out
    labels = [line for line in out.splitlines() if line.startswith("grasp")]
    assert labels[0].startswith('grasp 1 ("\\ud800"): closure')
    assert labels[1].startswith('grasp 2 ("evil\\nforceclosure: error: forged"): closure')
    assert labels[2].startswith('grasp 3 ("\\x1b[31mred\\x1b[0m"): closure')
    assert err.splitlines() == ['forceclosure: error: grasp 4 ("\\x1b[2J"): field \'contacts\' '
                                "must be a non-empty list"]
    status, out, _ = _utf8_run(["analyze", str(path), "--json"])
    assert [r.get("name") for r in _strict_json(out)["results"]] == [*names, "\x1b[2J"]


def test_error_lines_show_a_readable_part_of_a_huge_value(tmp_path, capsys):
    huge = {"contacts": [{"point": list(range(100_000)), "normal": [1, 0]}],
            "name": "n" * 10_000}
    path = _three(tmp_path, huge)
    assert main(["analyze", path]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and len(err) < 500
    assert "field 'point' must be a list of 2 or 3 numbers, got [0, 1, 2" in err
    assert "(688,890 characters)" in err  # len(json.dumps(list(range(100_000))))


# ---------------------------------------------------------------- what is read

def test_fifos_devices_and_symlink_loops_are_refused_in_one_line(tmp_path, capsys):
    fifo = tmp_path / "g.json"
    os.mkfifo(fifo)
    loop = tmp_path / "loop.json"
    loop.symlink_to(tmp_path / "loop2.json")
    (tmp_path / "loop2.json").symlink_to(loop)
    link = tmp_path / "zero.json"
    link.symlink_to("/dev/zero")
    for path, message in ((fifo, "is a FIFO"), (link, "is a device"),
                          ("/dev/urandom", "is a device"),
                          (loop, "Too many levels of symbolic links"),
                          (tmp_path / "npz-fifo.npz", "is a FIFO")):
        if str(path).endswith("npz-fifo.npz"):
            os.mkfifo(path)
        assert main(["analyze", str(path)]) == 2  # would block or read forever
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and message in err, err
    shape = tmp_path / "shape.json"  # inspect reads objects the same way
    os.mkfifo(shape)
    assert main(["inspect", str(shape)]) == 2
    assert "is a FIFO" in capsys.readouterr().err


def test_a_json_file_beyond_the_cap_is_refused_without_reading_it_all(tmp_path, capsys):
    from forceclosure.files.read import TEXT_CAP

    path = tmp_path / "big.json"
    with open(path, "wb") as f:  # sparse: 4 GiB of nothing, which would fill memory
        f.truncate(4 * 2**30)
    tracemalloc.start()  # a count, not a clock: the bytes held at the most
    try:
        assert main(["analyze", str(path)]) == 2
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert TEXT_CAP < peak < 2 * TEXT_CAP  # the cap and one byte read, no more
    assert f"larger than {TEXT_CAP // 2**20} MiB" in capsys.readouterr().err


def test_an_npz_claiming_more_grasps_than_its_bytes_is_refused_before_allocating(tmp_path):
    import io
    import zipfile

    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        header, {"descr": "<f8", "fortran_order": False, "shape": (300_000_000, 2, 2)})
    path = tmp_path / "claim.npz"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        for name in ("points", "normals"):
            archive.writestr(name + ".npy", header.getvalue() + bytes(64))
    assert path.stat().st_size < 1000
    status, _out, err = _utf8_run(["analyze", str(path)])
    assert status == 2 and err.count("\n") == 1
    assert "claim 300,000,000 grasps but the file holds at most 2\n" in err  # 64 / 32 bytes


# ---------------------------------------------------------------- --out

@pytest.fixture
def no_analysis(monkeypatch):
    """Fail if any grasp is analysed: the output must be checked before the work."""
    import forceclosure.io.grasp_arrays as ga

    def refuse(*args, **kwargs):
        raise AssertionError("analysed before the output was checked")
    monkeypatch.setattr(ga, "analyze_npz", refuse)


def test_bad_outputs_are_refused_before_any_work(tmp_path, capsys, no_analysis):
    grasps = tmp_path / "g.npz"
    _write_pinches(grasps, 10)
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    os.symlink(grasps, tmp_path / "alias.npz")
    for out, message in ((tmp_path / "missing" / "r.npz", "does not exist"),
                         ("/proc/r.npz", "cannot write in /proc"),  # a read-only folder
                         (grasps, "is the input file"),
                         (tmp_path / "." / "g.npz", "is the input file"),
                         (tmp_path / "alias.npz", "is the input file"),
                         ("/dev/null", "is a device"), (fifo, "is a FIFO"),
                         (tmp_path, "is a folder")):
        before = grasps.read_bytes()
        assert main(["analyze", str(grasps), "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and message in err, err
        assert grasps.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["alias.npz", "fifo", "g.npz"]


def test_out_is_written_to_exactly_the_name_given(tmp_path, capsys):
    grasps = tmp_path / "g.npz"
    expected = _write_pinches(grasps, 30)
    assert main(["analyze", str(grasps), "--out", str(tmp_path / "results")]) == 0
    assert "results in " + str(tmp_path / "results") in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.npz", "results"]
    saved = np.load(tmp_path / "results")
    np.testing.assert_array_equal(saved["verdict"], expected)
    assert int(saved["done"]) == 30 and not saved["partial"]


def test_a_full_disk_keeps_the_previous_results_and_leaves_no_temporary(tmp_path, capsys,
                                                                         monkeypatch):
    grasps = tmp_path / "g.npz"
    _write_pinches(grasps, 30)
    out = tmp_path / "r.npz"
    out.write_bytes(b"previous good results")
    write = np.lib.format.write_array

    def full_disk(fp, array, *args, **kwargs):
        write(fp, array[: len(array) // 2] if array.ndim else array, *args, **kwargs)
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(np.lib.format, "write_array", full_disk)
    assert main(["analyze", str(grasps), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "No space left on device" in err
    assert "previous file, if any, is unchanged" in err
    assert out.read_bytes() == b"previous good results"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["g.npz", "r.npz"]


def test_a_partial_file_of_another_input_is_not_overwritten(tmp_path, capsys):
    from forceclosure.io.grasp_arrays import NpzResults

    grasps = tmp_path / "g.npz"
    _write_pinches(grasps, 10)
    out = tmp_path / "r.npz"
    NpzResults(np.full(10, -1, np.int8), np.zeros(10, np.int8), np.full(10, np.nan), [],
               done=4, input="sha256:" + "0" * 64).save(str(out))
    before = out.read_bytes()
    assert main(["analyze", str(grasps), "--out", str(out)]) == 2
    assert "holds the partial results of another grasp file" in capsys.readouterr().err
    assert out.read_bytes() == before


# ---------------------------------------------------------------- real processes, real faults

def _read_until(fd, pattern):
    """Read a pseudo-terminal until ``pattern`` matches what came (the text read), or fail when
    the process closes the terminal first: events, no clock."""
    text = ""
    while True:
        try:
            chunk = os.read(fd, 4096)
        except OSError:  # the process closed the terminal
            chunk = b""
        if not chunk:
            raise AssertionError(f"no {pattern!r} in {text[-500:]!r}")
        text += chunk.decode("utf-8", "replace")
        if re.search(pattern, text):
            return text


def test_ctrl_c_saves_the_grasps_done_and_the_same_command_resumes(tmp_path):
    """SIGINT mid-run (seen on the progress bar, a terminal's): exit 130, a partial file
    with exactly the grasps done; the same command completes it, equal to the closed form
    and to an uninterrupted run."""
    n = 400_000
    grasps = tmp_path / "big.npz"
    expected = _write_pinches(grasps, n, seed=9)
    out = tmp_path / "r.npz"
    command = [sys.executable, "-m", "forceclosure", "analyze", str(grasps), "--out", str(out),
               "--chunk", "4000"]
    master, slave = pty.openpty()  # tqdm draws its bar on a terminal only, this one 120 wide
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 120, 0, 0))
    proc = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    try:
        # between 1 % and 39 %: the rest (0.6 s or more) outlasts the signal's way in
        _read_until(master, r"\b([1-9]|[1-3]\d)%\|")
        proc.send_signal(signal.SIGINT)
        tail = _read_until(master, r"run the same command again to resume")
        assert proc.wait() == 130
    finally:
        proc.kill()
        os.close(master)
    said = re.search(r"interrupted: ([\d,]+) of 400,000 grasps analysed, saved in", tail)
    assert said, tail
    partial = np.load(out)
    done = int(partial["done"])
    assert int(said.group(1).replace(",", "")) == done and 0 < done < n and partial["partial"]
    np.testing.assert_array_equal(partial["verdict"][:done], expected[:done])
    np.testing.assert_array_equal(partial["verdict"][done:], -1)
    assert [p.name for p in tmp_path.iterdir() if p.name.endswith(".tmp")] == []

    resumed = subprocess.run(command, capture_output=True, text=True)
    assert resumed.returncode == 0, resumed.stderr
    assert f"resumed: {done:,} grasps were analysed before" in resumed.stdout
    whole = tmp_path / "whole.npz"
    assert main(["analyze", str(grasps), "--out", str(whole), "--chunk", "4000"]) == 0
    final, reference = np.load(out), np.load(whole)
    np.testing.assert_array_equal(final["verdict"], expected)
    assert int(final["done"]) == n and not final["partial"]
    for key in ("verdict", "rank", "margin"):
        np.testing.assert_array_equal(final[key], reference[key])


SLOW_SAVE = """
import sys, time
import numpy as np
from forceclosure.io.grasp_arrays import NpzResults
write = np.lib.format.write_array
def slow(fp, array, *args, **kwargs):
    write(fp, array, *args, **kwargs)
    open(sys.argv[2], "w").close()  # half the file is written: kill me now
    while True:  # until killed: however long the test takes to send the signal
        time.sleep(1)
np.lib.format.write_array = slow
n = 1000
NpzResults(np.zeros(n, np.int8), np.zeros(n, np.int8), np.zeros(n), []).save(sys.argv[1])
"""


def test_sigkill_during_the_save_leaves_the_previous_results_intact(tmp_path):
    from forceclosure.io.grasp_arrays import NpzResults, load_results

    out = tmp_path / "r.npz"
    good = NpzResults(np.full(5, 2, np.int8), np.full(5, 3, np.int8), np.ones(5), [])
    good.save(str(out))
    before = out.read_bytes()
    ready = tmp_path / "writing"
    proc = subprocess.Popen([sys.executable, "-c", SLOW_SAVE, str(out), str(ready)])
    try:
        while not ready.exists():  # the event: half written; or the writer died first
            assert proc.poll() is None
            time.sleep(0.05)
        proc.send_signal(signal.SIGKILL)
        assert proc.wait() == -signal.SIGKILL
    finally:
        proc.kill()
    assert out.read_bytes() == before
    assert load_results(str(out)).code.tolist() == [2] * 5
    # what a SIGKILL cannot clean: one hidden temporary, never the target
    assert [p.name.startswith(".r.npz.") for p in tmp_path.iterdir() if p.suffix == ".tmp"] == [
        True]


def test_resuming_keeps_the_bad_rows_and_refuses_other_options(tmp_path, capsys, monkeypatch):
    """Ctrl-C (in this process: raised from the third chunk's analysis) with --epsilon; a
    re-run without --epsilon is refused, the same command resumes and counts the bad rows
    it did not analyse again."""
    import forceclosure.io.grasp_arrays as ga

    P, N, mu, closed = _pinches(100, np.random.default_rng(11))
    N[5, 0] = 0.0  # bad rows: one before the interruption, one after
    P[80, 1, 1] = np.nan
    grasps = tmp_path / "g.npz"
    np.savez(grasps, points=P, normals=N, mu=mu)
    out = tmp_path / "r.npz"
    analyse, calls = ga._analyse_rows, []

    def interrupted_third(*args):
        calls.append(1)
        if len(calls) == 3:
            raise KeyboardInterrupt
        analyse(*args)
    monkeypatch.setattr(ga, "_analyse_rows", interrupted_third)
    command = ["analyze", str(grasps), "--out", str(out), "--chunk", "20", "--epsilon"]
    assert main(command) == 130
    assert "interrupted: 40 of 100 grasps analysed, saved in" in capsys.readouterr().err
    monkeypatch.setattr(ga, "_analyse_rows", analyse)
    assert main(command[:-1]) == 2  # without --epsilon
    assert "holds partial results computed with epsilon" in capsys.readouterr().err
    assert int(np.load(out)["done"]) == 40
    assert main(command) == 2
    captured = capsys.readouterr()
    assert captured.err.splitlines() == [
        "forceclosure: error: grasp 81, contact 2: 'point' has a non-finite coordinate",
        "forceclosure: error: 1 grasps with bad input among the 40 analysed before this run "
        "resumed (their verdict is -1 in the results)"]
    assert "resumed: 40 grasps were analysed before" in captured.out
    final = np.load(out)
    expected = np.where(closed, 2, 0)
    expected[[5, 80]] = -1
    np.testing.assert_array_equal(final["verdict"], expected)
    eps = final["epsilon"]  # positive exactly for the closed grasps, NaN for bad input
    assert np.all(eps[expected == 2] > 0) and np.all(eps[expected == 0] == 0)
    assert np.isnan(eps[[5, 80]]).all()


def test_inspect_refuses_coordinates_beyond_1e100_and_nan_geojson_in_one_line(tmp_path, capsys):
    import warnings

    far = tmp_path / "far.json"
    far.write_text("[[1e200, 0], [-0.5, 0.866], [-0.5, -0.866]]")
    nan = tmp_path / "nan.geojson"
    nan.write_text('{"type": "Polygon", "coordinates": [[[1, 0], [NaN, 0.8], [-0.5, -0.8], '
                   '[1, 0]]]}')
    for path, message in ((far, "vertex 1 is beyond 1e100 in magnitude"),
                          (nan, "vertex 2 is not finite")):
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a warning would be a second line on stderr
            assert main(["inspect", str(path)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and message in err, err
