"""The verdicts' one home (``forceclosure.verdicts``): each word and its integer code, as the
compiled kernels write the codes and the reference path the words."""

import numpy as np
import pytest

from forceclosure import analyze, point_contact
from forceclosure.analysis.batch import analyze_batch
from forceclosure.verdicts import VERDICT_WORDS, Verdict, VerdictCode, verdict_words


def test_words_and_codes_are_one_table():
    assert [(v.value, int(v.code)) for v in Verdict] == [("closure", 2), ("marginal", 1),
                                                         ("none", 0)]
    for code in VerdictCode:
        assert code.verdict.code is code and Verdict.of_code(int(code)) is code.verdict
        assert VERDICT_WORDS[code] == code.verdict.value
    for bad in (-1, 3):
        with pytest.raises(IndexError, match=f"no verdict has the code {bad}"):
            Verdict.of_code(bad)
    assert verdict_words(np.array([[0, 2], [1, 0]], np.int8)).tolist() == [
        ["none", "closure"], ["marginal", "none"]]


def test_the_kernels_codes_are_the_reference_verdicts():
    """Three hand-derived planar pairs (see tests/analysis/test_closure.py): an antipodal
    pinch with mu 0.5 (closure), a line at 45 degrees to the normals with mu 1 (on the cones'
    edges: marginal), and the pinch with its second normal turned along the edge (none)."""
    P = np.array([[[-1.0, 0.0], [1.0, 0.0]], [[-1.0, 0.0], [1.0, 2.0]],
                  [[-1.0, 0.0], [1.0, 0.0]]])
    N = np.array([[[-1.0, 0.0], [1.0, 0.0]], [[-1.0, 0.0], [1.0, 0.0]],
                  [[-1.0, 0.0], [0.0, 1.0]]])
    mu = np.array([0.5, 1.0, 0.5])
    expected = [VerdictCode.CLOSURE, VerdictCode.MARGINAL, VerdictCode.NONE]
    batch = analyze_batch(P, N, mu=mu[:, None])
    assert batch.code.tolist() == expected
    assert batch.verdict.tolist() == ["closure", "marginal", "none"]
    assert batch.force_closure.tolist() == [True, False, False]
    for g in range(3):
        one = analyze([point_contact(P[g, i], N[g, i], "hard", mu[g]) for i in range(2)])
        assert one.verdict is expected[g].verdict and one.verdict.code == batch.code[g]
