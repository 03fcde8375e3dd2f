"""The drive-limited pace against TOPP-RA (``toppra``), the reference implementation of the
time-optimal path parameterisation: on the UR5 (``models/ur5``) along a closed joint-space
curve under torque limits, with and without Coulomb friction compensation counted against
them, ``Robot.drive_limited_rates`` gives the same fastest rates (to 1e-7 relative, measured) and the same lap time as
TOPP-RA's ``JointTorqueConstraint`` on the same path, inverse dynamics (pvfc's RNEA, checked
against Pinocchio in ``test_pinocchio.py``) and limits, started and ended at pvfc's rate at
τ = 0 (the closed contour's rate there).
"""

import os
import pathlib

import numpy as np
import pytest

import pvfc

try:
    import toppra
    import toppra.algorithm
    import toppra.constraint
    import toppra.interpolator
except ImportError:  # pragma: no cover - CI installs it (scripts/test.sh)
    if os.environ.get("CI"):
        raise
    pytest.skip("toppra (pip install toppra) is not installed", allow_module_level=True)

REPO = pathlib.Path(__file__).resolve().parents[3]
LIMITS = np.array([60.0, 60.0, 30.0, 5.0, 5.0, 5.0])
POINTS = 2000


def ur5() -> pvfc.Robot:
    return pvfc.Robot.from_urdf(REPO / "models" / "ur5" / "ur5_robot.urdf", tip="tool0")


