//! Running a scenario: the sampled-data or continuous PVFC loop, and the timed baseline.

use crate::contact::{ContactForces, Environment, PlanarArm};
use crate::error::{Result, SimError};
use crate::integrate::{ClosedLoop, Derivative, RK4_WEIGHTS};
use crate::run_loop::{self, Surroundings};
use crate::scenario::{joint_vector, BaselineSpec, Mode, Scenario};
use crate::series::JointSeries;
use crate::stepper::{Sample, Stepper};
use nalgebra::{SVector, Vector2};
use pvfc_core::prelude::*;

/// The time series of one run, sampled at the controller's rate.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Trace {
    /// The scenario's name (and `-timed` for the baseline).
    pub name: String,
    /// Time (s).
    pub t: Vec<f64>,
    /// Joint positions (rad, or m for prismatic joints), one row per sample.
    pub q: JointSeries,
    /// Joint velocities (rad/s, m/s).
    pub v: JointSeries,
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
    /// Motor torques (N·m, N).
    pub torque: JointSeries,
    /// Augmented kinetic energy `κ_a` (J): arm + `½τ̇²` + flywheel.
    pub energy: Vec<f64>,
    /// Power of the plant's friction on the arm, `F_fᵀq̇ ≤ 0` (W).
    pub friction_power: Vec<f64>,
    /// The contact columns, for a run with an [`Environment`].
    pub contact: Option<ContactTrace>,
}

/// The contact columns of a [`Trace`], and the work of every force on the arm, each
/// integrated by the RK4 quadrature of the state's own stages (so that
/// `energy − energy[0] − work_contact − work_friction − work_controller` is integration
/// error only: [`ContactTrace::audit_residual`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactTrace {
    /// The sum of the Cartesian contact forces on the arm (N; 2 numbers per sample for the
    /// planar arm, 3 for a URDF arm).
    pub force: JointSeries,
    /// The sum of the contact normal forces (N): the measured contact force.
    pub normal_force: Vec<f64>,
    /// The deepest penetration (m).
    pub depth: Vec<f64>,
    /// The environment's joint torques `F_e = Jᵀf` (N·m), one per joint.
    pub torque: JointSeries,
    /// The tool centre (m; 2 or 3 numbers, as `force`).
    pub tool: JointSeries,
    /// `∫ F_eᵀq̇ dt`: the work the environment did on the arm (J); its negative is the
    /// energy the arm pumped into the contact.
    pub work_contact: Vec<f64>,
    /// `∫ F_fᵀq̇ dt`: the work of the plant's joint friction (J, ≤ 0).
    pub work_friction: Vec<f64>,
    /// The work of everything in the motor torques that is not the workless PVFC coupling:
    /// the add-ons (35) and (36) for PVFC, all of `∫ uᵀq̇ dt` for the timed baseline (J).
    pub work_controller: Vec<f64>,
    /// `−∫ g(q)ᵀq̇ dt`: the work of gravity on the arm (J; 0 for the horizontal SCARA).
    pub work_gravity: Vec<f64>,
    /// The nominal speed `r` of (36) in force (scheduled on the contact force); 0 without.
    pub nominal_speed: Vec<f64>,
}

impl ContactTrace {
    /// Empty columns for `n` samples of an arm with `dof` joints in a `dim`-D workspace.
    pub(crate) fn with_capacity(n: usize, dof: usize, dim: usize) -> Self {
        ContactTrace {
            force: JointSeries::with_capacity(dim, n),
            normal_force: Vec::with_capacity(n),
            depth: Vec::with_capacity(n),
            torque: JointSeries::with_capacity(dof, n),
            tool: JointSeries::with_capacity(dim, n),
            work_contact: Vec::with_capacity(n),
            work_friction: Vec::with_capacity(n),
            work_controller: Vec::with_capacity(n),
            work_gravity: Vec::with_capacity(n),
            nominal_speed: Vec::with_capacity(n),
        }
    }

    /// One sample of the planar arm's contact.
    pub(crate) fn push(&mut self, c: &ContactForces, tool: Vector2<f64>, w: &Work, r: f64) {
        self.push_sample(
            &ContactSample {
                force: &[c.force.x, c.force.y],
                normal_force: c.normal_force,
                depth: c.depth,
                torque: c.torque.as_slice(),
                tool: &[tool.x, tool.y],
            },
            w,
            r,
        );
    }

