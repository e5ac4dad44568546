"""The examples in python/examples run, and what they show holds."""

import importlib.util
import subprocess
import sys

import numpy as np
import pytest

from conftest import PY_EXAMPLES, require


def example(name):
    spec = importlib.util.spec_from_file_location(name, PY_EXAMPLES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("name", ["side_beam_study", "deck_to_exudyn_pendulum", "scipy_to_sid"])
def test_the_example_runs_as_a_script(name, tmp_path):
    if name == "deck_to_exudyn_pendulum":
        require("exudyn")
    done = subprocess.run([sys.executable, str(PY_EXAMPLES / f"{name}.py")], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip()


def test_the_side_beam_study_finds_the_reports_ranking():
    out = example("side_beam_study").main()
    result = out["result"]
    assert result.failed == []
    rows = {(r["method"], r["r"], round(r["omega"])): r for r in result.records}
    # At 122 rad/s, with the same few coordinates, the residual methods
    # give the section forces far better than free-interface modes.
    free, residual = rows[("free", 7, 122)], rows[("free-residual", 7, 122)]
    assert residual["err_m"] < free["err_m"] / 100
    assert residual["err_q"] < free["err_q"] / 100
    # All 42 free modes: the full model itself, to round-off.
    assert rows[("free", 42, 0)]["err_w"] < 1e-8


def test_the_exudyn_pendulum_swings_at_the_full_models_frequency():
    require("exudyn")
    out = example("deck_to_exudyn_pendulum").main(swing_seconds=0.3)
    exudyn_hz, full_hz = out["exudyn_hz"], out["full_hz"]
    # Three rotations about the ball joint, then the first bending mode.
    assert np.all(exudyn_hz[:3] < 1e-3 * exudyn_hz[3])
    assert np.all(full_hz[:3] < 1e-3 * full_hz[3])
    assert exudyn_hz[3] == pytest.approx(full_hz[3], rel=1e-4)
    # Pinned-free Euler-Bernoulli bar: beta L = 3.9266.
    closed_form = 3.926602312**2 / (2 * np.pi) * np.sqrt(2.1e11 * 0.02 * 0.01**3 / 12 / (7850 * 0.02 * 0.01))
    assert full_hz[3] == pytest.approx(closed_form, rel=2e-3)
    # The tip stays 1 m from the pivot (a stiff arm) while it falls.
    tip = out["tip_path"]
    np.testing.assert_allclose(np.linalg.norm(tip, axis=1), 1.0, atol=1e-3)
    assert tip[-1, 2] < -0.3
