"""Matrices from SciPy to a SID file for an MBS code.

An Euler-Bernoulli beam (steel, 2 m, 40 mm x 20 mm, 40 elements, bending
in the x-z plane: DOFs uz and ry per node) is assembled with
scipy.sparse, handed to flexbody with its node coordinates, reduced by
Craig-Bampton on its two end nodes and written as a SID. The check: its
free-free frequencies against the closed form, and the SID's mass.

Run: python python/examples/scipy_to_sid.py [out.sid]
"""

import sys
from pathlib import Path

import numpy as np
import scipy.sparse as sp

import flexbody

E, RHO = 2.1e11, 7850.0
LENGTH, WIDTH, HEIGHT = 2.0, 0.04, 0.02
ELEMENTS = 40


def beam_matrices(elements=ELEMENTS):
    """K and M of a uniform Euler-Bernoulli beam (cubic Hermite elements,
    consistent mass) over DOFs (uz, ry) of nodes 1..elements+1, and the
    node coordinates."""
    area, inertia = WIDTH * HEIGHT, WIDTH * HEIGHT**3 / 12
    h = LENGTH / elements
    # uz along +z and ry about +y: a rotation ry tilts the beam by -duz/dx.
    k = E * inertia / h**3 * np.array(
        [[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
         [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]]
    )
    m = RHO * area * h / 420 * np.array(
        [[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
         [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]]
    )
    sign = np.diag([1.0, -1.0, 1.0, -1.0])  # from (uz, -ry) to flexbody's (uz, ry)
    k, m = sign @ k @ sign, sign @ m @ sign
    n = 2 * (elements + 1)
    rows, cols, kv, mv = [], [], [], []
    for e in range(elements):
        idx = np.arange(2 * e, 2 * e + 4)
        rows += list(np.repeat(idx, 4))
        cols += list(np.tile(idx, 4))
        kv += list(k.ravel())
        mv += list(m.ravel())
    K = sp.csc_array((kv, (rows, cols)), shape=(n, n))
    M = sp.csc_array((mv, (rows, cols)), shape=(n, n))
    nodes = np.arange(1, elements + 2)
    dofs = [(node, dof) for node in nodes for dof in ("uz", "ry")]
    coords = (nodes, np.column_stack([np.linspace(0, LENGTH, elements + 1), np.zeros(elements + 1), np.zeros(elements + 1)]))
    return K, M, dofs, coords


def free_free_hz(count):
    """Closed form: beta_n L = 4.7300, 7.8532, 10.9956, ... (n + 1/2) pi."""
    roots = [4.730040745, 7.853204624, 10.995607838, 14.137165491]
    roots += [(n + 0.5) * np.pi for n in range(5, count + 1)]
    area, inertia = WIDTH * HEIGHT, WIDTH * HEIGHT**3 / 12
    return np.array(roots[:count]) ** 2 / (2 * np.pi) * np.sqrt(E * inertia / (RHO * area * LENGTH**4))


def main(out="beam.sid"):
    K, M, dofs, coords = beam_matrices()
    model = flexbody.Model.from_matrices(K, M, dofs, coords=coords)
    body = model.reduce("craig-bampton", interface=[1, ELEMENTS + 1], modes=6)
    body.write(out, format="sid")
    sid = flexbody.load(out)
    reduced = body.frequencies_hz()
    return {
        "reduced_hz": reduced[2:6],          # the two rigid modes first
        "closed_form_hz": free_free_hz(4),
        "sid_mass": sid.mass,
        "mass": RHO * WIDTH * HEIGHT * LENGTH,
        "sid": sid,
    }


if __name__ == "__main__":
    result = main(*sys.argv[1:2])
    print(result["sid"])
    for f, g in zip(result["reduced_hz"], result["closed_form_hz"]):
        print(f"{f:12.5f} Hz (reduced)  {g:12.5f} Hz (closed form)")
