"""The control law's properties checked from Python, at random states (hypothesis)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import pvfc

angle = st.floats(-3.1, 3.1)
# Velocities are 0 (rest) or at least 1e-6 in size: below that the relative tolerances below
# compare against norms whose squares underflow (e.g. |q̇| ~ 1e-228), which tests nothing.
speed = st.one_of(st.just(0.0), st.floats(1e-6, 3.0), st.floats(-3.0, -1e-6))


@settings(max_examples=300, deadline=None)
@given(q1=angle, q2=angle, v1=speed, v2=speed, tau=st.floats(-10, 10), tau_dot=st.one_of(st.just(0.0), st.floats(1e-6, 2), st.floats(-2, -1e-6)), fly=st.one_of(st.just(0.0), st.floats(1e-6, 60), st.floats(-60, -1e-6)),
       preset=st.sampled_from(["fig8_R0", "fig8_R200", "fig9_R50", "fig6_unforced"]))
def test_coupling_is_passive_and_skew(q1, q2, v1, v2, tau, tau_dot, fly, preset):
    c = pvfc.Controller(pvfc.Scenario.preset(preset))
    out = c.evaluate([q1, q2], [v1, v2], tau, tau_dot, fly)
    qa = np.array([v1, v2, tau_dot, fly])
    g, r = out["G"], out["R"]
    np.testing.assert_allclose(g + g.T, 0.0, atol=1e-12 * max(1.0, np.abs(g).max()))
    np.testing.assert_allclose(r + r.T, 0.0, atol=1e-12 * max(1.0, np.abs(r).max()))
    # q̇_aᵀ T_a = 0 for the coupling torque of eq. (7), relative to the cancelling products.
    t = out["coupling_torque"]
    w, p_big, p = out["w"], out["desired_momentum"], out["momentum"]
    scale = np.linalg.norm(qa) ** 2 * (np.linalg.norm(w) * np.linalg.norm(p_big) + np.linalg.norm(p_big) * np.linalg.norm(p)) + 1e-300
    assert abs(t @ qa) <= 1e-12 * scale
    # The field has energy Ē: ½ Pᵀ V_a = Ē, and wᵀV_a = 0.
    va = out["field_velocity"]
    energy = pvfc.Scenario.preset(preset).to_dict()["controller"]["energy"]
    assert 0.5 * p_big @ va == np.float64(energy) or abs(0.5 * p_big @ va - energy) <= 1e-12 * energy
    assert abs(w @ va) <= 1e-10 * (np.linalg.norm(w) * np.linalg.norm(va) + 1e-300)


def test_energy_is_constant_without_friction():
    d = pvfc.Scenario.preset("energy_continuous").to_dict()
    d["duration"] = 10.0
    r = pvfc.simulate(pvfc.Scenario.from_dict(d))
    drift = np.max(np.abs(r.energy - r.energy[0])) / r.energy[0]
    assert drift < 1e-6, drift
    assert r.potential[-1] < 1e-6 * r.potential[0]
