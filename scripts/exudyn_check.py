#!/usr/bin/env python3
"""A real MBS client for flexbody's reduced bodies: Exudyn (FFRF).

1. Runs flexbody's integration test `exchange::exudyn_check_data`, which
   writes, for the free C3D8 bar tests/fixtures/calculix/hex_beam (reduced by
   free-residual, tip node 13, 4 eigenmodes; in its SID elastic coordinates,
   mean axes, 7 modes): the full M and K, the node positions, the mode shapes
   Phi, and flexbody's own time response (trapezoidal rule) of the tip to a
   harmonic force of 1 kN in z at node 13.
2. Loads the body into Exudyn through FEMinterface and
   ObjectFFRFreducedOrderInterface / ObjectFFRFreducedOrder. Exudyn computes
   its reduced matrices and FFRF terms itself from M, K and Phi.
3. Holds the reference frame fixed (six coordinate constraints on the
   frame's rigid-body node, rotation-vector parameters): ObjectFFRFreducedOrder
   is nonlinear in large rigid motion, flexbody's MBS is linear; with the
   frame fixed both solve Me q'' + Ke q = Phi_tip^T f(t).
4. Compares the eigenfrequencies of the Exudyn system with flexbody's and the
   tip displacement history (same step, Newmark trapezoidal rule in Exudyn)
   within 1e-3 relative to the peak. Exits non-zero on a mismatch.

Installs exudyn, numpy and scipy with pip if they are missing. Usage:
    python3 scripts/exudyn_check.py [WORKDIR [--reuse]]
(--reuse: use the data already in WORKDIR, do not run cargo)
"""

import json
import os
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TOLERANCE = 1e-3


def ensure(modules):
    missing = []
    for module, package in modules:
        try:
            __import__(module)
        except ImportError:
            missing.append(package)
    if missing:
        subprocess.check_call([sys.executable, "-m", "pip", "install", "--quiet", *missing])


def read_mtx(path):
    import numpy as np
    import scipy.sparse as sp

    with open(path) as f:
        header = f.readline().split()
        lines = [l for l in f if l.strip() and not l.startswith("%")]
    dims = [int(t) for t in lines[0].split()]
    if header[2] == "array":
        values = np.array([float(l) for l in lines[1:]])
        return values.reshape((dims[1], dims[0])).T
    rows, cols, vals = [], [], []
    for l in lines[1:]:
        i, j, v = l.split()
        rows.append(int(i) - 1)
        cols.append(int(j) - 1)
        vals.append(float(v))
    return sp.csr_matrix((vals, (rows, cols)), shape=(dims[0], dims[1]))


