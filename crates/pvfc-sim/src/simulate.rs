//! Running a scenario: the sampled-data or continuous PVFC loop, and the timed baseline.

use crate::arm::ArmSystem;
use crate::contact::{ContactForces, Environment, PlanarArm};
use crate::error::{Result, SimError};
use crate::integrate::{ClosedLoop, Derivative};
use crate::run_loop::{self, Surroundings};
use crate::scenario::{joint_vector, BaselineSpec, Mode, Scenario};
use crate::stepper::Stepper;
use crate::trace::Work;
use nalgebra::{SVector, Vector2};
use pvfc_core::prelude::*;

pub use crate::trace::{ContactTrace, Trace};

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

/// Runs one scenario: the PVFC loop, and the timed baseline if the scenario asks for one
/// (at PVFC's mean `τ̇` over its last 12 s unless the scenario fixes the rate).
pub fn run_scenario(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Vec<Trace>> {
    let system = if s.is_chain() {
        Some(ArmSystem::build(s)?)
    } else {
        None
    };
    run_scenario_with(s, system.as_ref(), progress)
}

/// [`run_scenario`] with a URDF arm's system already built (`None` for the SCARA): the URDF
/// is read and a Cartesian path solved once for both runs.
pub fn run_scenario_with(
    s: &Scenario,
    system: Option<&ArmSystem>,
    progress: &mut dyn FnMut(f64),
) -> Result<Vec<Trace>> {
    let pvfc = match system {
        Some(sys) => crate::chain_run::simulate_chain_with(s, sys, progress)?,
        None => simulate(s, progress)?,
    };
    let mut out = vec![];
    if let Some(b) = &s.baseline {
        let rate = match b.tau_rate {
            Some(r) => r,
            None => {
                let n = pvfc.len() - 1;
                let from = pvfc
                    .t
                    .iter()
                    .position(|&t| t >= pvfc.t[n] - 12.0)
                    .unwrap_or(0);
                (pvfc.tau[n] - pvfc.tau[from]) / (pvfc.t[n] - pvfc.t[from]).max(f64::EPSILON)
            }
        };
        out.push(match system {
            Some(sys) => crate::chain_run::simulate_timed_chain_with(s, sys, b, rate, &mut |_| {})?,
            None => simulate_timed(s, b, rate, &mut |_| {})?,
        });
    }
    out.insert(0, pvfc);
    Ok(out)
}
