"""Any serial arm from Python: pvfc.Robot from a URDF and pvfc.Controller.arm driving a plant
integrated in Python (the way a user drives their own simulator), on the UR5 and the Panda."""

import pathlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pvfc

MODELS = pathlib.Path(__file__).resolve().parents[3] / "models"
UR5 = MODELS / "ur5" / "ur5_robot.urdf"
PANDA = MODELS / "panda" / "panda.urdf"
UR5_WAYPOINTS = [
    [0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
    [0.5, -1.0, 1.2, -1.7, -1.4, 0.3],
    [0.8, -1.4, 1.6, -1.6, -1.2, 0.6],
    [0.3, -1.7, 1.9, -1.9, -1.5, 0.2],
    [-0.3, -1.5, 1.7, -2.0, -1.8, -0.3],
    [-0.5, -1.1, 1.3, -1.8, -1.7, -0.4],
]


def ur5() -> pvfc.Robot:
    return pvfc.Robot.from_urdf(UR5, tip="tool0")


def test_robot_metadata() -> None:
    r = ur5()
    assert r.dof == 6 and r.name == "ur5" and r.tip_link == "tool0" and r.base_link == "world"
    assert r.joint_names[0] == "shoulder_pan_joint"
    assert r.joint_kinds == ["revolute"] * 6
    lim = r.limits
    assert lim["lower"].shape == (6,) and np.all(lim["effort"] > 0)
    p = pvfc.Robot.from_urdf(PANDA, tip="panda_hand_tcp")
    assert p.dof == 7 and sorted(p.locked_joints) == ["panda_finger_joint1", "panda_finger_joint2"]
    fk = p.forward_kinematics(np.zeros(7))
    assert fk.shape == (8, 4, 4)
    assert np.allclose(fk[-1], p.tool_pose(np.zeros(7)))


def rk4(robot: pvfc.Robot, q, v, torque, h):
    def acc(q, v):
        m = robot.inertia(q)
        return np.linalg.solve(m, torque - robot.coriolis(q, v) @ v - robot.gravity(q))

    a1 = acc(q, v)
    q2, v2 = q + 0.5 * h * v, v + 0.5 * h * a1
    a2 = acc(q2, v2)
    q3, v3 = q + 0.5 * h * v2, v + 0.5 * h * a2
    a3 = acc(q3, v3)
    q4, v4 = q + h * v3, v + h * a3
    a4 = acc(q4, v4)
    return q + h / 6 * (v + 2 * v2 + 2 * v3 + v4), v + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)


def test_arm_controller_drives_a_python_plant_onto_the_contour() -> None:
    robot = ur5()
    ctl = pvfc.Controller.arm(
        robot, UR5_WAYPOINTS, 1.0, h=[4.0] * 6, self_pacing=50.0, energy=40.0, gamma=1.0
    )
    q = np.array(UR5_WAYPOINTS[0]) + 0.25
    v = np.zeros(6)
    u0 = ctl.evaluate(q, v, *ctl.state[:3])["potential"]
    dt = 1e-3
    for _ in range(4000):
        torque = ctl.step(q, v, dt)
        for _ in range(2):  # the plant at 2 kHz, torque held (zero-order hold)
            q, v = rk4(robot, q, v, torque, dt / 2)
    u = ctl.evaluate(q, v, *ctl.state[:3])["potential"]
    assert u < 1e-3 * u0, (u0, u)
    assert ctl.state[1] > 0.0  # τ advances


@settings(max_examples=200, deadline=None)
@given(
    q=st.lists(st.floats(-3, 3), min_size=6, max_size=6),
    v=st.lists(st.floats(-2, 2), min_size=6, max_size=6),
    tau=st.floats(-10, 10),
    tau_dot=st.floats(-2, 2),
    fly=st.floats(1, 12),
)
def test_the_coupling_is_workless(q, v, tau, tau_dot, fly) -> None:
    """q̇ᵀ(T − g(q)) + τ̇ T_τ + q̇_F T_F = 0: gravity compensation aside, no energy is made."""
    robot = ur5()
    ctl = pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0, energy=400.0, self_pacing=20.0)
    q, v = np.array(q), np.array(v)
    try:
        out = ctl.evaluate(q, v, tau, tau_dot, fly)
    except pvfc.EnergyTooLowError:
        return
    t = out["robot_torque"] - robot.gravity(q)
    power = t @ v + out["tau_torque"] * tau_dot + out["flywheel_torque"] * fly
    scale = np.abs(t * v).sum() + abs(out["tau_torque"] * tau_dot) + abs(out["flywheel_torque"] * fly)
    assert abs(power) <= 1e-11 * (1.0 + scale)


