#!/usr/bin/env python3
"""Writes the large-model cases of docs/performance.md beside the
decks that `bench/eigen.py` generates (run it first, with --sizes 3e5 and,
for the solid, --types solid --sizes 1e6). SI units.

usage: large_cases.py [--dir target/bench-eigen]

- beam_er.toml: the 3e5 C3D8 beam on springs of 1e7 N/m in x, y, z at its
  interface nodes (elastic-residual);
- beam_clamped.inp: the same beam with every node of its end x = 0 fixed
  (free-residual of a supported body, interface at the other end);
- beam_study.toml, beam_frf.toml: the beam on four track springs, with a
  [study] at 100 rad/s and an [frf] of two frequencies and two time steps
  (the full model's response: study, frf --full, simulate --full);
- solid_er.toml: the 1e6 C3D10 solid on the same springs (if its deck is
  there).
"""
import argparse
import os

BEAM = "beam_c3d8_3e5.inp"
BEAM_INTERFACE = [1, 325801, 13033, 338833]
SOLID = "solid_c3d10_1e6.inp"
SOLID_INTERFACE = [1, 318781, 7085, 325865]
AXES = {"x": "[1.0, 0.0, 0.0]", "y": "[0.0, 1.0, 0.0]", "z": "[0.0, 0.0, 1.0]"}


def springs(nodes, to, axes):
    out = []
    for n in nodes:
        for a in axes:
            name = f"n{n}{a}" if len(axes) > 1 else f"n{n}"
            out += ["[[connection]]", f'name = "{name}"', f"node = {n}", f'to = "{to}"',
                    f"direction = {AXES[a]}", "stiffness = 1.0e7", ""]
    return out


def write(path, lines):
    with open(path, "w") as f:
        f.write("\n".join(lines))
    print("wrote", path)


def clamped(deck, out):
    """`deck` with every node at x = 0 fixed in ux, uy, uz (*BOUNDARY)."""
    lines = open(deck).read().split("\n")
    end, in_nodes = [], False
    for line in lines:
        if line.startswith("*"):
            in_nodes = line.upper().startswith("*NODE")
            continue
        if in_nodes:
            p = line.split(",")
            if len(p) == 4 and float(p[1]) == 0.0:
                end.append(p[0].strip())
    step = lines.index("*STEP")
    nset = ["*NSET, NSET=CLAMP"] + [", ".join(end[k:k + 16]) for k in range(0, len(end), 16)]
    write(out, lines[:step] + nset + ["*BOUNDARY", "CLAMP, 1, 3"] + lines[step:])


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--dir", default="target/bench-eigen")
    d = p.parse_args().dir
    if not os.path.exists(os.path.join(d, BEAM)):
        raise SystemExit(f"{os.path.join(d, BEAM)} is missing: run python3 bench/eigen.py "
                         "--sizes 3e5 --types C3D8 first")
    head = [f'mesh = "{BEAM}"', ""]
    write(os.path.join(d, "beam_er.toml"),
          ["# The 3e5 C3D8 beam on springs at its 4 interface nodes (SI units)."] + head
          + springs(BEAM_INTERFACE, "ground", "xyz"))
    track = ["[interface]", f"nodes = {BEAM_INTERFACE}", "", "[track]", "amplitude = 0.001",
             "wavelength = 4.0", ""] + springs(BEAM_INTERFACE, "track", "z")
    study = ["[study]", "omegas = [100.0]",
             'cases = [{ method = "free-residual", modes = 20 }]', ""]
    write(os.path.join(d, "beam_study.toml"),
          ["# The 3e5 C3D8 beam on four track springs (SI units)."] + head + track + study)
    write(os.path.join(d, "beam_frf.toml"),
          ["# The 3e5 C3D8 beam on four track springs (SI units)."] + head + track + study
          + ["[frf]", "band_hz = [10.0, 40.0]", "points = 2", "", "[simulation]",
             'method = "free-residual"', "modes = 20", "speed = 10.0", "duration = 0.001",
             "step = 0.0005", ""])
    clamped(os.path.join(d, BEAM), os.path.join(d, "beam_clamped.inp"))
    if os.path.exists(os.path.join(d, SOLID)):
        write(os.path.join(d, "solid_er.toml"),
              ["# The 1e6 C3D10 solid on springs at its 4 interface nodes (SI units).",
               f'mesh = "{SOLID}"', ""] + springs(SOLID_INTERFACE, "ground", "xyz"))


if __name__ == "__main__":
    main()
