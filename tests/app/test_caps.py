"""Stated caps on the work one command asks (issue 28: bounded work).

A grasp has at most MAX_CONTACTS contacts; a spatial grasp's quality is computed for at most
MAX_QUALITY_CONTACTS contact points (beyond it the verdict comes alone, the quality's null
saying why); a hand in space has at most MAX_FINGERS fingers. Above the others: one line
naming the cap, exit status 2, before the long work. The verdicts asked
for within them are checked against hand-derived cases.
"""

import json

import numpy as np
import pytest

from forceclosure.analysis.batch import analyze_batch
from forceclosure.app.cli import main
from forceclosure.contacts import MAX_CONTACTS, MAX_QUALITY_CONTACTS, check_grasp, point_contact
from forceclosure.errors import InputError
from forceclosure.synthesis.best import MAX_FINGERS, check_hand

#: The six face centres of the unit cube with outward normals: hard fingers there with
#: mu 0.5 are force-closure (the normals sum to zero with equal weights, so a strictly
#: positive combination vanishes; the friction forces along z on the +-y faces give the
#: torques +-x, and likewise for the other axes: rank 6).
FACES = [([s * (i == a) for i in range(3)], [s * (i == a) for i in range(3)])
         for a in range(3) for s in (1, -1)]


def grasp_file(tmp_path, contacts, name="g.json"):
    path = tmp_path / name
    path.write_text(json.dumps({"grasps": [{"contacts": [
        {"point": p, "normal": n, "model": "hard", "mu": 0.5} for p, n in contacts]}]}))
    return path


def run(argv, capsys):
    status = main(argv)
    captured = capsys.readouterr()
    return status, captured.out, captured.err.strip().splitlines()


def test_300_spatial_contacts_verdict_given_quality_not_computed(tmp_path, capsys):
    """300 hard contacts (the six faces, 50 times each): the quality would run for minutes,
    so it is left out with its reason in null_reasons; the verdict is closure; 300 contacts
    all on one face are not (every force points the same way)."""
    path = grasp_file(tmp_path, FACES * 50)
    status, out, err = run(["analyze", str(path), "--json"], capsys)
    assert status == 0 and err == []
    record = json.loads(out)["results"][0]
    assert record["verdict"] == "closure"
    assert record["epsilon"] is None and record["least_friction"] is None
    assert record["null_reasons"]["epsilon"].startswith(
        f"not computed: more than {MAX_QUALITY_CONTACTS} spatial contact points")
    one_face = grasp_file(tmp_path, FACES[:1] * 300, "one.json")
    status, out, _ = run(["analyze", str(one_face), "--no-quality", "--json"], capsys)
    assert status == 0 and json.loads(out)["results"][0]["verdict"] == "none"
    # the six faces once: within the cap, epsilon computed
    status, out, _ = run(["analyze", str(grasp_file(tmp_path, FACES, "six.json")), "--json"],
                         capsys)
    record = json.loads(out)["results"][0]
    assert status == 0 and record["verdict"] == "closure" and record["epsilon"] > 0


def test_more_than_max_contacts_refused(tmp_path, capsys):
    path = grasp_file(tmp_path, FACES[:2] * (MAX_CONTACTS // 2 + 1))
    status, _, err = run(["analyze", str(path), "--no-quality"], capsys)
    assert status == 2 and len(err) == 1
    assert f"{MAX_CONTACTS + 2:,} contacts; at most {MAX_CONTACTS:,} are analysed" in err[0]
    contacts = [point_contact([0, 0], [0, 1], "hard", 0.5)] * (MAX_CONTACTS + 1)
    with pytest.raises(InputError, match="at most 1,024 are analysed"):
        check_grasp(contacts)
    points = np.zeros((1, MAX_CONTACTS + 1, 2))
    with pytest.raises(InputError, match="1,025 contacts a grasp"):
        analyze_batch(points, np.ones_like(points), mu=0.5)


def test_npz_epsilon_over_the_quality_cap(tmp_path, capsys):
    """13 spatial contacts a grasp: --epsilon is refused up front; the verdicts alone run."""
    k = MAX_QUALITY_CONTACTS + 1
    pts = np.array([p for p, _ in FACES] * 3, dtype=float)[:k]
    path = tmp_path / "g.npz"
    np.savez(path, points=pts[None], normals=pts[None], mu=0.5, model="hard")
    status, _, err = run(["analyze", str(path), "--epsilon"], capsys)
    assert status == 2 and len(err) == 1 and "epsilon is computed for at most" in err[0]
    status, out, _ = run(["analyze", str(path), "--json"], capsys)
    assert status == 0 and json.loads(out)["closure"] == 1


def test_fingers_cap(capsys):
    """--fingers 10000 on the cube: refused in one line before any sampling; the cap itself
    passes the check."""
    status, _, err = run(["synthesize", "cube", "--contact", "soft", "--fingers", "10000"],
                         capsys)
    assert status == 2 and len(err) == 1
    assert f"--fingers 10000: at most {MAX_FINGERS} fingers" in err[0]
    assert check_hand(3, MAX_FINGERS, "soft") == MAX_FINGERS
    with pytest.raises(InputError, match=f"at most {MAX_FINGERS} fingers"):
        check_hand(3, MAX_FINGERS + 1, "frictionless")
