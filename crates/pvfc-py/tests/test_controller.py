"""pvfc.Controller, the one controller class for any robot: built from a scenario of each kind
of robot (the paper's SCARA, a URDF arm, a rigid body) it is the law the scenario's run
applies; its evaluation is the paper's coupling (eq. 7) for every kind; and the names of
earlier releases (ArmController, AttitudeController) are subclasses that warn."""

import pathlib
from typing import Optional
import warnings

import numpy as np
import pytest
import pvfc
from test_attitude import expm

ROOT = pathlib.Path(__file__).resolve().parents[3]
UR5 = ROOT / "models" / "ur5" / "ur5_robot.urdf"
UR5_WAYPOINTS = np.array(
    [
        [0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
        [0.4, -1.0, 1.2, -1.8, -1.57, 0.2],
        [0.8, -1.2, 1.4, -1.7, -1.57, 0.4],
        [0.4, -1.4, 1.6, -1.8, -1.57, 0.2],
    ]
)
SATELLITE = {
    "name": "satellite",
    "duration": 3.0,
    "plant": {"kind": "rigid_body", "inertia": [[1.2, 0.05, 0.0], [0.05, 1.0, 0.02], [0.0, 0.02, 0.8]]},
    "contour": {"attitude": {"rate": [0.2, 0.1, 0.5]}},
    "controller": {"h": [1.0, 2.0, 3.0], "self_pacing": 20.0, "energy": 20.0, "gamma": 0.1},
    "initial": {"q": [1.2, -0.8, 0.5]},
    "simulation": {"mode": "continuous", "plant_substeps": 5},
}


def continuous(scenario: pvfc.Scenario, duration: float) -> pvfc.Scenario:
    d = scenario.to_dict()
    d["duration"] = duration
    d["simulation"]["mode"] = "continuous"
    return pvfc.Scenario.from_dict(d, base_dir=ROOT / "scenarios")


def scenarios() -> dict[str, pvfc.Scenario]:
    return {
        "scara": continuous(pvfc.Scenario.preset("fig8_R100"), 2.0),
        "scara_urdf": continuous(pvfc.Scenario.from_file(ROOT / "scenarios" / "example_urdf_arm.toml"), 2.0),
        "panda": continuous(pvfc.Scenario.from_file(ROOT / "scenarios" / "panda_lissajous.toml"), 1.0),
        "ur5": continuous(pvfc.Scenario.from_file(ROOT / "scenarios" / "ur5_waypoints.toml"), 1.0),
        "rigid_body": pvfc.Scenario.from_dict(SATELLITE),
    }


def configuration(kind: str, q: np.ndarray) -> np.ndarray:
    """A logged configuration as the controller takes it: a rigid body's rotation vector as
    its rotation matrix."""
    return expm(q) if kind == "rigid_body" else q


@pytest.mark.parametrize("name", ["scara", "scara_urdf", "ur5", "panda", "rigid_body"])
def test_a_scenarios_controller_is_the_law_its_run_applies(name: str) -> None:
    """`pvfc.Controller(scenario)` evaluated at the states a continuous run logged gives the
    torques the run applied, for every kind of robot (a SCARA's URDF gives the closed-form
    SCARA); it starts at the run's internal states."""
    s = scenarios()[name]
    ctl = pvfc.Controller(s)
    kind = {"scara": "scara", "scara_urdf": "scara", "rigid_body": "rigid_body"}.get(name, "arm")
    assert ctl.robot == kind
    r = pvfc.simulate(s)
    assert ctl.dof == r.q.shape[1]
    assert ctl.state[:3] == pytest.approx((r.tau[0], r.tau_dot[0], r.flywheel_speed[0]), rel=1e-12, abs=1e-12)
    for k in [0, 1, len(r) // 3, len(r) - 1]:
        q = configuration(kind, r.q[k])
        d = ctl.evaluate(q, r.qdot[k], r.tau[k], r.tau_dot[k], r.flywheel_speed[k])
        scale = 1.0 + np.abs(r.torque[k]).max()
        np.testing.assert_allclose(d["robot_torque"], r.torque[k], rtol=0, atol=1e-9 * scale)
        assert d["potential"] == pytest.approx(r.potential[k], rel=1e-9, abs=1e-12)
    first = ctl.step(configuration(kind, r.q[0]), r.qdot[0], 1e-3)
    np.testing.assert_allclose(first, r.torque[0], rtol=0, atol=1e-9 * (1.0 + np.abs(r.torque[0]).max()))
    assert ctl.state[0] != r.tau[0] or ctl.state[1] != r.tau_dot[0]
    ctl.reset()
    assert ctl.state[:3] == pytest.approx((r.tau[0], r.tau_dot[0], r.flywheel_speed[0]), rel=1e-12, abs=1e-12)


def built() -> list[tuple[pvfc.Controller, float]]:
    """A controller of every kind, with its γ."""
    robot = pvfc.Robot.from_urdf(UR5, tip="tool0")
    arm = pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0, energy=400.0, self_pacing=20.0, gamma=0.7)
    body = pvfc.Controller.attitude(
        np.diag([0.8, 1.2, 1.5]),
        pvfc.So3ConstantRate(np.eye(3), [0.0, 0.3, 0.6]),
        pvfc.So3Navigation(np.diag([1.0, 2.0, 3.0])),
        gamma=0.1,
    )
    scara = pvfc.Scenario.preset("fig8_R100")
    return [(pvfc.Controller(scara), scara.to_dict()["controller"]["gamma"]), (arm, 0.7), (body, 0.1)]


def test_every_kind_evaluates_the_papers_coupling() -> None:
    """At random states of each kind of robot: G and R are skew-symmetric, the coupling torque
    is G q̇_a + γ R q̇_a (eq. 7) and does no work on q̇_a, the full torque's robot part is the
    motors' torque, W_β ≥ 0 and μ ∈ [0, 1] (eqs. 12-13), β = √(κ_a/Ē)."""
    rng = np.random.default_rng(7)
    for ctl, gamma in built():
        n = ctl.dof
        checked = 0
        for _ in range(30):
            if ctl.robot == "rigid_body":
                q = expm(rng.uniform(-1, 1, 3))
            elif ctl.robot == "arm":
                q = UR5_WAYPOINTS[0] + rng.uniform(-0.5, 0.5, n)
            else:
                q = rng.uniform(-1, 1, n)
            v, tau, tau_dot, fly = rng.uniform(-0.5, 0.5, n), rng.uniform(0, 5), rng.uniform(-1, 1), rng.uniform(1, 20)
            try:
                d = ctl.evaluate(q, v, tau, tau_dot, fly)
            except pvfc.EnergyTooLowError:
                continue
            checked += 1
            qa = np.concatenate([v, [tau_dot, fly]])
            g, r = d["G"], d["R"]
            assert g.shape == r.shape == (n + 2, n + 2)
            np.testing.assert_allclose(g, -g.T, atol=1e-12 * (1 + np.abs(g).max()))
            np.testing.assert_allclose(r, -r.T, atol=1e-12 * (1 + np.abs(r).max()))
            t = d["coupling_torque"]
            np.testing.assert_allclose(t, g @ qa + gamma * r @ qa, atol=1e-10 * (1 + np.abs(t).max()))
            assert abs(t @ qa) <= 1e-10 * (1 + np.abs(t * qa).sum())
            assert d["torque"].shape == (n + 2,)
            np.testing.assert_array_equal(d["robot_torque"], d["torque"][:n])
            assert (d["tau_torque"], d["flywheel_torque"]) == (d["torque"][n], d["torque"][n + 1])
            np.testing.assert_array_equal(ctl.torque(q, v, tau, tau_dot, fly), d["torque"])
            assert d["beta"] == pytest.approx(np.sqrt(d["kinetic_energy"] / d["energy_level"]), rel=1e-12)
            assert d["velocity_field_error_energy"] >= 0.0 and 0.0 <= d["convergence_factor"] <= 1.0
        assert checked >= 20, (ctl.robot, checked)


def test_the_contour_point_is_the_robots_configuration() -> None:
    for ctl, _ in built():
        p = ctl.contour_point(0.4)
        if ctl.robot == "rigid_body":
            assert p.shape == (3, 3)
            np.testing.assert_allclose(p @ p.T, np.eye(3), atol=1e-12)
            np.testing.assert_allclose(p, expm(0.4 * np.array([0.0, 0.3, 0.6])), atol=1e-12)
        else:
            assert p.shape == (ctl.dof,)


def test_bad_input_names_the_argument() -> None:
    for ctl, _ in built():
        with pytest.raises(ValueError, match="qdot"):
            ctl.step(ctl.contour_point(0.0), np.zeros(ctl.dof + 1), 1e-3)
        before = ctl.state
        with pytest.raises((pvfc.NonFiniteError, ValueError)):
            ctl.step(np.full_like(ctl.contour_point(0.0), np.nan), np.zeros(ctl.dof), 1e-3)
        assert ctl.state == before
    with pytest.raises(TypeError):
        pvfc.Controller(3.0)  # type: ignore[arg-type]
    robot = pvfc.Robot.from_urdf(UR5, tip="tool0")
    with pytest.raises(TypeError, match="energi"):
        pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0, energi=3.0)  # type: ignore[call-arg]
    with pytest.raises(pvfc.PvfcError, match="friction_compensation: 5 entries"):
        pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0, friction_compensation=[1.0] * 5)


