"""Benchmarks (pytest-benchmark; medians are in the report, nothing is asserted on time)."""

import numpy as np

import pvfc


def test_bench_controller_torque(benchmark):
    c = pvfc.Controller(pvfc.Scenario.preset("fig8_R100"))
    q, v = np.array([0.1, 1.4]), np.array([0.5, -0.2])
    out = benchmark(c.torque, q, v, 0.3, 0.9, 60.0)
    assert out.shape == (4,)


def test_bench_controller_step(benchmark):
    c = pvfc.Controller(pvfc.Scenario.preset("fig8_R100"))
    q, v = np.array([0.1, 1.4]), np.array([0.5, -0.2])

    def step():
        c.reset()
        return c.step(q, v, 1e-3)

    assert benchmark(step).shape == (2,)


def test_bench_simulate_10s_continuous(benchmark):
    d = pvfc.Scenario.preset("fig8_R100").to_dict()
    d["duration"] = 10.0
    d["simulation"] = {"mode": "continuous", "plant_substeps": 1}
    s = pvfc.Scenario.from_dict(d)
    r = benchmark(pvfc.simulate, s)
    assert len(r) == 10001


def test_bench_simulate_10s_sampled(benchmark):
    d = pvfc.Scenario.preset("fig8_R100").to_dict()
    d["duration"] = 10.0
    s = pvfc.Scenario.from_dict(d)
    assert len(benchmark(pvfc.simulate, s)) == 10001


# ---- pvfc against Pinocchio, side by side in one run: M(q) and C(q, v) of the UR5 and the
# Panda from Python (the same call overhead on both sides: two calls each, numpy in and out).
# Compare the medians of each pair (group "dynamics-<robot>").

try:
    import pinocchio as _pin
except ImportError:  # pragma: no cover - CI installs it (scripts/test.sh)
    _pin = None

import pathlib

import pytest

_MODELS = pathlib.Path(__file__).resolve().parents[3] / "models"
_ARMS = {
    "ur5": (_MODELS / "ur5" / "ur5_robot.urdf", "tool0", []),
    "panda": (_MODELS / "panda" / "panda.urdf", "panda_hand_tcp", ["panda_finger_joint1", "panda_finger_joint2"]),
}


def _state(n):
    rng = np.random.default_rng(3)
    return rng.uniform(-np.pi, np.pi, n), rng.uniform(-2, 2, n)


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_bench_dynamics_pvfc(benchmark, name):
    path, tip, _ = _ARMS[name]
    robot = pvfc.Robot.from_urdf(path, tip=tip)
    q, v = _state(robot.dof)
    benchmark.group = f"dynamics-{name}"

    def both():
        return robot.inertia(q), robot.coriolis(q, v)

    m, c = benchmark(both)
    assert m.shape == c.shape == (robot.dof, robot.dof)


@pytest.mark.skipif(_pin is None, reason="pinocchio (pip install pin) is not installed")
@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_bench_dynamics_pinocchio(benchmark, name):
    path, _, locked = _ARMS[name]
    model = _pin.buildModelFromUrdf(str(path))
    if locked:
        model = _pin.buildReducedModel(model, [model.getJointId(j) for j in locked], _pin.neutral(model))
    data = model.createData()
    q, v = _state(model.nv)
    benchmark.group = f"dynamics-{name}"

    def both():
        return _pin.crba(model, data, q), _pin.computeCoriolisMatrix(model, data, q, v)

    m, c = benchmark(both)
    assert m.shape == c.shape == (model.nv, model.nv)
