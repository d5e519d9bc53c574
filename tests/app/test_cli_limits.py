"""Every option checked up front by its own name and range (app/limits.py).

Each bad command line is run in this process as the command runs: exit status
2 and exactly one line on standard error, naming the option. The object or
input named is a file that does not exist, so a refusal that came after any
work (reading the object) would name the missing file instead: the line names
the option only if the check came first.
"""

import contextlib
import io

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from forceclosure.app.cli import main
from forceclosure.app.limits import check_scheduler, memory_budget

MISSING = "/no/such/object.obj"
GRASPS = ["grasps", MISSING, "--width", "3"]
DATASET = ["dataset", MISSING, "--out"]

BAD = [
    (["--count", "1000000000000"], "--count"),  # 8 TiB of labels
    (["--count", "1" + "0" * 22], "--count"),  # was an OverflowError
    (["--count", "1e12"], "--count"),  # not a whole number: argparse's own line
    (["--robust", "--robust-samples", "100000000"], "--robust-samples"),
    (["--approaches", "100000000"], "--approaches"),
    (["--depths", "100000000"], "--depths"),
    (["--seed", "-1"], "--seed"),
    (["--seed", str(2**63)], "--seed"),
    (["--pad-radius", "1e300"], "--pad-radius"),
    (["--clearance", "1e300"], "--clearance"),
    (["--mu", "1e300"], "--mu"),
    (["--plot-top", "100000000000", "--plot", "p.png"], "--plot-top"),
    (["--task-mass", "1e300"], "--task-mass"),
    (["--out", "x.npz/"], "--out"),
    (["--out", ""], "--out"),
    (["--out", "-"], "--out"),
    (["--plot", "-"], "--plot"),
    (["--html", "v.html/"], "--html"),
    (["--export", "graspnet", ""], "--export graspnet"),
]


def run(argv, capsys):
    status = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    return status, err


@pytest.mark.parametrize(("extra", "flag"), BAD, ids=[" ".join(a)[:40] for a, _ in BAD])
def test_grasps_options_refused_up_front(extra, flag, capsys):
    try:
        status, err = run([*GRASPS, *extra], capsys)
    except SystemExit as e:  # argparse's own refusal of a malformed number
        status, err = e.code, capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1, err
    assert flag in err[0] and "object.obj" not in err[0] and "Traceback" not in err[0], err


@pytest.mark.parametrize("width", ["1e300", "1e-300"])
def test_width_is_named_not_an_internal_field(width, capsys):
    status, err = run(["grasps", MISSING, "--width", width], capsys)
    assert status == 2 and len(err) == 1
    assert err[0].startswith("forceclosure: error: --width must be at ")
    assert "finger_length" not in err[0]


@pytest.mark.parametrize(("argv", "flag"), [
    ([*DATASET, "o", "--scheduler", "garbage"], "--scheduler"),
    ([*DATASET, "o", "--scheduler", "foo://x"], "--scheduler"),
    ([*DATASET, "o", "--scheduler", "tcp://host:99999"], "--scheduler"),
    ([*DATASET, "", "--contact", "soft"], "--out"),
    ([*DATASET, "-"], "--out"),
    ([*DATASET, "o", "--seed", "-1"], "--seed"),
    ([*DATASET, "o", "--gripper", "panda", "--mu", "0.5", "--count", str(10**13)], "--count"),
    (["synthesize", MISSING, "--samples", str(10**11)], "--samples"),
    (["synthesize", MISSING, "--top", str(10**12)], "--top"),
    (["synthesize", MISSING, "--seed", "-5"], "--seed"),
    (["synthesize", MISSING, "--plot", ""], "--plot"),
    (["analyze", "/no/such/g.npz", "--chunk", str(10**14)], "--chunk"),
    (["analyze", "/no/such/g.npz", "--out", "r.npz/"], "--out"),
    (["export", "/no/such/labels.npz", "--graspnet", "-"], "--graspnet"),
])
def test_other_commands_refused_up_front(argv, flag, capsys):
    status, err = run(argv, capsys)
    assert status == 2 and len(err) == 1, err
    assert flag in err[0] and "no/such" not in err[0], err