def test_the_old_names_warn_and_are_the_new_controllers() -> None:
    """ArmController and AttitudeController build the same controllers as Controller.arm,
    Controller.compose and Controller.attitude, warn once per construction, and keep their old
    dicts and argument names; the passive controller takes them as any Controller."""
    robot = pvfc.Robot.from_urdf(UR5, tip="tool0")
    new = pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0, energy=400.0)
    with pytest.warns(DeprecationWarning, match=r"pvfc\.ArmController is deprecated: use pvfc\.Controller\.arm"):
        old = pvfc.ArmController(robot, UR5_WAYPOINTS, 1.0, energy=400.0)
    with pytest.warns(DeprecationWarning, match=r"Controller\.compose"):
        composed = pvfc.ArmController.compose(robot, pvfc.WaypointCurve(UR5_WAYPOINTS, 1.0))
    assert isinstance(old, pvfc.Controller) and isinstance(composed, pvfc.ArmController)
    q, v = UR5_WAYPOINTS[1] + 0.05, np.full(6, 0.1)
    a, b = old.evaluate(q, v, 0.3, 0.2, 20.0), new.evaluate(q, v, 0.3, 0.2, 20.0)
    np.testing.assert_array_equal(a["torque"], b["robot_torque"])
    assert a["tau_torque"] == b["tau_torque"] and a["potential"] == b["potential"]
    np.testing.assert_array_equal(old.step(q, v, 1e-3), new.step(q, v, 1e-3))
    assert old.state == new.state
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p_old = pvfc.PassiveController(old, torque_limit=[150.0] * 6)
        p_new = pvfc.PassiveController(new, torque_limit=[150.0] * 6)
    np.testing.assert_array_equal(p_old.step(q, v, 1e-3), p_new.step(q, v, 1e-3))

    args = (np.diag([0.8, 1.2, 1.5]), pvfc.So3ConstantRate(np.eye(3), [0.0, 0.3, 0.6]), pvfc.So3Navigation(np.diag([1.0, 2.0, 3.0])))
    with pytest.warns(DeprecationWarning, match=r"pvfc\.Controller\.attitude"):
        old_body = pvfc.AttitudeController(*args)
    new_body = pvfc.Controller.attitude(*args)
    r = expm(np.array([0.3, -0.2, 0.1]))
    d_old = old_body.evaluate(rotation=r, omega=[0.1, 0.0, 0.2], tau=0.0, tau_dot=0.1, flywheel_speed=5.0)
    d_new = new_body.evaluate(r, [0.1, 0.0, 0.2], 0.0, 0.1, 5.0)
    np.testing.assert_array_equal(d_old["torque"], d_new["torque"])
    np.testing.assert_array_equal(old_body.step(rotation=r, omega=np.zeros(3), dt=1e-3), new_body.step(r, np.zeros(3), 1e-3))
    with pytest.raises(ValueError, match="omega"):
        old_body.step(r, np.zeros(2), 1e-3)
    with pytest.raises(TypeError, match="rigid body"):
        pvfc.PassiveController(new_body)


