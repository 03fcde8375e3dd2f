"""The same scenario from Python and from the Rust command line gives identical arrays."""

import subprocess

import numpy as np

import pvfc


def test_python_and_rust_give_identical_arrays(pvfc_cli, repo, tmp_path):
    scenario = repo / "scenarios" / "fig9_R100.toml"
    subprocess.run([pvfc_cli, "run", scenario, "--out", tmp_path], check=True, capture_output=True)
    msgs = pvfc.read_mcap(tmp_path / "logs" / "fig9_R100.mcap")
    rust_q = np.array([m[2]["q"] for m in msgs if m[0] == "/joint_state"])
    rust_torque = np.array([m[2]["torque"] for m in msgs if m[0] == "/joint_state"])
    rust_u = np.array([m[2]["potential"] for m in msgs if m[0] == "/pvfc/controller"])
    rust_t = np.array([m[1] for m in msgs if m[0] == "/joint_state"]) / 1e9
    py = pvfc.simulate(pvfc.Scenario.from_file(scenario))
    assert rust_q.shape == py.q.shape == (40001, 2)
    # The log's plot channels are float32 (the energy audit's columns float64): the same
    # rounding of the same numbers.
    np.testing.assert_array_equal(py.q.astype(np.float32), rust_q)
    np.testing.assert_array_equal(py.torque.astype(np.float32), rust_torque)
    np.testing.assert_array_equal(py.potential.astype(np.float32), rust_u)
    rust_energy = np.array([m[2]["energy"] for m in msgs if m[0] == "/pvfc/controller"])
    np.testing.assert_array_equal(py.energy, rust_energy)
    np.testing.assert_allclose(py.t, rust_t, atol=1e-9)
