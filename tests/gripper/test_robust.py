"""Robust labels against closed forms: a box pinch under rotation and friction noise.

The bundled cube is 2 × 2 × 2 about the origin. A pose at its centre closing
along x, with point soft pads, pinches the x faces; turned by an angle θ its
jaws' line meets them at ``∓tan θ`` off centre, the normals stay ±x
(antiparallel), so the pair is force-closure iff ``tan|θ| < μ`` (Corollary 3,
necessary and sufficient for antiparallel normals). Hence:

* θ ~ N(0, σ) in one plane: ``P = erf(atan μ / (σ √2))``;
* a rotation by two perpendicular Gaussian angles of σ each turns the axis
  by a Rayleigh angle: ``P = 1 - exp(-atan(μ)² / (2σ²))``;
* a fixed tilt ``t`` and μ ~ N(μ0, σμ): ``P = Φ((μ0 - tan t) / σμ)``.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.special import erf, ndtr

from forceclosure import point_contact
from forceclosure.analysis.quality import epsilon
from forceclosure.app.cli import main
from forceclosure.errors import InputError
from forceclosure.gripper.jaw import JawPose, ParallelJaw
from forceclosure.gripper.labels import grasp_labels
from forceclosure.gripper.robust import robust_labels

#: point soft pads, as the closed forms take them: pads 1e-9 across, pressing nothing, their
#: torsion the paper's (unlimited); the contacts are the jaws' line's, to 1e-9
GRIPPER = ParallelJaw(3.0, pad_radius=0, pad_length=1e-9, pad_height=1e-9, depth=5e-10,
                      pad_compliance=0)
HEAD_ON = JawPose([0, 0, 0], [1, 0, 0], [0, 0, 1], 2.0)
QUIET = {"pose_sigma": 0.0, "angle_sigma": 0.0, "mu_sigma": 0.0, "normal_sigma": 0.0}


def _robust(poses, mu, samples, seed=1, confidence=0.99, epsilon=False, **noise):
    return robust_labels("cube", poses, GRIPPER, mu, samples=samples, seed=seed,
                         confidence=confidence, epsilon=epsilon, **{**QUIET, **noise})


def _inside(r, truth):
    return float(r.probability_low[0]) <= truth <= float(r.probability_high[0])


def test_tilt_in_one_plane_matches_erf():
    mu, sigma = 0.2, 0.25
    truth = erf(math.atan(mu) / (sigma * math.sqrt(2)))  # 0.570
    r = _robust(HEAD_ON, mu, 20_000, angle_sigma=(sigma, 0.0))  # about the approach axis only
    assert _inside(r, truth), (r.probability, r.probability_low, r.probability_high, truth)
    assert abs(r.probability[0] - truth) < 0.015
    assert r.missed[0] == 0
    # the other axis alone gives the same law (a tilt in the perpendicular plane)
    r = _robust(HEAD_ON, mu, 20_000, seed=2, angle_sigma=(0.0, sigma))
    assert _inside(r, truth)


def test_rotation_in_both_planes_matches_rayleigh():
    mu, sigma = 0.3, 0.2
    truth = 1 - math.exp(-math.atan(mu) ** 2 / (2 * sigma**2))  # 0.596
    r = _robust(HEAD_ON, mu, 20_000, angle_sigma=sigma)
    assert _inside(r, truth), (r.probability, truth)
    assert abs(r.probability[0] - truth) < 0.015
    # not the one-plane law: erf(...) = 0.866 here, far outside the interval
    assert not _inside(r, erf(math.atan(mu) / (sigma * math.sqrt(2))))


def test_friction_noise_on_a_fixed_tilt_matches_the_normal_cdf():
    t, mu0, s_mu = math.atan(0.25), 0.3, 0.05
    pose = JawPose([0, 0, 0], [math.cos(t), math.sin(t), 0], [0, 0, 1], 2.0)
    truth = float(ndtr((mu0 - math.tan(t)) / s_mu))  # Phi(1) = 0.841
    r = _robust(pose, mu0, 20_000, mu_sigma=s_mu)
    assert _inside(r, truth), (r.probability, truth)
    assert abs(r.probability[0] - truth) < 0.012


def test_translation_noise_alone_matches_the_jaws_clearing_the_faces():
    # moving the jaws (not turning them) keeps the line along x, so a sample closes unless
    # it leaves the faces (|y| or |z| > 1: the pads close on nothing); a shift along x
    # changes nothing: the hand closes about the object wherever it starts (the opening, 3,
    # holds the 2-wide cube)
    sigma = 0.3
    r = _robust(HEAD_ON, 0.2, 20_000, pose_sigma=sigma)
    truth = erf(1 / (sigma * math.sqrt(2))) ** 2  # 0.9987
    assert _inside(r, truth), (r.probability, truth)
    assert r.closed[0] + r.missed[0] == 20_000  # every sample not closed made no pair


def test_normal_noise_closes_at_least_when_both_normals_stay_in_the_cones():
    # each normal of the head-on pinch turns by a Rayleigh angle (two Gaussian components of
    # sigma): both stay within atan(mu) of -+x with probability (1 - exp(-a^2/2s^2))^2, and
    # then the line x lies in both cones (Corollary 3: closed). With non-parallel normals
    # the soft pads' torques can close more pairs, so this is a lower bound only
    mu, sigma = 0.2, 0.15
    a = math.atan(mu)
    rayleigh = 1 - math.exp(-a * a / (2 * sigma**2))
    r = _robust(HEAD_ON, mu, 20_000, normal_sigma=sigma)
    assert r.probability_high[0] >= rayleigh**2
    assert r.probability[0] > rayleigh**2 + 0.02  # the torques do close some more


def test_interval_shrinks_like_one_over_root_n_and_converges():
    mu, sigma = 0.2, 0.25
    truth = erf(math.atan(mu) / (sigma * math.sqrt(2)))
    widths, errors = [], []
    for n in (1000, 4000, 16000):
        r = _robust(HEAD_ON, mu, n, seed=7, angle_sigma=(sigma, 0.0))
        widths.append(float(r.probability_high[0] - r.probability_low[0]))
        errors.append(abs(float(r.probability[0]) - truth))
        assert _inside(r, truth)
    assert 1.8 < widths[0] / widths[1] < 2.2
    assert 1.8 < widths[1] / widths[2] < 2.2
    assert errors[-1] < 0.5 * widths[-1]


def test_expected_epsilon_under_friction_noise_matches_quadrature():
    # fixed tilt, mu ~ N(mu0, s): E[eps] = integral of eps(mu) (0 below tan t) against the
    # normal density, eps(mu) from the reference Qhull path (forceclosure.analysis.quality.epsilon)
    t, mu0, s_mu = 0.1, 0.3, 0.08
    pose = JawPose([0, 0, 0], [math.cos(t), math.sin(t), 0], [0, 0, 1], 2.0)
    r = _robust(pose, mu0, 4000, mu_sigma=s_mu, epsilon=True)
    y = math.tan(t)
    grid = np.linspace(max(0.0, mu0 - 6 * s_mu), mu0 + 6 * s_mu, 121)
    eps = np.array([epsilon([point_contact([-1, -y, 0], [-1, 0, 0], "soft", m),
                             point_contact([1, y, 0], [1, 0, 0], "soft", m)]).value
                    for m in grid])
    density = np.exp(-0.5 * ((grid - mu0) / s_mu) ** 2) / (s_mu * math.sqrt(2 * math.pi))
    truth = float(np.sum(0.5 * (eps[1:] * density[1:] + eps[:-1] * density[:-1])
                         * np.diff(grid)))
    assert truth > 0.01
    assert r.epsilon_low[0] <= truth <= r.epsilon_high[0], (r.epsilon, truth)
    assert r.epsilon_high[0] - r.epsilon_low[0] < 0.1 * truth


def test_without_noise_the_labels_are_the_nominal_ones():
    labels = grasp_labels("cube", GRIPPER, 0.3, 30, seed=3)
    r = robust_labels("cube", labels, GRIPPER, 0.3, samples=5, seed=0, epsilon=True, **QUIET)
    closed = labels.code == 2
    assert np.array_equal(r.probability, closed.astype(float))
    # the nominal epsilon, by the reference path, for every sample
    for i in np.flatnonzero(closed)[:5]:
        ref = epsilon([point_contact(p, n, "soft", 0.3)
                       for p, n in zip(labels.points[i], labels.normals[i], strict=True)]).value
        assert r.epsilon[i] == pytest.approx(ref, rel=1e-6)
        assert r.epsilon_high[i] - r.epsilon_low[i] == pytest.approx(0.0, abs=1e-9)


def test_misses_count_as_not_closed_and_hard_pairs_never_close():
    beside = JawPose([0, 5, 0], [1, 0, 0], [0, 0, 1], 2.0)
    r = _robust([HEAD_ON, beside], 0.5, 50, angle_sigma=0.05)
    assert r.probability.tolist() == [1.0, 0.0]
    assert r.missed.tolist() == [0, 50]
    # Wilson's interval for 0 of n is [0, z^2 / (n + z^2)], not [0, 0]
    z = 2.5758293035489004  # the 99.5% quantile of the normal
    assert r.probability_low[1] == 0.0
    assert r.probability_high[1] == pytest.approx(z * z / (50 + z * z), rel=1e-12)
    r = robust_labels("cube", HEAD_ON, GRIPPER, 0.5, samples=20, contact="hard")
    assert r.probability.tolist() == [0.0]


def test_seeded_and_deterministic():
    labels = grasp_labels("cube", GRIPPER, 0.3, 20, seed=0, least_friction=False)
    a = robust_labels("cube", labels, GRIPPER, 0.3, samples=30, seed=4, normal_sigma=0.05)
    b = robust_labels("cube", labels, GRIPPER, 0.3, samples=30, seed=4, normal_sigma=0.05)
    c = robust_labels("cube", labels, GRIPPER, 0.3, samples=30, seed=5, normal_sigma=0.05)
    assert np.array_equal(a.closed, b.closed) and np.array_equal(a.epsilon, b.epsilon)
    assert not np.array_equal(a.epsilon, c.epsilon)


@pytest.mark.parametrize("bad", [{"samples": 1}, {"samples": 0}, {"confidence": 1.0},
                                 {"pose_sigma": -1.0}, {"angle_sigma": (0.1, 0.2, 0.3)},
                                 {"mu_sigma": float("nan")}, {"contact": "sticky"}])
def test_bad_settings_are_refused(bad):
    with pytest.raises(InputError):
        robust_labels("cube", HEAD_ON, GRIPPER, 0.3, **{"samples": 10, **bad})


def test_cli_grasps_robust(tmp_path, capsys):
    out = tmp_path / "X.npz"
    assert main(["grasps", "cube", "--width", "3", "--count", "20", "--mu", "0.3", "--robust",
                 "--robust-samples", "50", "--out", str(out)]) == 0
    z = np.load(out)
    for name in ("code", "least_friction", "epsilon"):  # the existing arrays stay
        assert z[name].shape == (20,)
    p, lo, hi = z["robust_probability"], z["robust_probability_low"], \
        z["robust_probability_high"]
    assert p.shape == (20,) and np.all((lo <= p) & (p <= hi)) and np.all((lo >= 0) & (hi <= 1))
    assert np.all(z["robust_epsilon_low"] <= z["robust_epsilon"])
    assert np.all(z["robust_epsilon"] <= z["robust_epsilon_high"])
    assert z["robust_missed"].dtype.kind == "i"
    # the probability is a count out of 50
    assert np.allclose(p * 50, np.round(p * 50))
    meta = json.loads(str(z["meta"]))
    assert meta["robust"]["samples"] == 50 and meta["robust"]["pose_sigma"] == 0.03
    assert "robust" in capsys.readouterr().out
    assert main(["grasps", "cube", "--width", "3", "--count", "5", "--robust",
                 "--robust-samples", "10", "--no-robust-epsilon", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["robust"]["samples"] == 10 and summary["robust"]["epsilon_median"] is None
    assert 0 <= summary["robust"]["probability_mean"] <= 1


@pytest.mark.parametrize("bad", [["--robust", "--robust-samples", "0"],
                                 ["--robust", "--pose-sigma", "-1"],
                                 ["--robust", "--angle-sigma", "inf"],
                                 ["--robust", "--robust-confidence", "1.5"],
                                 ["--mu-sigma", "0.1"]])
def test_cli_grasps_robust_bad_values(bad, capsys):
    assert main(["grasps", "cube", "--width", "3", "--count", "20", "--mu", "0.3", *bad]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("forceclosure: error:")