def test_the_passive_mode_of_a_scara_controller_is_the_scenarios() -> None:
    """`PassiveController(Controller(scenario))` is `PassiveController(scenario)` with the same
    settings."""
    s = pvfc.Scenario.preset("fig8_R100")
    a = pvfc.PassiveController(s, torque_limit=[15.0, 5.0])
    b = pvfc.PassiveController(pvfc.Controller(s), torque_limit=[15.0, 5.0])
    for k in range(5):
        q = np.array([0.1 + 0.01 * k, 0.2])
        np.testing.assert_array_equal(a.step(q, None, 1e-3), b.step(q, None, 1e-3))
    assert a.storage == b.storage


def test_a_throttled_pace_slows_on_the_torque_margin_as_the_scenario_runs() -> None:
    """`[controller.passive.pace_throttle]` (the fair study's SCARA circle, on a plant with more
    friction than planned) is what `PassiveController(scenario)` does at the run's samples;
    its pace slows below 1 where the drive nears its limit. `pace_throttle=` sets it on a
    controller; it needs torque limits, and a bad setting is a named error."""
    d = pvfc.Scenario.from_file(ROOT / "examples" / "studies" / "bases" / "scara_circle_saturated.toml").to_dict()
    del d["controller"]["passive"]["pace_learning"]
    d["controller"]["passive"]["pace_throttle"] = {"threshold": 0.97, "time_constant": 2.0, "floor": 0.05}
    d["duration"] = 3.0
    d["plant"]["friction"]["coulomb"] = [2.5, 4.2]
    s = pvfc.Scenario.from_dict(d, base_dir=ROOT / "examples" / "studies" / "bases")
    r = pvfc.simulate(s)
    p = pvfc.PassiveController(s)
    assert p.pace_scale == 1.0
    worst = 0.0
    for k in range(len(r) - 1):
        worst = max(worst, float(np.abs(p.step(r.q[k], r.qdot[k], 1e-3) - r.torque[k]).max()))
    assert worst == 0.0
    assert 0.05 <= p.pace_scale < 0.99
    # The same throttle given as an argument, on a controller of the scenario.
    t = tuple(d["controller"]["passive"]["pace_throttle"][k] for k in ("threshold", "time_constant", "floor"))
    c = pvfc.PassiveController(pvfc.Controller(s), torque_limit=[15.0, 5.0], pace_throttle=t)
    for k in range(len(r) - 1):
        c.step(r.q[k], r.qdot[k], 1e-3)
    assert c.pace_scale == p.pace_scale
    with pytest.raises(pvfc.PvfcError, match="torque_limit"):
        pvfc.PassiveController(pvfc.Controller(s), pace_throttle=t)
    with pytest.raises(pvfc.PvfcError, match="threshold"):
        pvfc.PassiveController(s, pace_throttle=(1.0, 0.1, 0.1))


