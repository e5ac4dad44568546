"""Body arrays and files: what a Body holds, written and read back."""

import numpy as np
import pytest

import flexbody
from conftest import EXAMPLES, PY_EXAMPLES


@pytest.fixture(scope="module")
def arm():
    model = flexbody.read(PY_EXAMPLES / "pendulum_arm.inp")
    return model, model.reduce("craig-bampton", interface="PIVOT,TIP", modes=5)


def test_the_reduced_matrices_are_the_projections_of_k_and_m(arm):
    model, body = arm
    T = body.basis
    assert T.shape == (len(model), body.r) == (126, 12 + 5)
    assert T.flags.f_contiguous
    np.testing.assert_allclose(body.mass, T.T @ (model.M @ T), atol=1e-12 * np.abs(body.mass).max())
    np.testing.assert_allclose(body.stiffness, T.T @ (model.K @ T), atol=1e-10 * np.abs(body.stiffness).max())
    np.testing.assert_array_equal(body.dofs, model.dofs)
    # Craig-Bampton: the interface rows are the identity on the constraint modes.
    rows = body.interface_rows
    np.testing.assert_allclose(rows[:, :12], np.eye(12), atol=1e-12)
    np.testing.assert_allclose(rows[:, 12:], 0.0, atol=1e-12)
    assert body.mode_kinds[0] == "constraint node 1 ux"
    assert body.mode_kinds[-1].startswith("eigen ")


def test_the_invariants_are_what_the_sid_file_holds(arm, tmp_path):
    _, body = arm
    inv = body.invariants()
    assert inv["mass"] == pytest.approx(7850 * 0.02 * 0.01 * 1.0, rel=1e-12)
    # The arm from 0 to 1 m along x: the first moment is m * 0.5 m.
    np.testing.assert_allclose(inv["md_cm"], [inv["mass"] * 0.5, 0, 0], atol=1e-12)
    body.write(tmp_path / "arm.sid", format="sid")
    sid = flexbody.load(tmp_path / "arm.sid")
    assert isinstance(sid, flexbody.Sid)
    assert sid.mass == pytest.approx(inv["mass"], rel=1e-12)
    for name, key in [("me", "me"), ("ke", "ke"), ("ct", "ct"), ("cr", "cr"), ("gr", "gr"), ("oe", "oe")]:
        m0, _ = sid.term(name)
        np.testing.assert_allclose(m0, inv[key], rtol=1e-12, atol=1e-12 * max(1.0, np.abs(inv[key]).max()))
    _, cr1 = sid.term("cr")
    np.testing.assert_allclose(np.array(cr1), inv["cr1"], atol=1e-12 * np.abs(inv["cr1"]).max())
    nodes = sid.nodes()
    assert [n["id"] for n in nodes] == [n["id"] for n in inv["nodes"]] == [1, 21]


@pytest.mark.parametrize("fmt", ["json", "mtx"])
def test_a_body_written_and_loaded_is_the_same_body(arm, tmp_path, fmt):
    _, body = arm
    path = tmp_path / ("arm.json" if fmt == "json" else "arm")
    body.write(path, format=fmt)
    back = flexbody.load(path)
    assert isinstance(back, flexbody.Body)
    assert (back.method, back.r) == (body.method, body.r)
    np.testing.assert_array_equal(back.basis, body.basis)
    np.testing.assert_array_equal(back.mass, body.mass)
    np.testing.assert_array_equal(back.stiffness, body.stiffness)
    np.testing.assert_array_equal(back.interface, body.interface)
    ids, xyz = back.nodes()
    assert len(ids) == 21 and xyz[-1] == pytest.approx([1.0, 0.0, 0.0])
    # A loaded body has no model: the SID needs its mass matrix.
    with pytest.raises(flexbody.Error, match="needs the model the body was reduced from"):
        back.write(tmp_path / "back.sid", format="sid")


def test_model_arrays_describe_the_deck():
    model = flexbody.read(EXAMPLES / "side_beam_solid.toml")
    K = model.K
    assert K.shape == (len(model), len(model)) and K.format == "csc"
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    ids, xyz = model.node_ids, model.coords
    assert xyz.shape == (len(ids), 3)
    assert set(model.node_sets) >= {"SEAT_PF", "SEAT_PR", "SEAT_SF", "SEAT_SR"}
    assert model.dofs.shape == (len(model), 2)
    # The mass along x: each translation's rigid motion carries the whole mass.
    ux = (model.dofs[:, 1] == 1).astype(float)
    mass = ux @ (model.M @ ux)
    assert mass > 0
    dofs, source = model.default_interface
    assert len(dofs) > 0 and "interface" in source


def test_damping_given_with_the_matrices_is_reduced_with_them():
    model = flexbody.read(PY_EXAMPLES / "pendulum_arm.inp")
    K, M = model.K, model.M
    D = 2.0 * M + 1e-5 * K
    ids, xyz = model.node_ids, model.coords
    damped = flexbody.Model.from_matrices(K, M, model.dofs, coords=(ids, xyz), D=D)
    assert abs(damped.D - D).max() <= 1e-15 * abs(D).max()
    body = damped.reduce("craig-bampton", interface="1,21", modes=4)
    T = body.basis
    np.testing.assert_allclose(body.damping, T.T @ (D @ T), atol=1e-12 * np.abs(body.damping).max())
    assert body.invariants()["de"] is not None
    # Without damping there is none.
    assert model.D is None and model.reduce("guyan", interface="1").damping is None


def test_stress_recovery_of_a_free_solid_body_is_zero_on_its_rigid_modes():
    model = flexbody.read(EXAMPLES / "side_beam_solid.toml")
    body = model.reduce("free-residual", modes=2)
    R = body.recovery()
    assert R.shape[1] == body.r and R.shape[0] % 6 == 0 and R.shape[0] > 0
    rigid = [i for i, kind in enumerate(body.mode_kinds) if kind.startswith("rigid")]
    assert len(rigid) == 6
    # Rigid-body motion strains nothing.
    assert np.abs(R[:, rigid]).max() <= 1e-9 * np.abs(R).max()


def test_an_mbdyn_file_is_written_but_not_read(arm, tmp_path):
    _, body = arm
    path = tmp_path / "arm.fem"
    body.write(path, format="mbdyn")
    assert path.read_text().lstrip().startswith("**")
    with pytest.raises(flexbody.Error, match="MBDyn's modal FEM file, which flexbody writes"):
        flexbody.load(path)


def test_the_study_becomes_a_dataframe():
    pandas = pytest.importorskip("pandas")
    result = flexbody.read(EXAMPLES / "side_beam.toml").study()
    frame = result.to_dataframe()
    assert isinstance(frame, pandas.DataFrame)
    assert len(frame) == len(result.records)
    assert list(frame["method"]) == [r["method"] for r in result.records]
