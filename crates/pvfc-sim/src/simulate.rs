//! Running a scenario: the sampled-data or continuous PVFC loop, and the timed baseline.

use crate::error::{Result, SimError};
use crate::friction::JointFriction;
use crate::integrate::ClosedLoop;
use crate::scenario::{BaselineSpec, Mode, Scenario};
use nalgebra::Vector2;
use pvfc_core::prelude::*;

/// The time series of one run, sampled at the controller's rate.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// The scenario's name (and `-timed` for the baseline).
    pub name: String,
    /// Time (s).
    pub t: Vec<f64>,
    /// Joint angles (rad).
    pub q: Vec<[f64; 2]>,
    /// Joint velocities (rad/s).
    pub v: Vec<[f64; 2]>,
    /// Contour parameter, unwrapped.
    pub tau: Vec<f64>,
    /// Its rate.
    pub tau_dot: Vec<f64>,
    /// Flywheel speed (rad/s; 0 for the baseline).
    pub flywheel_speed: Vec<f64>,
    /// `β = √(κ_a/Ē)`.
    pub beta: Vec<f64>,
    /// `U(E)` of eq. (17).
    pub potential: Vec<f64>,
    /// Self-pacing gain `λ₁`.
    pub lambda1: Vec<f64>,
    /// Self-pacing gain `λ₂`.
    pub lambda2: Vec<f64>,
    /// Motor torques (N·m).
    pub torque: Vec<[f64; 2]>,
    /// Augmented kinetic energy `κ_a` (J): arm + `½τ̇²` + flywheel.
    pub energy: Vec<f64>,
    /// Power of the plant's friction on the arm, `F_fᵀq̇ ≤ 0` (W).
    pub friction_power: Vec<f64>,
}

impl Trace {
    /// An empty trace named `name`, with room for `n` samples (no reallocation in the run).
    fn with_capacity(name: String, n: usize) -> Self {
        Trace {
            name,
            t: Vec::with_capacity(n),
            q: Vec::with_capacity(n),
            v: Vec::with_capacity(n),
            tau: Vec::with_capacity(n),
            tau_dot: Vec::with_capacity(n),
            flywheel_speed: Vec::with_capacity(n),
            beta: Vec::with_capacity(n),
            potential: Vec::with_capacity(n),
            lambda1: Vec::with_capacity(n),
            lambda2: Vec::with_capacity(n),
            torque: Vec::with_capacity(n),
            energy: Vec::with_capacity(n),
            friction_power: Vec::with_capacity(n),
        }
    }

