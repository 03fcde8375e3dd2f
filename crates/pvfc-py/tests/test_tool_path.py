"""The tool path's error budget from Python: the joint contour of an adaptively sampled
Cartesian path is within its tolerance of the path, checked with Pinocchio's forward
kinematics and the path's closed-form distance (a UR5 rounded rectangle, a Panda circle in a
tilted plane); the budget of a run splits the distance along the surface from the normal
offset."""

import numpy as np
import pytest

import pvfc
from test_pinocchio import models, pin

RECTANGLE = [[0.45, -0.15, 0.30], [0.65, -0.15, 0.30], [0.65, 0.20, 0.30], [0.45, 0.20, 0.30]]
UR5_SEED = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]
PANDA_SEED = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8]


def rounded_rectangle_distance(p: np.ndarray) -> np.ndarray:
    """The distance of points (n, 3) to the rounded rectangle's boundary (its signed distance
    function in the plane z = 0.3, and the height above it)."""
    centre, half, r = np.array([0.55, 0.025]), np.array([0.1, 0.175]), 0.03
    q = np.abs(p[:, :2] - centre) - (half - r)
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=1)
    inside = np.minimum(np.max(q, axis=1), 0.0)
    in_plane = np.abs(outside + inside - r)
    return np.hypot(in_plane, p[:, 2] - 0.3)


def circle_distance(p, centre, radius, normal):
    n = np.asarray(normal) / np.linalg.norm(normal)
    d = p - centre
    h = d @ n
    rho = np.linalg.norm(d - np.outer(h, n), axis=1)
    return np.hypot(rho - radius, h)


def contour_tool(name, waypoints, samples_per_waypoint=24):
    """Pinocchio's tool positions along the joint contour a controller follows."""
    robot, model, frame = models(name)
    data = model.createData()
    k = len(waypoints)
    arm = pvfc.Controller.arm(robot, waypoints, 1.0, h=[4.0] * robot.dof, energy=40.0)
    out = []
    for i in range(k * samples_per_waypoint):
        q = arm.contour_point((i + 0.5) / samples_per_waypoint)
        pin.framesForwardKinematics(model, data, q)
        out.append(data.oMf[frame].translation.copy())
    return np.array(out)


def test_a_ur5_rectangle_is_sampled_to_its_tolerance():
    robot, _, _ = models("ur5")
    coarse = pvfc.CartesianPath(points=RECTANGLE, corner_radius=0.03, samples=24)
    fine = pvfc.CartesianPath(points=RECTANGLE, corner_radius=0.03, samples=0, tolerance=1e-5)
    assert abs(fine.length - (2 * 0.55 - 8 * 0.03 + 2 * np.pi * 0.03)) < 1e-12
    g24 = coarse.geometry(robot, UR5_SEED, fixed_orientation=True)
    g = fine.geometry(robot, UR5_SEED, fixed_orientation=True)
    assert g24["samples"] == 24 and g24["max"] > 1e-3
    assert g["samples"] > 24 and g["max"] <= 1e-5 and g["max_angle"] < 1e-3
    q = fine.joint_waypoints(robot, UR5_SEED, fixed_orientation=True)
    assert q.shape == (g["samples"], 6)
    tool = contour_tool("ur5", q)
    d = rounded_rectangle_distance(tool)
    assert d.max() <= 1e-5, d.max()
    # The check can fail: the 24-sample contour is millimetres off.
    d24 = rounded_rectangle_distance(
        contour_tool("ur5", coarse.joint_waypoints(robot, UR5_SEED, fixed_orientation=True))
    )
    assert d24.max() > 1e-3
    # Our closest points agree with the closed form.
    np.testing.assert_allclose(fine.closest(tool)["distance"], d, atol=1e-9)


def test_a_panda_circle_in_a_tilted_plane_is_sampled_to_its_tolerance():
    robot, _, _ = models("panda")
    p0 = robot.tool_pose(PANDA_SEED)[:3, 3]
    centre, normal = p0 + [0.0, 0.1, 0.0], [0.0, 0.3, 1.0]
    path = pvfc.CartesianPath(circle=(centre, 0.1, normal), samples=0)
    g = path.geometry(robot, PANDA_SEED)
    assert g["max"] <= 1e-5 and g["max_angle"] is None
    tool = contour_tool("panda", path.joint_waypoints(robot, PANDA_SEED))
    d = circle_distance(tool, centre, 0.1, normal)
    assert d.max() <= 1e-5, d.max()


