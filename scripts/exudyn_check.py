#!/usr/bin/env python3
"""A real MBS client for flexbody's reduced bodies: Exudyn (FFRF).

The integration test `exudyn::exudyn_agrees_with_flexbody` writes, into
WORKDIR, one reduced body (for example the free C3D8 bar
tests/fixtures/calculix/hex_beam reduced by free-residual, tip node 13, 4
eigenmodes; in its SID elastic coordinates, mean axes, 7 modes):

  body.sid        the SID file, written by `flexbody reduce --format sid`;
  nodes.txt       x y z per node, in the order of the mesh's nodes;
  mass.mtx,       the full M and K (Matrix Market), each node's DOFs
  stiffness.mtx   together (3 translations of a solid, 6 DOFs of a beam);
  modes.mtx       the elastic mode shapes Phi (m x nq) on those DOFs;
  beam.json       for a beam, the mesh and Phi as scripts/beam_invariants.py
                  reads them;
  flexbody.json   flexbody's frequencies and its own time response
                  (trapezoidal rule) of the tip to a harmonic force of 1 kN
                  in z at the tip node;

and runs this script on it. The script builds two Exudyn bodies:

  A  "SID": an ObjectFFRFreducedOrder whose floating-frame terms come only
     from the SID file, read by the small reader below (written from
     docs/sid.md, independent of flexbody's Rust reader), as an MBS user
     would; its mesh is the SID's interface node.
  B  "FEM": the same object built apart from flexbody's invariants. For a
     solid, by Exudyn's FEMinterface and ObjectFFRFreducedOrderInterface
     from the full M, K, node positions and Phi (Exudyn computes its
     reduced matrices and FFRF terms itself). For a beam, whose sections
     turn and carry rotary inertia (which FEMinterface, a mesh of points,
     does not know), from the mass integrals P(a, b) = int a b^T dm of
     the fields x0 and Phi_k over the beam's shape functions
     (scripts/beam_invariants.py, numpy), Ke = Phi^T K Phi from the full
     K, and Phi's translations at the nodes as the mesh.

and compares:

  1. the FFRF terms of A (from the SID invariants) with those of B, each
     relative to its own scale;
  2. the frequencies of the elastic modes (reference frame held fixed) of A
     and B with flexbody's;
  3. the tip displacement history under the harmonic force, frame held
     fixed (both codes then solve Me q'' + Ke q = Phi_tip^T f(t)), same step,
     trapezoidal rule: A with flexbody's, and A with B;
  4. a short free tumble (initial angular velocity, 0.05 s, no load): the
     tip position, the frame's coordinates and the modal coordinates of A
     against B. It exercises the terms that a fixed frame leaves out (J, Cr,
     Gr, Ge, Oe and their first orders);
  5. energy and momentum of B's tumble, computed from the mass integrals
     P(a, b) (of a solid: from the full M) and Ke and the frame's and modal
     motion (apart from any FFRF term): their drift over the run must fall
     with the square of the step (the trapezoidal rule's order);
  6. large motion under a joint and gravity (50 g): a free body swings as a
     pendulum from the tip node on a spherical joint; a clamped body
     (flexbody.json "clamped") turns on a hub, a revolute joint about z at
     the frame origin (its clamped face). A against B: frame and modal
     coordinates.

The case (flexbody.json "case"): free-residual or Craig-Bampton of a free
body (the bar, a skew Timoshenko beam), or Craig-Bampton of a body clamped
at the frame origin (the bar at x = 0, a beam at its first node); for a
clamped one, M and the mode shapes cover the clamped nodes too (zero
there), so that B has the whole mass, and A must have it from the SID
alone.

Prints one line per comparison and exits non-zero on a mismatch. Needs numpy,
scipy and exudyn (`bash scripts/install_peers.sh` installs them). Usage:
    python3 scripts/exudyn_check.py WORKDIR
"""

import json
import os
import re
import sys

