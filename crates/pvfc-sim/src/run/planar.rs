//! The paper's SCARA run: its closed-form model in free space or in its planar contact world
//! ([`Environment`]), through the loops every robot shares (`run::loops`), and its timed
//! baseline.

use crate::contact::{ContactForces, Environment, PlanarArm};
use crate::error::Result;
use crate::run::link::LinkDrive;
use crate::run::loops::{self, Surroundings};
use crate::run::path_clock::tracker_clock;
use crate::run::stepper::Stepper;
use crate::run::Tracker;
use crate::scenario::{joint_vector, BaselineSpec, Mode, Scenario};
use crate::trace::Work;
use nalgebra::Vector2;
use pvfc_core::prelude::*;

use crate::trace::{ContactTrace, Trace};

/// Runs the PVFC loop of the SCARA's scenario on its arm's model `arm` (with its `[contact]`
/// world, if it has one). `progress` is called with the fraction done.
pub fn simulate_with(
    s: &Scenario,
    arm: Scara<f64>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    simulate_on(s, arm, None, progress)
}

/// [`simulate_with`], the controller the drive across `link` if given (hardware in the loop:
/// the sampled mode only).
pub(crate) fn simulate_on(
    s: &Scenario,
    arm: Scara<f64>,
    link: Option<&mut LinkDrive<'_>>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    match (s.simulation.mode, environment_with(s, &arm)?) {
        (Mode::Sampled, None) => sampled(s, arm, &mut Free, false, link, progress),
        (Mode::Sampled, Some(mut env)) => sampled(s, arm, &mut *env, true, link, progress),
        (Mode::Continuous, _) if link.is_some() => Err(crate::error::SimError::Setting(
            "hardware in the loop: the drive runs in the sampled mode".into(),
        )),
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
    let arm = Scara::new(s.scara()?)?;
    match s.simulation.mode {
        Mode::Continuous => simulate_continuous(s, arm, env, true, progress),
        Mode::Sampled => sampled(s, arm, env, true, None, progress),
    }
}

/// The contact columns' workspace dimension when the run keeps them: with contact, or with a
/// disturbance or faults (their work is the environment's, in `work_contact`).
fn columns(s: &Scenario, with_contact: bool) -> Option<usize> {
    (with_contact || s.plant.disturbance.is_some() || !s.faults.is_empty()).then_some(2)
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
        Some(_) => environment_with(s, &Scara::new(s.scara()?)?),
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
            Err(crate::error::SimError::Setting(
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
    link: Option<&mut LinkDrive<'_>>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    // The controller has the model `arm`; the simulated arm has the scenario's model error.
    let plant = s.plant_scara(arm)?;
    // Across a line the drive's controller replaces the scenario's (none is built here).
    if let Some(drive) = link {
        return simulate_sampled(s, plant, env, true, drive, progress);
    }
    let ctl = s.controller_with(arm)?;
    match &s.controller.passive {
        None => simulate_sampled(s, plant, env, with_contact, ctl, progress),
        Some(spec) => {
            let miss = s.scara_miss_learner(&arm, spec.miss_weight())?;
            let drive = crate::run::stepper::PassiveDrive::new(ctl, spec, [true; 2], s, miss)?;
            simulate_sampled(s, plant, env, true, drive, progress)
        }
    }
}

/// The planar arm's surroundings for the generic loops ([`crate::run::loops`]): an
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

/// The SCARA's sampled-data loop ([`loops::sampled`]) with the controller `ctl` on the
/// simulated arm `arm`.
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
    loops::sampled(
        s,
        &arm,
        ctl,
        (q, v),
        &mut planar,
        columns(s, with_contact),
        progress,
    )
}

/// The SCARA's continuous-time loop ([`loops::continuous`]).
fn simulate_continuous<E: Environment + ?Sized>(
    s: &Scenario,
    arm: Scara<f64>,
    env: &mut E,
    with_contact: bool,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    // (A model error is refused here: the continuous loop integrates the controller's model.)
    s.plant_scara(arm)?;
    let ctl = s.controller_with(arm)?;
    let q = Torus::new(joint_vector::<2>(&s.initial.q, "initial.q")?);
    let v = joint_vector::<2>(&s.initial.v, "initial.v")?;
    let mut planar = Planar {
        env,
        kin: PlanarArm::from(arm),
    };
    let columns = columns(s, with_contact);
    loops::continuous(s, ctl, (q, v), &mut planar, columns, progress)
}

/// A tracker of the baseline (`tracker`) on the SCARA `arm` and its contact world.
pub fn simulate_tracker(
    s: &Scenario,
    arm: Scara<f64>,
    b: &BaselineSpec,
    tau_rate: f64,
    tracker: Tracker,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let scaled = tracker == Tracker::SpeedScaling;
    match environment_with(s, &arm)? {
        Some(mut env) => timed_in(s, arm, b, (tau_rate, scaled), Some(&mut *env), progress),
        None => timed_in(s, arm, b, (tau_rate, scaled), None, progress),
    }
}

/// The timed tracker against a given environment (or none).
pub fn simulate_timed_in(
    s: &Scenario,
    b: &BaselineSpec,
    tau_rate: f64,
    env: Option<&mut dyn Environment>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    timed_in(
        s,
        Scara::new(s.scara()?)?,
        b,
        (tau_rate, false),
        env,
        progress,
    )
}

/// [`simulate_timed_in`] with the arm's model already built.
fn timed_in(
    s: &Scenario,
    arm: Scara<f64>,
    b: &BaselineSpec,
    (tau_rate, scaled): (f64, bool),
    env: Option<&mut dyn Environment>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let with_contact = env.is_some();
    let env: &mut dyn Environment = match env {
        Some(e) => e,
        None => &mut Free,
    };
    let (clock, suffix) = tracker_clock(s, b, tau_rate, scaled)?;
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
    let limits = b.limits::<2>()?;
    let q = Torus::new(joint_vector::<2>(&s.initial.q, "initial.q")?);
    let v = joint_vector::<2>(&s.initial.v, "initial.v")?;
    let mut planar = Planar {
        env,
        kin: PlanarArm::from(arm),
    };
    let law = |(tau, tau_rate, tau_accel): (f64, f64, f64), q: &Torus<f64, 2>, v: &Vector2<f64>| {
        let [xd, dxd, ddxd] = contour.coordinates(tau);
        let (xd_v, mut xd_a) = (dxd * tau_rate, ddxd * tau_rate * tau_rate);
        if tau_accel != 0.0 {
            xd_a += dxd * tau_accel;
        }
        let e = xd - q.angles();
        let (m, c) = arm.inertia_and_coriolis(q, v);
        let mut u = m * (xd_a + (xd_v - v).component_mul(&kd) + e.component_mul(&kp)) + c * v;
        if let Some(fc) = &comp {
            u += fc.torque(v);
        }
        let err = q.compose(&Torus::new(xd).inverse());
        Ok((u, nav.value(&err)))
    };
    let columns = columns(s, with_contact);
    // The tracker's computed torque has the model `arm`; the simulated arm the model error.
    let plant = s.plant_scara(arm)?;
    loops::timed(
        s,
        &plant,
        &mut planar,
        (q, v),
        columns,
        (clock, limits, suffix),
        law,
        progress,
    )
}
