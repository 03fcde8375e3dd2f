"""A controller composed of parts: a robot, a joint-space contour, a navigation function and
settings (Controller.compose), with the contours and the navigation function usable on
their own for any number of joints."""

import math
import pathlib

import numpy as np
import pytest

import pvfc
import test_arm

MODELS = pathlib.Path(__file__).resolve().parents[3] / "models"
UR5_WAYPOINTS = np.array(test_arm.UR5_WAYPOINTS)


def ur5() -> pvfc.Robot:
    return pvfc.Robot.from_urdf(MODELS / "ur5" / "ur5_robot.urdf", tip="tool0")


def test_composed_controller_equals_the_one_built_from_arguments() -> None:
    robot = ur5()
    settings = pvfc.ControllerSettings(self_pacing=50.0, energy=400.0, gamma=1.0, nominal_speed=(0.5, 1.0))
    composed = pvfc.Controller.compose(
        robot, pvfc.WaypointCurve(UR5_WAYPOINTS, 1.0), pvfc.JointNavigation([4.0] * 6), settings
    )
    direct = pvfc.Controller.arm(
        robot, UR5_WAYPOINTS, 1.0, h=[4.0] * 6, self_pacing=50.0, energy=400.0, gamma=1.0, nominal_speed=(0.5, 1.0)
    )
    rng = np.random.default_rng(3)
    for _ in range(20):
        q, v = UR5_WAYPOINTS[0] + rng.uniform(-0.5, 0.5, 6), rng.uniform(-0.2, 0.2, 6)
        a = composed.evaluate(q, v, 1.3, 0.4, 25.0)
        b = direct.evaluate(q, v, 1.3, 0.4, 25.0)
        assert np.array_equal(a["torque"], b["torque"]) and a["potential"] == b["potential"]
    assert np.array_equal(composed.step(q, v, 1e-3), direct.step(q, v, 1e-3))


def test_the_nominal_speeds_integral_adds_to_r_as_the_controller_steps() -> None:
    """With `nominal_speed_integral` the nominal speed's integral of its error advances once
    per step: the first step's torque is the proportional law's, the later ones push harder
    while β stays below r (the arm held at rest); a negative gain is a named error."""
    robot = ur5()

    def controller(ki: float) -> pvfc.Controller:
        settings = pvfc.ControllerSettings(
            self_pacing=50.0, energy=400.0, gamma=1.0, nominal_speed=(0.5, 2.0), nominal_speed_integral=ki
        )
        return pvfc.Controller.compose(robot, pvfc.WaypointCurve(UR5_WAYPOINTS, 1.0), pvfc.JointNavigation([4.0] * 6), settings)

    plain, integral = controller(0.0), controller(2.0)
    q, v = UR5_WAYPOINTS[0], np.zeros(6)
    np.testing.assert_array_equal(plain.step(q, v, 1e-3), integral.step(q, v, 1e-3))
    for _ in range(200):
        a, b = plain.step(q, v, 1e-3), integral.step(q, v, 1e-3)
    # τ̇ and the flywheel gain energy faster with the integral (β starts at 1 < r = 2).
    assert integral.state[1] > plain.state[1] or integral.state[2] > plain.state[2]
    assert not np.array_equal(a, b)
    with pytest.raises(pvfc.PvfcError, match="integral"):
        controller(-1.0)