def test_a_learned_pace_is_the_runs_and_learns_from_the_torque_margin() -> None:
    """`[controller.passive.pace_learning]` (the fair study's Lissajous curve on its heaviest
    plant) is what `PassiveController(scenario)` does at the run's samples, to the bit;
    `pace_learning=` sets the same rule on a controller. It needs torque limits, and a bad
    setting is a named error."""
    bases = ROOT / "examples" / "studies" / "bases"
    d = pvfc.Scenario.from_file(bases / "scara_lissajous_saturated.toml").to_dict()
    rule = d["controller"]["passive"]["pace_learning"]
    d["duration"] = 8.0
    d["plant"]["mass_scale"] = [1.01, 1.14]
    d["plant"]["friction"]["coulomb"] = [2.2, 3.71]
    s = pvfc.Scenario.from_dict(d, base_dir=bases)
    r = pvfc.simulate(s)
    p = pvfc.PassiveController(s)
    t = tuple(rule[k] for k in ("target", "fall", "rise", "slope", "floor"))
    c = pvfc.PassiveController(pvfc.Controller(s), torque_limit=[15.0, 5.0], pace_learning=t)
    plain = pvfc.PassiveController(pvfc.Controller(s), torque_limit=[15.0, 5.0])
    worst = apart = 0.0
    for k in range(len(r) - 1):
        u = p.step(r.q[k], r.qdot[k], 1e-3)
        worst = max(worst, float(np.abs(u - r.torque[k]).max()))
        worst = max(worst, float(np.abs(c.step(r.q[k], r.qdot[k], 1e-3) - u).max()))
        apart = max(apart, float(np.abs(plain.step(r.q[k], r.qdot[k], 1e-3) - u).max()))
    assert worst == 0.0
    # After the first lap the learned pace is not the planned one.
    assert apart > 0.1
    with pytest.raises(pvfc.PvfcError, match="torque_limit"):
        pvfc.PassiveController(pvfc.Controller(s), pace_learning=t)
    with pytest.raises(pvfc.PvfcError, match="pace_learning.fall"):
        pvfc.PassiveController(s, pace_learning=(1.0, 1.0, 0.1, 0.03, 0.2))