# Allowed differences, each a few times what is measured with exudyn 1.13
# (numpy 2.4, scipy 1.17) on x86-64; the figures are in the comments.
TOLERANCES = {
    # SID terms against FEMinterface's, relative to each term's scale. The
    # SID numbers round-trip exactly; both sides sum the same products of M in
    # a different order. Measured 7.2e-16 (stiffnessMatrixReduced; the others
    # 4e-17 to 3.3e-16). The same bound holds for a beam's SID terms against
    # the numpy integration of the beam (measured up to 8.9e-16,
    # massMatrixReduced), and for the terms built from the mass integrals of
    # the solid's M against FEMinterface's (up to 3.3e-16): the formulas of
    # the beam's body B, checked on the solid.
    "terms": 5e-15,
    # The ielastq names carry the frequencies to 7 significant digits
    # ("{f:.6e} Hz"): a rounding of at most 5e-7. Measured 2.8e-7.
    "names": 1e-6,
    # Elastic frequencies of the fixed-frame bodies against flexbody's
    # (relative). Measured up to 1.7e-14 (SID body) and 8.7e-14 (FEM body
    # of the clamped bar, whose Ke Exudyn forms from the singular full K).
    "frequency": 3e-13,
    # The same for a beam. Its Ke = Phi^T K Phi from the full K loses digits
    # to cancellation: for the clamped 2 m beam K's entries reach 1e9 and
    # its lowest eigenvalue is 2e4. Measured 9.4e-13 (FEM body) and 2.3e-13
    # (SID body) on that beam, 3.1e-14 on the free skew beam.
    "frequency_beam": 3e-12,
    # Tip history of the SID body against flexbody's (relative to the peak):
    # the same trapezoidal rule on the same equations. Measured 1.8e-15.
    "response": 1e-14,
    # The same for a beam, whose SID reduced matrices are integrals over
    # the mesh (P(a, b)) and agree with flexbody's Phi^T M Phi to about
    # 1e-15 of the largest entry, not to the last bit: frequencies of the
    # SID body within 3e-14 of flexbody's, a phase difference that grows to
    # 1e-12 of the peak over the run's 6 periods of f1 (145 of the highest
    # mode). Measured 1.2e-12 against flexbody, 4.7e-12 against the FEM body
    # (the clamped beam, whose FEM body's frequencies differ by 9.4e-13).
    "response_beam": 2e-11,
    # Tip history, SID body against FEM body (relative to the peak).
    # Measured 1.4e-14 (free bar), 7.4e-13 (clamped bar).
    "response_fem": 3e-12,
    # Free tumble, SID body against FEM body, each history relative to its
    # peak. Measured up to 1.7e-12 (tip position, free bar) and 1.1e-11
    # (modal coordinates, clamped bar); beams up to 9e-13. A 1e-6 relative
    # error in one entry of J or of Gr moves these by 4e-8 to 1e-6; the
    # transposed blocks of mPsiTildePsiTilde by 3e-9 to 6e-8.
    "tumble": 5e-11,
    # Drift of energy, angular and linear momentum over the tumble (each
    # relative to its size): the drift at h/2 over the drift at h, 1/4 for a
    # second-order rule (1/2 for first, 1/8 for third order); allowed
    # 1/4 +- 0.05. Free bar: drift 1.8e-5, 1.5e-4 and 2.4e-5 at
    # h = 2.5e-5 s, ratios within 4e-4 of 1/4; clamped bar: within 0.018;
    # beams: within 1.7e-4.
    "order": 0.05,
    # Pendulum and hub under 50 g, SID body against FEM body, relative to
    # the peak. Measured up to 5.5e-13 (frame) and 2.1e-10 (modal
    # coordinates of the Craig-Bampton pendulum, which peak at 1.1e-4);
    # beams up to 2.2e-10 (the skew beam's Craig-Bampton pendulum).
    "joint": 1e-9,
}


def require_modules():
    try:
        import numpy  # noqa: F401
        import scipy  # noqa: F401
        import exudyn  # noqa: F401
    except ImportError as e:
        sys.exit(f"exudyn_check.py: {e}; run `bash scripts/install_peers.sh` first")


# ---------------------------------------------------------------------------
# SID reader, from docs/sid.md.


class SidError(Exception):
    pass


ENTRY = re.compile(r"^(m0|m1)\(\s*(\d+)\s*,\s*(\d+)\s*(?:,\s*(\d+)\s*)?\)\s*=\s*(\S+)$", re.I)
TAYLOR_FIELDS = ("order", "nrow", "ncol", "nq", "nqn", "structure")


def read_sid(path):
    """Reads a SID file into a dict:

    mass, nq, names (ielastq), nodes (a list of dicts with 'rframe' and the
    Taylor objects 'origin', 'phi', 'psi', 'ap'), and the Taylor objects of
    the modal block by lower-case name ('mdcm', 'j', 'ct', 'cr', 'me', 'gr',
    'ge', 'oe', 'ksigma', 'ke', 'de'). A Taylor object is a dict with 'm0'
    (nrow x ncol array) and 'm1' (a list of nq arrays, empty for order 0).
    """
    import numpy as np

    with open(path) as f:
        lines = f.readlines()
    sid = {"nodes": [], "names": {}}
    stack = []  # open blocks: (name, line number, fields or entries)
    taylor = None

    def fail(number, message):
        raise SidError(f"{path}: line {number}: {message}")

    for number, raw in enumerate(lines, start=1):
        line = raw.strip()
        if not line or line[0] in "#!":
            continue
        low = line.lower()
        if taylor is not None:
            name, start, header, entries = taylor
            if low == f"end {name}":
                sid_taylor = build_taylor(np, path, name, start, header, entries)
                owner = stack[-1][0] if stack else None
                if owner == "node":
                    sid["nodes"][-1][name] = sid_taylor
                else:
                    sid[name] = sid_taylor
                taylor = None
                continue
            match = ENTRY.match(line)
            if match:
                kind, i, j, k, value = match.groups()
                entries.append((kind.lower(), int(i), int(j), int(k) if k else None, float(value), number))
                continue
            key, sep, value = line.partition("=")
            if sep and key.strip().lower() in TAYLOR_FIELDS:
                header[key.strip().lower()] = int(value)
                continue
            fail(number, f"unexpected line in block '{name}': {line}")
        if low.startswith("end "):
            name = low[4:].strip()
            if not stack or stack[-1][0] != name:
                fail(number, f"'end {name}' does not close the open block")
            stack.pop()
            continue
        if low in ("part", "new modal", "new frame", "new node", "refmod"):
            name = low.split()[-1]
            stack.append((name, number))
            if name == "node":
                sid["nodes"].append({})
            continue
        if "=" in line:
            key, _, value = line.partition("=")
            key, value = key.strip().lower(), value.strip()
            owner = stack[-1][0] if stack else None
            if owner == "refmod" and key == "mass":
                sid["mass"] = float(value)
            elif owner == "refmod" and key == "nelastq":
                sid["nq"] = int(value)
            elif owner == "refmod" and key.startswith("ielastq("):
                sid["names"][int(key[8:-1])] = value.strip("'")
            elif owner == "node" and key == "rframe":
                sid["nodes"][-1]["rframe"] = value.strip("'")
            else:
                fail(number, f"unknown field '{key}' in block '{owner}'")
            continue
        if re.fullmatch(r"[a-z][a-z0-9]*", low):
            taylor = (low, number, {}, [])
            continue
        fail(number, f"unexpected line: {line}")
    if taylor is not None:
        fail(len(lines), f"the file ends inside block '{taylor[0]}'")
    if stack:
        fail(len(lines), f"the file ends inside block '{stack[-1][0]}'")
    for key in ("mass", "nq", "mdcm", "j", "ct", "cr", "me", "gr", "ge", "oe", "ke"):
        if key not in sid:
            raise SidError(f"{path}: no '{key}'")
    if sorted(sid["names"]) != list(range(1, sid["nq"] + 1)):
        raise SidError(f"{path}: ielastq names do not match nelastq = {sid['nq']}")
    return sid