def main():
    ensure([("numpy", "numpy"), ("scipy", "scipy"), ("exudyn", "exudyn")])
    import numpy as np
    import exudyn as exu
    import exudyn.itemInterface as eii
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface

    work = sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="exudyn_check_")
    env = dict(os.environ, FLEXBODY_EXUDYN_DIR=work)
    if "--reuse" not in sys.argv:
        subprocess.check_call(
            ["cargo", "test", "--quiet", "--test", "flexbody", "exchange::exudyn_check_data"],
            cwd=REPO,
            env=env,
        )
    with open(os.path.join(work, "flexbody.json")) as f:
        ours = json.load(f)

    fem = FEMinterface()
    fem.nodes = {"Position": np.loadtxt(os.path.join(work, "nodes.txt"))}
    fem.massMatrix = read_mtx(os.path.join(work, "mass.mtx"))
    fem.stiffnessMatrix = read_mtx(os.path.join(work, "stiffness.mtx"))
    phi = read_mtx(os.path.join(work, "modes.mtx"))
    fem.modeBasis = {"matrix": phi, "type": "NormalModes"}
    cms = ObjectFFRFreducedOrderInterface(fem, rigidBodyNodeType="NodeType.RotationRotationVector")

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    body = cms.AddObjectFFRFreducedOrder(mbs, positionRef=[0, 0, 0])
    # Fix the reference frame: 6 coordinates of its rigid-body node.
    ground = mbs.AddNode(eii.NodePointGround())
    m_ground = mbs.AddMarker(eii.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    for c in range(6):
        m = mbs.AddMarker(eii.MarkerNodeCoordinate(nodeNumber=body["nRigidBody"], coordinate=c))
        mbs.AddObject(eii.CoordinateConstraint(markerNumbers=[m_ground, m]))
    tip = ours["tip_node_index"]
    m_tip = mbs.AddMarker(
        eii.MarkerSuperElementPosition(
            bodyNumber=body["oFFRFreducedOrder"], meshNodeNumbers=[tip], weightingFactors=[1.0]
        )
    )
    force = ours["force"]
    amp, freq = force["amplitude"], force["frequency_hz"]
    direction = np.array(force["direction"])

    def load(mbs, t, load_vector):
        return list(amp * np.sin(2 * np.pi * freq * t) * direction)

    mbs.AddLoad(eii.LoadForceVector(markerNumber=m_tip, loadVector=[0, 0, 0], loadVectorUserFunction=load))
    sensor = mbs.AddSensor(
        eii.SensorSuperElement(
            bodyNumber=body["oFFRFreducedOrder"],
            meshNodeNumber=tip,
            storeInternal=True,
            outputVariableType=exu.OutputVariableType.Displacement,
        )
    )
    mbs.Assemble()

    # Eigenfrequencies of the constrained system: the elastic modes.
    values, _ = mbs.ComputeODE2Eigenvalues(computeComplexEigenvalues=False, useAbsoluteValues=True)
    exu_hz = np.sort(np.sqrt(np.abs(values)) / (2 * np.pi))
    exu_hz = exu_hz[exu_hz > 1e-3 * max(exu_hz)]
    ref_hz = np.array(ours["frequencies_hz"])
    n = min(len(exu_hz), len(ref_hz))
    freq_err = np.max(np.abs(exu_hz[:n] - ref_hz[:n]) / ref_hz[:n])
    print("frequencies (Hz), flexbody:", " ".join(f"{f:.4f}" for f in ref_hz))
    print("frequencies (Hz), Exudyn:  ", " ".join(f"{f:.4f}" for f in exu_hz[:n]))
    print(f"largest relative frequency difference: {freq_err:.3e}")

    settings = exu.SimulationSettings()
    h = ours["step"]
    settings.timeIntegration.numberOfSteps = int(round(ours["duration"] / h))
    settings.timeIntegration.endTime = settings.timeIntegration.numberOfSteps * h
    settings.timeIntegration.generalizedAlpha.useNewmark = True
    settings.timeIntegration.generalizedAlpha.newmarkBeta = 0.25
    settings.timeIntegration.generalizedAlpha.newmarkGamma = 0.5
    settings.timeIntegration.generalizedAlpha.useIndex2Constraints = True
    settings.timeIntegration.generalizedAlpha.computeInitialAccelerations = True
    settings.timeIntegration.newton.relativeTolerance = 1e-12
    settings.timeIntegration.newton.absoluteTolerance = 1e-14
    settings.timeIntegration.verboseMode = 0
    settings.solution.file.write = False
    settings.solution.sensors.writePeriod = h
    mbs.SolveDynamic(settings)
    data = mbs.GetSensorStoredData(sensor)
    t_exu, uz_exu = data[:, 0], data[:, 3]
    t_ref, uz_ref = np.array(ours["times"]), np.array(ours["tip_uz"])
    uz_on_ref = np.interp(t_ref, t_exu, uz_exu)
    peak = np.max(np.abs(uz_ref))
    time_err = np.max(np.abs(uz_on_ref - uz_ref)) / peak
    print(f"tip uz: peak {peak:.6e} m, largest difference / peak: {time_err:.3e}")

    ok = freq_err < TOLERANCE and time_err < TOLERANCE and n == len(ref_hz)
    print("exudyn check:", "OK" if ok else "FAILED", f"(tolerance {TOLERANCE})")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
