#!/usr/bin/env python3
"""Benchmark: what eliminating a tie costs, against what couplings cost,
on a free steel C3D8 block of about 3e5 DOFs (2 x 0.6 x 0.6 m).

usage: bench/constraints.py [--repeat N] [--work DIR] [--keep]

Variants, each a deck written here:
  one-piece     96 x 31 x 31 cells, no constraints (the baseline);
  two-parts     the block cut at x = 1 m into part A (78 x 24 x 24 cells)
                and part B (48 x 31 x 31 cells), meshes not matching at
                the cut, no *TIE (the control: the same mesh unjoined);
  tied          two-parts with a *TIE of B's 32 x 32 = 1024 face nodes (a
                node set) to A's 24 x 24 faces (an element *SURFACE);
  kinematic     one-piece with 10 reference nodes, each *COUPLING with
                *KINEMATIC to a 10 x 10 patch of its side face (1000
                coupled nodes);
  distributing  the same with *DISTRIBUTING.

Each variant runs `flexbody info DECK` (read, eliminate, assemble) and
`flexbody --verbose modes DECK --count 10` (also order, factorise and run
Lanczos), each in a fresh child process (--repeat N: N times, the fastest
counts, all times printed). Printed: wall seconds and peak memory, info's
read and assembly split, and from the modes log the time before the
ordering, the ordering, the two factorisations (Lanczos operator and
Sturm check), the Lanczos run and the entries of L. The tie's elimination
is `tied` over `two-parts` (same mesh); the couplings' is theirs over
`one-piece`.
The decks and each modes log (VARIANT.modes.log) go to
$CARGO_TARGET_DIR/bench-constraints (or --work DIR), removed at the end
unless --keep or --work is given.
Needs: cargo, python3. Builds flexbody with `cargo build --release`
(into $CARGO_TARGET_DIR when it is set).
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

from measure import run_child

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIZE = (2.0, 0.6, 0.6)
ONE_PIECE = (96, 31, 31)
PART_A = (78, 24, 24)  # x in [0, 1]: the coarser face, master
PART_B = (48, 31, 31)  # x in [1, 2]: the finer face, slave
PATCH = 10  # nodes along each side of a coupling's patch
PATCHES = [(5 + 18 * p, k0) for p in range(5) for k0 in (3, 18)]  # (i0, k0) on y = 0


class Grid:
    """A structured C3D8 block: node and element numbers from `first_node`
    and `first_element`, x fastest."""

    def __init__(self, cells, origin, size, first_node=1, first_element=1):
        self.cells, self.origin, self.size = cells, origin, size
        self.first_node, self.first_element = first_node, first_element

    def node(self, i, j, k):
        nx, ny, _ = self.cells
        return self.first_node + i + (nx + 1) * (j + (ny + 1) * k)

    def coords(self, i, j, k):
        return [self.origin[a] + self.size[a] * v / self.cells[a] for a, v in enumerate((i, j, k))]

    def element(self, i, j, k):
        nx, ny, _ = self.cells
        return self.first_element + i + nx * (j + ny * k)

    def last_node(self):
        return self.node(*self.cells)

    def last_element(self):
        return self.element(*(c - 1 for c in self.cells))

    def write_nodes(self, out):
        nx, ny, nz = self.cells
        for k in range(nz + 1):
            for j in range(ny + 1):
                for i in range(nx + 1):
                    x, y, z = self.coords(i, j, k)
                    out.append("%d, %.9g, %.9g, %.9g\n" % (self.node(i, j, k), x, y, z))

    def write_elements(self, out):
        """C3D8 in CalculiX order: face S4 is the cell's +x face, S6 its -x face."""
        nx, ny, nz = self.cells
        for k in range(nz):
            for j in range(ny):
                for i in range(nx):
                    n = self.node
                    out.append("%d, %d, %d, %d, %d, %d, %d, %d, %d\n" % (
                        self.element(i, j, k),
                        n(i, j, k), n(i + 1, j, k), n(i + 1, j + 1, k), n(i, j + 1, k),
                        n(i, j, k + 1), n(i + 1, j, k + 1), n(i + 1, j + 1, k + 1), n(i, j + 1, k + 1)))


