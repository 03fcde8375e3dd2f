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
