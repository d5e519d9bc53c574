"""The result of :func:`forceclosure.analyze` (and :func:`vector_closure`) in a condition:
``bool(result)`` is "force-closure", never "a result exists"."""

import numpy as np

from forceclosure import Verdict, analyze, point_contact
from forceclosure.analysis.closure import vector_closure


def test_bool_of_an_analysis_is_closure_only():
    """Hand-derived planar pairs: an antipodal pinch with mu = 0.5 (the line through the
    contacts is along both normals: closed), the same line at exactly 45 degrees to the normals
    with mu = 1 (on the friction cones' edges: marginal), and one finger alone (none)."""
    pinch = [point_contact([x, 0], [x, 0], "hard", 0.5) for x in (-1, 1)]
    edge = [point_contact([-1, 0], [-1, 0], "hard", 1.0),
            point_contact([1, 2], [1, 0], "hard", 1.0)]
    cases = {Verdict.CLOSURE: pinch, Verdict.MARGINAL: edge, Verdict.NONE: pinch[:1]}
    for verdict, grasp in cases.items():
        result = analyze(grasp)
        assert result.verdict is verdict
        assert bool(result) is (verdict is Verdict.CLOSURE)
        assert (not result) is (verdict is not Verdict.CLOSURE)


def test_bool_of_a_vector_closure_is_closure_only():
    """Theorem 1 on vectors: +-e1, +-e2 positively span the plane; e1, e2 do not."""
    cross = np.array([[1.0, -1.0, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0]])
    assert vector_closure(cross).verdict is Verdict.CLOSURE and bool(vector_closure(cross))
    half = np.array([[1.0, 0.0], [0.0, 1.0]])
    assert vector_closure(half).verdict is Verdict.NONE and not vector_closure(half)
