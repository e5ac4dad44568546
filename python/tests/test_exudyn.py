"""flexbody.exudyn.add_body: a reduced body in Exudyn is the same body."""

import numpy as np
import pytest

import flexbody
import flexbody.exudyn
from conftest import PY_EXAMPLES, require


@pytest.fixture(scope="module")
def arm():
    return flexbody.read(PY_EXAMPLES / "pendulum_arm.inp").reduce("free-residual", interface="PIVOT,TIP", modes=4)


def new_system():
    exu = require("exudyn")
    SC = exu.SystemContainer()
    return exu, SC, SC.AddSystem()


def test_a_free_body_in_exudyn_vibrates_at_the_bodys_frequencies(arm):
    # The linearisation of the floating-frame equations about rest: six
    # rigid-body modes, then the free elastic modes of K_red, M_red; they
    # match only if the floating-frame terms couple frame and modes right.
    exu, SC, mbs = new_system()
    flexbody.exudyn.add_body(mbs, arm)
    mbs.Assemble()
    values, _ = mbs.ComputeODE2Eigenvalues(convert2Frequencies=True)
    exudyn_hz = np.sort(np.abs(np.asarray(values)))
    body_hz = arm.frequencies_hz()
    assert np.all(exudyn_hz[:6] < 1e-6 * body_hz[6])
    np.testing.assert_allclose(exudyn_hz[6:], body_hz[6:], rtol=1e-8)


def test_a_placed_body_has_its_nodes_where_the_frame_puts_them(arm):
    exu, SC, mbs = new_system()
    import exudyn.itemInterface as eii

    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # 90 degrees about z
    placed = flexbody.exudyn.add_body(mbs, arm, position=[1.0, 2.0, 3.0], rotation=turn, nodes=[11])
    assert placed.mesh_nodes == {1: 0, 21: 1, 11: 2}
    sensors = {
        node: mbs.AddSensor(eii.SensorMarker(markerNumber=placed.position_marker(node),
                                             outputVariableType=exu.OutputVariableType.Position))
        for node in (1, 11, 21)
    }
    mbs.Assemble()
    for node, x in [(1, 0.0), (11, 0.5), (21, 1.0)]:
        np.testing.assert_allclose(mbs.GetSensorValues(sensors[node]), [1.0, 2.0 + x, 3.0], atol=1e-12)
    with pytest.raises(KeyError, match="node 5 is not an interface node"):
        placed.mesh_node(5)


def test_the_terms_are_the_bodys_invariants(arm):
    inv = arm.invariants()
    terms = flexbody.exudyn.ffrf_terms(inv)
    nq = inv["me"].shape[0]
    assert terms["mass"] == pytest.approx(7850 * 0.02 * 0.01, rel=1e-12)
    np.testing.assert_allclose(terms["centerOfMass"], [0.5, 0.0, 0.0], atol=1e-12)
    assert terms["mPsiTildePsiTilde"].shape == (3 * nq, 3 * nq)
    # The translation-mode coupling: int Phi dm of each mode is Ct's row.
    np.testing.assert_allclose(terms["mPhitTPsi"], inv["ct"].T)
