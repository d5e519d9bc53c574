import math

import numpy as np
import pytest

from forceclosure import (
    Cone,
    InputError,
    analyze,
    edge_contact,
    face_contact,
    generating_wrenches,
    point_contact,
    vertex_contact,
)


def test_planar_hard_finger_generators_by_hand():
    c = point_contact([2, 1], [0, 1], "hard", 0.5)  # top edge; finger pushes down
    W = generating_wrenches([c], reference=[0, 0], length_scale=1).wrenches
    # forces -n ± mu t with t = (-1, 0): (-0.5, -1) and (0.5, -1); torque px fy - py fx
    want = {(-0.5, -1.0, 2 * -1 - 1 * -0.5), (0.5, -1.0, 2 * -1 - 1 * 0.5)}
    assert {tuple(np.round(col, 12)) for col in W.T} == want


@pytest.mark.parametrize("fit,radius", [("inscribed", 0.4),
                                        ("circumscribed", 0.4 / math.cos(math.pi / 6))])
def test_spatial_pyramid_edges_lie_on_their_cone(fit, radius):
    n = np.array([1.0, 2.0, 2.0]) / 3
    ws = generating_wrenches([point_contact([0, 0, 0], n, "hard", 0.4)], Cone(6, fit),
                             reference=[0, 0, 0], length_scale=1)
    forces = ws.wrenches[:3].T
    assert forces.shape == (6, 3)
    np.testing.assert_allclose(forces @ -n, 1.0)  # unit normal component
    np.testing.assert_allclose(np.linalg.norm(forces + n, axis=1), radius)
    np.testing.assert_allclose(ws.wrenches[3:], 0, atol=1e-15)  # at the reference point


def test_soft_finger_torques():
    n = [0, 0, 1]
    paper = generating_wrenches([point_contact([0, 0, 0], n, "soft", 0.3)], Cone(4),
                                reference=[0, 0, 0], length_scale=2).wrenches
    pure = paper[:, -2:]
    np.testing.assert_allclose(pure, [[0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [1, -1]])
    coupled = generating_wrenches([point_contact([0, 0, 0], n, "soft", 0.3, torsion=0.1)],
                                  Cone(4), reference=[0, 0, 0], length_scale=2).wrenches
    assert coupled.shape == (6, 8)
    # |tau_n| / f_n = torsion, torque divided by the length scale 2
    np.testing.assert_allclose(np.abs(coupled[5]) * 2 / -coupled[2], 0.1)


def test_complex_contacts_are_unions():
    e = edge_contact([0, -1], [1, -1], [0, -1], "frictionless")
    assert generating_wrenches([e]).wrenches.shape == (3, 2)
    f = face_contact([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [0, 0, -1], "hard", 0.2)
    assert generating_wrenches([f], Cone(5)).wrenches.shape == (6, 15)
    v = vertex_contact([1, 1], [[1, 0], [0, 1]], "soft", 0.2)
    assert generating_wrenches([v]).wrenches.shape == (3, 4)


@pytest.mark.parametrize("kwargs,message", [
    ({"point": [0, 0], "normal": [0, 0]}, "zero vector"),
    ({"point": [0, float("nan")], "normal": [0, 1]}, "non-finite"),
    ({"point": [0, 0], "normal": [0, 1], "mu": -1}, "'mu' must be finite and >= 0"),
    ({"point": [0, 0], "normal": [0, 1], "model": "glue"}, "'model' must be one of"),
    ({"point": [0, 0, 0, 0], "normal": [0, 1]}, "2 or 3 coordinates"),
    ({"point": [0, 0], "normal": [0, 0, 1]}, "mix 2-D and 3-D"),
])
def test_bad_contacts_are_refused_in_one_line(kwargs, message):
    with pytest.raises(InputError, match=message) as e:
        point_contact(**kwargs)
    assert "\n" not in str(e.value)


def test_normals_are_normalised():
    assert point_contact([0, 0], [0, 5]).normal.tolist() == [0.0, 1.0]


CONE_FORMS = [("exact", "exact"), ({"edges": 4}, Cone(4)), ({}, Cone(8)),
              ({"edges": 6, "fit": "circumscribed"}, Cone(6, "circumscribed")),
              ("16-circumscribed", Cone(16, "circumscribed")), ("3-inscribed", Cone(3))]
BAD_CONES = [("8", "cone must be"), ("8-outside", "cone must be"), ({"edges": "8"}, "'edges'"),
             ({"edges": 2}, "'edges' must be an integer >= 3"), ({"k": 8}, "cone must be"),
             ("2-inscribed", "'edges' must be an integer >= 3"), (8, "cone must be")]


@pytest.mark.parametrize("spec, cone", CONE_FORMS)
def test_one_cone_reader_for_the_api_and_both_grasp_files(spec, cone, tmp_path):
    """A cone asked for as the API's argument, a JSON grasp file's field and an .npz grasp
    file's array (text only) reads the same."""
    import json

    from forceclosure.contacts import fixed_cone, parse_cone
    from forceclosure.io.grasp_arrays import open_npz
    from forceclosure.io.grasp_file import parse_grasp_file

    assert parse_cone(spec) == cone and fixed_cone(spec) == (None if cone == "exact" else cone)
    grasp = {"contacts": [{"point": [0, 0, 1], "normal": [0, 0, 1], "mu": 0.5},
                          {"point": [0, 0, -1], "normal": [0, 0, -1], "mu": 0.5}], "cone": spec}
    assert parse_grasp_file(json.dumps(grasp)).cone == cone
    if isinstance(spec, str):
        path = tmp_path / "g.npz"
        np.savez(path, points=np.zeros((1, 2, 3)), normals=np.ones((1, 2, 3)), cone=spec)
        assert open_npz(str(path)).cone == cone


@pytest.mark.parametrize("spec, message", BAD_CONES)
def test_a_bad_cone_is_refused_in_one_line_by_every_reader(spec, message):
    import json

    from forceclosure.contacts import parse_cone
    from forceclosure.io.grasp_file import parse_grasp_file

    grasp = [point_contact([x, 0, 0], [x, 0, 0], "hard", 0.5) for x in (-1, 1)]
    for read in (parse_cone, lambda s: analyze(grasp, cone=s),
                 lambda s: parse_grasp_file(json.dumps({"contacts": [
                     {"point": [1, 0, 0], "normal": [1, 0, 0]}], "cone": s}))):
        with pytest.raises(InputError, match=message) as e:
            read(spec)
        assert "\n" not in str(e.value)
