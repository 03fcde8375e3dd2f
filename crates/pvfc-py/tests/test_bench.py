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