def ids(values):
    """Numbers, 16 a line."""
    values = list(values)
    return "".join(", ".join(str(v) for v in values[a:a + 16]) + "\n" for a in range(0, len(values), 16))


def material(out):
    out.append("*MATERIAL, NAME=STEEL\n*ELASTIC\n2.1e11, 0.3\n*DENSITY\n7850\n"
               "*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")


def one_piece(out, coupling=None):
    g = Grid(ONE_PIECE, (0.0, 0.0, 0.0), SIZE)
    out.append("*NODE\n")
    g.write_nodes(out)
    out.append("*ELEMENT, TYPE=C3D8, ELSET=EALL\n")
    g.write_elements(out)
    material(out)
    if coupling is None:
        return
    ref = g.last_node() + 1
    h = SIZE[0] / ONE_PIECE[0]
    for c, (i0, k0) in enumerate(PATCHES):
        x, _, z = g.coords(i0 + (PATCH - 1) / 2.0, 0, k0 + (PATCH - 1) / 2.0)
        out.append("*NODE\n%d, %.9g, %.9g, %.9g\n" % (ref + c, x, -5 * h, z))
        patch = [g.node(i, 0, k) for k in range(k0, k0 + PATCH) for i in range(i0, i0 + PATCH)]
        out.append("*NSET, NSET=PATCH%d\n%s" % (c, ids(patch)))
        out.append("*SURFACE, NAME=S%d, TYPE=NODE\nPATCH%d\n" % (c, c))
        out.append("*COUPLING, REF NODE=%d, SURFACE=S%d, CONSTRAINT NAME=C%d\n" % (ref + c, c, c))
        out.append("*KINEMATIC\n1, 3\n" if coupling == "kinematic" else "*DISTRIBUTING\n1, 6\n")


def two_parts(out, tie):
    a = Grid(PART_A, (0.0, 0.0, 0.0), (1.0, SIZE[1], SIZE[2]))
    b = Grid(PART_B, (1.0, 0.0, 0.0), (1.0, SIZE[1], SIZE[2]),
             first_node=a.last_node() + 1, first_element=a.last_element() + 1)
    out.append("*NODE\n")
    a.write_nodes(out)
    b.write_nodes(out)
    out.append("*ELEMENT, TYPE=C3D8, ELSET=EALL\n")
    a.write_elements(out)
    b.write_elements(out)
    material(out)
    if not tie:
        return
    nx, ny, nz = PART_A
    face = [a.element(nx - 1, j, k) for k in range(nz) for j in range(ny)]
    out.append("*ELSET, ELSET=AFACE\n%s" % ids(face))
    out.append("*SURFACE, NAME=MASTER, TYPE=ELEMENT\nAFACE, S4\n")
    _, ny, nz = PART_B
    slaves = [b.node(0, j, k) for k in range(nz + 1) for j in range(ny + 1)]
    out.append("*NSET, NSET=BFACE\n%s" % ids(slaves))
    out.append("*SURFACE, NAME=SLAVE, TYPE=NODE\nBFACE\n")
    out.append("*TIE, NAME=CUT, ADJUST=NO\nSLAVE, MASTER\n")


VARIANTS = {
    "one-piece": lambda out: one_piece(out),
    "two-parts": lambda out: two_parts(out, tie=False),
    "tied": lambda out: two_parts(out, tie=True),
    "kinematic": lambda out: one_piece(out, "kinematic"),
    "distributing": lambda out: one_piece(out, "distributing"),
}


def write_deck(path, variant):
    out = ["** bench/constraints.py: %s, steel C3D8, SI units\n" % variant]
    VARIANTS[variant](out)
    out.append("*STEP\n*FREQUENCY\n10\n*END STEP\n")
    with open(path, "w") as f:
        f.write("".join(out))


