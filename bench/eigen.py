#!/usr/bin/env python3
"""Benchmark: the lowest 20 elastic modes (+6 rigid) of free steel
box-section beams meshed with C3D8 and C3D10, flexbody against SciPy eigsh
(SuperLU, and CHOLMOD as OPinv) and CalculiX *FREQUENCY, side by side; then
the free-residual and Craig-Bampton reductions (4 interface nodes = 12 DOFs)
on the largest model, against Exudyn's
FEMinterface.ComputeHurtyCraigBamptonModes (Craig-Bampton).

usage: bench/eigen.py [--sizes 3e4,1e5,3e5] [--types C3D8,C3D10]
       [--skip ccx,superlu,cholmod,exudyn] [--reductions] [--no-install]
       [--repeat N] [--work DIR]

--types solid: a solid block of C3D10 (2 x 0.55 x 0.55 m, the shape of a
real component rather than a thin wall; sizes 3e5 and 1e6), where the
factorisation, not the Lanczos run, takes most of the time. At 1e6 DOFs
its factor alone is 16.8 GiB: run it with --skip superlu,cholmod,ccx,exudyn
on a 24 GiB machine.

Each tool runs in a fresh child process (--repeat N: N times, the fastest
counts, all times printed); its wall time and peak RSS are printed with the
ratio of each peer's time to flexbody's, and every tool's
elastic frequencies are checked against flexbody's (relative 1e-6). K and M
for SciPy and Exudyn come from CalculiX's MATRIXSTORAGE output of the same
deck (not timed; SciPy's time includes reading them, eigsh alone is shown).
The reductions also print the floor: one ordering plus one
factorisation of K - sigma M, from flexbody's --verbose log of the modes run.
"""
import argparse
import json
import os
import re
import subprocess
import sys

from measure import run_child

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
COUNT = 26  # 6 rigid + 20 elastic
# type -> target DOFs -> (nx, ny, nz) of a one-element-wall box section,
# 2 x 0.24 x 0.2 m (C3D10 has nodes on a grid of half the cell size)
SIZES = {
    "C3D8": {"3e4": (138, 10, 10), "1e5": (277, 16, 16), "3e5": (542, 24, 24)},
    "C3D10": {"3e4": (52, 5, 5), "1e5": (100, 8, 8), "3e5": (190, 12, 12)},
    "solid": {"3e5": (54, 15, 15), "1e6": (80, 22, 22)},
}


def model(kind, size):
    """The deck's base name and gen_block.py's options for a model."""
    if kind == "solid":
        return "solid_c3d10_%s" % size, ["--type", "C3D10", "--size", "2.0", "0.55", "0.55"]
    return "beam_%s_%s" % (kind.lower(), size), ["--type", kind, "--hollow", "1"]
ENV = dict(os.environ, OMP_NUM_THREADS="2", OPENBLAS_NUM_THREADS="1")


REPEAT = 1  # --repeat: runs per tool, the fastest reported


def measured(cmd, cwd, env=ENV):
    """Runs cmd REPEAT times, each in a fresh Python child so its max RSS is
    its own; returns the fastest run (every run's time is printed when
    there are several)."""
    runs = []
    for _ in range(REPEAT):
        r = measured_once(cmd, cwd, env)
        if r is None:
            return None
        runs.append(r)
    if len(runs) > 1:
        label = " ".join(os.path.basename(c) for c in cmd if "\n" not in c)[:70]
        print("  %s: %s s" % (label, ", ".join("%.2f" % r[0] for r in runs)))
    return min(runs, key=lambda r: r[0])


def measured_once(cmd, cwd, env):
    """One run of cmd in a fresh Python child."""
    r = run_child(cmd, cwd, env, 20000)
    if r["rc"] != 0:
        print("%s failed (%d):\n%s\n%s" % (" ".join(cmd), r["rc"], r["out"][-2000:], r["err"][-2000:]))
        return None
    return r["s"], r["gib"], r["out"], r["err"]