def test_a_six_joint_lissajous_and_ellipse_sample_their_formulas() -> None:
    amp, per = np.array([0.5, 0.2, 0.3, 0.2, 0.3, 0.4]), np.array([8.0, 4.0, 8.0, 4.0, 8.0, 2.0])
    phase, off = np.linspace(0, 1, 6), UR5_WAYPOINTS[0]
    c = pvfc.Lissajous(amp, per, phase, off, period=8.0)
    assert c.dim == 6 and c.period == 8.0
    x, dx, _ = c.sample(1.7)
    np.testing.assert_allclose(x, off + amp * np.sin(2 * np.pi * 1.7 / per + phase), atol=1e-9)
    np.testing.assert_allclose(dx, amp * 2 * np.pi / per * np.cos(2 * np.pi * 1.7 / per + phase), atol=1e-9)
    e = pvfc.Ellipse(off, [0.4, 0, 0, 0, 0, 0], [0, 0.3, 0, 0, 0, 0.2], 5.0)
    assert e.dim == 6 and e.period == 5.0
    np.testing.assert_allclose(e.sample(1.25)[0], off + [0, 0.3, 0, 0, 0, 0.2], atol=1e-12)
    # The navigation function: ½ h (1 − cos e) per revolute joint, ¼ h e² per prismatic one.
    nav = pvfc.JointNavigation([1.0, 2.0, 4.0], kinds=["revolute", "revolute", "prismatic"])
    err = np.array([0.3, -1.0, 0.5])
    assert nav.value(err) == pytest.approx(0.5 * (1 - math.cos(0.3)) + (1 - math.cos(-1.0)) + 0.25)
    h = 1e-6
    fd = [(nav.value(err + h * np.eye(3)[i]) - nav.value(err - h * np.eye(3)[i])) / (2 * h) for i in range(3)]
    np.testing.assert_allclose(nav.differential(err), fd, atol=1e-8)
    # The gradient is in the navigation function's metric (weight ½, eq. 17's convention).
    np.testing.assert_allclose(nav.gradient(err), 2 * np.array(fd), atol=1e-8)


def test_a_composed_lissajous_controller_drives_the_ur5_onto_its_contour() -> None:
    robot = ur5()
    contour = pvfc.Lissajous([0.4, 0.2, 0.2, 0.2, 0.2, 0.3], [8.0, 4.0, 8.0, 4.0, 8.0, 8.0], offset=UR5_WAYPOINTS[0], period=8.0)
    ctl = pvfc.Controller.compose(
        robot, contour, pvfc.JointNavigation([4.0] * 6), pvfc.ControllerSettings(self_pacing=50.0, energy=40.0)
    )
    q, v = UR5_WAYPOINTS[0] + 0.25, np.zeros(6)
    u0 = ctl.evaluate(q, v, *ctl.state[:3])["potential"]
    for _ in range(4000):
        torque = ctl.step(q, v, 1e-3)
        for _ in range(2):
            q, v = test_arm.rk4(robot, q, v, torque, 5e-4)
    u = ctl.evaluate(q, v, *ctl.state[:3])["potential"]
    assert u < 1e-3 * u0, (u0, u)
    np.testing.assert_allclose(ctl.contour_point(2.0), contour.sample(2.0)[0], atol=1e-12)


def test_composition_errors_name_the_part() -> None:
    robot = ur5()
    with pytest.raises(ValueError, match="contour: 2 coordinates for the 6-joint robot"):
        pvfc.Controller.compose(robot, pvfc.Lissajous.paper())
    with pytest.raises(ValueError, match="navigation: 3 weights"):
        pvfc.Controller.compose(robot, pvfc.WaypointCurve(UR5_WAYPOINTS, 1.0), pvfc.JointNavigation([1.0] * 3))
    with pytest.raises(ValueError, match="joint kinds differ"):
        pvfc.Controller.compose(
            robot, pvfc.WaypointCurve(UR5_WAYPOINTS, 1.0), pvfc.JointNavigation([1.0] * 6, kinds=["prismatic"] * 6)
        )
    with pytest.raises(TypeError, match="contour"):
        pvfc.Controller.compose(robot, UR5_WAYPOINTS)
    with pytest.raises(pvfc.InvalidParameterError, match="friction_compensation"):
        pvfc.Controller.compose(
            robot, pvfc.WaypointCurve(UR5_WAYPOINTS, 1.0), settings=pvfc.ControllerSettings(friction_compensation=[1.0, 2.0])
        )
    with pytest.raises(pvfc.InvalidParameterError):
        pvfc.JointNavigation([1.0, -1.0])
    with pytest.raises(ValueError, match="kinds"):
        pvfc.JointNavigation([1.0], kinds=["spherical"])
    with pytest.raises(ValueError, match="waypoints"):
        pvfc.WaypointCurve(np.zeros((4, 9)), 1.0)
    with pytest.raises(ValueError, match="phase"):
        pvfc.Lissajous([1.0, 1.0, 1.0], [1.0, 1.0, 1.0], phase=[0.0])
