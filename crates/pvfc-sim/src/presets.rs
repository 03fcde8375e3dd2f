//! The paper's section V as built-in scenarios (also shipped as `scenarios/*.toml`).
//!
//! Parameters the paper does not publish, chosen once here (README, "Parameters"):
//! * the arm: [`direct_drive_arm`] (`models/scara.urdf`);
//! * plant friction: Coulomb (2.5, 3.5) N·m — 25 % and 17 % more than the compensation
//!   (2.0, 3.0) of eq. (35) assumes, the paper's "imperfect friction compensation" — viscous
//!   0.1 N·m·s/rad, stiction velocity 0.01 rad/s;
//! * `h = (1, 1)`, `M_F = 1`, and `γĒ = 50` (convergence rate `2γβĒ ≈ 100 s⁻¹`); with a
//!   smaller `γĒ` the largest torque the coupling gives an arm at rest, `≈ 2γĒ·M·λ₂h sin E`,
//!   does not break the Coulomb friction of the elbow and the arm sticks off the contour;
//! * `Ē = 50` for Fig. 6 (the paper's "flywheel at 10, energy 50" with `M_F = 1` is `β = 1`);
//!   `Ē = 2000` for the forced runs (Figs. 1, 7–10): with `c = 0.01` the nominal-speed term
//!   (36) injects at most `c·2Ē·β(r − β)` W, which must cover the friction losses (~5 W).

use crate::friction::JointFriction;
use crate::scenario::*;

/// The plant friction of every preset.
pub fn plant_friction() -> JointFriction {
    JointFriction {
        coulomb: [2.5, 3.5],
        viscous: [0.1, 0.1],
        stiction_velocity: 0.01,
    }
}

/// The friction compensation of eq. (35) used in the paper.
pub const PAPER_COMPENSATION: [f64; 2] = [2.0, 3.0];

fn forced(name: &str, description: &str, r_pacing: f64, compensation: bool, r: f64) -> Scenario {
    let energy = 2000.0;
    Scenario {
        name: name.into(),
        description: description.into(),
        duration: 40.0,
        plant: PlantSpec {
            arm: ArmSpec::DirectDrive,
            friction: plant_friction(),
        },
        contour: ContourSpec::default(),
        controller: ControllerSpec {
            self_pacing: r_pacing,
            h: [1.0, 1.0],
            energy,
            flywheel_inertia: 1.0,
            gamma: 50.0 / energy,
            rate: 1000.0,
            friction_compensation: compensation.then_some(PAPER_COMPENSATION),
            nominal_speed: Some(NominalSpeedSpec { c: 0.01, r }),
        },
        initial: InitialSpec::default(),
        simulation: SimulationSpec::default(),
        baseline: None,
        contact: None,
        base_dir: Default::default(),
    }
}

/// Fig. 6: unforced (`r = c = 0`), flywheel at 10 rad/s with the arm at rest (energy 50),
/// `R = 100`, friction, no compensation.
pub fn fig6() -> Scenario {
    let mut s = forced(
        "fig6_unforced",
        "Fig. 6: unforced response; energy 50 dissipates in friction, the contour is still followed, more slowly",
        100.0,
        false,
        1.0,
    );
    s.duration = 60.0;
    s.controller.energy = 50.0;
    s.controller.gamma = 1.0;
    s.controller.nominal_speed = None;
    s.initial.flywheel_speed = Some(10.0);
    s
}

/// Fig. 7: from `q = (0, 0)`, `R = 0` or `R = 100` (with compensation, `r = 1`).
pub fn fig7(r_pacing: f64) -> Scenario {
    let mut s = forced(
        &format!("fig7_R{r_pacing}"),
        "Fig. 7: approach to the contour from (0, 0) with and without self-pacing",
        r_pacing,
        true,
        1.0,
    );
    s.duration = 15.0;
    s.initial.q = [0.0, 0.0];
    s
}

/// Fig. 8: `R ∈ {0, 100, 200}` with friction compensation, `r = 1`, `c = 0.01`.
pub fn fig8(r_pacing: f64) -> Scenario {
    forced(
        &format!("fig8_R{r_pacing}"),
        "Fig. 8: self-pacing R with friction compensation, r = 1",
        r_pacing,
        true,
        1.0,
    )
}

/// Fig. 9: `R ∈ {0, 50, 100, 200}` without friction compensation.
pub fn fig9(r_pacing: f64) -> Scenario {
    forced(
        &format!("fig9_R{r_pacing}"),
        "Fig. 9: self-pacing R without friction compensation, r = 1",
        r_pacing,
        false,
        1.0,
    )
}

/// Fig. 10: `r ∈ {1, 2, 3}`, `R = 100`, without compensation.
pub fn fig10(r: f64) -> Scenario {
    forced(
        &format!("fig10_r{r}"),
        "Fig. 10: nominal speed r, R = 100, without friction compensation",
        100.0,
        false,
        r,
    )
}

/// Fig. 1: PVFC (Fig. 8's `R = 100` run) next to a timed-trajectory tracker (computed
/// torque + PD, `ω_n = 20 rad/s`, critically damped) at PVFC's mean `τ̇`, same plant.
pub fn fig1() -> Scenario {
    let mut s = fig8(100.0);
    s.name = "fig1_pvfc_vs_timed".into();
    s.description = "Fig. 1: PVFC versus a timed-trajectory tracker at the same mean speed".into();
    s.baseline = Some(BaselineSpec {
        kp: [400.0, 400.0],
        kd: [40.0, 40.0],
        tau_rate: None,
    });
    s
}

/// Frictionless runs of 60 s at 1 kHz for the energy claims: the continuous closed loop
/// (`mode = continuous`, RK4 at 1 kHz) and the sampled-data loop (1 kHz controller, plant at
/// 10 kHz).
pub fn energy_check(mode: Mode) -> Scenario {
    let mut s = fig8(100.0);
    s.name = format!(
        "energy_{}",
        match mode {
            Mode::Continuous => "continuous",
            Mode::Sampled => "sampled",
        }
    );
    s.description = "Frictionless closed loop: the augmented kinetic energy is conserved".into();
    s.duration = 60.0;
    s.plant.friction = JointFriction::default();
    s.controller.friction_compensation = None;
    s.controller.nominal_speed = None;
    s.initial.q = [0.0, 0.0];
    s.simulation.mode = mode;
    s.simulation.plant_substeps = match mode {
        Mode::Continuous => 1,
        Mode::Sampled => 10,
    };
    s
}

/// Every preset, in the order `pvfc reproduce` runs them.
pub fn all() -> Vec<Scenario> {
    let mut v = vec![fig6(), fig7(0.0), fig7(100.0)];
    v.extend([0.0, 100.0, 200.0].map(fig8));
    v.extend([0.0, 50.0, 100.0, 200.0].map(fig9));
    v.extend([1.0, 2.0, 3.0].map(fig10));
    v.push(fig1());
    v.push(energy_check(Mode::Continuous));
    v.push(energy_check(Mode::Sampled));
    v
}