SCIPY = r'''
import sys, time, json, numpy as np, scipy.sparse as sp, scipy.sparse.linalg as sla
job, mode, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
def read(path, n=None):
    d = np.loadtxt(path, ndmin=2)
    r, c, v = d[:, 0].astype(int) - 1, d[:, 1].astype(int) - 1, d[:, 2]
    n = n or max(r.max(), c.max()) + 1
    off = r != c
    return sp.coo_matrix((np.r_[v, v[off]], (np.r_[r, c[off]], np.r_[c, r[off]])), shape=(n, n)).tocsc()
K = read(job + ".sti"); M = read(job + ".mas", K.shape[0])
sigma = -(2 * np.pi * 10.0) ** 2  # SuperLU loses digits at -1 on a free body
t = time.perf_counter()
if mode == "superlu":
    w, _ = sla.eigsh(K, k=count, M=M, sigma=sigma, which="LM")
else:
    from sksparse.cholmod import cholesky
    f = cholesky((K - sigma * M).tocsc())
    op = sla.LinearOperator(K.shape, matvec=f, dtype=float)
    w, _ = sla.eigsh(K, k=count, M=M, sigma=sigma, which="LM", OPinv=op)
dt = time.perf_counter() - t
w = np.sort(w)
print(json.dumps({"hz": list(np.sqrt(np.maximum(w, 0)) / 2 / np.pi), "solve_s": dt}))
'''

EXUDYN = r'''
import sys, time, json, numpy as np, scipy.linalg as sl, scipy.sparse as sp
import exudyn.FEM as F
job, deck, boundary = sys.argv[1], sys.argv[2], [int(x) for x in sys.argv[3].split(",")]
def read(path, n=None):
    d = np.loadtxt(path, ndmin=2)
    r, c, v = d[:, 0].astype(int) - 1, d[:, 1].astype(int) - 1, d[:, 2]
    n = n or max(r.max(), c.max()) + 1
    off = r != c
    return sp.coo_matrix((np.r_[v, v[off]], (np.r_[r, c[off]], np.r_[c, r[off]])), shape=(n, n)).tocsr()
# Equation order of CalculiX (node.direction per equation): node-major,
# 3 translations each, which is Exudyn's 'Position' node layout.
eq = [line.split()[0].split(".") for line in open(job + ".dof") if line.strip()]
order = [int(n) for n, d in eq[::3]]
assert [int(d) for n, d in eq] == [1, 2, 3] * len(order), "3 DOFs per node expected"
sys.path.insert(0, sys.argv[4])
from eigen import read_nodes
xyz = read_nodes(deck)
index = {n: i for i, n in enumerate(order)}
fem = F.FEMinterface()
fem.nodes = {"Position": np.array([xyz[n] for n in order])}
fem.stiffnessMatrix = read(job + ".sti")
fem.massMatrix = read(job + ".mas", fem.stiffnessMatrix.shape[0])
t = time.perf_counter()
fem.ComputeHurtyCraigBamptonModes(boundaryNodesList=[[index[n] for n in boundary]], nEigenModes=20,
                                  useSparseSolver=True,
                                  computationMode=F.HCBstaticModeSelection.allBoundaryNodes)
dt = time.perf_counter() - t
K, M, phi = fem.GetStiffnessMatrix(sparse=True), fem.GetMassMatrix(sparse=True), fem.modeBasis["matrix"]
w = sl.eigh(phi.T @ (K @ phi), phi.T @ (M @ phi), eigvals_only=True)
print(json.dumps({"s": dt, "hz": list(np.sqrt(np.maximum(w, 0)) / 2 / np.pi)}))
'''


def ccx_frequencies(dat):
    hz, on = [], False
    for line in open(dat):
        if "E I G E N V A L U E   O U T P U T" in line:
            on = True
            continue
        if on:
            parts = line.split()
            if len(parts) == 5 and parts[0].isdigit():
                hz.append(float(parts[3]))
            elif hz and "P A R T I C I P" in line:
                break
    return hz


