"""Contact from Python: the contact columns, the audit, passivity, errors."""

import subprocess
import sys

import numpy as np
import pytest

import pvfc


def _short(name, duration):
    d = pvfc.Scenario.preset(name).to_dict()
    d["duration"] = duration
    return pvfc.Scenario.from_dict(d)


def test_wall_run_has_contact_columns_and_stays_passive():
    r = pvfc.simulate(_short("contact_wall", 4.0))
    c = r.contact
    n = len(r)
    assert c["force"].shape == (n, 2) and c["tool"].shape == (n, 2) and c["torque"].shape == (n, 2)
    for k in ["normal_force", "depth", "work_contact", "work_friction", "work_controller",
              "nominal_speed", "audit_residual"]:
        assert c[k].shape == (n,), k
    assert c["normal_force"].max() > 50.0
    e0 = r.energy[0]
    assert np.abs(c["audit_residual"]).max() < 1e-3 * e0
    assert (c["work_contact"] >= -e0).all()
    assert (r.energy <= e0 + c["work_contact"] + c["work_controller"] + 1e-6 * e0).all()
    s = r.contact_summary()
    assert s["passivity_margin"] >= 0.0 and s["audit"] < 1e-6
    # Fresh arrays: changing one does not change the result.
    c["normal_force"][:] = 0.0
    assert r.contact["normal_force"].max() > 50.0


def test_timed_baseline_pushes_harder_into_the_wall():
    s = _short("contact_wall", 6.0)
    pv = pvfc.simulate(s).contact_summary()
    timed = pvfc.simulate_timed(s, kp=[400.0, 400.0], kd=[40.0, 40.0], tau_rate=1.0).contact_summary()
    assert timed["peak_force"] > pv["peak_force"]
    assert timed["energy_pumped"] > pv["energy_pumped"]


def test_runs_without_contact_have_none():
    r = pvfc.simulate(_short("fig8_R100", 0.2))
    assert r.contact is None and r.contact_summary() is None


def test_bad_contact_settings_raise_scenario_errors():
    d = pvfc.Scenario.preset("contact_wall").to_dict()
    d["contact"]["law"]["stiffness"] = -1.0
    with pytest.raises(pvfc.ScenarioError, match="stiffness"):
        pvfc.Scenario.from_dict(d)
    d = pvfc.Scenario.preset("contact_wall").to_dict()
    d["contact"]["force_schedule"] = {"onset": 1.0, "limit": 5.0, "min_fraction": 0.1}
    with pytest.raises(pvfc.ScenarioError, match="nominal_speed"):
        pvfc.Scenario.from_dict(d)
    d = pvfc.Scenario.preset("contact_wall").to_dict()
    d["contact"]["obstacles"][0]["shape"] = {"cone": {"radius": 1.0}}
    with pytest.raises(pvfc.ScenarioError, match="cone"):
        pvfc.Scenario.from_dict(d)


def test_contact_example_script(repo, tmp_path):
    script = repo / "examples" / "python" / "contact_wall.py"
    out = subprocess.run([sys.executable, script, "--out", tmp_path, "--duration", "3"],
                         check=True, capture_output=True, text=True).stdout
    assert "PVFC: peak force" in out and "timed tracker: peak force" in out
    assert (tmp_path / "contact_wall_python.png").stat().st_size > 10_000


def test_urdf_arm_contact_3d_from_python(repo):
    """A UR5 pressing its tool on a table ([contact_3d]): 3-D force and tool columns, one
    torque per joint, gravity's work in the account, and the audit at integration error."""
    d = pvfc.Scenario.from_file(repo / "scenarios" / "ur5_press.toml").to_dict()
    d["duration"] = 2.0
    r = pvfc.simulate(pvfc.Scenario.from_dict(d, base_dir=repo / "scenarios"))
    c = r.contact
    n = len(r)
    assert c["force"].shape == (n, 3) and c["tool"].shape == (n, 3) and c["torque"].shape == (n, 6)
    assert c["normal_force"].max() > 1.0
    assert np.abs(c["work_gravity"]).max() > 1e-3
    assert np.abs(c["audit_residual"]).max() < 1e-6 * r.energy[0]
    with pytest.raises(pvfc.ScenarioError, match="contact_3d"):
        bad = {**d, "contact_3d": {**d["contact_3d"], "tool_radius": -1.0}}
        pvfc.Scenario.from_dict(bad, base_dir=repo / "scenarios")
