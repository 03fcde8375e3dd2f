"""The passive digital controller on an independent plant: MuJoCo (RK4 at 10 kHz, its own
URDF import of models/scara.urdf, frictionless) driven from Python at 1 kHz and 100 Hz with
encoder-free measurements. κ_a = MuJoCo's kinetic energy (½ q̇ᵀ M q̇ with MuJoCo's M) + the
controller's storage must stay within 1e-6 of κ_a(0) over 30 s, and U must converge;
`Controller.step` (zero-order hold, not passive) beside it for contrast."""

import numpy as np
import pytest

import pvfc

mujoco = pytest.importorskip("mujoco", reason="MuJoCo (pip install mujoco) is not installed")

PLANT_DT = 1e-4
DURATION = 30.0


def scenario() -> pvfc.Scenario:
    # The wall scenario's controller (Ē = 50, γ = 1, R = 5, flywheel at 10 rad/s, the arm at
    # rest), without the wall; the arm starts off the contour.
    d = pvfc.Scenario.preset("contact_wall_sampled").to_dict()
    d.pop("contact", None)
    d["name"] = "mujoco_free"
    return pvfc.Scenario.from_dict(d)


def plant(repo):
    model = mujoco.MjModel.from_xml_path(str(repo / "models" / "scara.urdf"))
    model.opt.timestep = PLANT_DT
    model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
    model.opt.gravity[:] = 0.0
    assert model.nv == 2
    return model, mujoco.MjData(model)


def full_mass(model, data) -> np.ndarray:
    """The joint-space inertia matrix MuJoCo holds for `data`'s state (`mj_fullM` takes the
    data since MuJoCo 3.4, its sparse `qM` before)."""
    m = np.zeros((model.nv, model.nv))
    try:
        mujoco.mj_fullM(model, data, m)
    except TypeError:
        mujoco.mj_fullM(model, m, data.qM)
    return m


def kinetic(model, data) -> float:
    return 0.5 * data.qvel @ full_mass(model, data) @ data.qvel


def run(repo, rate: float, passive: bool):
    s = scenario()
    model, data = plant(repo)
    data.qpos[:] = [0.6, 0.4]  # off the contour (it starts at (0, 1.5))
    data.qvel[:] = 0.0
    mujoco.mj_forward(model, data)
    law = pvfc.Controller(s)
    ctl = pvfc.PassiveController(s) if passive else pvfc.Controller(s)
    dt = 1.0 / rate
    sub = int(round(dt / PLANT_DT))
    kappa, potential = [], []
    for _ in range(int(round(DURATION * rate)) + 1):
        mujoco.mj_forward(model, data)
        q, v = data.qpos.copy(), data.qvel.copy()
        state = ctl.state
        u = ctl.step(q, v, dt)
        if passive:
            storage = ctl.energy["storage"]
        else:
            storage = 0.5 * (state[1] ** 2 + state[2] ** 2)  # M_F = 1
        kappa.append(kinetic(model, data) + storage)
        potential.append(law.evaluate(q, v, state[0], state[1], state[2])["potential"])
        data.qfrc_applied[:] = u
        for _ in range(sub):
            mujoco.mj_step(model, data)
    return np.array(kappa), np.array(potential)


