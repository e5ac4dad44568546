#!/usr/bin/env python3
"""Writes examples/side_beam_solid.inp: the report's side beam (side_beam.toml) as
a C3D8 mesh of its box section, b = 0.24 m (y) x h = 0.20 m (z), wall
t = 0.012 m, length 2.5 m, steel E = 2.1e11 Pa, rho = 6800 kg/m^3.

20 elements along x (0.125 m: the seats at x = 0.75 and 1.75 m fall on
section lines), one element through the wall. Node sets for the spring
seats (patches the interface points are coupled to):
  SEAT_PF, SEAT_PR: bottom flange (z = 0) at x = 0..0.125 and 2.375..2.5
  SEAT_SF, SEAT_SR: top flange (z = h) at x = 0.625..0.875 and 1.625..1.875
usage: python3 examples/side_beam_solid.py [OUT.inp]
"""
import os
import sys

L, B, H, T = 2.5, 0.24, 0.20, 0.012
NX = 20
YS = [0.0, T, 0.08, 0.16, B - T, B]
ZS = [0.0, T, 0.10, H - T, H]


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "side_beam_solid.inp")
    ny, nz = len(YS) - 1, len(ZS) - 1

    def wall(j, k):
        return j == 0 or k == 0 or j == ny - 1 or k == nz - 1

    def nid(i, j, k):
        return 1 + i + (NX + 1) * (j + (ny + 1) * k)

    elements, used = [], set()
    for i in range(NX):
        for k in range(nz):
            for j in range(ny):
                if not wall(j, k):
                    continue
                n = [nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                     nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)]
                used.update(n)
                elements.append(n)
    xs = [L * i / NX for i in range(NX + 1)]

    def patch(x0, x1, k):
        return sorted(nid(i, j, k) for i in range(NX + 1) for j in range(ny + 1)
                      if x0 - 1e-9 <= xs[i] <= x1 + 1e-9 and nid(i, j, k) in used)

    sets = {
        "SEAT_PF": patch(0.0, 0.125, 0),
        "SEAT_PR": patch(2.375, 2.5, 0),
        "SEAT_SF": patch(0.625, 0.875, nz),
        "SEAT_SR": patch(1.625, 1.875, nz),
    }
    with open(out, "w") as f:
        f.write("** The report's side beam as a C3D8 box-section mesh (examples/side_beam_solid.py).\n")
        f.write("** Units: SI (m, kg, s, N, Pa).\n*NODE\n")
        for k in range(nz + 1):
            for j in range(ny + 1):
                for i in range(NX + 1):
                    n = nid(i, j, k)
                    if n in used:
                        f.write("%d, %.6f, %.6f, %.6f\n" % (n, xs[i], YS[j], ZS[k]))
        f.write("*ELEMENT, TYPE=C3D8, ELSET=BEAM\n")
        for e, n in enumerate(elements, 1):
            f.write("%d, %s\n" % (e, ", ".join(map(str, n))))
        for name, nodes in sets.items():
            f.write("*NSET, NSET=%s\n" % name)
            for c in range(0, len(nodes), 12):
                f.write(", ".join(map(str, nodes[c:c + 12])) + "\n")
        f.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n6800.\n")
        f.write("*SOLID SECTION, ELSET=BEAM, MATERIAL=STEEL\n")
    print("%s: %d nodes, %d DOFs, %d elements" % (out, len(used), 3 * len(used), len(elements)))


if __name__ == "__main__":
    main()
