#!/usr/bin/env python3
"""Benchmark of issue 6: the lowest 20 elastic modes (+6 rigid) of free steel
box-section beams, flexbody against SciPy eigsh (SuperLU and CHOLMOD as
OPinv) and CalculiX *FREQUENCY, side by side; plus the free-residual and
Craig-Bampton reductions (4 interface nodes = 12 DOFs) on the largest model
against Exudyn's FEMinterface.ComputeHurtyCraigBamptonModes.

usage: bench/eigen.py [--sizes 3e4,1e5,3e5] [--no-install] [--skip ccx,superlu,...]
       [--reductions] [--work DIR]

Each tool runs in a fresh child process; wall time and its peak RSS are
printed, with the ratio of each peer's time to flexbody's, and the check that
every tool's elastic frequencies agree with flexbody's to 1e-6 relative.
K and M for SciPy and Exudyn come from CalculiX's MATRIXSTORAGE output of the
same deck (its time is not counted). Only C3D8 decks are generated (the deck
generator has no C3D10 yet).
"""
import argparse
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
COUNT = 26  # 6 rigid + 20 elastic
# target DOFs -> (nx, ny, nz) of a one-element-wall box section, 2 x 0.24 x 0.2 m
# (a one-element wall keeps 4 (ny + nz) - 8 nodes per cross-section)
SIZES = {"3e4": (138, 10, 10), "1e5": (277, 16, 16), "3e5": (542, 24, 24)}
ENV = dict(os.environ, OMP_NUM_THREADS="2", OPENBLAS_NUM_THREADS="1")


def measured(cmd, cwd, env=ENV):
    """Runs cmd in a fresh Python child so its max RSS is its own."""
    code = (
        "import resource,subprocess,sys,time,json\n"
        "t=time.perf_counter()\n"
        "p=subprocess.run(sys.argv[1:],capture_output=True,text=True)\n"
        "dt=time.perf_counter()-t\n"
        "print(json.dumps({'rc':p.returncode,'s':dt,'kb':resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss,"
        "'out':p.stdout[-20000:],'err':p.stderr[-4000:]}))\n"
    )
    p = subprocess.run([sys.executable, "-c", code] + cmd, cwd=cwd, env=env, capture_output=True, text=True)
    r = json.loads(p.stdout)
    if r["rc"] != 0:
        print("%s failed (%d):\n%s\n%s" % (" ".join(cmd), r["rc"], r["out"][-2000:], r["err"]))
        return None
    return r["s"], r["kb"] / 1024.0 / 1024.0, r["out"]


