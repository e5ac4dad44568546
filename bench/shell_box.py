#!/usr/bin/env python3
"""Benchmark: a thin-walled box of S4 shells, about 10^6 DOFs, the lowest 26
modes by `flexbody modes` and by CalculiX (which expands each shell into a
solid through the thickness) on the same deck, in the same run.

The box: 10 m long, a 1.0 x 0.5 m section (mid-surfaces), 5 mm steel,
free; --cells N elements along its length and N * 3 / 10 round its
section (N = 750: 751 x 225 nodes, 1.01e6 DOFs). Both tools run with two
threads (OMP_NUM_THREADS=2), each in a fresh child process whose peak RSS
is its own. The frequencies of the two differ by the difference of the
discretisations (flexbody's shells against CalculiX's solids), which the
script prints.

usage: bench/shell_box.py [--cells 750] [--work DIR] [--skip ccx]
"""
import argparse
import os
import subprocess
import sys

from eigen import ENV, ccx_frequencies
from measure import run_child

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
L, B, H, T = 10.0, 1.0, 0.5, 0.005
COUNT = 26


def write_deck(path, cells):
    """The box's deck: nodes ring by ring along x, S4 cells, a *FREQUENCY step."""
    nx = cells
    per_b, per_h = max(1, round(cells * 0.1)), max(1, round(cells * 0.05))
    ring = []
    for s in range(per_b):
        ring.append((B * s / per_b, 0.0))
    for s in range(per_h):
        ring.append((B, H * s / per_h))
    for s in range(per_b):
        ring.append((B - B * s / per_b, H))
    for s in range(per_h):
        ring.append((0.0, H - H * s / per_h))
    nr = len(ring)

    def nid(i, p):
        return 1 + (p % nr) + nr * i

    with open(path, "w") as f:
        f.write("** A thin-walled box of S4 shells (bench/shell_box.py)\n*NODE\n")
        for i in range(nx + 1):
            x = L * i / nx
            for p, (y, z) in enumerate(ring):
                f.write("%d, %.9g, %.9g, %.9g\n" % (nid(i, p), x, y, z))
        f.write("*ELEMENT, TYPE=S4, ELSET=BOX\n")
        e = 0
        for i in range(nx):
            for p in range(nr):
                e += 1
                f.write("%d, %d, %d, %d, %d\n" % (e, nid(i, p), nid(i, p + 1), nid(i + 1, p + 1), nid(i + 1, p)))
        f.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850.\n")
        f.write("*SHELL SECTION, ELSET=BOX, MATERIAL=STEEL\n%g\n" % T)
        f.write("*STEP\n*FREQUENCY\n%d\n*END STEP\n" % COUNT)
    return (nx + 1) * nr


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--cells", type=int, default=750)
    p.add_argument("--work", default=os.path.join(ROOT, "target", "bench-shell"))
    p.add_argument("--skip", default="")
    a = p.parse_args()
    skip = set(filter(None, a.skip.split(",")))
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    exe = os.path.join(ROOT, "target", "release", "flexbody")
    os.makedirs(a.work, exist_ok=True)
    base = "shell_box_%d" % a.cells
    nodes = write_deck(os.path.join(a.work, base + ".inp"), a.cells)
    print("%s: %d nodes, %d DOFs" % (base, nodes, 6 * nodes))
    rows = []
    r = run_child([exe, "--quiet", "modes", base + ".inp", "--count", str(COUNT), "--json"], a.work, ENV, 200000)
    if r["rc"] != 0:
        sys.exit("flexbody failed:\n" + r["err"][-2000:])
    import json
    ours = json.loads(r["out"])["frequencies_hz"]
    rows.append(("`flexbody modes --count 26`", r["s"], r["gib"]))
    theirs = None
    if "ccx" not in skip:
        c = run_child(["ccx", "-i", base], a.work, ENV, 2000)
        if c["rc"] != 0:
            print("ccx failed:\n" + c["out"][-2000:])
        else:
            theirs = ccx_frequencies(os.path.join(a.work, base + ".dat"))
            rows.append(("CalculiX 2.20 `*FREQUENCY` (expanded to solids)", c["s"], c["gib"]))
    print("\n| S4 box, %.2e DOFs, 26 modes | seconds | peak GiB | x flexbody |" % (6 * nodes))
    print("| --- | --- | --- | --- |")
    for name, s, gib in rows:
        print("| %s | %.1f | %.2f | %.2f |" % (name, s, gib, s / rows[0][1]))
    print("\nflexbody (Hz): " + ", ".join("%.4g" % f for f in ours))
    if theirs:
        print("CalculiX (Hz): " + ", ".join("%.4g" % f for f in theirs))
        el = [(x, y) for x, y in zip(ours, theirs) if y > 1e-2]
        if el:
            print("elastic modes, CalculiX against flexbody: %+.2f %% to %+.2f %%" % (
                min(100 * (y - x) / x for x, y in el), max(100 * (y - x) / x for x, y in el)))


if __name__ == "__main__":
    main()