def test_the_missed_torque_is_learned_beside_a_controller_built_alone() -> None:
    """`pace_learning`'s sixth number `miss` (the torque the model misses, learned lap over
    lap beside the controller, its caps the learned pace's ceilings) is what the scenario's
    run does, to the bit, from `PassiveController(scenario)`; once laps are learned its
    torques part from the same rule without it. On a URDF arm a `pvfc.Controller` keeps the
    settings it was built from and learns the same as the scenario's; without a pace to plan
    on, `miss` is a named error."""
    bases = ROOT / "examples" / "studies" / "bases"
    d = pvfc.Scenario.from_file(bases / "scara_circle_saturated.toml").to_dict()
    d["duration"] = 18.0  # the caps bite from about 16 s (the first lap is not measured)
    d["plant"]["mass_scale"] = [1.1, 1.14]
    rule = d["controller"]["passive"]["pace_learning"]
    rule["miss"] = 0.5
    s = pvfc.Scenario.from_dict(d, base_dir=bases)
    r = pvfc.simulate(s)
    p = pvfc.PassiveController(s)
    t = tuple(rule[k] for k in ("target", "fall", "rise", "slope", "floor"))
    plain = pvfc.PassiveController(s, pace_learning=t)
    worst = apart = 0.0
    for k in range(len(r) - 1):
        u = p.step(r.q[k], r.qdot[k], 1e-3)
        worst = max(worst, float(np.abs(u - r.torque[k]).max()))
        apart = max(apart, float(np.abs(plain.step(r.q[k], r.qdot[k], 1e-3) - u).max()))
    assert worst == 0.0
    assert apart > 0.1
    with pytest.raises(ValueError, match="pvfc.Scenario"):
        pvfc.PassiveController(pvfc.Controller(s), torque_limit=[15.0, 5.0], pace_learning=t + (0.5,))
    with pytest.raises(ValueError, match="got 4 numbers"):
        pvfc.PassiveController(s, pace_learning=t[:4])
    with pytest.raises(pvfc.PvfcError, match="pace_learning.miss"):
        pvfc.PassiveController(s, pace_learning=t + (1.5,))
    # A URDF arm: the scenario's controller and a pvfc.Controller of it, stepped alike.
    d = pvfc.Scenario.from_file(bases / "ur5_circle_saturated.toml").to_dict()
    d["duration"] = 0.3
    arm_rule = d["controller"]["passive"]["pace_learning"]
    arm_rule["miss"] = 0.5
    ur5 = pvfc.Scenario.from_dict(d, base_dir=bases)
    r = pvfc.simulate(ur5)
    alone = pvfc.PassiveController(
        pvfc.Controller(ur5),
        torque_limit=d["controller"]["passive"]["torque_limit"],
        pace_learning=tuple(arm_rule[k] for k in ("target", "fall", "rise", "slope", "floor", "miss")),
    )
    q = pvfc.PassiveController(ur5)
    for k in range(len(r) - 1):
        assert np.array_equal(alone.step(r.q[k], r.qdot[k], 1e-3), q.step(r.q[k], r.qdot[k], 1e-3))
    robot = pvfc.Robot.from_urdf(ROOT / "models" / "ur5" / "ur5_robot.urdf", tip="tool0")
    ring = np.array([[0.0, -1.2 + 0.1 * np.sin(a), 1.4, -1.8, -1.57, 0.1 * np.cos(a)] for a in np.linspace(0, 2 * np.pi, 8, endpoint=False)])
    unpaced = pvfc.Controller.arm(robot, ring, 1.0)
    with pytest.raises(pvfc.PvfcError, match="pace_learning.miss"):
        pvfc.PassiveController(unpaced, torque_limit=[150.0] * 3 + [28.0] * 3, pace_learning=t + (0.5,))