SCIPY = r'''
import sys, time, json, numpy as np, scipy.sparse as sp, scipy.sparse.linalg as sla
job, mode, count = sys.argv[1], sys.argv[2], int(sys.argv[3])
def read(path, n=None):
    d = np.loadtxt(path, ndmin=2)
    r, c, v = d[:, 0].astype(int) - 1, d[:, 1].astype(int) - 1, d[:, 2]
    n = n or max(r.max(), c.max()) + 1
    off = r != c
    a = sp.coo_matrix((np.r_[v, v[off]], (np.r_[r, c[off]], np.r_[c, r[off]])), shape=(n, n)).tocsc()
    return a
K = read(job + ".sti"); M = read(job + ".mas", K.shape[0])
sigma = -1e-6 * abs(K.diagonal()).sum() / abs(M.diagonal()).sum()
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
import sys, time, json, numpy as np
import exudyn.FEM as F
job, nodes = sys.argv[1], [int(x) for x in sys.argv[2].split(",")]
def triplets(path):
    d = np.loadtxt(path, ndmin=2)
    r, c, v = d[:, 0].astype(int) - 1, d[:, 1].astype(int) - 1, d[:, 2]
    off = r != c
    return np.c_[np.r_[r, c[off]], np.r_[c, r[off]], np.r_[v, v[off]]]
fem = F.FEMinterface()
fem.stiffnessMatrix = triplets(job + ".sti")
fem.massMatrix = triplets(job + ".mas")
dofs = np.loadtxt(job + ".dof", ndmin=2) if False else None
t = time.perf_counter()
fem.ComputeHurtyCraigBamptonModes(boundaryNodesList=[[n] for n in nodes], nEigenModes=20,
                                  useSparseSolver=True, computationMode=F.HCBstaticModeSelection.RBE2)
print(json.dumps({"s": time.perf_counter() - t}))
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


def agree(name, hz, ref):
    el = [(a, b) for a, b in zip(hz, ref) if b > 1.0]
    if len(el) < 20:
        return "%s: only %d elastic frequencies" % (name, len(el))
    worst = max(abs(a - b) / b for a, b in el)
    return "%s: max rel diff %.1e %s" % (name, worst, "ok" if worst < 1e-6 else "DIFFERS")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--sizes", default="3e4,1e5,3e5")
    p.add_argument("--skip", default="")
    p.add_argument("--no-install", action="store_true")
    p.add_argument("--reductions", action="store_true")
    p.add_argument("--work", default=os.path.join(ROOT, "target", "bench-eigen"))
    a = p.parse_args()
    skip = set(a.skip.split(","))
    if not a.no_install:
        subprocess.run(["apt-get", "install", "-y", "-q", "libsuitesparse-dev"], capture_output=True)
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "scipy", "scikit-sparse==0.4.16", "exudyn"])
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    exe = os.path.join(ROOT, "target", "release", "flexbody")
    os.makedirs(a.work, exist_ok=True)
    sizes = a.sizes.split(",")
    for size in sizes:
        nx, ny, nz = SIZES[size]
        base = "beam_%s" % size
        gen = [sys.executable, os.path.join(ROOT, "bench", "gen_block.py"), str(nx), str(ny), str(nz)]
        out = subprocess.run(gen + [base + ".inp", "--hollow", "1", "--step", "frequency:%d" % COUNT],
                             cwd=a.work, check=True, capture_output=True, text=True).stdout
        subprocess.run(gen + [base + "_k.inp", "--hollow", "1", "--step", "matrixstorage"],
                       cwd=a.work, check=True, capture_output=True)
        print("\n== %s" % out.strip())
        rows = []
        r = measured([exe, "modes", base + ".inp", "--count", str(COUNT), "--json"], a.work)
        if r is None:
            continue
        ref = json.loads(r[2])["frequencies_hz"]
        rows.append(("flexbody", r[0], r[1], "max residual %.1e" % max(json.loads(r[2])["residuals"])))
        if not ({"superlu", "cholmod"} <= skip) and not os.path.exists(os.path.join(a.work, base + "_k.sti")):
            subprocess.run(["ccx", "-i", base + "_k"], cwd=a.work, env=ENV, check=True, capture_output=True)
        for mode in ("superlu", "cholmod"):
            if mode in skip:
                continue
            r = measured([sys.executable, "-c", SCIPY, base + "_k", mode, str(COUNT)], a.work)
            if r:
                d = json.loads(r[2].strip().splitlines()[-1])
                rows.append(("scipy+" + mode, r[0], r[1], agree(mode, d["hz"], ref) + ", eigsh %.1f s" % d["solve_s"]))
        if "ccx" not in skip:
            r = measured(["ccx", "-i", base], a.work)
            if r:
                rows.append(("calculix", r[0], r[1], agree("ccx", ccx_frequencies(os.path.join(a.work, base + ".dat")), ref)))
        t0 = rows[0][1]
        print("%-16s %10s %10s %8s  %s" % ("tool", "seconds", "peak GB", "x flexb", "check"))
        for name, s, gb, note in rows:
            print("%-16s %10.2f %10.2f %8.2f  %s" % (name, s, gb, s / t0, note))
    if a.reductions:
        size = sizes[-1]
        nx, ny, nz = SIZES[size]
        base = "beam_%s" % size
        # 4 corner nodes of the end face x = 0 (12 DOFs)
        nid = lambda i, j, k: 1 + i + (nx + 1) * (j + (ny + 1) * k)
        nodes = [nid(0, 0, 0), nid(0, ny, 0), nid(0, 0, nz), nid(0, ny, nz)]
        iface = ",".join(map(str, nodes))
        print("\n== reductions on %s, interface nodes %s" % (base, iface))
        for method in ("free-residual", "craig-bampton"):
            r = measured([exe, "reduce", base + ".inp", "--method", method, "--modes", "20",
                          "--interface", iface, "--out", method + ".json", "--json"], a.work)
            if r:
                print("flexbody %-14s %8.2f s %6.2f GB" % (method, r[0], r[1]))
        if "exudyn" not in skip:
            r = measured([sys.executable, "-c", EXUDYN, base + "_k", iface], a.work)
            if r:
                print("exudyn HCB          %8.2f s %6.2f GB" % (r[0], r[1]))


if __name__ == "__main__":
    main()