def build_taylor(np, path, name, start, header, entries):
    for field in ("order", "nrow", "ncol", "nq", "structure"):
        if field not in header:
            raise SidError(f"{path}: line {start}: block '{name}' has no '{field}'")
    order, nrow, ncol, nq = header["order"], header["nrow"], header["ncol"], header["nq"]
    m0 = np.zeros((nrow, ncol))
    m1 = [np.zeros((nrow, ncol)) for _ in range(nq)] if order == 1 else []
    counts = {"m0": 0, "m1": 0}
    for kind, i, j, k, value, number in entries:
        if not (1 <= i <= nrow and 1 <= j <= ncol):
            raise SidError(f"{path}: line {number}: index ({i}, {j}) outside {nrow} x {ncol}")
        if kind == "m0":
            m0[i - 1, j - 1] = value
        else:
            if order != 1 or k is None or not 1 <= k <= nq:
                raise SidError(f"{path}: line {number}: m1 entry in block '{name}' of order {order}")
            m1[k - 1][i - 1, j - 1] = value
        counts[kind] += 1
    if header["structure"] == 3:
        want = {"m0": nrow * ncol, "m1": nrow * ncol * nq if order == 1 else 0}
        if counts != want:
            raise SidError(f"{path}: block '{name}' (line {start}): {counts} entries, expected {want}")
    return {"m0": m0, "m1": m1}


# ---------------------------------------------------------------------------
# Exudyn's FFRF terms from the SID invariants.