def measured(cmd, cwd, repeat):
    """The fastest of `repeat` runs of cmd, each in a fresh Python child;
    every run's seconds."""
    runs = []
    for _ in range(repeat):
        r = run_child(cmd, cwd, None, 200000)
        if r["rc"] != 0:
            sys.exit("%s failed (%d):\n%s\n%s" % (" ".join(cmd), r["rc"], r["out"][-3000:], r["err"][-3000:]))
        runs.append(r)
    best = min(runs, key=lambda r: r["s"])
    best["all"] = [r["s"] for r in runs]
    return best


def info_split(out):
    """info's "read in X s, assembled in Y s" and its DOFs."""
    m = re.search(r"read in ([0-9.]+) s, assembled in ([0-9.]+) s", out)
    d = re.search(r"DOFs (\d+), nonzeros of K (\d+)", out)
    return float(m.group(1)), float(m.group(2)), int(d.group(1)), int(d.group(2))


def modes_stages(log):
    """From the --verbose log: seconds before the ordering (reading,
    eliminating, assembling), the ordering, the factorisations (Lanczos
    operator and Sturm check), the Lanczos run, and the entries of L."""
    first = re.search(r"\[\s*([0-9.]+) s [^\]]*\] ordering", log)
    analysed = re.search(r"analysed: (\d+) entries in L, [0-9.]+ GFlop per factorisation \(([0-9.]+) s\)", log)
    factorised = [float(v) for v in re.findall(r"factorised \(([0-9.]+) s\)", log)]
    lanczos = re.search(r"Lanczos done \(([0-9.]+) s\)", log)
    value = lambda m, g=1: float(m.group(g)) if m else float("nan")
    return {
        "before": value(first),
        "ordering": value(analysed, 2),
        # The Lanczos operator's factorisation and the Sturm check's.
        "factor": sum(factorised) if factorised else float("nan"),
        "lanczos": value(lanczos),
        "entries": int(analysed.group(1)) if analysed else 0,
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeat", type=int, default=1)
    p.add_argument("--work", default=None, help="folder of the decks (default: a new temporary one)")
    p.add_argument("--keep", action="store_true", help="keep the decks")
    p.add_argument("--variants", default=",".join(VARIANTS))
    a = p.parse_args()
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    target = os.environ.get("CARGO_TARGET_DIR", os.path.join(ROOT, "target"))
    exe = os.path.join(target, "release", "flexbody")
    work = a.work or os.path.join(target, "bench-constraints")
    os.makedirs(work, exist_ok=True)
    rows = []
    for variant in a.variants.split(","):
        deck = os.path.join(work, variant + ".inp")
        write_deck(deck, variant)
        info = measured([exe, "info", deck], work, a.repeat)
        read, assembled, dofs, nnz = info_split(info["out"])
        modes = measured([exe, "--verbose", "modes", deck, "--count", "10", "--json"], work, a.repeat)
        stages = modes_stages(modes["err"])
        with open(os.path.join(work, variant + ".modes.log"), "w") as f:
            f.write(modes["err"])
        print("%-12s %7d DOFs; info %s s; modes %s s" % (
            variant, dofs, ", ".join("%.2f" % s for s in info["all"]),
            ", ".join("%.2f" % s for s in modes["all"])), flush=True)
        rows.append((variant, dofs, nnz, read, assembled, info, modes, stages))
    print()
    print("%-12s %7s %10s | %6s %6s %6s %6s | %6s %6s %6s %6s %6s %11s %6s" % (
        "variant", "DOFs", "nnz(K)", "read", "assem", "info", "GiB",
        "before", "order", "factors", "Lancz", "modes", "entries L", "GiB"))
    for variant, dofs, nnz, read, assembled, info, modes, st in rows:
        print("%-12s %7d %10d | %6.2f %6.2f %6.2f %6.2f | %6.2f %6.2f %6.2f %6.2f %6.2f %11d %6.2f" % (
            variant, dofs, nnz, read, assembled, info["s"], info["gib"],
            st["before"], st["ordering"], st["factor"], st["lanczos"], modes["s"], st["entries"], modes["gib"]))
    if not a.keep and a.work is None:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