def agree(name, hz, ref, least=20):
    el = [(a, b) for a, b in zip(hz, ref) if b > 1.0]
    if len(el) < least:
        return "%s: only %d elastic frequencies" % (name, len(el))
    worst = max(abs(a - b) / b for a, b in el)
    return "%s: max rel diff %.1e %s" % (name, worst, "ok" if worst < 1e-6 else "DIFFERS")


def reduction_seconds(log):
    """Seconds from the ordering to the reduced body (no reading, no
    writing) from a --verbose log of flexbody reduce: the stages a reduction
    adds to the floor (ordering, factorisation, eigenmodes, inertia-relief
    attachment modes, residualisation)."""
    stamp = r"\[\s*([\d.]+) s[^\]]*\] "
    start = re.search(stamp + "ordering", log)
    end = re.search(stamp + "reduced:", log)
    if start and end:
        return float(end.group(1)) - float(start.group(1))
    return None


def floor_seconds(log):
    """Ordering + one factorisation of K - sigma M from a --verbose log."""
    analysed = re.search(r"analysed: \d+ entries in L[^(]*\(([\d.]+) s\)", log)
    factorised = re.search(r"factorised \(([\d.]+) s\)", log)
    if analysed and factorised:
        return float(analysed.group(1)) + float(factorised.group(1))
    return None


def read_nodes(deck):
    """Node number -> (x, y, z) from the *NODE cards of a generated deck."""
    xyz, on = {}, False
    for line in open(deck):
        if line.startswith("*"):
            on = line.upper().startswith("*NODE")
            continue
        if on:
            p = line.split(",")
            xyz[int(p[0])] = tuple(float(x) for x in p[1:4])
    return xyz


def corner_nodes(deck):
    """The 4 corner nodes of the end face x = 0 (12 DOFs)."""
    xyz = read_nodes(deck)
    face = [(n, p) for n, p in xyz.items() if abs(p[0]) < 1e-12]
    ys = [p[1] for _, p in face]
    zs = [p[2] for _, p in face]
    pick = []
    for y in (min(ys), max(ys)):
        for z in (min(zs), max(zs)):
            pick.append(min(face, key=lambda q: abs(q[1][1] - y) + abs(q[1][2] - z))[0])
    return pick


