"""A pendulum with a flexible arm, from a deck to a running Exudyn model.

The arm (pendulum_arm.inp: a steel bar of B31 beams, node 1 its pivot) is
reduced by Craig-Bampton on the pivot node, added to Exudyn with
flexbody.exudyn.add_body, and hung on a spherical joint at the pivot. The
check: the first elastic frequency of the assembled Exudyn system (its
linearisation about rest, by Exudyn) against the full FE model held at
the pivot; then the pendulum swings under gravity for a while.

Run: python python/examples/deck_to_exudyn_pendulum.py
"""

from pathlib import Path

import numpy as np
import scipy.linalg

import flexbody
import flexbody.exudyn

HERE = Path(__file__).resolve().parent


def full_model_hz(model, pivot, count):
    """The lowest frequencies of the full FE model with the pivot's
    translations held (a ball joint): three rigid rotations, then the
    elastic modes."""
    dofs = model.dofs
    keep = ~((dofs[:, 0] == pivot) & (dofs[:, 1] <= 3))
    K = model.K.toarray()[np.ix_(keep, keep)]
    M = model.M.toarray()[np.ix_(keep, keep)]
    values = scipy.linalg.eigh(K, M, eigvals_only=True)[:count]
    return np.sqrt(np.abs(values)) / (2 * np.pi)


def main(swing_seconds=0.5):
    import exudyn as exu
    import exudyn.itemInterface as eii

    model = flexbody.read(HERE / "pendulum_arm.inp")
    body = model.reduce("craig-bampton", interface="PIVOT", modes=8)

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    arm = flexbody.exudyn.add_body(mbs, body, nodes=[21])
    ground = mbs.AddObject(eii.ObjectGround(referencePosition=[0, 0, 0]))
    m_ground = mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=ground, localPosition=[0, 0, 0]))
    mbs.AddObject(eii.SphericalJoint(markerNumbers=[m_ground, arm.position_marker(1)]))
    m_mass = arm.mass_marker()
    gravity = mbs.AddLoad(eii.LoadMassProportional(markerNumber=m_mass, loadVector=[0, 0, 0]))
    mbs.Assemble()

    # The linearised system about rest: 3 zero frequencies (the ball
    # joint's rotations), then the arm's elastic modes.
    values, _ = mbs.ComputeODE2Eigenvalues(convert2Frequencies=True)
    exudyn_hz = np.sort(np.abs(np.asarray(values)))
    full_hz = full_model_hz(model, 1, 6)

    # Released horizontally under gravity (along -z), it swings down.
    mbs.SetLoadParameter(gravity, "loadVector", [0, 0, -9.81])
    settings = exu.SimulationSettings()
    steps = max(1, int(swing_seconds / 1e-3))
    settings.timeIntegration.numberOfSteps = steps
    settings.timeIntegration.endTime = swing_seconds
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    tip = mbs.AddSensor(
        eii.SensorMarker(markerNumber=arm.position_marker(21), storeInternal=True,
                         outputVariableType=exu.OutputVariableType.Position)
    )
    mbs.Assemble()
    mbs.SolveDynamic(settings)
    tip_path = mbs.GetSensorStoredData(tip)[:, 1:]

    return {
        "exudyn_hz": exudyn_hz,
        "full_hz": full_hz,
        "tip_path": tip_path,
    }


if __name__ == "__main__":
    result = main()
    print("first elastic frequency about the pivot:")
    print(f"  Exudyn, reduced arm: {result['exudyn_hz'][3]:.6f} Hz")
    print(f"  full FE model:       {result['full_hz'][3]:.6f} Hz")
    print(f"tip after the swing: {result['tip_path'][-1]} m")