def test_a_bad_tolerance_is_an_error():
    with pytest.raises(pvfc.PvfcError, match="tolerance"):
        pvfc.CartesianPath(points=RECTANGLE, samples=0, tolerance=-1.0)


def test_the_budget_of_a_run_splits_the_surface_from_the_normal(repo):
    s = pvfc.Scenario.from_file(repo / "scenarios" / "ur5_deburr.toml")
    d = s.to_dict()
    d["plant"]["urdf"] = str(repo / "models" / "ur5" / "ur5_robot.urdf")
    d["contour"]["cartesian"]["tolerance"] = 1e-4  # fewer samples: a quicker test
    d.pop("baseline")
    s = pvfc.Scenario.from_dict(d)
    r = pvfc.simulate(s)
    b = r.path_budget(s)
    assert b is not None
    assert b["geometry"]["max"] <= 1e-4
    surface, normal, distance = b["surface"], b["normal"], b["distance"]
    # The tool rides on the workpiece, pushed up from the path: the normal offset is positive
    # and nearly constant, and the 3-D distance is the two together.
    np.testing.assert_allclose(normal["normal"], [0.0, 0.0, 1.0], atol=1e-12)
    assert 0.0 < normal["min"] <= normal["mean"] <= normal["max"] < 1e-3
    assert distance["max"] <= np.hypot(surface["max"], max(-normal["min"], normal["max"])) + 1e-12
    assert surface["mean"] <= surface["p95"] <= surface["max"]
    assert 0.05 < b["speed"] < 0.2
    assert r.path_budget(pvfc.Scenario.preset("fig6_unforced")) is None


def test_a_scenario_chooses_the_task_space_field(repo):
    """``[contour.cartesian.task]`` from a dict: the run follows the exact path (the budget
    has no geometry term) within the machining target, and a bad gain names its key."""
    s = pvfc.Scenario.from_file(repo / "scenarios" / "ur5_cartesian.toml")
    d = s.to_dict()
    d["plant"]["urdf"] = str(repo / "models" / "ur5" / "ur5_robot.urdf")
    d["contour"]["cartesian"]["task"] = {"stiffness": 4.0}
    d["contour"]["cartesian"]["tolerance"] = 1e-4  # the joint image only: a quicker test
    d.pop("baseline")
    d["duration"] = 25.0
    r = pvfc.simulate(pvfc.Scenario.from_dict(d))
    b = r.path_budget(pvfc.Scenario.from_dict(d))
    assert b["geometry"] is None
    assert b["surface"]["mean"] <= 1e-4 and b["surface"]["max"] <= 3e-4, b["surface"]
    d["contour"]["cartesian"]["task"] = {"damping": -1.0}
    with pytest.raises(pvfc.PvfcError, match="task.damping"):
        pvfc.Scenario.from_dict(d)