    /// One sample: the contact, the works so far, the nominal speed in force.
    pub(crate) fn push_sample(&mut self, c: &ContactSample<'_>, w: &Work, r: f64) {
        self.force.push(c.force);
        self.normal_force.push(c.normal_force);
        self.depth.push(c.depth);
        self.torque.push(c.torque);
        self.tool.push(c.tool);
        self.work_contact.push(w.0[0]);
        self.work_friction.push(w.0[1]);
        self.work_controller.push(w.0[2]);
        self.work_gravity.push(w.0[3]);
        self.nominal_speed.push(r);
    }

    /// `true` when the arm touches something at sample `i`.
    pub fn contacts_at(&self, i: usize) -> bool {
        self.depth.get(i).is_some_and(|d| *d > 0.0)
    }

    /// The energy audit `E(t) − E(0) − W_contact − W_friction − W_controller − W_gravity` at
    /// every sample, for the trace's `energy` column `E` (`κ_a` for PVFC, the arm's kinetic
    /// energy for the baseline).
    pub fn audit_residual(&self, energy: &[f64]) -> Vec<f64> {
        let e0 = energy.first().copied().unwrap_or(0.0);
        energy
            .iter()
            .zip(&self.work_contact)
            .zip(&self.work_friction)
            .zip(&self.work_controller)
            .zip(&self.work_gravity)
            .map(|((((e, c), f), u), g)| e - e0 - c - f - u - g)
            .collect()
    }
}

/// The contact at one sample, as the trace logs it (any workspace and number of joints).
pub(crate) struct ContactSample<'a> {
    pub(crate) force: &'a [f64],
    pub(crate) normal_force: f64,
    pub(crate) depth: f64,
    pub(crate) torque: &'a [f64],
    pub(crate) tool: &'a [f64],
}

/// Works `[contact, friction, controller, gravity]` accumulated along a run.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Work(pub(crate) [f64; 4]);

impl Work {
    /// Adds one RK4 step of length `h` given the powers at its four stages.
    pub(crate) fn add(&mut self, h: f64, p: &[[f64; 4]; 4]) {
        for (w, pi) in RK4_WEIGHTS.iter().zip(p) {
            for (acc, x) in self.0.iter_mut().zip(pi) {
                *acc += h * w * x;
            }
        }
    }
}

impl Trace {
    /// An empty trace of a `dof`-joint robot named `name`, with room for `n` samples (no
    /// reallocation in the run).
    pub(crate) fn with_capacity(name: String, dof: usize, n: usize) -> Self {
        Trace {
            name,
            t: Vec::with_capacity(n),
            q: JointSeries::with_capacity(dof, n),
            v: JointSeries::with_capacity(dof, n),
            tau: Vec::with_capacity(n),
            tau_dot: Vec::with_capacity(n),
            flywheel_speed: Vec::with_capacity(n),
            beta: Vec::with_capacity(n),
            potential: Vec::with_capacity(n),
            lambda1: Vec::with_capacity(n),
            lambda2: Vec::with_capacity(n),
            torque: JointSeries::with_capacity(dof, n),
            energy: Vec::with_capacity(n),
            friction_power: Vec::with_capacity(n),
            contact: None,
        }
    }