def loop() -> pvfc.WaypointCurve:
    """A closed curve through six joint-space waypoints, one every 0.5 of τ (period 3)."""
    base = np.array([0.0, -1.2, 1.4, -1.8, -1.57, 0.0])
    bumps = np.array(
        [
            [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            [0.6, 0.2, -0.3, 0.2, 0.3, 0.5],
            [1.0, -0.1, 0.2, 0.4, -0.2, 1.0],
            [0.7, -0.4, 0.5, -0.1, 0.1, 0.4],
            [0.1, -0.2, 0.3, -0.4, 0.4, -0.3],
            [-0.3, 0.1, -0.1, 0.1, -0.3, -0.6],
        ]
    )
    return pvfc.WaypointCurve(base + bumps, 0.5)


class ContourPath(toppra.interpolator.AbstractGeometricPath):
    """pvfc's contour as a TOPP-RA path over one period (positions, and their first and second
    derivatives in τ)."""

    def __init__(self, contour: pvfc.WaypointCurve) -> None:
        self.contour = contour

    def __call__(self, path_positions, order=0):  # type: ignore[no-untyped-def]
        s = np.atleast_1d(np.asarray(path_positions, dtype=float))
        out = np.array([self.contour.sample(float(x))[order] for x in s])
        return out if np.ndim(path_positions) else out[0]

    @property
    def dof(self) -> int:
        return 6

    @property
    def path_interval(self) -> np.ndarray:
        return np.array([0.0, self.contour.period])


def lap(rates: np.ndarray, period: float) -> float:
    """Σ 2Δ / (ṡ_j + ṡ_{j+1}) over one period (closed)."""
    step = period / len(rates)
    return float(np.sum(2.0 * step / (rates + np.roll(rates, -1))))


@pytest.mark.parametrize("friction", [None, np.array([4.0, 4.0, 2.0, 0.5, 0.5, 0.5])])
def test_the_fastest_rates_are_toppras(friction) -> None:
    robot, contour = ur5(), loop()
    period = contour.period
    ours = robot.drive_limited_rates(
        contour, LIMITS, friction_compensation=friction, points=POINTS
    )
    assert ours.shape == (POINTS,)
    fs = np.zeros(6) if friction is None else friction
    constraint = toppra.constraint.JointTorqueConstraint(
        lambda q, qd, qdd: robot.rnea(q, qd, qdd),
        np.column_stack([-LIMITS, LIMITS]),
        fs,
        discretization_scheme=toppra.constraint.DiscretizationType.Collocation,
    )
    grid = np.linspace(0.0, period, POINTS + 1)
    algo = toppra.algorithm.TOPPRA(
        [constraint], ContourPath(contour), gridpoints=grid, solver_wrapper="seidel"
    )
    _, sd, _ = algo.compute_parameterization(ours[0], ours[0])
    theirs = np.asarray(sd)[:-1]
    assert np.all(np.isfinite(theirs)), "TOPP-RA found no parameterisation from pvfc's rate at τ = 0"

    # The drives limit the rate somewhere (it is not the rate asked for anywhere near).
    assert ours.max() < 1e3 and ours.min() > 0.05
    # The same lap time, and the same profile point by point (the same discretisation: the
    # rates agree to ~1e-7, TOPP-RA's own margins of 0.01 % on its forward pass).
    t_ours, t_theirs = lap(ours, period), lap(theirs, period)
    rel = np.abs(ours - theirs) / theirs
    what = f"lap {t_ours:.6f} s against TOPP-RA's {t_theirs:.6f} s; rates within {rel.max():.1e}"
    assert abs(t_ours - t_theirs) <= 1e-6 * t_theirs, what
    assert rel.max() < 1e-5, what


def test_the_rates_asked_for_and_the_headroom_bound_the_profile() -> None:
    robot, contour = ur5(), loop()
    full = robot.drive_limited_rates(contour, LIMITS, points=POINTS)
    slow = robot.drive_limited_rates(contour, LIMITS, rate=0.5 * full.min(), points=POINTS)
    assert np.all(slow == 0.5 * full.min())
    kept = robot.drive_limited_rates(contour, LIMITS, headroom=0.8, points=POINTS)
    assert np.all(kept <= full * (1 + 1e-12)) and lap(kept, 3.0) > 1.05 * lap(full, 3.0)


def test_viscous_friction_takes_its_share_of_the_limits() -> None:
    """A plant's viscous friction (a torque ``b q̇``, not affine in ``τ̇²``, which TOPP-RA's
    ``JointTorqueConstraint`` cannot express): every torque along the profile, from pvfc's RNEA
    plus Coulomb and viscous friction written out here, is within the limits; wherever the
    profile is below the rate asked for a joint is at its limit; the lap is longer than with
    Coulomb friction alone."""
    robot, contour = ur5(), loop()
    period = contour.period
    coulomb = np.array([3.0, 3.0, 2.0, 0.8, 0.8, 0.8])
    viscous = np.array([5.0, 5.0, 3.0, 1.0, 1.0, 1.0])
    plain = robot.drive_limited_rates(contour, LIMITS, friction_compensation=coulomb, points=POINTS)
    rates = robot.drive_limited_rates(
        contour, LIMITS, friction_compensation=coulomb, viscous_friction=viscous, points=POINTS
    )
    step = period / POINTS
    at_limit = 0
    for j in range(POINTS):
        x0, x1 = rates[j] ** 2, rates[(j + 1) % POINTS] ** 2
        accel = (x1 - x0) / (2.0 * step)
        q, dq, ddq = (np.asarray(v) for v in contour.sample(j * step))
        qd = dq * rates[j]
        torque = robot.rnea(q, qd, dq * accel + ddq * rates[j] ** 2)
        torque = torque + coulomb * np.sign(qd) + viscous * qd
        share = np.max(np.abs(torque) / LIMITS)
        assert share <= 1.0 + 1e-6, f"τ = {j * step:.4f}: {share} of the limits"
        at_limit += share >= 1.0 - 1e-6
    assert at_limit >= 0.99 * POINTS, f"{at_limit} of {POINTS} points at a limit"
    assert lap(rates, period) > 1.01 * lap(plain, period)


def test_bad_input_is_a_named_error() -> None:
    robot, contour = ur5(), loop()
    with pytest.raises(ValueError, match="torque_limit"):
        robot.drive_limited_rates(contour, LIMITS[:5])
    with pytest.raises(pvfc.PvfcError, match="headroom"):
        robot.drive_limited_rates(contour, LIMITS, headroom=1.5)
    with pytest.raises(pvfc.PvfcError, match="torque limits"):
        robot.drive_limited_rates(contour, -LIMITS)
    with pytest.raises(TypeError, match="contour"):
        robot.drive_limited_rates("circle", LIMITS)
    with pytest.raises(pvfc.PvfcError, match="viscous"):
        robot.drive_limited_rates(contour, LIMITS, viscous_friction=-np.ones(6))


def test_a_controller_paced_at_a_joint_speed_moves_its_field_at_that_speed() -> None:
    """``Controller.compose(..., pace={"joint_speed": v})``: on the contour the field's joint
    velocity has the norm asked for (λ₁ = σ(τ) = v / |ξ_d(τ)|), at every τ; with
    ``energy=0`` the level is sized from it (the field is evaluated without finding it too
    low)."""
    robot, contour = ur5(), loop()
    settings = pvfc.ControllerSettings(self_pacing=0.0, energy=0.0, gamma=1.0)
    ctl = pvfc.Controller.compose(robot, contour, settings=settings, pace={"joint_speed": 0.5})
    for tau in np.linspace(0.0, contour.period, 13)[:-1]:
        q = contour.sample(float(tau))[0]
        e = ctl.evaluate(q, np.zeros(6), float(tau), 0.0, 1.0)
        speed = np.linalg.norm(e["field_velocity"][:6])
        # The profile (256 knots, each the least rate within a knot's spacing of it) stays at
        # or below the speed asked for, and above its least within two spacings.
        h = contour.period / 256
        near = np.linspace(tau - 2 * h, tau + 2 * h, 101)
        least = min(0.5 / np.linalg.norm(contour.sample(float(t))[1]) for t in near)
        here = np.linalg.norm(contour.sample(float(tau))[1])
        assert least * here * (1 - 1e-9) <= speed <= 0.5 * (1 + 1e-9), (tau, speed)
        # The energy level was sized (evaluating the field does not find it too low).
        assert e["energy_level"] > 0.5 * speed**2


def test_a_coupling_rate_sets_gamma_for_the_sized_energy_level() -> None:
    """``ControllerSettings(coupling_rate=k)`` with ``energy=0``: the controller is the one
    with the sized level Ē and ``gamma = k / (βĒ)`` (β = 1 without a nominal speed): the same
    torques to the bit, off the contour and moving."""
    robot, contour = ur5(), loop()
    pace = {"joint_speed": 0.5}
    by_rate = pvfc.Controller.compose(
        robot,
        contour,
        settings=pvfc.ControllerSettings(energy=0.0, coupling_rate=400.0),
        pace=pace,
    )
    q = contour.sample(0.4)[0] + 0.01
    e = by_rate.evaluate(q, np.full(6, 0.05), 0.4, 0.3, 2.0)
    level = e["energy_level"]
    by_gain = pvfc.Controller.compose(
        robot,
        contour,
        settings=pvfc.ControllerSettings(energy=level, gamma=400.0 / level),
        pace=pace,
    )
    for ctl in (by_rate, by_gain):
        assert ctl.evaluate(q, np.full(6, 0.05), 0.4, 0.3, 2.0)["energy_level"] == level
    a = by_rate.torque(q, np.full(6, 0.05), 0.4, 0.3, 2.0)
    b = by_gain.torque(q, np.full(6, 0.05), 0.4, 0.3, 2.0)
    np.testing.assert_array_equal(a, b)
    with pytest.raises(pvfc.PvfcError, match="coupling_rate"):
        pvfc.Controller.compose(
            robot, contour, settings=pvfc.ControllerSettings(coupling_rate=-1.0)
        )


def test_a_pace_bounded_by_the_drives_is_never_faster_than_asked() -> None:
    robot, contour = ur5(), loop()
    slow = pvfc.Controller.compose(robot, contour, pace={"torque_limit": LIMITS})
    q = contour.sample(0.0)[0]
    e = slow.evaluate(q, np.zeros(6), 0.0, 0.0, 1.0)
    assert 0.0 < e["lambda1"] <= 1.0


def test_bad_paces_are_named_errors() -> None:
    robot, contour = ur5(), loop()
    for pace, what in [
        ({"speed": 1.0}, "unknown key"),
        ({"tool_speed": 0.1, "joint_speed": 1.0}, "not both"),
        ({"headroom": 0.5}, "give a speed"),
    ]:
        with pytest.raises(ValueError, match=what):
            pvfc.Controller.compose(robot, contour, pace=pace)
    with pytest.raises(pvfc.PvfcError, match="pace.speed"):
        pvfc.Controller.compose(robot, contour, pace={"joint_speed": -1.0})


def test_a_scenarios_least_lap_is_its_plants() -> None:
    """``Scenario.least_lap()``: the fig1_saturated circle's least lap at r = 4 on its plant
    (Coulomb 2.5 / 3.5 and viscous 0.1 N·m·s/rad against 15 / 5 N·m) is longer than on a
    plant whose friction were only the controller's compensation (2 / 3), longer again with a
    heavier second link (``plant.mass_scale``), and a scenario without a drive-limited pace
    says so."""
    s = pvfc.Scenario.preset("fig1_saturated_r4")
    lap = s.least_lap()
    d = s.to_dict()
    d["plant"]["friction"] = {"coulomb": [2.0, 3.0], "viscous": [0.0, 0.0]}
    light = pvfc.Scenario.from_dict(d).least_lap()
    assert 0 < light < lap
    d = s.to_dict()
    d["plant"]["mass_scale"] = [1.0, 1.15]
    heavy = pvfc.Scenario.from_dict(d).least_lap()
    assert heavy > lap
    # τ̇ never above r = 4 on the period 6: at least 1.5 s.
    assert lap >= 6.0 / 4.0
    with pytest.raises(pvfc.PvfcError, match="drive-limited pace"):
        pvfc.Scenario.preset("fig8_R100").least_lap()
