#!/usr/bin/env python3
"""Benchmark: what calling flexbody from Python costs over the command line.

The lowest 26 modes of the free C3D8 box-section beam of bench/eigen.py
(3e5 DOFs), once by `flexbody modes DECK --count 26 --json` and once by
`flexbody.read(DECK).modes(count=26)` in a fresh Python process (the
interpreter's start and the import included), alternating, each run in
its own child; the medians and the fastest of --repeat runs are
compared, and all runs are printed.
Both are release builds: the binary by `cargo build --release`, the
package by `pip install ./python` into target/bench-python-venv. The
frequencies of the two must agree to 1e-12.

usage: bench/python_overhead.py [--size 3e5] [--repeat 3] [--work DIR]
"""
import argparse
import json
import os
import subprocess
import sys

from eigen import COUNT, ENV, SIZES, model
from measure import run_child

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

PYTHON_RUN = r'''
import json, sys, flexbody
modes = flexbody.read(sys.argv[1]).modes(count=int(sys.argv[2]))
print(json.dumps({"frequencies_hz": modes.frequencies_hz.tolist()}))
'''


def once(cmd, cwd):
    r = run_child(cmd, cwd, ENV, 20000)
    if r["rc"] != 0:
        sys.exit("%s failed:\n%s" % (" ".join(cmd), r["err"][-2000:]))
    return r["s"], r["gib"], json.loads(r["out"])["frequencies_hz"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--size", default="3e5")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--work", default=os.path.join(ROOT, "target", "bench-eigen"))
    a = p.parse_args()
    subprocess.run(["cargo", "build", "--release", "-q"], cwd=ROOT, check=True)
    exe = os.path.join(ROOT, "target", "release", "flexbody")
    venv = os.path.join(ROOT, "target", "bench-python-venv")
    python = os.path.join(venv, "bin", "python")
    if not os.path.exists(python):
        subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", venv], check=True)
    subprocess.run([python, "-m", "pip", "install", "-q", "--disable-pip-version-check",
                    os.path.join(ROOT, "python")], check=True)
    os.makedirs(a.work, exist_ok=True)
    nx, ny, nz = SIZES["C3D8"][a.size]
    base, shape = model("C3D8", a.size)
    deck = base + ".inp"
    if not os.path.exists(os.path.join(a.work, deck)):
        gen = [sys.executable, os.path.join(ROOT, "bench", "gen_block.py"), str(nx), str(ny), str(nz)]
        subprocess.run(gen + [deck] + shape + ["--step", "frequency:%d" % COUNT],
                       cwd=a.work, check=True, capture_output=True)
    cli_cmd = [exe, "--quiet", "modes", deck, "--count", str(COUNT), "--json"]
    py_cmd = [python, "-c", PYTHON_RUN, deck, str(COUNT)]
    runs = {"cli": [], "python": []}
    for _ in range(max(1, a.repeat)):
        runs["cli"].append(once(cli_cmd, a.work))
        runs["python"].append(once(py_cmd, a.work))
    for name, rs in runs.items():
        print("%s: %s s" % (name, ", ".join("%.2f" % r[0] for r in rs)))
    cli = min(runs["cli"], key=lambda r: r[0])
    py = min(runs["python"], key=lambda r: r[0])
    median = {name: sorted(r[0] for r in rs)[len(rs) // 2] for name, rs in runs.items()}
    worst = max(abs(x - y) / max(abs(y), 1e-300) for x, y in zip(py[2][6:], cli[2][6:]))
    print("\n| C3D8 beam, %s DOFs, modes (26) | median s | fastest s | peak GiB | x CLI (medians) | x CLI (fastest) |" % a.size)
    print("| --- | --- | --- | --- | --- | --- |")
    print("| `flexbody modes` | %.2f | %.2f | %.2f | 1 | 1 |" % (median["cli"], cli[0], cli[1]))
    print("| `flexbody.read(deck).modes(count=26)` | %.2f | %.2f | %.2f | %.3f | %.3f |"
          % (median["python"], py[0], py[1], median["python"] / median["cli"], py[0] / cli[0]))
    print("\nelastic frequencies, Python against the CLI: largest relative difference %.1e" % worst)
    if worst > 1e-12:
        sys.exit("the frequencies differ")


if __name__ == "__main__":
    main()