    pub(crate) fn push(&mut self, row: Row<'_>) {
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

/// One sample of a [`Trace`] (the joint columns as slices of the robot's dimension).
pub(crate) struct Row<'a> {
    pub(crate) t: f64,
    pub(crate) q: &'a [f64],
    pub(crate) v: &'a [f64],
    pub(crate) tau: f64,
    pub(crate) tau_dot: f64,
    pub(crate) flywheel_speed: f64,
    pub(crate) beta: f64,
    pub(crate) potential: f64,
    pub(crate) lambda1: f64,
    pub(crate) lambda2: f64,
    pub(crate) torque: &'a [f64],
    pub(crate) energy: f64,
    pub(crate) friction_power: f64,
}

impl<'a> Row<'a> {
    /// The row of a sampled loop's sample: the state `(q, q̇)` and what the controller gave,
    /// with `κ_a` = the arm's kinetic energy + the controller's storage.
    pub(crate) fn of_sample<const N: usize>(
        t: f64,
        (q, v): (&'a [f64], &'a [f64]),
        out: &'a Sample<N>,
        period: f64,
        kinetic_energy: f64,
        friction_power: f64,
    ) -> Self {
        let st = out.state;
        Row {
            t,
            q,
            v,
            tau: st.unwrapped_tau(Some(period)),
            tau_dot: st.tau_dot,
            flywheel_speed: st.flywheel_speed,
            beta: out.diagnostics.beta,
            potential: out.diagnostics.potential,
            lambda1: out.diagnostics.lambda1,
            lambda2: out.diagnostics.lambda2,
            torque: out.torque.as_slice(),
            energy: kinetic_energy + out.storage,
            friction_power,
        }
    }
}

/// One RK4 step of the arm alone under the generalized force `force(i, c, q, q̇)` at the
/// stages `i = 0..4` (time offsets `c = 0, h/2, h/2, h`): motor torque, friction, contact.
/// The step is the simulation's one integrator, [`crate::integrate::rkmk4`], on `(q, q̇)`
/// with the controller's internal states held (their rates zero).
pub(crate) fn plant_rk4<G, Sys, const N: usize>(
    arm: &Sys,
    q: &G,
    v: &SVector<f64, N>,
    h: f64,
    mut force: impl FnMut(usize, f64, &G, &SVector<f64, N>) -> Result<SVector<f64, N>>,
) -> Result<(G, SVector<f64, N>)>
where
    G: LieGroup<f64, N>,
    Sys: MechanicalSystem<f64, G, N>,
{
    let mut rate =
        |i: usize, c: f64, x: &AugmentedState<f64, G, N>| -> Result<Derivative<f64, N>> {
            let u = force(i, c, &x.q, &x.v)?;
            Ok(Derivative {
                q: x.v,
                v: arm.acceleration(&x.q, &x.v, &u)?,
                tau: 0.0,
                tau_dot: 0.0,
                flywheel_speed: 0.0,
            })
        };
    let s = AugmentedState {
        q: *q,
        v: *v,
        tau: 0.0,
        tau_dot: 0.0,
        flywheel_speed: 0.0,
    };
    let k1 = rate(0, 0.0, &s)?;
    let next = crate::integrate::rkmk4(&s, &k1, h, rate)?;
    Ok((next.q, next.v))
}

/// Timing of a run: controller period, plant step, number of controller periods.
pub(crate) fn timing(s: &Scenario) -> Result<(f64, f64, usize)> {
    // Checked again here: a Scenario's fields are public and may have changed since it was
    // validated, and the trace is sized from them.
    let n = crate::scenario::run_size(s.duration, s.controller.rate, s.simulation.plant_substeps)?;
    let dt = 1.0 / s.controller.rate;
    Ok((dt, dt / s.simulation.plant_substeps as f64, n))
}

/// Runs the PVFC loop of a scenario (with its `[contact]` world, if it has one). `progress`
/// is called with the fraction done.
pub fn simulate(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Trace> {
    if s.is_chain() {
        return crate::chain_run::simulate_chain(s, progress);
    }
    // The arm is read once per run (a URDF arm's file included).
    let arm = Scara::new(s.arm()?)?;
    match (s.simulation.mode, environment_with(s, &arm)?) {
        (Mode::Sampled, None) => sampled(s, arm, &mut Free, false, progress),
        (Mode::Sampled, Some(mut env)) => sampled(s, arm, &mut *env, true, progress),
        (Mode::Continuous, None) => simulate_continuous(s, arm, &mut Free, false, progress),
        (Mode::Continuous, Some(mut env)) => simulate_continuous(s, arm, &mut *env, true, progress),
    }
}

/// Runs the PVFC loop of a scenario against a given environment (one of your own, or a
/// [`HalfPlane`](crate::contact::HalfPlane)) instead of the scenario's `[contact]` world. The
/// scenario's force schedule, if any, still applies.
pub fn simulate_in(
    s: &Scenario,
    env: &mut dyn Environment,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let arm = Scara::new(s.arm()?)?;
    match s.simulation.mode {
        Mode::Continuous => simulate_continuous(s, arm, env, true, progress),
        Mode::Sampled => sampled(s, arm, env, true, progress),
    }
}

/// Free space: no contact.
struct Free;

impl Environment for Free {
    #[inline]
    fn contact(&mut self, _: f64, _: &Torus<f64, 2>, _: &Vector2<f64>) -> Result<ContactForces> {
        Ok(ContactForces::default())
    }
}

/// The scenario's contact world, if it has a `[contact]` table.
pub fn environment(s: &Scenario) -> Result<Option<Box<dyn Environment>>> {
    match &s.contact {
        None => Ok(None),
        Some(_) => environment_with(s, &Scara::new(s.arm()?)?),
    }
}

/// [`environment`] around the arm's model already built.
fn environment_with(s: &Scenario, arm: &Scara<f64>) -> Result<Option<Box<dyn Environment>>> {
    match &s.contact {
        None => Ok(None),
        #[cfg(feature = "contact")]
        Some(spec) => Ok(Some(Box::new(crate::contact::ContactWorld::new(
            spec,
            arm.parameters(),
        )?))),
        #[cfg(not(feature = "contact"))]
        Some(_) => {
            let _ = arm;
            Err(SimError::Setting(
                "the scenario has a [contact] table, but pvfc-sim was built without its `contact` feature".into(),
            ))
        }
    }
}

/// The sampled-data loop with the scenario's controller: `Controller::step` (zero-order
/// hold), or the passive digital controller of `[controller.passive]`, whose runs always carry
/// the work columns (with no contact they hold the audit).
fn sampled<E: Environment + ?Sized>(
    s: &Scenario,
    arm: Scara<f64>,
    env: &mut E,
    with_contact: bool,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let ctl = s.controller_with(arm)?;
    match &s.controller.passive {
        None => simulate_sampled(s, arm, env, with_contact, ctl, progress),
        Some(spec) => {
            let drive = crate::stepper::PassiveDrive::new(ctl, spec, [true; 2])?;
            simulate_sampled(s, arm, env, true, drive, progress)
        }
    }
}

/// The planar arm's surroundings for the generic loops ([`crate::run_loop`]): an
/// [`Environment`], and the arm's kinematics for the tool's position in the log.
struct Planar<'a, E: ?Sized> {
    env: &'a mut E,
    kin: PlanarArm,
}

impl<E: Environment + ?Sized> Surroundings<Torus<f64, 2>, 2> for Planar<'_, E> {
    type Contact = ContactForces;

