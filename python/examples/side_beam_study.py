"""The report's side beam: which reduction, with how many modes, gives
the displacements and section forces how accurately?

Reads the model file examples/side_beam.toml (its [study] table: methods,
mode counts, excitation frequencies), runs the study against the full
model, and prints the error table; with pandas installed, as a DataFrame.

Run: python python/examples/side_beam_study.py
"""

from pathlib import Path

import flexbody

MODEL = Path(__file__).resolve().parents[2] / "examples" / "side_beam.toml"


def main():
    model = flexbody.read(MODEL)
    result = model.study()
    best = {}
    for row in result.records:
        key = (row["method"], row["omega"])
        if key not in best or row["r"] > best[key]["r"]:
            best[key] = row
    return {"model": model, "result": result, "largest_r": best}


if __name__ == "__main__":
    out = main()
    result = out["result"]
    try:
        print(result.to_dataframe().to_string(index=False))
    except ImportError:
        print(f"{'method':>17} {'r':>4} {'omega (rad/s)':>14} {'err_w':>10} {'err_m':>10} {'err_q':>10}")
        for row in result.records:
            print(f"{row['method']:>17} {row['r']:>4} {row['omega']:>14.4g} {row['err_w']:>10.2e} "
                  f"{row.get('err_m', float('nan')):>10.2e} {row.get('err_q', float('nan')):>10.2e}")
    for case in result.failed:
        print("failed:", case)