def test_bad_inputs_raise_documented_errors(tmp_path: pathlib.Path) -> None:
    robot = ur5()
    with pytest.raises(ValueError, match="q"):
        robot.inertia(np.zeros(5))
    with pytest.raises(ValueError, match="frame"):
        robot.jacobian(np.zeros(6), frame="nowhere")
    with pytest.raises(pvfc.NonFiniteError):
        robot.gravity([np.nan] * 6)
    with pytest.raises(pvfc.UrdfError, match="nowhere"):
        pvfc.Robot.from_urdf(UR5, tip="nowhere")
    with pytest.raises(pvfc.UrdfError, match="tree"):
        pvfc.Robot.from_urdf(PANDA)
    with pytest.raises(ValueError, match="waypoints"):
        pvfc.Controller.arm(robot, UR5_WAYPOINTS[:2], 1.0)
    with pytest.raises(ValueError, match="waypoints"):
        pvfc.Controller.arm(robot, [w[:5] for w in UR5_WAYPOINTS], 1.0)
    ctl = pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0)
    with pytest.raises(ValueError, match="qdot"):
        ctl.step(np.zeros(6), np.zeros(7), 1e-3)
    before = ctl.state
    with pytest.raises(pvfc.NonFiniteError):
        ctl.step([np.nan] * 6, np.zeros(6), 1e-3)
    assert ctl.state == before
    with pytest.raises(pvfc.EnergyTooLowError):
        pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0, energy=1e-6).evaluate(
            np.zeros(6), np.zeros(6), 0.0, 0.0, 1e-3
        )
    # The same state with the field bounded at half of Ē: scaled onto it, not refused.
    bounded = pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0, energy=1e-6, field_energy_bound=0.5)
    out = bounded.evaluate(np.zeros(6), np.zeros(6), 0.0, 0.0, 1e-3)
    v, p = out["field_velocity"], out["desired_momentum"]
    assert np.all(np.isfinite(out["torque"]))
    assert 0.5 * (p[:6] @ v[:6] + v[6] ** 2) == pytest.approx(0.5e-6, rel=1e-9)
    assert 0.5 * v[7] ** 2 == pytest.approx(0.5e-6, rel=1e-9)  # the flywheel keeps the rest
    with pytest.raises(Exception, match="field_energy_bound"):
        pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0, field_energy_bound=1.5)
    floating = UR5.read_text().replace('name="shoulder_pan_joint" type="revolute"', 'name="shoulder_pan_joint" type="floating"')
    f = tmp_path / "floating.urdf"
    f.write_text(floating)
    with pytest.raises(pvfc.UrdfError, match="joint shoulder_pan_joint"):
        pvfc.Robot.from_urdf(f, tip="tool0")



def test_a_urdf_scenario_runs_from_python(repo) -> None:
    d = pvfc.Scenario.from_file(repo / "scenarios" / "ur5_waypoints.toml").to_dict()
    d["plant"]["urdf"] = str(UR5)  # from a dict, relative paths are relative to the cwd
    d["duration"] = 1.0
    r = pvfc.simulate(pvfc.Scenario.from_dict(d))
    assert r.q.shape == (1001, 6) and r.torque.shape == (1001, 6)
    assert r.potential[-1] < r.potential[0]
    d["initial"]["q"] = [0.0, 0.0]
    with pytest.raises(pvfc.PvfcError, match="initial.q"):
        pvfc.Scenario.from_dict(d)


def test_robot_from_arrays_matches_the_scara_closed_form() -> None:
    """The Pelican SCARA given as arrays equals pvfc.Scara's closed-form M and C."""
    p = pvfc.Scara.pelican().parameters()
    robot = pvfc.Robot.from_arrays(
        ["revolute", "revolute"],
        [[0, 0, 0], [p["l1"], 0, 0]],
        np.zeros((2, 3)),
        [[0, 0, 1], [0, 0, 1]],
        [p["m1"], p["m2"]],
        [[p["lc1"], 0, 0], [p["lc2"], 0, 0]],
        [np.diag([0.1, 0.1, p["i1"]]), np.diag([0.1, 0.1, p["i2"]])],
    )
    scara = pvfc.Scara.pelican()
    rng = np.random.default_rng(1)
    for _ in range(50):
        q, v = rng.uniform(-3, 3, 2), rng.uniform(-2, 2, 2)
        assert np.allclose(robot.inertia(q), scara.inertia(q), rtol=1e-12, atol=1e-14)
        assert np.allclose(robot.coriolis(q, v), scara.coriolis(q, v), rtol=1e-12, atol=1e-14)
    with pytest.raises(pvfc.PvfcError):
        pvfc.Robot.from_arrays(["revolute"], [[0, 0, 0]], [[0, 0, 0]], [[0, 0, 1]], [-1.0], [[0, 0, 0]], [np.eye(3)])
    with pytest.raises(ValueError, match="kinds"):
        pvfc.Robot.from_arrays(["spherical"], [[0, 0, 0]], [[0, 0, 0]], [[0, 0, 1]], [1.0], [[0, 0, 0]], [np.eye(3)])
    with pytest.raises(ValueError, match="inertias"):
        pvfc.Robot.from_arrays(["revolute"], [[0, 0, 0]], [[0, 0, 0]], [[0, 0, 1]], [1.0], [[0, 0, 0]], np.eye(3))