    fn contact(&mut self, t: f64, q: &Torus<f64, 2>, v: &Vector2<f64>) -> Result<ContactForces> {
        self.env.contact(t, q, v)
    }

    fn torque(c: &ContactForces) -> Vector2<f64> {
        c.torque
    }

    fn normal_force(c: &ContactForces) -> f64 {
        c.normal_force
    }

    fn log(
        &self,
        ct: &mut ContactTrace,
        q: &Torus<f64, 2>,
        c: &ContactForces,
        work: &Work,
        nominal_speed: f64,
    ) -> Result<()> {
        ct.push(c, self.kin.tip(q), work, nominal_speed);
        Ok(())
    }
}

/// The SCARA's sampled-data loop ([`run_loop::sampled`]) with the controller `ctl`.
fn simulate_sampled<E: Environment + ?Sized, S: Stepper<Torus<f64, 2>, 2>>(
    s: &Scenario,
    arm: Scara<f64>,
    env: &mut E,
    with_contact: bool,
    ctl: S,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let q = Torus::new(joint_vector::<2>(&s.initial.q, "initial.q")?);
    let v = joint_vector::<2>(&s.initial.v, "initial.v")?;
    let mut planar = Planar {
        env,
        kin: PlanarArm::from(arm),
    };
    run_loop::sampled(
        s,
        &arm,
        ctl,
        (q, v),
        &mut planar,
        with_contact.then_some(2),
        progress,
    )
}