def skew(v):
    return [[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]


def terms_from_sid(sid):
    """The inputs of ObjectFFRFreducedOrder from the SID (docs/sid.md).

    With P_kl = int Phi_k Phi_l^T dm and a~^T b~ = (a . b) I - b a^T:
      mPhitTPsi          = Ct^T                      (int Phi_k dm, columns)
      mPhitTPsiTilde     block k = (int Phi_k dm)~
      mXRefTildePsi      column k = int x0~^T Phi_k dm = -(Cr row k)
      mXRefTildePsiTilde block k = int x0~^T Phi_k~ dm = Gr_k / 2
      mPsiTildePsi       rows 3k..3k+2, column l = int Phi_l x Phi_k dm = row k of Cr m1_l
      mPsiTildePsiTilde  block (k, l) = tr(P_kl) I - P_kl^T, where the
                         symmetric part of P_kl comes from row k of Oe m1_l
                         (S = sym P - I tr P, so tr P = -tr S / 2) and the
                         skew part from int Phi_k x Phi_l dm = row l of Cr m1_k.
    """
    import numpy as np

    nq = sid["nq"]
    mass = sid["mass"]
    ct = sid["ct"]["m0"]
    cr = sid["cr"]["m0"]
    cr1 = sid["cr"]["m1"]
    gr = sid["gr"]["m0"]
    oe1 = sid["oe"]["m1"]
    t = {
        "mass": mass,
        "inertia": sid["j"]["m0"],
        "centerOfMass": sid["mdcm"]["m0"][:, 0] / mass,
        "massMatrixReduced": sid["me"]["m0"],
        "stiffnessMatrixReduced": sid["ke"]["m0"],
        "mPhitTPsi": ct.T.copy(),
        "mPhitTPsiTilde": np.zeros((3, 3 * nq)),
        "mXRefTildePsi": -cr.T,
        "mXRefTildePsiTilde": gr / 2.0,
        "mPsiTildePsi": np.zeros((3 * nq, nq)),
        "mPsiTildePsiTilde": np.zeros((3 * nq, 3 * nq)),
    }
    for k in range(nq):
        t["mPhitTPsiTilde"][:, 3 * k : 3 * k + 3] = skew(ct[k])
        for l in range(nq):
            t["mPsiTildePsi"][3 * k : 3 * k + 3, l] = cr1[l][k]
            s = oe1[l][k]
            sym = np.array([[s[0], s[3] / 2, s[5] / 2], [s[3] / 2, s[1], s[4] / 2], [s[5] / 2, s[4] / 2, s[2]]])
            trace = -np.trace(sym) / 2.0
            sym += trace * np.eye(3)
            cross = cr1[k][l]  # int Phi_k x Phi_l dm
            p = sym - 0.5 * np.array(skew(cross))
            t["mPsiTildePsiTilde"][3 * k : 3 * k + 3, 3 * l : 3 * l + 3] = trace * np.eye(3) - p.T
    return t


# ---------------------------------------------------------------------------
# The two Exudyn bodies.


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


NODE_TYPE = "NodeType.RotationRotationVector"


def fem_interface(work):
    import numpy as np
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface

    fem = FEMinterface()
    fem.nodes = {"Position": np.loadtxt(os.path.join(work, "nodes.txt"))}
    fem.massMatrix = read_mtx(os.path.join(work, "mass.mtx"))
    fem.stiffnessMatrix = read_mtx(os.path.join(work, "stiffness.mtx"))
    fem.modeBasis = {"matrix": read_mtx(os.path.join(work, "modes.mtx")), "type": "NormalModes"}
    # No rounding of the reduced matrices: the comparison is at round-off.
    return ObjectFFRFreducedOrderInterface(fem, rigidBodyNodeType=NODE_TYPE, roundMassMatrix=0, roundStiffnessMatrix=0)


def terms_from_fem(cms):
    return {
        "mass": cms.totalMass,
        "inertia": cms.inertiaLocal,
        "centerOfMass": cms.chiU,
        "massMatrixReduced": cms.massMatrixReduced,
        "stiffnessMatrixReduced": cms.stiffnessMatrixReduced,
        "mPhitTPsi": cms.mPhitTPsi,
        "mPhitTPsiTilde": cms.mPhitTPsiTilde,
        "mXRefTildePsi": cms.mXRefTildePsi,
        "mXRefTildePsiTilde": cms.mXRefTildePsiTilde,
        "mPsiTildePsi": cms.mPsiTildePsi,
        "mPsiTildePsiTilde": cms.mPsiTildePsiTilde,
    }


def cross_of(m):
    """int a x b dm from P = int a b^T dm."""
    import numpy as np

    return np.array([m[1, 2] - m[2, 1], m[2, 0] - m[0, 2], m[0, 1] - m[1, 0]])


def products_from_mass_matrix(mass_matrix, xref, phi):
    """The mass integrals of a mesh of points (3 translations per node) from
    its full M: mass, first[f] = int f dm and P[f, g] = int f g^T dm for
    the fields f, g in (x0, Phi_1, ..), each a vector of 3 values per node.
    P's entry (i, j) is the integral of a product of two scalar fields,
    component i of f and j of g, which M's x-x block (every node's x
    translation) integrates: each scalar field goes into the x rows."""
    import numpy as np

    n3 = len(xref)
    fields = [np.asarray(xref)] + [np.asarray(phi)[:, k] for k in range(phi.shape[1])]
    nf = len(fields)
    scalar = np.zeros((nf, 3, n3))
    for f, field in enumerate(fields):
        for i in range(3):
            scalar[f, i, 0::3] = field[i::3]
    m_scalar = np.array([[mass_matrix @ scalar[f, i] for i in range(3)] for f in range(nf)])
    one = np.zeros(n3)
    one[0::3] = 1.0
    mass = one @ mass_matrix @ one
    first = np.array([[one @ m_scalar[f, i] for i in range(3)] for f in range(nf)])
    p = np.einsum("fik,gjk->fgij", scalar, m_scalar)
    return mass, first, p


def terms_from_products(mass, first, p, ke):
    """The inputs of ObjectFFRFreducedOrder from the mass integrals (with
    a~^T b~ = (a . b) I - b a^T, P_fg = int f g^T dm, field 0 = x0):
      inertia            tr(P00) I - P00
      massMatrixReduced  (k, l) = tr(P_kl)
      mPhitTPsi          column k = int Phi_k dm
      mPhitTPsiTilde     block k = (int Phi_k dm)~
      mXRefTildePsi      column k = int x0~^T Phi_k dm = -int x0 x Phi_k dm
      mXRefTildePsiTilde block k = int x0~^T Phi_k~ dm = tr(P0k) I - Pk0
      mPsiTildePsi       rows 3k..3k+2, column l = int Phi_l x Phi_k dm
      mPsiTildePsiTilde  block (k, l) = tr(P_kl) I - P_lk
    """
    import numpy as np

    nq = p.shape[0] - 1
    eye = np.eye(3)
    t = {
        "mass": mass,
        "inertia": np.trace(p[0, 0]) * eye - p[0, 0],
        "centerOfMass": first[0] / mass,
        "massMatrixReduced": np.array([[np.trace(p[k, l]) for l in range(1, nq + 1)] for k in range(1, nq + 1)]),
        "stiffnessMatrixReduced": np.asarray(ke),
        "mPhitTPsi": first[1:].T.copy(),
        "mPhitTPsiTilde": np.hstack([np.array(skew(first[k])) for k in range(1, nq + 1)]),
        "mXRefTildePsi": np.array([-cross_of(p[0, k]) for k in range(1, nq + 1)]).T,
        "mXRefTildePsiTilde": np.hstack([np.trace(p[0, k]) * eye - p[k, 0] for k in range(1, nq + 1)]),
        "mPsiTildePsi": np.zeros((3 * nq, nq)),
        "mPsiTildePsiTilde": np.zeros((3 * nq, 3 * nq)),
    }
    for k in range(nq):
        for l in range(nq):
            t["mPsiTildePsi"][3 * k : 3 * k + 3, l] = cross_of(p[l + 1, k + 1])
            block = np.trace(p[k + 1, l + 1]) * eye - p[l + 1, k + 1]
            t["mPsiTildePsiTilde"][3 * k : 3 * k + 3, 3 * l : 3 * l + 3] = block
    return t


class Reference:
    """Body B: terms, mesh (Phi's translations at the nodes and their
    positions, flattened) and mass integrals (mass, first, P), built apart
    from flexbody's invariants (see the module docs)."""

    def __init__(self, work, ours):
        import numpy as np

        mass_matrix = read_mtx(os.path.join(work, "mass.mtx"))
        stiffness = read_mtx(os.path.join(work, "stiffness.mtx"))
        phi = read_mtx(os.path.join(work, "modes.mtx"))
        self.beam = bool(ours.get("beam", False))
        if self.beam:
            sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
            import beam_invariants

            with open(os.path.join(work, "beam.json")) as f:
                case = json.load(f)
            self.mass, self.first, self.p, _ = beam_invariants.products(case)
            ke = phi.T @ (stiffness @ phi)
            self.terms = terms_from_products(self.mass, self.first, self.p, 0.5 * (ke + ke.T))
            # The mesh: Phi's translations, 3 of the 6 rows per node.
            rows = np.array([6 * n + i for n in range(phi.shape[0] // 6) for i in range(3)])
            self.mode_basis = phi[rows]
            self.xref = np.loadtxt(os.path.join(work, "nodes.txt")).reshape(-1)
            # The integrals' reduced mass against Phi^T M Phi of the beam's
            # consistent mass matrix.
            self.me_full = phi.T @ (mass_matrix @ phi)
        else:
            cms = fem_interface(work)
            self.terms = terms_from_fem(cms)
            self.mode_basis = np.asarray(cms.modeBasis)
            self.xref = np.asarray(cms.xRef)
            self.mass, self.first, self.p = products_from_mass_matrix(mass_matrix, self.xref, self.mode_basis)
            self.me_full = None

    def length(self):
        """The largest distance of a node from the frame origin."""
        import numpy as np

        return np.max(np.linalg.norm(self.xref.reshape(-1, 3), axis=1))


def add_body(mbs, terms, mode_basis, reference_positions, angular_velocity):
    """An ObjectFFRFreducedOrder with a rotation-vector frame node at the
    origin; returns (object, rigid-body node, modal node)."""
    import numpy as np
    import exudyn as exu
    import exudyn.itemInterface as eii
    from exudyn.rigidBodyUtilities import GetRigidBodyNode

    nq = terms["massMatrixReduced"].shape[0]
    node = GetRigidBodyNode(
        nodeType=exu.NodeType.RotationRotationVector,
        position=[0, 0, 0],
        velocity=[0, 0, 0],
        rotationMatrix=np.eye(3),
        angularVelocity=angular_velocity,
    )
    n_rigid = mbs.AddNode(node)
    n_modal = mbs.AddNode(
        eii.NodeGenericODE2(
            numberOfODE2Coordinates=nq,
            referenceCoordinates=[0] * nq,
            initialCoordinates=[0] * nq,
            initialCoordinates_t=[0] * nq,
        )
    )

    def container(a):
        c = exu.MatrixContainer()
        c.SetWithDenseMatrix(np.asarray(a), useDenseMatrix=False)
        return c

    body = mbs.AddObject(
        eii.ObjectFFRFreducedOrder(
            nodeNumbers=[n_rigid, n_modal],
            massMatrixReduced=container(terms["massMatrixReduced"]),
            stiffnessMatrixReduced=container(terms["stiffnessMatrixReduced"]),
            dampingMatrixReduced=[],
            modeBasis=np.asarray(mode_basis),
            referencePositions=np.asarray(reference_positions),
            mass=terms["mass"],
            inertia=np.asarray(terms["inertia"]),
            centerOfMass=np.asarray(terms["centerOfMass"]),
            mPsiTildePsi=terms["mPsiTildePsi"],
            mPsiTildePsiTilde=terms["mPsiTildePsiTilde"],
            mPhitTPsi=terms["mPhitTPsi"],
            mPhitTPsiTilde=terms["mPhitTPsiTilde"],
            mXRefTildePsi=terms["mXRefTildePsi"],
            mXRefTildePsiTilde=terms["mXRefTildePsiTilde"],
            computeFFRFterms=True,
        )
    )
    return body, n_rigid, n_modal


def settings(step, steps):
    import exudyn as exu

    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = steps
    s.timeIntegration.endTime = steps * step
    s.timeIntegration.generalizedAlpha.useNewmark = True
    s.timeIntegration.generalizedAlpha.newmarkBeta = 0.25
    s.timeIntegration.generalizedAlpha.newmarkGamma = 0.5
    s.timeIntegration.generalizedAlpha.useIndex2Constraints = True
    s.timeIntegration.generalizedAlpha.computeInitialAccelerations = True
    s.timeIntegration.newton.relativeTolerance = 1e-14
    s.timeIntegration.newton.absoluteTolerance = 1e-16
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.writePeriod = step
    return s


def fixed_frame_run(terms, mode_basis, reference_positions, tip, ours):
    """Elastic frequencies and the tip's uz history with the frame held
    fixed (its six coordinates constrained)."""
    import numpy as np
    import exudyn as exu
    import exudyn.itemInterface as eii

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    body, n_rigid, _ = add_body(mbs, terms, mode_basis, reference_positions, [0, 0, 0])
    ground = mbs.AddNode(eii.NodePointGround())
    m_ground = mbs.AddMarker(eii.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))
    for c in range(6):
        m = mbs.AddMarker(eii.MarkerNodeCoordinate(nodeNumber=n_rigid, coordinate=c))
        mbs.AddObject(eii.CoordinateConstraint(markerNumbers=[m_ground, m]))
    m_tip = mbs.AddMarker(eii.MarkerSuperElementPosition(bodyNumber=body, meshNodeNumbers=[tip], weightingFactors=[1.0]))
    force = ours["force"]
    amp, freq = force["amplitude"], force["frequency_hz"]
    direction = np.array(force["direction"])

    def load(mbs, t, load_vector):
        return list(amp * np.sin(2 * np.pi * freq * t) * direction)

    mbs.AddLoad(eii.LoadForceVector(markerNumber=m_tip, loadVector=[0, 0, 0], loadVectorUserFunction=load))
    sensor = mbs.AddSensor(
        eii.SensorSuperElement(
            bodyNumber=body, meshNodeNumber=tip, storeInternal=True, outputVariableType=exu.OutputVariableType.Displacement
        )
    )
    mbs.Assemble()
    # The frame's six coordinates come first (the rigid-body node is node 0).
    values, _ = mbs.ComputeODE2Eigenvalues(
        constrainedCoordinates=list(range(6)), ignoreAlgebraicEquations=True, useAbsoluteValues=True
    )
    hz = np.sort(np.sqrt(np.abs(values)) / (2 * np.pi))
    step = ours["step"]
    mbs.SolveDynamic(settings(step, int(round(ours["duration"] / step))))
    data = mbs.GetSensorStoredData(sensor)
    return hz, data[:, 0], data[:, 3]


def tumble_run(terms, mode_basis, reference_positions, tip, omega, step, steps):
    """Free body, initial angular velocity `omega`, no load: histories of
    the tip position, the frame's coordinates and the modal coordinates."""
    import exudyn as exu
    import exudyn.itemInterface as eii

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    body, n_rigid, n_modal = add_body(mbs, terms, mode_basis, reference_positions, omega)
    sensors = {
        "tip position": mbs.AddSensor(
            eii.SensorSuperElement(
                bodyNumber=body, meshNodeNumber=tip, storeInternal=True, outputVariableType=exu.OutputVariableType.Position
            )
        ),
        "frame coordinates": mbs.AddSensor(
            eii.SensorNode(nodeNumber=n_rigid, storeInternal=True, outputVariableType=exu.OutputVariableType.Coordinates)
        ),
        "modal coordinates": mbs.AddSensor(
            eii.SensorNode(nodeNumber=n_modal, storeInternal=True, outputVariableType=exu.OutputVariableType.Coordinates)
        ),
    }
    mbs.Assemble()
    mbs.SolveDynamic(settings(step, steps))
    return {name: mbs.GetSensorStoredData(s)[:, 1:] for name, s in sensors.items()}


def tumble_conservation(reference, omega, step, duration):
    """Free tumble of body B: the largest drift of the kinetic plus strain
    energy, of the angular momentum about the origin and of the linear
    momentum, each relative to its initial size. From the frame's motion
    (position r, velocity v, angular velocity w, rotation R) and the modal
    coordinates q, q' alone, with the mass integrals and Ke (apart from any
    FFRF term): in the frame, a point moves with V + w x s + s', where V =
    R^T v, s = x0 + Phi q and s' = Phi q', so with c = (1, q), c' = (0, q')
    and S = sum c_f c_g P_fg, C = sum c_f c'_g P_fg, D = sum c'_f c'_g P_fg:
      T = m V.V / 2 + V . (w x int s) + V . int s' + w . (tr S I - S) w / 2
          + w . int s x s' + tr D / 2,
      L = R (m V + w x int s + int s'),
      H = r x L + R (int s x V + (tr S I - S) w + int s x s')."""
    import numpy as np
    import exudyn as exu
    import exudyn.itemInterface as eii

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    _, n_rigid, n_modal = add_body(mbs, reference.terms, reference.mode_basis, reference.xref, omega)

    def sensor(node, kind):
        return mbs.AddSensor(eii.SensorNode(nodeNumber=node, storeInternal=True, outputVariableType=kind))

    ovt = exu.OutputVariableType
    s = {
        "r": sensor(n_rigid, ovt.Position),
        "v": sensor(n_rigid, ovt.Velocity),
        "w": sensor(n_rigid, ovt.AngularVelocity),
        "R": sensor(n_rigid, ovt.RotationMatrix),
        "q": sensor(n_modal, ovt.Coordinates),
        "qd": sensor(n_modal, ovt.Coordinates_t),
    }
    mbs.Assemble()
    mbs.SolveDynamic(settings(step, int(round(duration / step))))
    d = {k: mbs.GetSensorStoredData(v)[:, 1:] for k, v in s.items()}
    mass, first, p = reference.mass, reference.first, reference.p
    ke = np.asarray(reference.terms["stiffnessMatrixReduced"])
    eye = np.eye(3)
    energy, angular, linear = [], [], []
    for i in range(len(d["r"])):
        rot = d["R"][i].reshape(3, 3)
        q, qd = d["q"][i], d["qd"][i]
        c, cd = np.concatenate([[1.0], q]), np.concatenate([[0.0], qd])
        big_s = np.einsum("f,g,fgij->ij", c, c, p)
        big_c = np.einsum("f,g,fgij->ij", c, cd, p)
        big_d = np.einsum("f,g,fgij->ij", cd, cd, p)
        s1, sd1 = c @ first, cd @ first
        v, w = rot.T @ d["v"][i], rot.T @ d["w"][i]
        jw = (np.trace(big_s) * eye - big_s) @ w
        spin = cross_of(big_c)
        kinetic = 0.5 * mass * v @ v + v @ np.cross(w, s1) + v @ sd1 + 0.5 * w @ jw + w @ spin + 0.5 * np.trace(big_d)
        momentum = rot @ (mass * v + np.cross(w, s1) + sd1)
        energy.append(kinetic + 0.5 * q @ ke @ q)
        linear.append(momentum)
        angular.append(np.cross(d["r"][i], momentum) + rot @ (np.cross(s1, v) + jw + spin))
    energy, angular, linear = np.array(energy), np.array(angular), np.array(linear)
    drift = lambda a: np.max(np.linalg.norm(np.atleast_2d((a - a[0]).T).T, axis=-1)) / np.linalg.norm(a[0])
    return drift(energy), drift(angular), drift(linear)


def joint_run(terms, mode_basis, reference_positions, tip, tip_position, clamped, step, steps):
    """Large motion under a joint and gravity (50 g along -y), initial
    angular velocity 40 rad/s about z: a free body swings from its tip node
    on a spherical joint (frame velocity such that the tip starts at
    rest); a clamped one turns on a hub, a revolute joint about z at the
    frame origin. Histories of the frame's and the modal coordinates."""
    import numpy as np
    import exudyn as exu
    import exudyn.itemInterface as eii

    omega = np.array([0.0, 0.0, 40.0])
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    body, n_rigid, n_modal = add_body(mbs, terms, mode_basis, reference_positions, list(omega))
    if clamped:
        ground = mbs.AddObject(eii.ObjectGround(referencePosition=[0, 0, 0]))
        m_ground = mbs.AddMarker(eii.MarkerBodyRigid(bodyNumber=ground, localPosition=[0, 0, 0]))
        m_hub = mbs.AddMarker(eii.MarkerNodeRigid(nodeNumber=n_rigid))
        mbs.AddObject(eii.GenericJoint(markerNumbers=[m_ground, m_hub], constrainedAxes=[1, 1, 1, 1, 1, 0]))
    else:
        velocities = mbs.GetNodeParameter(n_rigid, "initialVelocities")
        start = list(-np.cross(omega, tip_position)) + list(velocities[3:])
        mbs.SetNodeParameter(n_rigid, "initialVelocities", start)
        ground = mbs.AddObject(eii.ObjectGround(referencePosition=list(tip_position)))
        m_ground = mbs.AddMarker(eii.MarkerBodyPosition(bodyNumber=ground, localPosition=[0, 0, 0]))
        m_tip = mbs.AddMarker(eii.MarkerSuperElementPosition(bodyNumber=body, meshNodeNumbers=[tip], weightingFactors=[1.0]))
        mbs.AddObject(eii.SphericalJoint(markerNumbers=[m_ground, m_tip]))
    m_mass = mbs.AddMarker(eii.MarkerBodyMass(bodyNumber=body))
    mbs.AddLoad(eii.LoadMassProportional(markerNumber=m_mass, loadVector=[0, -50 * 9.81, 0]))
    ovt = exu.OutputVariableType.Coordinates
    frame = mbs.AddSensor(eii.SensorNode(nodeNumber=n_rigid, storeInternal=True, outputVariableType=ovt))
    modal = mbs.AddSensor(eii.SensorNode(nodeNumber=n_modal, storeInternal=True, outputVariableType=ovt))
    mbs.Assemble()
    mbs.SolveDynamic(settings(step, steps))
    return {
        "frame coordinates": mbs.GetSensorStoredData(frame)[:, 1:],
        "modal coordinates": mbs.GetSensorStoredData(modal)[:, 1:],
    }


# ---------------------------------------------------------------------------


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    require_modules()
    import numpy as np
    import exudyn as exu

    work = argv[1]
    with open(os.path.join(work, "flexbody.json")) as f:
        ours = json.load(f)
    sid = read_sid(os.path.join(work, "body.sid"))
    reference = Reference(work, ours)
    from_sid = terms_from_sid(sid)
    from_fem = reference.terms
    results = []  # (what, measured, tolerance)
    print(f"exudyn {exu.__version__}, numpy {np.__version__}; case {ours.get('case', '?')}")

    # 1. The FFRF terms. Scales: the mass for the rigid terms, the modal
    # stiffness for Ke, and for the terms with mode shapes the magnitude a
    # unit-modal-mass field gives: sqrt(m) per Phi, and L (the largest node
    # distance from the origin) per x0.
    mass = reference.mass
    length = reference.length()
    scales = {
        "mass": mass,
        "inertia": mass * length**2,
        "centerOfMass": length,
        "massMatrixReduced": 1.0,
        "stiffnessMatrixReduced": np.max(np.abs(from_fem["stiffnessMatrixReduced"])),
        "mPhitTPsi": np.sqrt(mass),
        "mPhitTPsiTilde": np.sqrt(mass),
        "mXRefTildePsi": np.sqrt(mass) * length,
        "mXRefTildePsiTilde": np.sqrt(mass) * length,
        "mPsiTildePsi": 1.0,
        "mPsiTildePsiTilde": 1.0,
    }
    body_b = "the beam's integrals" if reference.beam else "FEMinterface's"
    for name, scale in scales.items():
        d = np.max(np.abs(np.asarray(from_sid[name]) - np.asarray(from_fem[name]))) / scale
        results.append((f"{name} from the SID against {body_b} (/ {scale:.3g})", d, "terms"))
    if not reference.beam:
        # The formulas that build the beam's body B, on the solid's M,
        # against FEMinterface's.
        from_products = terms_from_products(reference.mass, reference.first, reference.p, from_fem["stiffnessMatrixReduced"])
        for name, scale in scales.items():
            d = np.max(np.abs(np.asarray(from_products[name]) - np.asarray(from_fem[name]))) / scale
            results.append((f"{name} from the mass integrals against FEMinterface's (/ {scale:.3g})", d, "terms"))
    if reference.me_full is not None:
        d = np.max(np.abs(from_fem["massMatrixReduced"] - reference.me_full))
        results.append(("massMatrixReduced of the beam's integrals against Phi^T M Phi", d, "terms"))

    # The SID body's mesh: its interface node; the FEM body's: all nodes.
    tip_id = str(ours["tip_node_id"])
    node = next((n for n in sid["nodes"] if n["rframe"] == tip_id), None)
    if node is None:
        print(f"exudyn check: the SID has no node '{tip_id}'", file=sys.stderr)
        return 1
    sid_basis = node["phi"]["m0"]  # 3 x nq
    sid_xref = node["origin"]["m0"][:, 0]
    fem_tip = ours["tip_node_index"]
    fem_basis, fem_xref = reference.mode_basis, reference.xref
    phi_tip = fem_basis[3 * fem_tip : 3 * fem_tip + 3]
    results.append(("tip mode shapes, SID against modes.mtx", np.max(np.abs(sid_basis - phi_tip)) / np.max(np.abs(phi_tip)), "terms"))

    # 2. and 3. Frame held fixed.
    ref_hz = np.array(ours["frequencies_hz"])
    sid_hz, t_sid, uz_sid = fixed_frame_run(from_sid, sid_basis, sid_xref, 0, ours)
    fem_hz, t_fem, uz_fem = fixed_frame_run(from_fem, fem_basis, fem_xref, fem_tip, ours)
    names_hz = np.array([float(re.search(r":\s*(\S+)\s*Hz", sid["names"][k + 1]).group(1)) for k in range(sid["nq"])])
    print("frequencies (Hz), flexbody:   ", " ".join(f"{f:.6f}" for f in ref_hz))
    print("frequencies (Hz), Exudyn SID: ", " ".join(f"{f:.6f}" for f in sid_hz))
    for what, hz in (("SID body", sid_hz), ("FEM body", fem_hz)):
        if len(hz) != len(ref_hz):
            print(f"exudyn check: {what} has {len(hz)} elastic modes, flexbody {len(ref_hz)}", file=sys.stderr)
            return 1
        key = "frequency_beam" if reference.beam else "frequency"
        results.append((f"frequencies, Exudyn {what} against flexbody", np.max(np.abs(hz - ref_hz) / ref_hz), key))
    results.append(("frequencies in the SID's ielastq names", np.max(np.abs(names_hz - ref_hz) / ref_hz), "names"))

    t_ref, uz_ref = np.array(ours["times"]), np.array(ours["tip_uz"])
    if len(t_sid) != len(t_ref) or np.max(np.abs(t_sid - t_ref)) > 1e-9 * t_ref[-1]:
        print(f"exudyn check: Exudyn's {len(t_sid)} output times are not flexbody's {len(t_ref)}", file=sys.stderr)
        return 1
    peak = np.max(np.abs(uz_ref))
    print(f"tip uz under the harmonic force: peak {peak:.6e} m over {len(t_ref) - 1} steps")
    key, key_fem = ("response_beam", "response_beam") if reference.beam else ("response", "response_fem")
    results.append(("tip uz, Exudyn SID body against flexbody (/ peak)", np.max(np.abs(uz_sid - uz_ref)) / peak, key))
    results.append(("tip uz, Exudyn SID body against FEM body (/ peak)", np.max(np.abs(uz_sid - uz_fem)) / peak, key_fem))

    # 4. Free tumble about all three axes, fast enough (tip speed ~200 m/s)
    # that the centrifugal and gyroscopic terms deform the bar (modal
    # coordinates ~3.5e-4) and the terms of second order in Phi count. At
    # most 12 % of the lowest elastic angular frequency (the bar's is 3 %,
    # the skew beam's 12 %; the 2 m clamped beam's 22.9 Hz takes a ninth of
    # the rate): spun near it, a linear elastic body diverges.
    omega = np.array([60.0, 150.0, 300.0])
    omega = list(omega * min(1.0, 0.12 * 2 * np.pi * ref_hz[0] / np.linalg.norm(omega)))
    step, steps = 2.5e-5, 2000
    sid_tumble = tumble_run(from_sid, sid_basis, sid_xref, 0, omega, step, steps)
    fem_tumble = tumble_run(from_fem, fem_basis, fem_xref, fem_tip, omega, step, steps)
    for name in sid_tumble:
        a, b = sid_tumble[name], fem_tumble[name]
        d = np.max(np.abs(a - b)) / np.max(np.abs(b))
        rates = ", ".join(f"{w:.4g}" for w in omega)
        results.append((f"tumble ({rates}) rad/s, {steps * step:g} s: {name}, SID against FEM (/ peak)", d, "tumble"))
    q_peak = np.max(np.abs(fem_tumble["modal coordinates"]))
    print(f"tumble: largest modal coordinate {q_peak:.3e} (unit modal mass)")

    # 5. Energy and momentum of the FEM body's tumble, from the mass
    # integrals.
    coarse = tumble_conservation(reference, omega, step, steps * step)
    fine = tumble_conservation(reference, omega, step / 2, steps * step)
    for k, name in enumerate(("energy", "angular momentum", "linear momentum")):
        print(f"tumble: {name} drift {coarse[k]:.3e} at {step:g} s, {fine[k]:.3e} at {step / 2:g} s")
        results.append((f"tumble: {name} drift at h/2 over drift at h, against 1/4", abs(fine[k] / coarse[k] - 0.25), "order"))

    # 6. A pendulum from the tip node, or a clamped body on a hub.
    clamped = bool(ours.get("clamped", False))
    what = "hub" if clamped else "pendulum"
    tip_position = fem_xref.reshape(-1, 3)[fem_tip]
    sid_joint = joint_run(from_sid, sid_basis, sid_xref, 0, tip_position, clamped, 1e-4, 500)
    fem_joint = joint_run(from_fem, fem_basis, fem_xref, fem_tip, tip_position, clamped, 1e-4, 500)
    turned = np.max(np.abs(fem_joint["frame coordinates"][:, 3:]))
    print(f"{what}: largest rotation coordinate {turned:.3f} rad, largest modal coordinate "
          f"{np.max(np.abs(fem_joint['modal coordinates'])):.3e}")
    for name in sid_joint:
        a, b = sid_joint[name], fem_joint[name]
        d = np.max(np.abs(a - b)) / np.max(np.abs(b))
        results.append((f"{what} under 50 g, 0.05 s: {name}, SID against FEM (/ peak)", d, "joint"))

    ok = True
    for what, measured, key in results:
        good = measured <= TOLERANCES[key]
        ok &= bool(good)
        print(f"  {what}: {measured:.2e} (allowed {TOLERANCES[key]:.0e}){'' if good else '  FAILED'}")
    print("exudyn check:", "OK" if ok else "FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