    fn push(&mut self, row: Row) {
        self.t.push(row.t);
        self.q.push(row.q);
        self.v.push(row.v);
        self.tau.push(row.tau);
        self.tau_dot.push(row.tau_dot);
        self.flywheel_speed.push(row.flywheel_speed);
        self.beta.push(row.beta);
        self.potential.push(row.potential);
        self.lambda1.push(row.lambda1);
        self.lambda2.push(row.lambda2);
        self.torque.push(row.torque);
        self.energy.push(row.energy);
        self.friction_power.push(row.friction_power);
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// `true` when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}

struct Row {
    t: f64,
    q: [f64; 2],
    v: [f64; 2],
    tau: f64,
    tau_dot: f64,
    flywheel_speed: f64,
    beta: f64,
    potential: f64,
    lambda1: f64,
    lambda2: f64,
    torque: [f64; 2],
    energy: f64,
    friction_power: f64,
}

/// One RK4 step of the arm alone under a held motor torque and the friction.
fn plant_step(
    arm: &Scara<f64>,
    friction: &JointFriction,
    q: &Torus<f64, 2>,
    v: &Vector2<f64>,
    u: &Vector2<f64>,
    h: f64,
) -> Result<(Torus<f64, 2>, Vector2<f64>)> {
    let f = |q: &Torus<f64, 2>, v: &Vector2<f64>| arm.acceleration(q, v, &(u + friction.torque(v)));
    let a1 = f(q, v)?;
    let (q2, v2) = (q.retract(v, 0.5 * h), v + a1 * (0.5 * h));
    let a2 = f(&q2, &v2)?;
    let (q3, v3) = (q.retract(&v2, 0.5 * h), v + a2 * (0.5 * h));
    let a3 = f(&q3, &v3)?;
    let (q4, v4) = (q.retract(&v3, h), v + a3 * h);
    let a4 = f(&q4, &v4)?;
    let qn = q.retract(&((v + v2 * 2.0 + v3 * 2.0 + v4) / 6.0), h);
    let vn = v + (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0);
    Ok((qn, vn))
}

/// Timing of a run: controller period, plant step, number of controller periods.
fn timing(s: &Scenario) -> Result<(f64, f64, usize)> {
    let dt = 1.0 / s.controller.rate;
    let n = (s.duration * s.controller.rate).round() as usize;
    if n == 0 {
        return Err(SimError::Setting(
            "duration shorter than one controller period".into(),
        ));
    }
    Ok((dt, dt / s.simulation.plant_substeps as f64, n))
}

/// Runs the PVFC loop of a scenario. `progress` is called with the fraction done.
pub fn simulate(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Trace> {
    match s.simulation.mode {
        Mode::Sampled => simulate_sampled(s, progress),
        Mode::Continuous => simulate_continuous(s, progress),
    }
}

fn simulate_sampled(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Trace> {
    let mut ctl = s.controller()?;
    let arm = Scara::new(s.arm()?)?;
    let friction = s.plant.friction;
    let (dt, h, n) = timing(s)?;
    let period = s.contour.period;
    let mf = s.controller.flywheel_inertia;
    let mut q = Torus::new(Vector2::from(s.initial.q));
    let mut v = Vector2::from(s.initial.v);
    let mut trace = Trace::with_capacity(s.name.clone(), n + 1);
    for k in 0..=n {
        let out = ctl.step(&q, &v, dt)?;
        let st = out.state;
        trace.push(Row {
            t: k as f64 * dt,
            q: [q.angles()[0], q.angles()[1]],
            v: [v[0], v[1]],
            tau: st.unwrapped_tau(Some(period)),
            tau_dot: st.tau_dot,
            flywheel_speed: st.flywheel_speed,
            beta: out.diagnostics.beta,
            potential: out.diagnostics.potential,
            lambda1: out.diagnostics.lambda1,
            lambda2: out.diagnostics.lambda2,
            torque: [out.torque[0], out.torque[1]],
            energy: arm.kinetic_energy(&q, &v)
                + 0.5 * (st.tau_dot * st.tau_dot + mf * st.flywheel_speed * st.flywheel_speed),
            friction_power: friction.torque(&v).dot(&v),
        });
        if k == n {
            break;
        }
        for _ in 0..s.simulation.plant_substeps {
            (q, v) = plant_step(&arm, &friction, &q, &v, &out.torque, h)?;
        }
        if k % 1000 == 0 {
            progress(k as f64 / n as f64);
        }
    }
    progress(1.0);
    Ok(trace)
}

fn simulate_continuous(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Trace> {
    let ctl = s.controller()?;
    let arm = Scara::new(s.arm()?)?;
    let friction = s.plant.friction;
    let (dt, h, n) = timing(s)?;
    let sys = ClosedLoop {
        plant: arm,
        controller: ctl,
    };
    let i = ctl.state();
    let mut st = AugmentedState {
        q: Torus::new(Vector2::from(s.initial.q)),
        v: Vector2::from(s.initial.v),
        tau: i.tau,
        tau_dot: i.tau_dot,
        flywheel_speed: i.flywheel_speed,
    };
    let force = |a: &AugmentedState<f64, Torus<f64, 2>, 2>| friction.torque(&a.v);
    let mut trace = Trace::with_capacity(s.name.clone(), n + 1);
    for k in 0..=n {
        let ev = sys.evaluate(&st, &force(&st))?;
        let c = &ev.coupling;
        trace.push(Row {
            t: k as f64 * dt,
            q: [st.q.angles()[0], st.q.angles()[1]],
            v: [st.v[0], st.v[1]],
            tau: st.tau,
            tau_dot: st.tau_dot,
            flywheel_speed: st.flywheel_speed,
            beta: c.beta,
            potential: c.field.potential,
            lambda1: c.field.lambda1,
            lambda2: c.field.lambda2,
            torque: [ev.torque.robot[0], ev.torque.robot[1]],
            energy: sys.kinetic_energy(&st),
            friction_power: force(&st).dot(&st.v),
        });
        if k == n {
            break;
        }
        st = sys.rk4_from(&st, &ev.derivative, h, force)?;
        for _ in 1..s.simulation.plant_substeps {
            st = sys.rk4_step_with(&st, h, force)?;
        }
        if k % 1000 == 0 {
            progress(k as f64 / n as f64);
        }
    }
    progress(1.0);
    Ok(trace)
}

/// The timed-trajectory baseline of Fig. 1: computed torque + PD tracking `x_d(τ(t))` with
/// `τ(t) = τ₀ + rate·t`, on the same plant and friction (and the same friction compensation
/// as the scenario's controller, if any):
/// `T = M(q)(ẍ_d + K_d(ẋ_d − q̇) + K_p(x_d − q)) + C(q, q̇) q̇`.
pub fn simulate_timed(
    s: &Scenario,
    b: &BaselineSpec,
    tau_rate: f64,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    if !tau_rate.is_finite() {
        return Err(SimError::Setting("baseline: τ rate must be finite".into()));
    }
    let arm = Scara::new(s.arm()?)?;
    let friction = s.plant.friction;
    let contour = s.contour()?;
    let nav = TorusNavigation::paper(Vector2::from(s.controller.h))?;
    let comp = s
        .controller
        .friction_compensation
        .map(|f| FrictionCompensation::new(Vector2::from(f)))
        .transpose()?;
    let (dt, h, n) = timing(s)?;
    let (kp, kd) = (Vector2::from(b.kp), Vector2::from(b.kd));
    let mut q = Torus::new(Vector2::from(s.initial.q));
    let mut v = Vector2::from(s.initial.v);
    let mut trace = Trace::with_capacity(format!("{}-timed", s.name), n + 1);
    for k in 0..=n {
        let t = k as f64 * dt;
        let tau = s.initial.tau + tau_rate * t;
        let [xd, dxd, ddxd] = contour.coordinates(tau);
        let (xd_v, xd_a) = (dxd * tau_rate, ddxd * tau_rate * tau_rate);
        let e = xd - q.angles();
        let (m, c) = arm.inertia_and_coriolis(&q, &v);
        let mut u = m * (xd_a + (xd_v - v).component_mul(&kd) + e.component_mul(&kp)) + c * v;
        if let Some(fc) = &comp {
            u += fc.torque(&v);
        }
        let err = q.compose(&Torus::new(xd).inverse());
        trace.push(Row {
            t,
            q: [q.angles()[0], q.angles()[1]],
            v: [v[0], v[1]],
            tau,
            tau_dot: tau_rate,
            flywheel_speed: 0.0,
            beta: 0.0,
            potential: nav.value(&err),
            lambda1: 1.0,
            lambda2: 1.0,
            torque: [u[0], u[1]],
            energy: arm.kinetic_energy(&q, &v),
            friction_power: friction.torque(&v).dot(&v),
        });
        if k == n {
            break;
        }
        for _ in 0..s.simulation.plant_substeps {
            (q, v) = plant_step(&arm, &friction, &q, &v, &u, h)?;
        }
        if k % 1000 == 0 {
            progress(k as f64 / n as f64);
        }
    }
    progress(1.0);
    Ok(trace)
}
