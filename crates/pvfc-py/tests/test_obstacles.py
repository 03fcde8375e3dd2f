"""Obstacles (the paper's Remark 3) from Python: a scenario's [obstacles] table reaches the
field through pvfc.simulate and pvfc.Controller, edited as a dict."""

import numpy as np
import pvfc
import pytest


def peak_force(result: pvfc.SimulationResult) -> float:
    contact = result.contact
    assert contact is not None
    return float(np.max(contact["normal_force"]))


def test_the_pelican_goes_around_the_post(repo):
    s = pvfc.Scenario.from_file(repo / "scenarios" / "example_obstacles.toml")
    r = pvfc.simulate(s)
    assert peak_force(r) == 0.0
    assert r.potential[-1] < 1e-4
    d = s.to_dict()
    assert d["obstacles"]["kappa"] == 4.0 and len(d["obstacles"]["body"]) == 5
    del d["obstacles"]
    without = pvfc.simulate(pvfc.Scenario.from_dict(d, base_dir=repo / "scenarios"))
    assert peak_force(without) > 1.0


def test_a_controller_steps_around_the_obstacles(repo):
    s = pvfc.Scenario.from_file(repo / "scenarios" / "example_obstacles.toml")
    ctl = pvfc.Controller(s)
    near = ctl.evaluate(np.array([1.6, 2.1]), np.zeros(2), 0.0, 0.0, 6.0)
    d = s.to_dict()
    del d["obstacles"]
    free = pvfc.Controller(pvfc.Scenario.from_dict(d, base_dir=repo / "scenarios"))
    far = free.evaluate(np.array([1.6, 2.1]), np.zeros(2), 0.0, 0.0, 6.0)
    # Beside the post, the composed function exceeds the contour's own U, and the field differs.
    assert near["potential"] > far["potential"]
    assert not np.allclose(near["field_velocity"], far["field_velocity"])


def test_bad_obstacles_are_named(repo):
    d = pvfc.Scenario.from_file(repo / "scenarios" / "example_obstacles.toml").to_dict()
    d["obstacles"]["body"][0]["link"] = 7
    with pytest.raises(pvfc.ScenarioError, match=r"obstacles\.body\[0\]\.link = 7"):
        pvfc.Scenario.from_dict(d, base_dir=repo / "scenarios")


def _ur5_parts(repo):
    import test_arm

    robot = pvfc.Robot.from_urdf(repo / "models" / "ur5" / "ur5_robot.urdf", tip="tool0")
    waypoints = np.array(test_arm.UR5_WAYPOINTS)
    settings = pvfc.ControllerSettings(self_pacing=50.0, energy=40.0)
    return robot, pvfc.WaypointCurve(waypoints, 1.0), settings, waypoints


def test_compose_takes_obstacles_as_a_scenario_table(repo):
    """Controller.compose(obstacles=...) with the [obstacles] table's layout: a joint-space
    ball beside the contour raises the composed potential near it, and the field's change
    points away from its centre; spheres on the tool against a world sphere do the same."""
    robot, curve, settings, waypoints = _ur5_parts(repo)
    free = pvfc.Controller.compose(robot, curve, settings=settings)
    centre = waypoints[0] + np.array([0.25, 0.0, 0.0, 0.0, 0.0, 0.0])
    joint = {"kappa": 2.0, "joint": [{"center": centre.tolist(), "radius": 0.1, "influence": 0.2}]}
    guarded = pvfc.Controller.compose(robot, curve, settings=settings, obstacles=joint)
    q = centre - np.array([0.15, 0.0, 0.0, 0.0, 0.0, 0.0])  # 0.05 rad outside the ball
    near = guarded.evaluate(q, np.zeros(6), 0.0, 0.0, 9.0)
    plain = free.evaluate(q, np.zeros(6), 0.0, 0.0, 9.0)
    assert near["potential"] > plain["potential"]
    away = q - centre
    assert float(np.dot(near["field_velocity"][:6] - plain["field_velocity"][:6], away)) > 0.0
    # A sphere on the tool (link 5) against a world sphere 8 cm from it.
    p = robot.tool_pose(q)[:3, 3]
    world = {
        "body": [{"link": 5, "radius": 0.03}],
        "world": [{"shape": "sphere", "center": (p + [0.08, 0.0, 0.0]).tolist(), "radius": 0.02, "influence": 0.1}],
    }
    shielded = pvfc.Controller.compose(robot, curve, settings=settings, obstacles=world)
    assert shielded.evaluate(q, np.zeros(6), 0.0, 0.0, 9.0)["potential"] > plain["potential"]


def test_compose_names_bad_obstacles(repo):
    import test_tool_path

    robot, curve, settings, _ = _ur5_parts(repo)
    with pytest.raises(ValueError, match="obstacles: unknown field `kapa`"):
        pvfc.Controller.compose(robot, curve, settings=settings, obstacles={"kapa": 2.0})
    bad_link = {"body": [{"link": 7, "radius": 0.03}], "world": [{"shape": "sphere", "center": [0.5, 0, 0.3], "radius": 0.02, "influence": 0.1}]}
    with pytest.raises(pvfc.PvfcError, match=r"obstacles\.body\[0\]\.link = 7"):
        pvfc.Controller.compose(robot, curve, settings=settings, obstacles=bad_link)
    with pytest.raises(pvfc.PvfcError, match=r"obstacles\.joint\[0\]\.center: 2 entries"):
        pvfc.Controller.compose(robot, curve, settings=settings, obstacles={"joint": [{"center": [0.0, 0.0], "radius": 0.1, "influence": 0.1}]})
    path = pvfc.CartesianPath(points=test_tool_path.RECTANGLE, corner_radius=0.03, samples=0)
    task = path.task_field(robot, test_tool_path.UR5_SEED, 12.0, fixed_orientation=True, stiffness=4.0)
    with pytest.raises(pvfc.PvfcError, match="task-space field .* does not take obstacles"):
        pvfc.Controller.compose(robot, task, settings=settings, obstacles={"joint": [{"center": [0.0] * 6, "radius": 0.1, "influence": 0.1}]})
