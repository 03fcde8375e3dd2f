"""The objects of the API behave as the paper and the Rust core say."""

import math

import numpy as np
import pytest

import pvfc


def test_paper_lissajous():
    c = pvfc.Lissajous.paper()
    assert c.period == 6.0
    x, dx, ddx = c.sample(1.0)
    assert x.shape == dx.shape == ddx.shape == (2,)
    assert x[0] == pytest.approx(math.sin(2 * math.pi / 3))
    assert x[1] == pytest.approx(1.5 * math.cos(2 * math.pi / 6))
    assert dx[0] == pytest.approx(2 * math.pi / 3 * math.cos(2 * math.pi / 3))


def test_scara_matches_the_closed_form():
    arm = pvfc.Scara.pelican()
    p = arm.parameters()
    a1 = p["i1"] + p["i2"] + p["m1"] * p["lc1"] ** 2 + p["m2"] * (p["l1"] ** 2 + p["lc2"] ** 2)
    a2 = p["i2"] + p["m2"] * p["lc2"] ** 2
    a3 = p["m2"] * p["l1"] * p["lc2"]
    q = np.array([0.3, -0.7])
    m = arm.inertia(q)
    assert m.shape == (2, 2)
    np.testing.assert_allclose(m, [[a1 + 2 * a3 * math.cos(q[1]), a2 + a3 * math.cos(q[1])], [a2 + a3 * math.cos(q[1]), a2]], rtol=1e-14)
    assert arm.kinetic_energy(q, [1.0, 0.0]) == pytest.approx(0.5 * m[0, 0])


def test_urdf_arm_is_the_direct_drive_arm(repo):
    assert pvfc.Scara.from_urdf(repo / "models" / "scara.urdf").parameters() == pvfc.Scara.direct_drive().parameters()


def test_navigation_functions():
    nav = pvfc.TorusNavigation([1.0, 2.0])
    assert nav.value([math.pi, 0.0]) == pytest.approx(1.0)  # ½·1·(1 − cos π)
    np.testing.assert_allclose(nav.gradient([0.3, -0.2]), [math.sin(0.3), 2 * math.sin(-0.2)])
    assert pvfc.TorusNavigation([1.0, 2.0], "eq28").value([math.pi, 0.0]) == pytest.approx(2.0)
    so3 = pvfc.So3Navigation(np.diag([1.0, 2.0, 3.0]))
    assert so3.eigenvalues == pytest.approx((1.0, 2.0, 3.0))
    assert so3.value(np.eye(3)) == pytest.approx(0.0)
    np.testing.assert_allclose(so3.gradient(np.eye(3)), 0.0, atol=1e-15)


def test_waypoint_curve_passes_through_its_waypoints():
    pts = np.array([[0.0, 0.0], [0.8, 0.3], [0.5, 1.2], [-0.4, 0.9], [-0.6, -0.2]])
    curve = pvfc.WaypointCurve(pts, 1.3)
    assert curve.period == pytest.approx(6.5)
    for k, p in enumerate(pts):
        np.testing.assert_allclose(curve.sample(1.3 * k)[0], p, atol=1e-10)


def test_so3_constant_rate():
    c = pvfc.So3ConstantRate(np.eye(3), [0.0, 0.0, 0.5])
    r, w, dw = c.sample(2.0)
    np.testing.assert_allclose(r, [[math.cos(1), -math.sin(1), 0], [math.sin(1), math.cos(1), 0], [0, 0, 1]], atol=1e-12)
    np.testing.assert_allclose(w, [0, 0, 0.5])
    np.testing.assert_allclose(dw, 0.0)


def test_ellipse_and_circle():
    c = pvfc.Ellipse.circle([0.5, 0.0], 0.3, 4.0)
    np.testing.assert_allclose(c.sample(1.0)[0], [0.5, 0.3], atol=1e-12)
    e = pvfc.Ellipse([0, 0], [1, 0], [0, 2], 2 * math.pi)
    np.testing.assert_allclose(e.sample(math.pi / 2)[0], [0, 2], atol=1e-12)


def test_simulation_result_arrays_are_fresh_and_shaped():
    s = pvfc.Scenario.from_dict({**pvfc.Scenario.preset("fig8_R100").to_dict(), "duration": 2.0})
    r = pvfc.simulate(s)
    n = len(r)
    assert n == 2001
    for name in ["t", "tau", "tau_dot", "flywheel_speed", "beta", "w_beta", "potential", "lambda1", "lambda2", "energy", "friction_power"]:
        a = getattr(r, name)
        assert a.shape == (n,) and a.dtype == np.float64, name
    for name in ["q", "qdot", "torque"]:
        assert getattr(r, name).shape == (n, 2), name
    a = r.q
    a[0, 0] = 123.0
    assert r.q[0, 0] != 123.0, "arrays are copies, not views into Rust memory"