def replayed(s: pvfc.Scenario, counts: Optional[float]) -> float:
    """The largest difference between the torques of a sampled run with `[controller.passive]`
    and those of `pvfc.PassiveController(scenario)` stepped at the run's samples (positions
    rounded to the encoder's counts as the run's drive rounds them)."""
    r = pvfc.simulate(s)
    p = pvfc.PassiveController(s)
    step = 2.0 * np.pi / counts if counts else None
    worst = 0.0
    for k in range(len(r) - 1):
        q = np.round(r.q[k] / step) * step if step else r.q[k]
        worst = max(worst, float(np.abs(p.step(q, r.qdot[k], 1e-3) - r.torque[k]).max()))
    return worst


def test_a_scenarios_passive_controller_is_its_sampled_runs() -> None:
    """`pvfc.PassiveController(scenario)` takes `[controller.passive]` of a URDF arm's scenario
    (torque limits, encoder counts, velocity filter) as of the SCARA's: stepped at the samples
    of the scenario's own run it gives the run's torques exactly, the limits active."""
    d = pvfc.Scenario.from_file(ROOT / "scenarios" / "ur5_push.toml").to_dict()
    d.pop("contact_3d")
    d["duration"] = 0.5
    d["controller"]["passive"] = {"torque_limit": [150.0] * 3 + [28.0] * 3, "encoder_counts": 2.0**17, "velocity_filter": 0.002}
    ur5 = pvfc.Scenario.from_dict(d, base_dir=ROOT / "scenarios")
    assert np.abs(pvfc.simulate(ur5).torque).max() == 150.0  # a limit is reached
    assert replayed(ur5, 2.0**17) == 0.0
    d = pvfc.Scenario.from_file(ROOT / "scenarios" / "digital_free_1000hz_passive.toml").to_dict()
    d["duration"] = 0.5
    assert replayed(pvfc.Scenario.from_dict(d), None) == 0.0
    with pytest.raises(TypeError, match="rigid body"):
        pvfc.PassiveController(pvfc.Scenario.from_dict(SATELLITE))
