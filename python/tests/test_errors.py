"""Bad input from Python raises flexbody.Error (a ValueError) naming the
problem; nothing crashes the interpreter."""

import numpy as np
import pytest
import scipy.sparse as sp

import flexbody
from conftest import EXAMPLES, PY_EXAMPLES

K2 = np.array([[2.0, -1.0], [-1.0, 2.0]])
M2 = np.eye(2)
DOFS2 = [(1, "ux"), (2, "ux")]


def refused(match):
    return pytest.raises(ValueError, match=match)


def test_the_error_is_a_value_error():
    assert issubclass(flexbody.Error, ValueError)


@pytest.mark.parametrize(
    "K, M, dofs, match",
    [
        (np.ones((2, 3)), M2, DOFS2, "must be square|but M is"),
        (K2, np.eye(3), DOFS2, "K is 2 x 2 but M is 3 x 3"),
        (np.array([[2.0, -1.0], [-0.5, 2.0]]), M2, DOFS2, r"K is not symmetric: entries \(1, 0\) and \(0, 1\)"),
        (np.array([[2.0, np.nan], [np.nan, 2.0]]), M2, DOFS2, r"K: entry \(1, 0\) is NaN"),
        (K2, np.array([[1.0, 0.0], [0.0, np.inf]]), DOFS2, r"M: entry \(1, 1\) is inf"),
        (K2, np.diag([1.0, -1.0]), DOFS2, r"M: diagonal entry \(1, 1\) is -1e0"),
        (K2, M2, [(1, "ux")], "K and M have 2 equations but dofs lists 1"),
        (K2, M2, [(1, "ux"), (1, "ux")], "node 1 ux is listed twice"),
        (K2, M2, [(1, "ux"), (2, "uw")], "unknown DOF 'uw'"),
        (K2, M2, [(1, 1), (2, 7)], "DOF 7 of node 2 is not one of 1..6"),
        (K2, M2, [(1, 1), (-2, 1)], "node -2 is negative"),
        (K2, M2, [[1, 1, 1], [2, 1, 1]], r"dofs must be an \(n, 2\) array"),
        (np.ones(4), M2, DOFS2, "K must be a 2-D matrix"),
        (K2.astype(complex), M2, DOFS2, "K must hold real numbers"),
    ],
)
def test_bad_matrices_are_named(K, M, dofs, match):
    with refused(match):
        flexbody.Model.from_matrices(K, M, dofs)


def test_bad_coordinates_are_named():
    with refused("node 2 has DOFs but no coordinates"):
        flexbody.Model.from_matrices(K2, M2, DOFS2, coords={1: (0, 0, 0)})
    with refused("node 1 has a coordinate that is not finite"):
        flexbody.Model.from_matrices(K2, M2, DOFS2, coords={1: (0, np.nan, 0), 2: (1, 0, 0)})


def test_bad_requests_are_named():
    model = flexbody.Model.from_matrices(sp.csc_array(K2), M2, DOFS2, coords={1: (0, 0, 0), 2: (1, 0, 0)})
    with refused("unknown method 'craig-bamptn'; expected one of: free, craig-bampton"):
        model.reduce("craig-bamptn", interface=[1], modes=1)
    with refused("count must be at least 1"):
        model.modes(count=0)
    with refused("fmax must be a positive frequency"):
        model.modes(fmax=-1.0)
    with refused("the craig-bampton method needs interface DOFs and none are given"):
        model.reduce("craig-bampton", modes=1)
    with refused("interface 'SEAT' is neither a node set nor a node number"):
        model.reduce("craig-bampton", interface="SEAT", modes=1)
    with refused("interface node 2 uy is not a DOF of the model"):
        model.reduce("craig-bampton", interface=np.array([[2, 2]]), modes=1)
    with refused("unknown format 'xml'"):
        model.reduce("guyan", interface=[1]).write("body.xml", format="xml")
    with refused("a study needs a model file"):
        model.study()


def test_bad_files_are_named(tmp_path):
    with refused("missing.inp"):
        flexbody.read(tmp_path / "missing.inp")
    deck = tmp_path / "bad.inp"
    arm = (PY_EXAMPLES / "pendulum_arm.inp").read_text()
    deck.write_text(arm + "*FOO\n")
    line = arm.count("\n") + 1
    with refused(rf"bad.inp:{line}: unknown keyword \*FOO"):
        flexbody.read(deck)
    # Skipped on request, and said.
    model = flexbody.read(deck, allow_unknown=True)
    assert any("*FOO" in w for w in model.warnings)
    deck.write_text("*NODE\n1, 0, 0, 0\n2, 1, zero, 0\n")
    with refused(r"bad.inp:3"):
        flexbody.read(deck)
    with refused("a model file|reduced body"):
        flexbody.load(EXAMPLES / "side_beam.toml")
    out = tmp_path / "no" / "such" / "folder" / "body.json"
    body = flexbody.read(EXAMPLES / "side_beam.toml").reduce("guyan")
    with refused("body.json"):
        body.write(out)
    assert not out.exists()