def test_scenarios_round_trip_through_dict_and_toml():
    s = pvfc.Scenario.preset("fig9_R50")
    assert pvfc.Scenario.from_dict(s.to_dict()).to_dict() == s.to_dict()
    assert pvfc.Scenario.from_toml(s.to_toml()).to_dict() == s.to_dict()
    assert set(pvfc.Scenario.presets()) >= {"fig6_unforced", "fig7_R100", "fig10_r3", "fig1_pvfc_vs_timed"}


def test_controller_step_and_reset():
    c = pvfc.Controller(pvfc.Scenario.preset("fig8_R100"))
    s0 = c.state
    t = c.step([0.0, 1.5], [0.0, 0.0], 1e-3)
    assert t.shape == (2,)
    assert c.state != s0
    c.reset()
    assert c.state == s0


def test_mcap_round_trip(tmp_path):
    s = pvfc.Scenario.from_dict({**pvfc.Scenario.preset("fig8_R100").to_dict(), "duration": 0.2})
    r = pvfc.simulate(s)
    path = tmp_path / "run.mcap"
    r.write_mcap(path)
    msgs = pvfc.read_mcap(path)
    assert len(msgs) == 2 * len(r)
    joints = [m for m in msgs if m[0] == "/joint_state"]
    np.testing.assert_array_equal(np.array([m[2]["q"] for m in joints]), r.q.astype(np.float32))
    ctl = [m for m in msgs if m[0] == "/pvfc/controller"]
    np.testing.assert_array_equal(
        np.array([m[2]["potential"] for m in ctl]), r.potential.astype(np.float32)
    )
    np.testing.assert_array_equal(np.array([m[2]["energy"] for m in ctl]), r.energy)


def test_simulate_many_matches_simulate():
    names = ["fig9_R0", "fig9_R100", "fig10_r2"]
    scenarios = [pvfc.Scenario.from_dict({**pvfc.Scenario.preset(n).to_dict(), "duration": 3.0}) for n in names]
    many = pvfc.simulate_many(scenarios, threads=2)
    assert [r.name for r in many] == names
    for s, r in zip(scenarios, many):
        np.testing.assert_array_equal(pvfc.simulate(s).q, r.q)


def test_timed_baseline_runs():
    s = pvfc.Scenario.from_dict({**pvfc.Scenario.preset("fig8_R100").to_dict(), "duration": 2.0})
    r = pvfc.simulate_timed(s, [400, 400], [40, 40], 1.0)
    assert r.name.endswith("-timed") and len(r) == 2001
    assert r.tau[-1] == pytest.approx(2.0)


def test_a_custom_arm_in_a_scenario_equals_the_same_arm_built_in():
    d = pvfc.Scenario.preset("fig8_R100").to_dict()
    d["duration"] = 1.0
    built_in = pvfc.simulate(pvfc.Scenario.from_dict(d))
    d["plant"]["arm"] = {"parameters": pvfc.Scara.direct_drive().parameters()}
    custom = pvfc.simulate(pvfc.Scenario.from_dict(d))
    np.testing.assert_array_equal(custom.q, built_in.q)
    d["plant"]["arm"]["parameters"]["m2"] = -1.0
    with pytest.raises(pvfc.ScenarioError, match="m2"):
        pvfc.Scenario.from_dict(d)


def test_a_disturbance_from_a_dict_is_the_environments_work():
    d = pvfc.Scenario.preset("robustness_g10").to_dict()
    assert d["plant"]["disturbance"]["amplitude"] == [0.5, 0.5]
    d["duration"] = 2.0
    r = pvfc.simulate(pvfc.Scenario.from_dict(d))
    # Its work is the environment's: the contact columns are kept, with no contact force.
    assert np.abs(r.contact["work_contact"]).max() > 1e-2 * r.energy[0]
    assert not r.contact["normal_force"].any()
    audit = r.energy - r.energy[0] - r.contact["work_contact"] - r.contact["work_friction"] \
        - r.contact["work_controller"] - r.contact["work_gravity"]
    assert np.abs(audit).max() < 1e-6 * r.energy[0]
    d["plant"]["disturbance"]["amplitude"] = [0.5]
    with pytest.raises(pvfc.ScenarioError, match="plant.disturbance.amplitude: 1 entries"):
        pvfc.Scenario.from_dict(d)