/// The SCARA's continuous-time loop ([`run_loop::continuous`]).
fn simulate_continuous<E: Environment + ?Sized>(
    s: &Scenario,
    arm: Scara<f64>,
    env: &mut E,
    with_contact: bool,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let ctl = s.controller_with(arm)?;
    let sys = ClosedLoop {
        plant: arm,
        controller: ctl,
    };
    let i = ctl.state();
    let st = AugmentedState {
        q: Torus::new(joint_vector::<2>(&s.initial.q, "initial.q")?),
        v: joint_vector::<2>(&s.initial.v, "initial.v")?,
        tau: i.tau,
        tau_dot: i.tau_dot,
        flywheel_speed: i.flywheel_speed,
    };
    let mut planar = Planar {
        env,
        kin: PlanarArm::from(arm),
    };
    run_loop::continuous(s, sys, st, &mut planar, with_contact.then_some(2), progress)
}

/// The timed-trajectory baseline of Fig. 1: computed torque + PD tracking `x_d(τ(t))` with
/// `τ(t) = τ₀ + rate·t`, on the same plant and friction (and the same friction compensation
/// as the scenario's controller, if any):
/// `T = M(q)(ẍ_d + K_d(ẋ_d − q̇) + K_p(x_d − q)) + C(q, q̇) q̇`.
///
/// With a `[contact]` table, the baseline runs against the same contact world, and its trace
/// has the contact columns.
pub fn simulate_timed(
    s: &Scenario,
    b: &BaselineSpec,
    tau_rate: f64,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    if s.is_chain() {
        return crate::chain_run::simulate_timed_chain(s, b, tau_rate, progress);
    }
    let arm = Scara::new(s.arm()?)?;
    match environment_with(s, &arm)? {
        Some(mut env) => timed_in(s, arm, b, tau_rate, Some(&mut *env), progress),
        None => timed_in(s, arm, b, tau_rate, None, progress),
    }
}

/// [`simulate_timed`] against a given environment (or none).
pub fn simulate_timed_in(
    s: &Scenario,
    b: &BaselineSpec,
    tau_rate: f64,
    env: Option<&mut dyn Environment>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    timed_in(s, Scara::new(s.arm()?)?, b, tau_rate, env, progress)
}

/// [`simulate_timed_in`] with the arm's model already built.
fn timed_in(
    s: &Scenario,
    arm: Scara<f64>,
    b: &BaselineSpec,
    tau_rate: f64,
    env: Option<&mut dyn Environment>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let with_contact = env.is_some();
    let env: &mut dyn Environment = match env {
        Some(e) => e,
        None => &mut Free,
    };
    if !tau_rate.is_finite() {
        return Err(SimError::Setting("baseline: τ rate must be finite".into()));
    }
    let contour = s.contour()?;
    let nav = TorusNavigation::paper(joint_vector::<2>(&s.controller.h, "controller.h")?)?;
    let comp = match &s.controller.friction_compensation {
        Some(f) => Some(FrictionCompensation::new(joint_vector::<2>(
            f,
            "controller.friction_compensation",
        )?)?),
        None => None,
    };
    let (kp, kd) = (
        joint_vector::<2>(&b.kp, "baseline.kp")?,
        joint_vector::<2>(&b.kd, "baseline.kd")?,
    );
    let q = Torus::new(joint_vector::<2>(&s.initial.q, "initial.q")?);
    let v = joint_vector::<2>(&s.initial.v, "initial.v")?;
    let mut planar = Planar {
        env,
        kin: PlanarArm::from(arm),
    };
    let law = |tau: f64, q: &Torus<f64, 2>, v: &Vector2<f64>| {
        let [xd, dxd, ddxd] = contour.coordinates(tau);
        let (xd_v, xd_a) = (dxd * tau_rate, ddxd * tau_rate * tau_rate);
        let e = xd - q.angles();
        let (m, c) = arm.inertia_and_coriolis(q, v);
        let mut u = m * (xd_a + (xd_v - v).component_mul(&kd) + e.component_mul(&kp)) + c * v;
        if let Some(fc) = &comp {
            u += fc.torque(v);
        }
        let err = q.compose(&Torus::new(xd).inverse());
        Ok((u, nav.value(&err)))
    };
    let columns = with_contact.then_some(2);
    run_loop::timed(
        s,
        &arm,
        &mut planar,
        (q, v),
        columns,
        tau_rate,
        law,
        progress,
    )
}