def test_mujoco_inertia_is_pvfcs(repo):
    model, data = plant(repo)
    scara = pvfc.Scara.from_urdf(repo / "models" / "scara.urdf")
    for q in ([0.0, 0.0], [0.3, 1.2], [-2.0, -0.7]):
        data.qpos[:] = q
        mujoco.mj_forward(model, data)
        m = full_mass(model, data)
        np.testing.assert_allclose(m, scara.inertia(q), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("rate", [1000.0, 100.0])
def test_passive_controller_on_mujoco_creates_no_energy(repo, rate):
    kappa, potential = run(repo, rate, passive=True)
    drift = np.max(np.abs(kappa - kappa[0])) / kappa[0]
    zoh_kappa, _ = run(repo, rate, passive=False)
    zoh = np.max(np.abs(zoh_kappa - zoh_kappa[0])) / zoh_kappa[0]
    print(f"{rate:.0f} Hz: passive drift {drift:.2e}, ZOH drift {zoh:.2e}, U {potential[0]:.2e} -> {potential[-1]:.2e}")
    assert drift <= 1e-6
    assert potential[-1] < 1e-3 * potential[0]
    assert zoh > 10 * drift


DELTA = 2.0 * np.pi / 2**17  # encoders of 2¹⁷ counts per turn
LIMITS = [40.0, 12.0]


def on_encoders(repo, seconds: float, nominal_c, velocity_filter: float):
    """MuJoCo's SCARA (frictionless, RK4 at 1 kHz) under the passive controller at 1 kHz on
    rounded positions only (the velocity estimated), torque limits 40 / 12 N·m, the applied
    torque fed back; nominal-speed control (36) at r = 1 with gain `nominal_c` if given.
    Returns κ_a once a second, and the encoder charge, the loop's energy and the largest
    κ_a − κ_a(0) − W_loop over the run (the energy the controller created)."""
    d = scenario().to_dict()
    if nominal_c is not None:
        d["controller"]["nominal_speed"] = {"c": nominal_c, "r": 1.0}
    s = pvfc.Scenario.from_dict(d)
    model, data = plant(repo)
    model.opt.timestep = 1e-3
    data.qpos[:] = [0.6, 0.4]
    data.qvel[:] = 0.0
    ctl = pvfc.PassiveController(
        s, torque_limit=LIMITS, encoder_resolution=[DELTA, DELTA], velocity_filter=velocity_filter
    )
    u = np.zeros(2)
    kappa, charge, loop, created = [], 0.0, 0.0, -np.inf
    for k in range(int(round(seconds * 1000)) + 1):
        mujoco.mj_forward(model, data)
        u = ctl.step(np.round(data.qpos / DELTA) * DELTA, None, 1e-3, applied=u)
        e = ctl.energy
        charge += e["quantisation"]
        loop += e["add_ons"]
        if k % 1000 == 0:
            kappa.append(kinetic(model, data) + e["storage"])
            created = max(created, kappa[-1] - kappa[0] - loop)
        data.qfrc_applied[:] = u
        mujoco.mj_step(model, data)
    return np.array(kappa), charge, loop, created


def test_the_energy_loop_holds_the_level_for_an_hour(repo):
    """On encoders the storage is charged for what the rounding could hide, and without a
    source κ_a falls (50 → 42.8 J in 30 s on positions alone). With a 5 ms filter on the
    velocity estimate and the energy loop (36), c = 1, κ_a holds within 1 % of Ē = 50 J for an
    hour at 1 kHz, without drifting, and the controller never creates more than the
    rounding's boundary terms (Σ δ_i L_i)."""
    drained, charge, _, _ = on_encoders(repo, 30.0, None, 0.0)
    print(f"30 s without the loop: κ_a {drained[0]:.2f} -> {drained[-1]:.2f} J, charge {charge:.2f} J")
    assert drained[-1] < 45.0
    kappa, charge, loop, created = on_encoders(repo, 3600.0, 1.0, 0.005)
    after = kappa[60:]
    print(
        f"one hour: κ_a {kappa[0]:.3f} -> {kappa[-1]:.4f} J, after a minute in [{after.min():.4f}, {after.max():.4f}],"
        f" charge {charge:.2f} J, energy loop {loop:.2f} J, created <= {created:.1e} J"
    )
    assert after.min() > 49.5 and after.max() < 50.5
    assert abs(kappa[3000:].mean() - kappa[60:660].mean()) < 0.05
    assert charge > 10.0 and loop > 0.5 * charge
    assert created <= DELTA * sum(LIMITS)