@pytest.mark.parametrize("field", ["joint", "task"])
def test_a_ur5_closed_loop_on_pinocchio_meets_the_tracking_target(field):
    """The UR5 on Pinocchio's dynamics (``aba``, RK4 at 4 kHz, gravity), pvfc's controller at
    1 kHz (γ = 10, Ē = 40 J, R = 50, gravity compensation, nominal
    speed (0.5, 1)), no friction, following the rectangle either as a joint contour sampled
    to 10 µm (h = 4) or with the task-space field on the exact path (k = 4, the tool held
    pointing down): over the second pass the tool, by Pinocchio's forward kinematics, stays
    within 0.1 mm of the path on average and 0.3 mm at most (the closed-form distance), at
    over 50 mm/s, and with the task-space field its orientation within 1 mrad of the seed's."""
    robot, model, frame = models("ur5")
    data = model.createData()
    path = pvfc.CartesianPath(points=RECTANGLE, corner_radius=0.03, samples=0)
    settings = pvfc.ControllerSettings(
        self_pacing=50.0, energy=40.0, gamma=10.0, nominal_speed=(0.5, 1.0)
    )
    if field == "joint":
        q_way = path.joint_waypoints(robot, UR5_SEED, fixed_orientation=True)
        contour = pvfc.WaypointCurve(q_way, 12.0 / len(q_way))
        arm = pvfc.Controller.compose(robot, contour, pvfc.JointNavigation([4.0] * 6), settings)
    else:
        task = path.task_field(robot, UR5_SEED, 12.0, fixed_orientation=True, stiffness=4.0)
        assert task.dof == 6 and task.period == pytest.approx(12.0)
        arm = pvfc.Controller.compose(robot, task, settings=settings)
        with pytest.raises(ValueError, match="navigation"):
            pvfc.Controller.compose(robot, task, pvfc.JointNavigation([4.0] * 6))
    dt, substeps = 1e-3, 4
    h = dt / substeps
    x = np.concatenate([np.array(UR5_SEED), np.zeros(6)])
    pin.framesForwardKinematics(model, data, x[:6])
    held = data.oMf[frame].rotation.copy()

    def f(x, u):
        return np.concatenate([x[6:], pin.aba(model, data, x[:6], x[6:], u)])

    tool, taus, angle = [], [], 0.0
    for _ in range(int(26.0 / dt)):
        u = arm.step(x[:6], x[6:], dt)
        tau, _, _, laps = arm.state
        taus.append(tau + 12.0 * laps)
        pin.framesForwardKinematics(model, data, x[:6])
        tool.append(data.oMf[frame].translation.copy())
        if taus[-1] >= 12.0:
            c = (np.trace(data.oMf[frame].rotation @ held.T) - 1.0) / 2.0
            angle = max(angle, np.arccos(np.clip(c, -1.0, 1.0)))
        for _ in range(substeps):
            k1 = f(x, u)
            k2 = f(x + 0.5 * h * k1, u)
            k3 = f(x + 0.5 * h * k2, u)
            k4 = f(x + h * k3, u)
            x = x + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    taus = np.array(taus)
    steady = (taus >= 12.0) & (taus < 24.0)
    assert steady.sum() > 1000, "a whole second pass"
    tool = np.array(tool)[steady]
    d = rounded_rectangle_distance(tool)
    speed = np.sum(np.linalg.norm(np.diff(tool, axis=0), axis=1)) / (steady.sum() * dt)
    print(
        f"{field}: steady samples {steady.sum()}, mean {d.mean():.2e} m, max {d.max():.2e} m, "
        f"speed {speed:.3f} m/s, orientation {angle:.1e} rad"
    )
    assert d.mean() <= 1e-4 and d.max() <= 3e-4, (d.mean(), d.max())
    # Without friction both are far inside the target: the joint contour at its geometry
    # (0.23 µm mean, 7.4 µm max for 10 µm), the task-space field on the exact path (0.08 µm,
    # 0.3 µm: the refined inverse leaves the damping's bias at (μ/σ)⁴).
    assert d.mean() <= 1e-6 and d.max() <= (1e-5 if field == "joint" else 1e-6), (d.mean(), d.max())
    assert speed >= 0.05, speed
    assert angle < 1e-3, angle


def test_the_timed_tracker_saturates_at_its_torque_limit():
    d = pvfc.Scenario.preset("fig1_saturated_r2").to_dict()
    d["duration"] = 3.0
    s = pvfc.Scenario.from_dict(d)
    limits = np.array([15.0, 5.0])
    free = pvfc.simulate_timed(s, [400.0, 400.0], [40.0, 40.0], 2.0)
    held = pvfc.simulate_timed(s, [400.0, 400.0], [40.0, 40.0], 2.0, torque_limit=limits)
    # Unlimited, the tracker asks for more than the drives have; limited, it gets at most that.
    assert np.any(np.abs(free.torque) > limits)
    assert np.all(np.abs(held.torque) <= limits)
    assert np.any(np.isclose(np.abs(held.torque), limits).any(axis=1))
    with pytest.raises(pvfc.PvfcError, match="torque_limit"):
        pvfc.simulate_timed(s, [400.0, 400.0], [40.0, 40.0], 2.0, torque_limit=[15.0, -1.0])
    assert held.period == s.to_dict()["contour"]["lissajous"]["period"]


def test_the_task_field_saturates_its_pull():
    """`saturation` bounds the position's pull: off the path U is below ½k|e|², and a bad
    distance is refused."""
    robot, _, _ = models("ur5")
    path = pvfc.CartesianPath(points=RECTANGLE, corner_radius=0.03, samples=0)
    settings = pvfc.ControllerSettings(self_pacing=50.0, energy=40.0, gamma=10.0)
    u = {}
    for ell in (None, 0.02):
        task = path.task_field(robot, UR5_SEED, 12.0, fixed_orientation=True, stiffness=4.0, saturation=ell)
        arm = pvfc.Controller.compose(robot, task, settings=settings)
        u[ell] = arm.evaluate(UR5_SEED, np.zeros(6), 0.0, 0.0, 9.0)["potential"]
    assert 0.0 < u[0.02] < u[None], u
    with pytest.raises(pvfc.PvfcError, match="saturation"):
        path.task_field(robot, UR5_SEED, 12.0, saturation=-0.01)
