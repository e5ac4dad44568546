#!/usr/bin/env python3
"""The floating-frame invariants of a beam body, integrated with numpy apart
from flexbody's code, against flexbody's (tests/flexbody/sid.rs writes the
cases).

usage: scripts/beam_invariants.py CASE.json...

A case holds the beam mesh (nodes with coordinates, elements with section,
material, theory, rotary inertia and orientation vector), the elastic mode
shapes Phi at every DOF of every node (ux uy uz rx ry rz, zero where
fixed), and flexbody's invariants. The body: each element a straight beam
whose centreline moves with Przemieniecki's shape functions (Theory of
Matrix Structural Analysis, 1968, sec. 11.6; for Timoshenko beams their
shear-dependent form, with phi = 12 E I / (G A_s L^2)), axial displacement
and twist linear; a section at the centreline point x_g turns as a rigid
body, so a material point x_g + r moves by u + theta x r. Mass per length
rho A; the section's rotary inertia per length is the polar rho (Iy + Iz)
always and the bending rho Iy, rho Iz with rotary inertia (what the beam's
mass matrix holds), as the tensor J_s, with int r r^T dm = tr(J_s)/2 I - J_s.
Six Gauss points per element (numpy's Gauss-Legendre), exact for these
polynomials.

Products P(a, b) = int a b^T dm of the fields a, b in {x0, Phi_k} give the
invariants (docs/sid.md):
  mass, mdCM = int x0, mdCM m1_k = Ct_k = int Phi_k, J = tr(P00) I - P00,
  J m1_k = 2 tr(P0k) I - P0k - P0k^T, Cr_k = int x0 x Phi_k,
  Cr m1 (for q_l, row k) = int Phi_l x Phi_k, Me = Phi^T M Phi (from the
  same products, with the rotations), Gr block k = -2 int x0~ Phi_k~,
  Ge block l row k = -2 int Phi_k x Phi_l,
  Oe row k from S = sym(P(Phi_k, x0)) - I tr(P(Phi_k, x0)), Oe m1 with x0
  replaced by Phi_l.
Each invariant must equal flexbody's to 1e-10 of its largest entry (at
least 1 in absolute terms where mean axes make it vanish). Prints the worst
of each and exits 1 on a failure.
"""
import json
import sys

import numpy as np

TOLERANCE = 1e-10


def skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def bending_shapes(phi, length, xi):
    """Deflection and section rotation shape functions of one bending plane,
    DOFs (v1, theta1, v2, theta2) with theta = dv/dx for phi = 0."""
    c = 1.0 / (1.0 + phi)
    n_v = c * np.array([
        1 - 3 * xi**2 + 2 * xi**3 + phi * (1 - xi),
        length * (xi - 2 * xi**2 + xi**3 + phi / 2 * (xi - xi**2)),
        3 * xi**2 - 2 * xi**3 + phi * xi,
        length * (-xi**2 + xi**3 - phi / 2 * (xi - xi**2)),
    ])
    n_t = c * np.array([
        6 * (xi**2 - xi) / length,
        1 - 4 * xi + 3 * xi**2 + phi * (1 - xi),
        -6 * (xi**2 - xi) / length,
        -2 * xi + 3 * xi**2 + phi * xi,
    ])
    return n_v, n_t


def local_frame(a, b, orientation):
    axis = b - a
    length = np.linalg.norm(axis)
    ex = axis / length
    v = np.asarray(orientation, float)
    ey = v - (v @ ex) * ex
    ey /= np.linalg.norm(ey)
    return length, np.array([ex, ey, np.cross(ex, ey)])


