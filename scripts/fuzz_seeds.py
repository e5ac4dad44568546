#!/usr/bin/env python3
"""Seed corpus of the fuzz targets (fuzz/fuzz_targets/), made from the
project's own inputs: the decks and model files of examples/ and
tests/fixtures/, the CalculiX matrices of tests/fixtures/calculix/ (cut to
their first equations, so that the fuzzer runs fast on them; decks and
model files over 16 kB are left out) and the same
matrices as Matrix Market files, and the reduced bodies (JSON, SID, Matrix
Market folder) that `flexbody reduce` writes for examples/side_beam.toml.

Usage: fuzz_seeds.py OUT_DIR FLEXBODY_BINARY
Writes OUT_DIR/<target>/<name> for every target; one input is a bundle
(fuzz/src/bundle.rs): the main file, then `@@@ name` lines starting the
other files.
"""

import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
MARK = "@@@ "
# Equations kept of a CalculiX fixture: enough for several nodes and
# every DOF direction, small enough for thousands of runs a second.
KEEP_EQUATIONS = 18
# Larger decks and model files are left out: a seed must run well within
# the fuzzer's one second per input (the 32 kB solid side beam takes longer
# in the lightly optimised fuzz build), and small inputs mutate faster.
MAX_SEED = 16 * 1024


def bundle(main, others=()):
    """One input: `main`, then each (name, text) of `others`."""
    text = main if main.endswith("\n") or not main else main + "\n"
    for name, body in others:
        text += f"{MARK}{name}\n{body}"
        if body and not body.endswith("\n"):
            text += "\n"
    return text


def write(out, target, name, text):
    if target in ("deck", "model_file") and len(text.encode()) > MAX_SEED:
        return
    path = out / target / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


def decks(out):
    for inp in sorted(ROOT.glob("examples/*.inp")) + sorted(
        ROOT.glob("tests/fixtures/**/*.inp")
    ):
        write(out, "deck", inp.stem, inp.read_text())
    # An *INCLUDE: the first fixture split in two files.
    first = sorted(ROOT.glob("tests/fixtures/calculix/*/*.inp"))[0].read_text()
    lines = first.splitlines(keepends=True)
    cut = next(i for i, l in enumerate(lines) if l.upper().startswith("*ELEMENT"))
    write(
        out,
        "deck",
        "include",
        bundle(
            "".join(lines[:cut]) + "*INCLUDE, INPUT=part.inp\n",
            [("part.inp", "".join(lines[cut:]))],
        ),
    )


def model_files(out):
    for toml in sorted(ROOT.glob("examples/*.toml")):
        text = toml.read_text()
        others = []
        for line in text.splitlines():
            key, _, value = line.partition("=")
            if key.strip() == "mesh":
                mesh = value.split("#")[0].strip().strip('"')
                others.append((mesh, (toml.parent / mesh).read_text()))
        write(out, "model_file", toml.stem, bundle(text, others))


def cut_matrices(folder):
    """(dof lines, K entries, M entries) of a CalculiX fixture, cut to its
    first KEEP_EQUATIONS equations."""
    job = next(folder.glob("*.dof")).with_suffix("")
    dofs = job.with_suffix(".dof").read_text().splitlines()[:KEEP_EQUATIONS]

    def entries(ext):
        kept = []
        for line in job.with_suffix(ext).read_text().splitlines():
            fields = line.split()
            if len(fields) == 3 and max(int(fields[0]), int(fields[1])) <= KEEP_EQUATIONS:
                kept.append(fields)
        return kept

    return dofs, entries(".sti"), entries(".mas")


def matrices(out):
    for folder in sorted(ROOT.glob("tests/fixtures/calculix/*")):
        if not any(folder.glob("*.sti")):
            continue
        dofs, k, m = cut_matrices(folder)
        lines = lambda es: "".join(f"{r} {c} {v}\n" for r, c, v in es)
        write(
            out,
            "calculix_matrices",
            folder.name,
            bundle(lines(k), [("job.mas", lines(m)), ("job.dof", "\n".join(dofs))]),
        )
        n = len(dofs)

        def market(es, symmetry):
            head = f"%%MatrixMarket matrix coordinate real {symmetry}\n% {folder.name}\n"
            rows = list(es)
            if symmetry == "general":
                rows += [(c, r, v) for r, c, v in es if r != c]
            return head + f"{n} {n} {len(rows)}\n" + lines(rows)

        dof_list = "# node dof\n" + "".join(
            f"{d.split('.')[0]} {d.split('.')[1]}\n" for d in dofs
        )
        for symmetry in ("symmetric", "general"):
            write(
                out,
                "matrix_market",
                f"{folder.name}-{symmetry}",
                bundle(
                    market(k, symmetry),
                    [("m.mtx", market(m, symmetry)), ("dofs.txt", dof_list)],
                ),
            )


def bodies(out, flexbody):
    model = ROOT / "examples" / "side_beam.toml"
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        for fmt, name in (("json", "body.json"), ("sid", "body.sid"), ("mtx", "body")):
            subprocess.run(
                [flexbody, "--quiet", "reduce", str(model), "--method",
                 "free-residual", "--modes", "1", "--format", fmt,
                 "--out", str(tmp / name), "--check", "never"],
                check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            )
        json_text = (tmp / "body.json").read_text()
        sid_text = (tmp / "body.sid").read_text()
        folder = tmp / "body"
        index = (folder / "index.json").read_text()
        mtx_files = [
            (p.name, p.read_text()) for p in sorted(folder.iterdir()) if p.name != "index.json"
        ]
        write(out, "body_json", "side_beam", json_text)
        write(out, "body_sid", "side_beam", sid_text)
        write(out, "body_mtx", "side_beam", bundle(index, mtx_files))
        write(out, "body_any", "side_beam-json", json_text)
        write(out, "body_any", "side_beam-sid", sid_text)
        write(out, "body_any", "side_beam-mtx", bundle("", [("index.json", index)] + mtx_files))


def main():
    out = pathlib.Path(sys.argv[1])
    flexbody = sys.argv[2]
    decks(out)
    model_files(out)
    matrices(out)
    bodies(out, flexbody)


if __name__ == "__main__":
    main()
