"""The Python package computes what the command line computes, on the same
inputs: the same frequencies and the same body files, byte for byte."""

import numpy as np
import pytest

import flexbody
from conftest import EXAMPLES, PY_EXAMPLES

MODELS = [EXAMPLES / "side_beam.toml", EXAMPLES / "side_beam_solid.toml", PY_EXAMPLES / "pendulum_arm.inp"]

# (model, interface, method, modes)
REDUCTIONS = [
    (EXAMPLES / "side_beam.toml", None, "craig-bampton", 4),
    (EXAMPLES / "side_beam.toml", None, "free-residual", 3),
    (EXAMPLES / "side_beam.toml", None, "elastic-residual", 3),
    (EXAMPLES / "side_beam.toml", None, "free", 8),
    (EXAMPLES / "side_beam.toml", None, "guyan", None),
    (EXAMPLES / "side_beam_solid.toml", None, "craig-bampton", 6),
    (PY_EXAMPLES / "pendulum_arm.inp", "PIVOT,TIP", "free-residual", 4),
]


@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.name)
def test_modes_equal_the_cli(cli, path):
    model = flexbody.read(path)
    ours = model.modes(count=12)
    theirs = cli.json("modes", path, "--count", 12, "--json")
    assert theirs["dofs"] == len(model)
    top = max(theirs["frequencies_hz"])
    np.testing.assert_allclose(ours.frequencies_hz, theirs["frequencies_hz"], rtol=1e-12, atol=1e-9 * top)
    np.testing.assert_allclose(ours.residuals, theirs["residuals"], rtol=1e-6, atol=1e-15)
    # The shapes are M-orthonormal eigenvectors of K and M.
    K, M, phi = model.K, model.M, ours.shapes
    np.testing.assert_allclose(phi.T @ (M @ phi), np.eye(12), atol=1e-10)
    np.testing.assert_allclose(phi.T @ (K @ phi), np.diag(ours.eigenvalues), atol=1e-9 * ours.eigenvalues[-1])


def test_modes_below_a_frequency_equal_the_cli(cli):
    path = EXAMPLES / "side_beam_solid.toml"
    ours = flexbody.read(path).modes(fmax=400.0)
    theirs = cli.json("modes", path, "--fmax", 400, "--json")
    assert len(ours.frequencies_hz) == len(theirs["frequencies_hz"]) > 6
    assert ours.frequencies_hz.max() < 400.0
    np.testing.assert_allclose(ours.frequencies_hz[6:], theirs["frequencies_hz"][6:], rtol=1e-12)


@pytest.mark.parametrize("path, interface, method, modes", REDUCTIONS, ids=lambda v: getattr(v, "name", str(v)))
def test_bodies_equal_the_cli_byte_for_byte(cli, tmp_path, path, interface, method, modes):
    body = flexbody.read(path).reduce(method, interface=interface, modes=modes)
    args = ["reduce", path, "--method", method]
    if modes is not None:
        args += ["--modes", modes]
    if interface is not None:
        args += ["--interface", interface]
    for fmt in ("json", "sid"):
        ours, theirs = tmp_path / f"py.{fmt}", tmp_path / f"cli.{fmt}"
        body.write(ours, format=fmt)
        cli(*args, "--format", fmt, "--out", theirs)
        assert ours.read_bytes() == theirs.read_bytes(), f"{fmt} differs"
    np.testing.assert_allclose(
        body.frequencies_hz()[:3],
        cli.json(*args, "--out", tmp_path / "again.json", "--json")["reduced_hz"][:3],
        rtol=1e-12,
        atol=1e-6,
    )


def test_study_equals_the_cli(cli):
    path = EXAMPLES / "side_beam.toml"
    ours = flexbody.read(path).study()
    theirs = cli.json("study", path, "--json", "--no-plots")
    assert len(ours.records) == len(theirs["cases"]) > 0
    assert ours.failed == theirs["failed"]
    for a, b in zip(ours.records, theirs["cases"]):
        assert (a["method"], a["r"]) == (b["method"], b["r"])
        for key in ("omega", "err_w", "err_m", "err_q", "err_force"):
            assert a[key] == pytest.approx(b[key], rel=1e-9, abs=1e-14), key
