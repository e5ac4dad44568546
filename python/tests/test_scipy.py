"""Matrices from SciPy: flexbody's modes are SciPy's (eigsh) to 1e-8."""

import numpy as np
import pytest
import scipy.sparse.linalg as sla

import flexbody
from conftest import PY_EXAMPLES

import importlib.util

_spec = importlib.util.spec_from_file_location("scipy_to_sid", PY_EXAMPLES / "scipy_to_sid.py")
scipy_to_sid = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(scipy_to_sid)


def cantilever(elements):
    """The example's beam clamped at node 1 (its two DOFs removed)."""
    K, M, dofs, coords = scipy_to_sid.beam_matrices(elements)
    return K[2:, 2:], M[2:, 2:], dofs[2:], coords


# The difference grows with the condition of K (as elements^4): it is the
# round-off of the Rayleigh quotients (x^T K x cancels for the lowest
# modes), 2e-10 at 40 elements, 7e-9 at 100, 4e-8 at 200.
@pytest.mark.parametrize("elements", [40, 80])
def test_modes_of_scipy_matrices_equal_eigsh(elements):
    K, M, dofs, coords = cantilever(elements)
    ours = flexbody.Model.from_matrices(K, M, dofs, coords=coords).modes(count=8)
    values = np.sort(sla.eigsh(K, k=8, M=M, sigma=0.0, which="LM", return_eigenvectors=False))
    np.testing.assert_allclose(ours.eigenvalues, values, rtol=1e-8)
    # And both near the closed form of a cantilever (beta L = 1.8751).
    area = scipy_to_sid.WIDTH * scipy_to_sid.HEIGHT
    inertia = scipy_to_sid.WIDTH * scipy_to_sid.HEIGHT**3 / 12
    first = 1.875104069**2 / (2 * np.pi) * np.sqrt(
        scipy_to_sid.E * inertia / (scipy_to_sid.RHO * area * scipy_to_sid.LENGTH**4)
    )
    assert ours.frequencies_hz[0] == pytest.approx(first, rel=1e-6)


def test_matrices_come_back_as_given():
    K, M, dofs, coords = cantilever(10)
    model = flexbody.Model.from_matrices(K, M, dofs, coords=coords)
    assert abs(model.K - K).max() <= 1e-15 * abs(K).max()
    assert abs(model.M - M).max() <= 1e-15 * abs(M).max()
    assert model.D is None
    np.testing.assert_array_equal(model.dofs[:2], [[2, 3], [2, 5]])
    np.testing.assert_array_equal(model.node_ids, np.arange(1, 12))


def test_the_scipy_beam_becomes_a_sid(tmp_path):
    result = scipy_to_sid.main(tmp_path / "beam.sid")
    np.testing.assert_allclose(result["reduced_hz"], result["closed_form_hz"], rtol=2e-3)
    assert result["sid_mass"] == pytest.approx(result["mass"], rel=1e-12)
    assert len(result["sid"].coordinates) == 8
