"""A reduced body in Exudyn: :func:`add_body` adds a flexbody
:class:`~flexbody.Body` to an Exudyn system as an
``ObjectFFRFreducedOrder`` with its floating-frame node and its modal node,
its floating-frame terms taken from flexbody's invariants (the SID's
content, docs/sid.md) rather than recomputed by Exudyn's FEMinterface.

    import exudyn, flexbody, flexbody.exudyn
    body = flexbody.read("arm.inp").reduce("craig-bampton", modes=6)
    SC = exudyn.SystemContainer(); mbs = SC.AddSystem()
    arm = flexbody.exudyn.add_body(mbs, body)
    pivot = arm.position_marker(9001)        # an interface node of the body
    ...

The mesh nodes Exudyn knows are the body's interface nodes (the frame
nodes of the SID), in ascending id, then the further FE nodes ``nodes``
names; :attr:`ExudynBody.mesh_nodes` maps an FE node id to Exudyn's mesh
node number.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Optional, Sequence

import numpy as np


def _skew(v) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def ffrf_terms(invariants: dict) -> dict:
    """The inputs of Exudyn's ``ObjectFFRFreducedOrder`` from flexbody's
    floating-frame invariants (``Body.invariants()``).

    With ``P_kl = int Phi_k Phi_l^T dm`` and ``a~^T b~ = (a . b) I - b a^T``:
    ``mPhitTPsi = Ct^T``; ``mPhitTPsiTilde`` block k is ``(int Phi_k dm)~``;
    ``mXRefTildePsi`` column k is ``-(Cr row k)``; ``mXRefTildePsiTilde`` is
    ``Gr / 2``; ``mPsiTildePsi`` rows 3k..3k+2, column l are row k of
    ``Cr1_l``; ``mPsiTildePsiTilde`` block (k, l) is ``tr(P_kl) I - P_kl^T``,
    the symmetric part of ``P_kl`` from row k of ``Oe1_l`` and its skew part
    from row l of ``Cr1_k``.
    """
    inv = invariants
    nq = inv["me"].shape[0]
    mass = inv["mass"]
    ct, cr, cr1, oe1 = inv["ct"], inv["cr"], inv["cr1"], inv["oe1"]
    t = {
        "mass": mass,
        "inertia": np.asarray(inv["j"]),
        "centerOfMass": np.asarray(inv["md_cm"]) / mass,
        "massMatrixReduced": np.asarray(inv["me"]),
        "stiffnessMatrixReduced": np.asarray(inv["ke"]),
        "dampingMatrixReduced": None if inv["de"] is None else np.asarray(inv["de"]),
        "mPhitTPsi": np.ascontiguousarray(ct.T),
        "mPhitTPsiTilde": np.zeros((3, 3 * nq)),
        "mXRefTildePsi": np.ascontiguousarray(-cr.T),
        "mXRefTildePsiTilde": np.asarray(inv["gr"]) / 2.0,
        "mPsiTildePsi": np.zeros((3 * nq, nq)),
        "mPsiTildePsiTilde": np.zeros((3 * nq, 3 * nq)),
    }
    for k in range(nq):
        t["mPhitTPsiTilde"][:, 3 * k : 3 * k + 3] = _skew(ct[k])
        for l in range(nq):
            t["mPsiTildePsi"][3 * k : 3 * k + 3, l] = cr1[l][k]
            s = oe1[l][k]
            sym = np.array(
                [[s[0], s[3] / 2, s[5] / 2], [s[3] / 2, s[1], s[4] / 2], [s[5] / 2, s[4] / 2, s[2]]]
            )
            trace = -np.trace(sym) / 2.0
            sym += trace * np.eye(3)
            p = sym - 0.5 * _skew(cr1[k][l])
            t["mPsiTildePsiTilde"][3 * k : 3 * k + 3, 3 * l : 3 * l + 3] = trace * np.eye(3) - p.T
    return t


@dataclass
class ExudynBody:
    """What :func:`add_body` added: the object, its floating-frame node and
    modal node, and the FE node id of each Exudyn mesh node."""

    mbs: object
    object: int
    frame_node: int
    modal_node: int
    mesh_nodes: Dict[int, int]
    elastic_hz: np.ndarray

    def mesh_node(self, node: int) -> int:
        """Exudyn's mesh node number of FE node ``node`` (an interface node)."""
        try:
            return self.mesh_nodes[int(node)]
        except KeyError:
            raise KeyError(
                f"node {node} is not an interface node of the body; Exudyn knows "
                f"{sorted(self.mesh_nodes)}"
            ) from None

    def position_marker(self, node: int) -> int:
        """A ``MarkerSuperElementPosition`` at FE node ``node``."""
        import exudyn.itemInterface as eii

        return self.mbs.AddMarker(
            eii.MarkerSuperElementPosition(
                bodyNumber=self.object, meshNodeNumbers=[self.mesh_node(node)], weightingFactors=[1.0]
            )
        )

    def frame_marker(self) -> int:
        """A ``MarkerNodeRigid`` on the floating frame."""
        import exudyn.itemInterface as eii

        return self.mbs.AddMarker(eii.MarkerNodeRigid(nodeNumber=self.frame_node))

    def mass_marker(self) -> int:
        """A ``MarkerBodyMass`` (for gravity: ``LoadMassProportional``)."""
        import exudyn.itemInterface as eii

        return self.mbs.AddMarker(eii.MarkerBodyMass(bodyNumber=self.object))


