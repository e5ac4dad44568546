#!/usr/bin/env python3
"""Benchmark: what the input checks cost. The current flexbody against a
baseline build (a git revision) reading and writing the same large model,
alternating the two builds in the same run.

usage: bench/checks.py BASELINE_REV [--size NX NY NZ] [--modes N] [--repeat N]

Generates a free C3D8 bar (gen_block.py; default 100 x 30 x 30 elements,
2.9e5 DOFs) and, per build and repeat:
  - `flexbody info DECK`: read the deck and assemble K and M (wall clock);
  - `flexbody reduce DECK --method free --modes N --format F` for F in json,
    sid and mtx: the seconds of writing the body, from the --verbose log
    (its time stamp at "written" less the one at "eigenmodes done"), so that
    the eigen solve's own variation stays out;
  - `flexbody inspect BODY` of each written body: read and check it
    (wall clock).
Prints the median of each over the repeats and the ratio current /
baseline. The baseline is built with `cargo build --release` in a git
worktree under target/bench-baseline; the current tree in target/release.
"""
import argparse
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

from measure import run_child

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FORMATS = ("json", "sid", "mtx")


def build(rev):
    """(baseline exe, current exe), both release builds."""
    base = os.path.join(ROOT, "target", "bench-baseline")
    tree = os.path.join(base, "tree")
    commit = lambda where, r: subprocess.run(["git", "rev-parse", r + "^{commit}"], cwd=where, check=True,
                                             capture_output=True, text=True).stdout.strip()
    if os.path.exists(tree) and commit(tree, "HEAD") != commit(ROOT, rev):
        subprocess.run(["git", "worktree", "remove", "--force", tree], cwd=ROOT, check=True)
    if not os.path.exists(tree):
        subprocess.run(["git", "worktree", "add", "--detach", "-q", tree, rev], cwd=ROOT, check=True)
    env = dict(os.environ, CARGO_TARGET_DIR=os.path.join(base, "target"))
    subprocess.run(["cargo", "build", "--release", "-q", "--bin", "flexbody"], cwd=tree, env=env, check=True)
    subprocess.run(["cargo", "build", "--release", "-q", "--bin", "flexbody"], cwd=ROOT, check=True)
    return (os.path.join(base, "target", "release", "flexbody"),
            os.path.join(ROOT, "target", "release", "flexbody"))


def run(cmd, cwd):
    r = run_child(cmd, cwd, None, 20000)
    if r["rc"] != 0:
        sys.exit("%s failed (%d):\n%s\n%s" % (" ".join(cmd), r["rc"], r["out"], r["err"]))
    return r


def stamp(log, what):
    """The time stamp (s) of the last log line holding `what`."""
    times = [float(m.group(1)) for m in re.finditer(r"^\[\s*([0-9.]+) s[^\]]*\] (.*)$", log, re.M)
             if what in m.group(2)]
    if not times:
        sys.exit("no '%s' line in the log:\n%s" % (what, log[-2000:]))
    return times[-1]


def one_round(exe, deck, work, modes):
    """Seconds of each measured step for one build."""
    out = {"info (read + assemble)": run([exe, "info", deck], work)["s"]}
    for fmt in FORMATS:
        body = os.path.join(work, "body." + fmt if fmt != "mtx" else "body-mtx")
        shutil.rmtree(body, ignore_errors=True)
        r = run([exe, "-v", "reduce", deck, "--method", "free", "--modes", str(modes),
                 "--format", fmt, "--out", body], work)
        out["reduce: write %s" % fmt] = stamp(r["err"], "written") - stamp(r["err"], "eigenmodes done")
        out["inspect %s (read + check)" % fmt] = run([exe, "inspect", body], work)["s"]
    return out


def main():
    p = argparse.ArgumentParser()
    p.add_argument("baseline")
    p.add_argument("--size", type=int, nargs=3, default=[100, 30, 30])
    p.add_argument("--modes", type=int, default=20)
    p.add_argument("--repeat", type=int, default=3)
    a = p.parse_args()
    old, new = build(a.baseline)
    work = tempfile.mkdtemp(prefix="flexbody-checks-")
    deck = os.path.join(work, "bar.inp")
    gen = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "gen_block.py")]
                         + [str(v) for v in a.size] + [deck, "--step", "none"],
                         check=True, capture_output=True, text=True)
    print(gen.stdout.strip())
    times = {"baseline": [], "current": []}
    for k in range(a.repeat):
        for name, exe in (("baseline", old), ("current", new)) if k % 2 == 0 else (("current", new), ("baseline", old)):
            times[name].append(one_round(exe, deck, work, a.modes))
    print()
    print("%-30s %10s %10s %8s" % ("median of %d (s)" % a.repeat, "baseline", "current", "ratio"))
    for step in times["current"][0]:
        b = statistics.median(t[step] for t in times["baseline"])
        c = statistics.median(t[step] for t in times["current"])
        spread = max(t[step] for t in times["current"] + times["baseline"]) - min(
            t[step] for t in times["current"] + times["baseline"])
        print("%-30s %10.2f %10.2f %8.2f   (range of all runs %.2f s)" % (step, b, c, c / b, spread))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