def test_memory_estimate_states_the_budget(capsys):
    """The refusal says how much the labels would take and what this run may use."""
    count = memory_budget() // 4096 + 1  # one grasp past the budget at 4 KiB a grasp
    status, err = run([*GRASPS, "--count", str(count)], capsys)
    assert status == 2 and "KiB a grasp" in err[0] and "may use" in err[0]
    status, err = run([*GRASPS, "--count", str(count - 2)], capsys)
    assert status == 2 and "object.obj" in err[0]  # within it: on to reading the object


@pytest.mark.parametrize("address", ["tcp://127.0.0.1:8786", "10.0.0.2:8786",
                                     "tls://[::1]:8786", "inproc://abc"])
def test_scheduler_addresses_accepted(address):
    check_scheduler(address)


def test_limits_accept_the_edges(tmp_path, capsys):
    """The largest seed is accepted: the grasps run (5 on the bundled cube), the labels are
    saved."""
    out = tmp_path / "r.npz"
    argv = ["grasps", "cube", "--width", "3", "--count", "5", "--seed", str(2**63 - 1),
            "--no-epsilon", "--no-collision", "--out", str(out), "--json"]
    assert main(argv) == 0, capsys.readouterr().err
    assert out.is_file()


# -- a light fuzz of every numeric option: one line, exit 2, never an internal error --------

NUMBERS = st.sampled_from(["0", "-0", "-1", "1", "1e-320", "1e-300", "1e300", "1e308", "nan",
                           "inf", "-inf", "1" + "0" * 30, "-" + "9" * 25, "2.5", "0x10", ""])
GRASPS_OPTIONS = ["--width", "--count", "--mu", "--pad-radius", "--seed", "--clearance",
                  "--approaches", "--depths", "--tilt", "--plot-top", "--robust-samples",
                  "--pose-sigma", "--angle-sigma", "--mu-sigma", "--normal-sigma",
                  "--robust-confidence", "--task-mass", "--f-max"]


@settings(max_examples=150, deadline=None, derandomize=True,
          suppress_health_check=list(HealthCheck))
@given(st.lists(st.tuples(st.sampled_from(GRASPS_OPTIONS), NUMBERS), min_size=1, max_size=4),
       st.booleans())
def test_grasps_option_fuzz(options, robust):
    """The object does not exist, so every run ends with exit 2: from an option's own check
    (named), argparse's, or the missing file; never an internal error, never two lines."""
    argv = ["grasps", MISSING] + (["--robust"] if robust else [])
    for flag, value in options:
        argv += [f"{flag}={value}"]
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            status = main(argv)
        except SystemExit as e:
            status = e.code
    lines = err.getvalue().strip().splitlines()
    assert status == 2 and len(lines) == 1, (argv, lines)
    assert "internal error" not in lines[0] and "Traceback" not in lines[0], lines


def test_library_output_check_refuses_a_folder_spelling(tmp_path):
    """files.atomic.check_output (every results file of the library): 'x.npz/' was taken as
    x.npz (abspath drops the slash) and failed only at the rename, after the work."""
    from forceclosure.errors import OutputError
    from forceclosure.files.atomic import check_output

    for path in (str(tmp_path / "x.npz") + "/", ""):
        with pytest.raises(OutputError):
            check_output(path)
    assert check_output(str(tmp_path / "x.npz")) == str(tmp_path / "x.npz")


def test_export_folder_with_a_slash_passes_the_spelling_check(tmp_path, capsys):
    """export writes a dataset's poses into a folder: 'out/' is a folder's spelling there,
    so the line that answers is about the missing labels, not the slash."""
    status, err = run(["export", str(tmp_path / "none"), "--graspnet", str(tmp_path) + "/"],
                      capsys)
    assert status == 2 and len(err) == 1 and "ends with '/'" not in err[0], err
