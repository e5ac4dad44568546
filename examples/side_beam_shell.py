#!/usr/bin/env python3
"""Writes examples/side_beam_shell.inp: the report's side beam (side_beam.toml) as
S4 shells on the mid-surfaces of its box section, b = 0.24 m (y) x h = 0.20 m
(z) outside, wall t = 0.012 m, length 2.5 m, steel E = 2.1e11 Pa,
rho = 6800 kg/m^3 (the section of examples/side_beam_solid.inp).

The mid-surfaces form a 0.228 x 0.188 m rectangle; 20 elements along x
(0.125 m: the seats at x = 0.75 and 1.75 m fall on section lines), four
across each flange and each web. Node sets for the spring seats (patches
the interface points are coupled to):
  SEAT_PF, SEAT_PR: bottom flange at x = 0..0.125 and 2.375..2.5
  SEAT_SF, SEAT_SR: top flange at x = 0.625..0.875 and 1.625..1.875
usage: python3 examples/side_beam_shell.py [OUT.inp]
"""
import os
import sys

L, B, H, T = 2.5, 0.24, 0.20, 0.012
NX, NSIDE = 20, 4
Y0, Y1, Z0, Z1 = T / 2, B - T / 2, T / 2, H - T / 2


def loop():
    """The mid-surface section's points, counter-clockwise seen from +x,
    starting at the bottom-left corner: bottom flange, right web, top
    flange, left web; with the wall each point's segment lies on."""
    pts = []
    for s in range(NSIDE):
        pts.append((Y0 + (Y1 - Y0) * s / NSIDE, Z0, "bottom"))
    for s in range(NSIDE):
        pts.append((Y1, Z0 + (Z1 - Z0) * s / NSIDE, "web"))
    for s in range(NSIDE):
        pts.append((Y1 - (Y1 - Y0) * s / NSIDE, Z1, "top"))
    for s in range(NSIDE):
        pts.append((Y0, Z1 - (Z1 - Z0) * s / NSIDE, "web"))
    return pts


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "side_beam_shell.inp")
    pts = loop()
    npt = len(pts)

    def nid(i, p):
        return 1 + i + (NX + 1) * (p % npt)

    xs = [L * i / NX for i in range(NX + 1)]
    elements = []
    for i in range(NX):
        for p in range(npt):
            # Normals point out of the box: along the loop, then along x.
            elements.append([nid(i, p), nid(i, p + 1), nid(i + 1, p + 1), nid(i + 1, p)])

    def patch(x0, x1, z):
        return sorted(nid(i, p) for i in range(NX + 1) for p in range(npt)
                      if x0 - 1e-9 <= xs[i] <= x1 + 1e-9 and abs(pts[p][1] - z) < 1e-9)

    sets = {
        "SEAT_PF": patch(0.0, 0.125, Z0),
        "SEAT_PR": patch(2.375, 2.5, Z0),
        "SEAT_SF": patch(0.625, 0.875, Z1),
        "SEAT_SR": patch(1.625, 1.875, Z1),
    }
    with open(out, "w") as f:
        f.write("** The report's side beam as S4 shells on its box section's mid-surfaces\n")
        f.write("** (examples/side_beam_shell.py). Units: SI (m, kg, s, N, Pa).\n*NODE\n")
        for p in range(npt):
            for i in range(NX + 1):
                f.write("%d, %.6f, %.6f, %.6f\n" % (nid(i, p), xs[i], pts[p][0], pts[p][1]))
        f.write("*ELEMENT, TYPE=S4, ELSET=BEAM\n")
        for e, n in enumerate(elements, 1):
            f.write("%d, %s\n" % (e, ", ".join(map(str, n))))
        for name, nodes in sets.items():
            f.write("*NSET, NSET=%s\n" % name)
            for c in range(0, len(nodes), 12):
                f.write(", ".join(map(str, nodes[c:c + 12])) + "\n")
        f.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n6800.\n")
        f.write("*SHELL SECTION, ELSET=BEAM, MATERIAL=STEEL\n%.3f\n" % T)
    n = npt * (NX + 1)
    print("%s: %d nodes, %d DOFs, %d elements" % (out, n, 6 * n, len(elements)))


if __name__ == "__main__":
    main()