def table(rows):
    t0 = rows[0][1]
    print("%-18s %10s %10s %8s  %s" % ("tool", "seconds", "peak GB", "x flexb", "check"))
    for name, s, gb, note in rows:
        print("%-18s %10.2f %10.2f %8.2f  %s" % (name, s, gb, s / t0, note))
    sys.stdout.flush()


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--sizes", default="3e4,1e5,3e5")
    p.add_argument("--types", default="C3D8,C3D10")
    p.add_argument("--skip", default="")
    p.add_argument("--no-install", action="store_true")
    p.add_argument("--reductions", action="store_true")
    p.add_argument("--repeat", type=int, default=1)
    p.add_argument("--work", default=os.path.join(ROOT, "target", "bench-eigen"))
    a = p.parse_args()
    global REPEAT
    REPEAT = max(1, a.repeat)
    skip = set(a.skip.split(","))
    if not a.no_install:
        subprocess.run(["apt-get", "install", "-y", "-q", "calculix-ccx", "libsuitesparse-dev"], capture_output=True)
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "scipy", "scikit-sparse==0.4.16", "exudyn"])
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    exe = os.path.join(ROOT, "target", "release", "flexbody")
    os.makedirs(a.work, exist_ok=True)
    sizes = a.sizes.split(",")
    types = a.types.split(",")
    floors = {}  # deck -> ordering + first factorisation of the modes run
    for kind in types:
        for size in sizes:
            nx, ny, nz = SIZES[kind][size]
            base, shape = model(kind, size)
            gen = [sys.executable, os.path.join(ROOT, "bench", "gen_block.py"), str(nx), str(ny), str(nz)]
            out = subprocess.run(gen + [base + ".inp"] + shape + ["--step",
                                        "frequency:%d" % COUNT],
                                 cwd=a.work, check=True, capture_output=True, text=True).stdout
            subprocess.run(gen + [base + "_k.inp"] + shape + ["--step", "matrixstorage"],
                           cwd=a.work, check=True, capture_output=True)
            print("\n== %s" % out.strip())
            rows = []
            r = measured([exe, "--verbose", "modes", base + ".inp", "--count", str(COUNT), "--json"], a.work)
            if r is None:
                continue
            ref = json.loads(r[2])["frequencies_hz"]
            floor = floor_seconds(r[3])
            floors[base] = floor
            rows.append(("flexbody", r[0], r[1], "max residual %.1e, order + factor %.1f s"
                         % (max(json.loads(r[2])["residuals"]), floor or float("nan"))))
            needs_k = not ({"superlu", "cholmod"} <= skip)
            if needs_k and not os.path.exists(os.path.join(a.work, base + "_k.sti")):
                subprocess.run(["ccx", "-i", base + "_k"], cwd=a.work, env=ENV, check=True, capture_output=True)
            for mode in ("superlu", "cholmod"):
                if mode in skip:
                    continue
                r = measured([sys.executable, "-c", SCIPY, base + "_k", mode, str(COUNT)], a.work)
                if r:
                    d = json.loads(r[2].strip().splitlines()[-1])
                    rows.append(("scipy+" + mode, r[0], r[1],
                                 agree(mode, d["hz"], ref) + ", eigsh %.1f s" % d["solve_s"]))
            if "ccx" not in skip:
                r = measured(["ccx", "-i", base], a.work)
                if r:
                    rows.append(("calculix", r[0], r[1],
                                 agree("ccx", ccx_frequencies(os.path.join(a.work, base + ".dat")), ref)))
            table(rows)
    if a.reductions:
        kind, size = types[0], sizes[-1]
        base = model(kind, size)[0]
        nodes = corner_nodes(os.path.join(a.work, base + ".inp"))
        iface = ",".join(map(str, nodes))
        print("\n== reductions on %s, 20 eigenmodes, interface nodes %s (12 DOFs)" % (base, iface))
        r = measured([exe, "info", base + ".inp"], a.work)
        read = r[0] if r else 0.0
        floor = floors.get(base)
        if floor is None:
            r = measured([exe, "--verbose", "modes", base + ".inp", "--count", "1"], a.work)
            floor = floor_seconds(r[3]) if r else None
        print("read + assemble %.1f s; floor (ordering + one factorisation of K - sigma M) %.1f s"
              % (read, floor or float("nan")))
        rows, cb_hz = [], None
        for method in ("craig-bampton", "free-residual"):
            r = measured([exe, "--verbose", "reduce", base + ".inp", "--method", method, "--modes", "20",
                          "--interface", iface, "--out", method + ".json", "--json", "--check", "never"],
                         a.work)
            if r:
                hz = json.loads(r[2])["reduced_hz"]
                if method == "craig-bampton":
                    cb_hz = hz
                note = ""
                if floor:
                    note = "without read %.1f s = %.1f x floor" % (r[0] - read, (r[0] - read) / floor)
                    own = reduction_seconds(r[3])
                    if own:
                        note += "; ordering to reduced body %.1f s = %.1f x floor" % (own, own / floor)
                rows.append(("flexbody " + method, r[0], r[1], note))
        if "exudyn" not in skip and cb_hz:
            if not os.path.exists(os.path.join(a.work, base + "_k.sti")):
                subprocess.run(["ccx", "-i", base + "_k"], cwd=a.work, env=ENV, check=True, capture_output=True)
            r = measured([sys.executable, "-c", EXUDYN, base + "_k", base + ".inp", iface,
                          os.path.join(ROOT, "bench")], a.work)
            if r:
                d = json.loads(r[2].strip().splitlines()[-1])
                rows.append(("exudyn HCB", r[0], r[1], agree("reduced CB", d["hz"], cb_hz, least=26)
                             + ", HCB alone %.1f s" % d["s"]))
        table(rows)


if __name__ == "__main__":
    main()
