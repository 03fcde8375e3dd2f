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


def kinetic(model, data) -> float:
    m = np.zeros((model.nv, model.nv))
    mujoco.mj_fullM(model, data, m)
    return 0.5 * data.qvel @ m @ data.qvel


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
        m = np.zeros((2, 2))
        mujoco.mj_fullM(model, data, m)
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
