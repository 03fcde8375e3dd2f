"""Faults survived from Python: a scenario's `[[faults]]` run (the trace's `fault` column), and
`pvfc.PassiveController(..., max_speed=, max_acceleration=, period=)` stepped by hand through a
NaN, a spike, a frozen encoder and a late sample: each a fault with the safe torque, zeros,
and the controller back at the next good sample."""

import pathlib

import numpy as np
import pytest
import pvfc

ROOT = pathlib.Path(__file__).resolve().parents[3]


def test_a_scenarios_faults_are_in_its_trace() -> None:
    s = pvfc.Scenario.from_file(ROOT / "scenarios" / "scara_faults.toml")
    r = pvfc.simulate(s)
    codes = set(np.unique(r.fault).astype(int))
    # Non-finite (1), the missed period (2), the spike (3) and the frozen encoder (5).
    assert codes == {0, 1, 2, 3, 5}, codes
    nan = np.flatnonzero(r.fault == 1)
    assert abs(r.t[nan[0]] - 3.0) < 1e-9
    assert np.all(r.torque[nan] == 0.0)
    d = s.to_dict()
    d.pop("controller")
    with pytest.raises(pvfc.PvfcError, match="controller.passive"):
        pvfc.Scenario.from_dict(d, base_dir=ROOT / "scenarios")


def test_a_supervised_controller_answers_faults_with_zero_torque() -> None:
    s = pvfc.Scenario.preset("fig8_R100")
    c = pvfc.PassiveController(
        s, torque_limit=[15.0, 5.0], max_speed=[4.0, 4.0], max_acceleration=[100.0, 100.0], period=(4e-4, 3.5e-3)
    )
    assert c.supervised
    t = 0.0

    def joint_at(t: float) -> np.ndarray:
        return np.array([2.0 * t, 0.1])  # joint 0 at 2 rad/s

    for _ in range(20):
        c.step(joint_at(t), None, 1e-3)
        assert c.fault is None
        t += 1e-3
    for offset, dt, fault in [
        (np.array([np.nan, 0.0]), 1e-3, ("non_finite", None)),
        (np.array([0.5, 0.0]), 1e-3, ("speed", 0)),
        (np.array([0.0, 0.0]), 1e-2, ("period", None)),
    ]:
        u = c.step(joint_at(t) + offset, None, dt)
        assert c.fault == fault
        np.testing.assert_array_equal(u, [0.0, 0.0])
        assert c.energy is not None and c.energy["scale"] == 0.0
        t += dt
    c.step(joint_at(t), None, 1e-3)
    assert c.fault is None, "back at the next good reading"
    # Joint 0's encoder stops dead at 2 rad/s: frozen until it reads something else.
    frozen = joint_at(t)
    for _ in range(3):
        t += 1e-3
        c.step(frozen, None, 1e-3)
        assert c.fault == ("frozen", 0)
    t += 1e-3
    c.step(joint_at(t), None, 1e-3)
    assert c.fault is None
    assert not pvfc.PassiveController(s).supervised


def test_supervision_arguments_are_checked() -> None:
    s = pvfc.Scenario.preset("fig8_R100")
    with pytest.raises(ValueError, match="period"):
        pvfc.PassiveController(s, max_speed=[4.0, 4.0])
    with pytest.raises(ValueError, match="max_speed"):
        pvfc.PassiveController(s, period=(1e-3, 2e-3))
    with pytest.raises(ValueError, match="max_speed"):
        pvfc.PassiveController(s, max_speed=[4.0], period=(1e-3, 2e-3))
    with pytest.raises(Exception, match="max_speed: each finite and > 0"):
        pvfc.PassiveController(s, max_speed=[4.0, -1.0], period=(1e-3, 2e-3))
