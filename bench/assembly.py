#!/usr/bin/env python3
"""Benchmark: read and assemble a generated C3D8 mesh, flexbody
against CalculiX reading the same deck with *FREQUENCY, SOLVER=MATRIXSTORAGE
(which reads, assembles, writes K and M, and stops), in the same run.

usage: bench/assembly.py [NX NY NZ]      (default 200 40 40: about 1.0e6 DOFs)

Prints seconds (wall clock) and peak memory (max RSS) of each program and
their ratios. Both run as child processes measured the same way. CalculiX
also writes its matrices as text; that time is part of its figure.
Needs: cargo, python3, ccx (installed with apt-get when missing and root).
"""
import os
import shutil
import subprocess
import sys
import tempfile

from measure import run_child

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def measured(cmd, cwd, env=None):
    """Runs cmd in a fresh Python child so its max RSS is its own."""
    r = run_child(cmd, cwd, env, 4000)
    if r["rc"] != 0:
        sys.exit("%s failed (%d):\n%s\n%s" % (" ".join(cmd), r["rc"], r["out"], r["err"]))
    return r["s"], r["gib"], r["out"]


def main():
    nx, ny, nz = (int(v) for v in sys.argv[1:4]) if len(sys.argv) >= 4 else (200, 40, 40)
    if shutil.which("ccx") is None:
        if os.geteuid() == 0:
            subprocess.run(["apt-get", "install", "-y", "-q", "calculix-ccx"], check=True, capture_output=True)
        else:
            sys.exit("ccx (Debian package calculix-ccx) is needed")
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    exe = os.path.join(ROOT, "target", "release", "flexbody")
    work = tempfile.mkdtemp(prefix="flexbody-bench-")
    deck = os.path.join(work, "block.inp")
    gen = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "gen_block.py"), str(nx), str(ny), str(nz), deck],
                         check=True, capture_output=True, text=True)
    print(gen.stdout.strip())
    fb_s, fb_gb, fb_out = measured([exe, "info", deck], work)
    print(fb_out.strip())
    env = dict(os.environ, OMP_NUM_THREADS="2", OPENBLAS_NUM_THREADS="1")
    ccx_s, ccx_gb, _ = measured(["ccx", "-i", "block"], work, env)
    for ext in ("sti", "mas", "dof"):
        if not os.path.exists(os.path.join(work, "block." + ext)):
            sys.exit("ccx wrote no block.%s" % ext)
    print()
    print("%-34s %10s %12s" % ("read + assemble K and M", "seconds", "peak GB"))
    print("%-34s %10.2f %12.2f" % ("flexbody info", fb_s, fb_gb))
    print("%-34s %10.2f %12.2f" % ("ccx *FREQUENCY MATRIXSTORAGE", ccx_s, ccx_gb))
    print("%-34s %10.2f %12.2f" % ("ratio ccx / flexbody", ccx_s / fb_s, ccx_gb / fb_gb))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