def products(case):
    """Mass, int f dm per field and P(f, g) for f, g in (x0, Phi_1..)."""
    nodes = {n["id"]: n for n in case["nodes"]}
    nq = len(case["nodes"][0]["phi"][0])
    nf = nq + 1
    mass = 0.0
    first = np.zeros((nf, 3))
    p = np.zeros((nf, nf, 3, 3))
    xg, wg = np.polynomial.legendre.leggauss(6)
    xg, wg = (xg + 1) / 2, wg / 2
    for e in case["elements"]:
        na, nb = (nodes[i] for i in e["nodes"])
        a, b = np.array(na["x"]), np.array(nb["x"])
        length, rot = local_frame(a, b, e["orientation"])
        if e["timoshenko"]:
            phi_y = 12 * e["E"] * e["Iz"] / (e["G"] * e["Asy"] * length**2)
            phi_z = 12 * e["E"] * e["Iy"] / (e["G"] * e["Asz"] * length**2)
        else:
            phi_y = phi_z = 0.0
        rho = e["rho"]
        bend = 1.0 if e["rotary_inertia"] else 0.0
        j_local = rho * np.diag([e["Iy"] + e["Iz"], bend * e["Iy"], bend * e["Iz"]])
        j_section = rot.T @ j_local @ rot
        r_section = np.trace(j_section) / 2 * np.eye(3) - j_section
        # Element DOFs per mode, local components: (u, theta) at both ends.
        ends = []
        for n in (na, nb):
            values = np.array(n["phi"])  # 6 x nq, global
            ends.append((rot @ values[:3], rot @ values[3:]))
        (u1, t1), (u2, t2) = ends
        for xi, w in zip(xg, wg):
            dm = rho * e["A"] * length * w
            # Section maps and translations of every field at the point.
            x = a + xi * (b - a)
            u = np.zeros((nf, 3))
            maps = np.zeros((nf, 3, 3))
            u[0], maps[0] = x, np.eye(3)
            ny_v, ny_t = bending_shapes(phi_y, length, xi)  # (uy, rz)
            nz_v, nz_t = bending_shapes(phi_z, length, xi)  # (uz, -ry)
            for k in range(nq):
                ux = (1 - xi) * u1[0, k] + xi * u2[0, k]
                tx = (1 - xi) * t1[0, k] + xi * t2[0, k]
                dofs_y = np.array([u1[1, k], t1[2, k], u2[1, k], t2[2, k]])
                dofs_z = np.array([u1[2, k], -t1[1, k], u2[2, k], -t2[1, k]])
                uy, tz = ny_v @ dofs_y, ny_t @ dofs_y
                uz, ty = nz_v @ dofs_z, -(nz_t @ dofs_z)
                u[k + 1] = rot.T @ np.array([ux, uy, uz])
                maps[k + 1] = skew(rot.T @ np.array([tx, ty, tz]))
            mass += dm
            first += dm * u
            for f in range(nf):
                for g in range(nf):
                    p[f, g] += dm * np.outer(u[f], u[g]) + w * length * maps[f] @ r_section @ maps[g].T
    return mass, first, p, nq


def cross_of(m):
    """int a x b dm from P = int a b^T dm."""
    return np.array([m[1, 2] - m[2, 1], m[2, 0] - m[0, 2], m[0, 1] - m[1, 0]])


def oe_row(m):
    s = 0.5 * (m + m.T) - np.trace(m) * np.eye(3)
    return np.array([s[0, 0], s[1, 1], s[2, 2], 2 * s[0, 1], 2 * s[1, 2], 2 * s[2, 0]])


def invariants(case):
    mass, first, p, nq = products(case)
    eye = np.eye(3)
    modes = range(1, nq + 1)
    out = {
        "mass": np.array([[mass]]),
        "mdCM": first[0][:, None],
        "J": np.trace(p[0, 0]) * eye - p[0, 0],
        "Ct": first[1:],
        "Cr": np.array([cross_of(p[0, k]) for k in modes]),
        "Me": np.array([[np.trace(p[k, l]) for l in modes] for k in modes]),
        "Gr": np.hstack([-2 * (p[k, 0] - np.trace(p[k, 0]) * eye) for k in modes]),
        "Ge": np.array([np.concatenate([-2 * cross_of(p[k, l]) for l in modes]) for k in modes]),
        "Oe": np.array([oe_row(p[k, 0]) for k in modes]),
    }
    for k in modes:
        out["mdCM1 %d" % k] = first[k][:, None]
        out["J1 %d" % k] = 2 * np.trace(p[0, k]) * eye - p[0, k] - p[0, k].T
        out["Cr1 %d" % k] = np.array([cross_of(p[k, l]) for l in modes])
        out["Oe1 %d" % k] = np.array([oe_row(p[l, k]) for l in modes])
    return out


def flexbody_invariants(case):
    inv = case["invariants"]
    out = {name: np.atleast_2d(np.array(inv[name], float)) for name in
           ("J", "Ct", "Cr", "Me", "Gr", "Ge", "Oe")}
    out["mass"] = np.array([[inv["mass"]]])
    out["mdCM"] = np.array(inv["mdCM"])[:, None]
    for k, values in enumerate(inv["mdCM1"], 1):
        out["mdCM1 %d" % k] = np.array(values)[:, None]
    for name in ("J1", "Cr1", "Oe1"):
        for k, values in enumerate(inv[name], 1):
            out["%s %d" % (name, k)] = np.array(values)
    return out


def main(paths):
    failed = False
    for path in paths:
        with open(path) as f:
            case = json.load(f)
        ours, theirs = invariants(case), flexbody_invariants(case)
        worst = {}
        for name, value in ours.items():
            other = theirs[name]
            if value.shape != other.shape:
                print("%s: %s is %s in numpy, %s in flexbody" % (path, name, value.shape, other.shape))
                failed = True
                continue
            scale = max(np.abs(value).max(), np.abs(other).max(), 1.0)
            d = np.abs(value - other).max() / scale
            group = name.split()[0]
            worst[group] = max(worst.get(group, 0.0), d)
        name = path.rsplit("/", 1)[-1]
        print("%s: mass %.6f kg, %d modes; largest difference per invariant (relative): %s" % (
            name, ours["mass"][0, 0], ours["Me"].shape[0],
            ", ".join("%s %.1e" % kv for kv in sorted(worst.items()))))
        bad = [g for g, d in worst.items() if d > TOLERANCE]
        if bad:
            print("%s: beyond %.0e: %s" % (name, TOLERANCE, ", ".join(bad)))
            failed = True
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main(sys.argv[1:])