def add_body(
    mbs,
    body,
    position: Sequence[float] = (0.0, 0.0, 0.0),
    rotation: Optional[np.ndarray] = None,
    velocity: Sequence[float] = (0.0, 0.0, 0.0),
    angular_velocity: Sequence[float] = (0.0, 0.0, 0.0),
    damping: bool = True,
    nodes: Sequence[int] = (),
) -> ExudynBody:
    """Adds ``body`` (a :class:`flexbody.Body` reduced in Python, which knows
    its model) to the Exudyn system ``mbs``: a rotation-vector rigid node
    for the floating frame at ``position`` with ``rotation`` (3 x 3; the
    FE model's axes by default) and initial ``velocity`` and
    ``angular_velocity`` (global), a generic ODE2 node for the elastic
    coordinates, and an ``ObjectFFRFreducedOrder`` with flexbody's
    floating-frame terms (``computeFFRFterms=True``). The body's damping
    ``De`` is taken where it has one and ``damping`` is true.

    Exudyn's mesh nodes (for markers) are the interface nodes, then
    ``nodes``: further FE nodes, with their translations' rows of the
    elastic modes."""
    import exudyn as exu
    import exudyn.itemInterface as eii
    from exudyn.rigidBodyUtilities import GetRigidBodyNode

    inv = body.invariants()
    terms = ffrf_terms(inv)
    nq = terms["massMatrixReduced"].shape[0]
    mesh = [(int(n["id"]), n["position"], n["translations"]) for n in inv["nodes"]]
    known = {m[0] for m in mesh}
    extra = [int(n) for n in nodes if int(n) not in known]
    if extra:
        ids, xyz = body.nodes()
        where = {int(i): k for k, i in enumerate(ids)}
        dofs = body.dofs
        rows = {(int(n), int(d)): k for k, (n, d) in enumerate(dofs)}
        shapes = inv["elastic_shapes"]
        for node in extra:
            if node not in where:
                raise KeyError(f"node {node} is not a node of the body's model")
            t = np.zeros((3, nq))
            for axis in range(3):
                k = rows.get((node, axis + 1))
                if k is not None:
                    t[axis] = shapes[k]
            mesh.append((node, xyz[where[node]], t))
    basis = np.zeros((3 * len(mesh), nq))
    reference = np.zeros(3 * len(mesh))
    for i, (_, x0, translations) in enumerate(mesh):
        basis[3 * i : 3 * i + 3, :] = translations
        reference[3 * i : 3 * i + 3] = x0
    rotation = np.eye(3) if rotation is None else np.asarray(rotation, dtype=float)
    frame = mbs.AddNode(
        GetRigidBodyNode(
            nodeType=exu.NodeType.RotationRotationVector,
            position=list(position),
            velocity=list(velocity),
            rotationMatrix=rotation,
            angularVelocity=list(angular_velocity),
        )
    )
    modal = mbs.AddNode(
        eii.NodeGenericODE2(
            numberOfODE2Coordinates=nq,
            referenceCoordinates=[0.0] * nq,
            initialCoordinates=[0.0] * nq,
            initialCoordinates_t=[0.0] * nq,
        )
    )

    def container(a):
        c = exu.MatrixContainer()
        c.SetWithDenseMatrix(np.asarray(a), useDenseMatrix=False)
        return c

    de = terms["dampingMatrixReduced"]
    obj = mbs.AddObject(
        eii.ObjectFFRFreducedOrder(
            nodeNumbers=[frame, modal],
            massMatrixReduced=container(terms["massMatrixReduced"]),
            stiffnessMatrixReduced=container(terms["stiffnessMatrixReduced"]),
            dampingMatrixReduced=container(de) if (damping and de is not None) else [],
            modeBasis=basis,
            referencePositions=reference,
            mass=terms["mass"],
            inertia=terms["inertia"],
            centerOfMass=terms["centerOfMass"],
            mPsiTildePsi=terms["mPsiTildePsi"],
            mPsiTildePsiTilde=terms["mPsiTildePsiTilde"],
            mPhitTPsi=terms["mPhitTPsi"],
            mPhitTPsiTilde=terms["mPhitTPsiTilde"],
            mXRefTildePsi=terms["mXRefTildePsi"],
            mXRefTildePsiTilde=terms["mXRefTildePsiTilde"],
            computeFFRFterms=True,
        )
    )
    mesh_nodes = {m[0]: i for i, m in enumerate(mesh)}
    return ExudynBody(mbs, obj, frame, modal, mesh_nodes, np.asarray(inv["elastic_hz"]))
