//! Running a scenario of a serial arm read from a URDF (`kind = "serial_chain"`): the sampled-data
//! or continuous PVFC loop for any number of joints (1 to 8), with gravity in the plant,
//! joint friction, the controller's gravity and friction compensation and the 3-D contact,
//! through the same generic loops as the SCARA (the crate-private `run_loop`); and the timed
//! baseline.

use crate::contact::spatial::SpatialContact;
use crate::error::{Result, SimError};
use crate::model::arm::{arm_controller, arm_miss_learner, ArmControllerN};
use crate::model::pace::PathSpeed;
use crate::run::link::LinkDrive;
use crate::run::loops::{self, Surroundings};
use crate::run::path_clock::{tracker_clock, PathClock};
use crate::run::stepper::PassiveDrive;
use crate::run::Tracker;
use crate::scenario::ArmSystem;
use crate::scenario::{joint_vector, BaselineSpec, Mode, Scenario};
use crate::trace::{ContactSample, ContactTrace, Trace, Work};
use crate::with_dof;
use nalgebra::SVector;
use pvfc_core::prelude::*;

/// Runs the PVFC loop of a URDF arm's scenario on its system. `progress` is called with the
/// fraction done.
pub fn simulate_chain_with(
    s: &Scenario,
    system: &ArmSystem,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    simulate_chain_on(s, system, None, progress)
}

/// [`simulate_chain_with`], the controller the drive across `link` if given (hardware in the
/// loop: the sampled mode, revolute joints).
pub(crate) fn simulate_chain_on(
    s: &Scenario,
    system: &ArmSystem,
    mut link: Option<&mut LinkDrive<'_>>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let robot = &system.robot;
    with_dof!(robot.dof(), N => {
        let chain = SerialChain::<f64, N>::try_from(robot.model())?;
        let plant = SerialChain::<f64, N>::try_from(system.plant.model())?;
        run::<N>(s, (chain, plant), system, link.take(), progress)
    }, otherwise Err(SimError::Setting(format!(
        "robot {}: {} joints; pvfc supports 1 to 8", robot.description().name, robot.dof()
    ))))
}

/// `chain`: the controller's model; `plant`: the simulated arm (the same chain, or it with
/// the scenario's model error).
fn run<const N: usize>(
    s: &Scenario,
    (chain, plant): (SerialChain<f64, N>, SerialChain<f64, N>),
    system: &ArmSystem,
    link: Option<&mut LinkDrive<'_>>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let (q, v) = initial_state(s, &chain)?;
    let mut env = Spatial::of(s, system, &plant)?;
    let columns = env.columns();
    // Across a line the drive's controller replaces the scenario's (none is built here).
    if let Some(drive) = link {
        if s.simulation.mode != Mode::Sampled
            || chain.kinds().iter().any(|k| *k != JointKind::Circular)
        {
            return Err(SimError::Setting(
                "hardware in the loop: the drive runs in the sampled mode and reads encoders on revolute joints".into(),
            ));
        }
        return loops::sampled(s, &plant, drive, (q, v), &mut env, columns, progress);
    }
    let base: ArmControllerN<N> = arm_controller(chain, &system.settings)?;
    let initial = s.initial_internal(base.law().flywheel());
    let ctl = base.with_state(initial);
    match s.simulation.mode {
        Mode::Sampled => match &s.controller.passive {
            None => loops::sampled(s, &plant, ctl, (q, v), &mut env, columns, progress),
            Some(spec) => {
                let circular = chain.kinds().map(|k| k == JointKind::Circular);
                let miss = arm_miss_learner::<N>(spec.miss_weight(), &ctl, &system.settings)?;
                let drive = PassiveDrive::new(ctl, spec, circular, s, miss)?;
                loops::sampled(s, &plant, drive, (q, v), &mut env, columns, progress)
            }
        },
        Mode::Continuous => loops::continuous(s, ctl, (q, v), &mut env, columns, progress),
    }
}

/// A tracker of the baseline for a URDF arm (`tracker`; the speed-scaling one's path time
/// slows while a commanded torque nears its limit, its trace `NAME-scaled`). The timed one: computed torque + PD tracking `x_d(τ(t))`,
/// `τ(t) = τ₀ + rate·t`, with gravity compensation,
/// `T = M(q)(ẍ_d + K_d(ẋ_d − q̇) + K_p(x_d − q)) + C(q, q̇) q̇ + g(q)` (+ the scenario's
/// friction compensation), on the same plant, friction and 3-D contact, held for each
/// controller period.
pub fn simulate_tracker(
    s: &Scenario,
    system: &ArmSystem,
    b: &BaselineSpec,
    tau_rate: f64,
    tracker: Tracker,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    tracker_run(
        s,
        system,
        b,
        (tau_rate, tracker == Tracker::SpeedScaling),
        progress,
    )
}

fn tracker_run(
    s: &Scenario,
    system: &ArmSystem,
    b: &BaselineSpec,
    (tau_rate, scaled): (f64, bool),
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let clock = tracker_clock(s, b, tau_rate, scaled)?;
    let robot = &system.robot;
    with_dof!(robot.dof(), N => {
        let chain = SerialChain::<f64, N>::try_from(robot.model())?;
        let plant = SerialChain::<f64, N>::try_from(system.plant.model())?;
        timed::<N>(s, b, clock, (chain, plant), system, progress)
    }, otherwise Err(SimError::Setting(format!(
        "robot {}: {} joints; pvfc supports 1 to 8", robot.description().name, robot.dof()
    ))))
}

fn timed<const N: usize>(
    s: &Scenario,
    b: &BaselineSpec,
    (clock, suffix): (PathClock, &str),
    (chain, plant): (SerialChain<f64, N>, SerialChain<f64, N>),
    system: &ArmSystem,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let settings = &system.settings;
    let ctl: ArmControllerN<N> = arm_controller(chain, settings)?;
    let contour = ctl.law().field().joint_contour();
    // A part program's tracker follows its feeds (the rates they ask for, not bounded by the
    // drives: what a user programs), unless the baseline fixes its rate.
    let clock = match (&settings.pace, b.tau_rate) {
        (Some(pace), None) if matches!(pace.speed, Some(PathSpeed::Feeds(_))) => {
            let period = settings.contour.period().ok_or_else(|| {
                SimError::Setting("a part program's feeds need a closed contour".into())
            })?;
            clock.following(pace.asked_profile(&chain, contour, period)?, pace.level)
        }
        _ => clock,
    };
    // U of the joint error, as for the joint-space field (the timed tracker follows the joint
    // contour whichever field PVFC uses).
    let navigation = JointNavigation::new(
        joint_vector::<N>(&settings.h, "controller.h")?,
        chain.kinds(),
    )?;
    let comp = match &settings.friction_compensation {
        Some(f) => Some(
            FrictionCompensation::new(joint_vector::<N>(f, "controller.friction_compensation")?)?
                .with_band(settings.friction_band)?,
        ),
        None => None,
    };
    let (kp, kd) = (
        joint_vector::<N>(&b.kp, "baseline.kp")?,
        joint_vector::<N>(&b.kd, "baseline.kd")?,
    );
    let limits = b.limits::<N>()?;
    let (q, v) = initial_state(s, &chain)?;
    let mut env = Spatial::of(s, system, &plant)?;
    let columns = env.columns();
    let law = |(tau, tau_rate, tau_accel): (f64, f64, f64),
               q: &JointSpace<f64, N>,
               v: &SVector<f64, N>| {
        let xd = contour.sample(tau);
        let (xd_v, mut xd_a) = (
            xd.velocity * tau_rate,
            xd.acceleration * (tau_rate * tau_rate),
        );
        if tau_accel != 0.0 {
            xd_a += xd.velocity * tau_accel;
        }
        let e = xd.point.coords() - q.coords();
        let (m, c) = chain.inertia_and_coriolis(q, v);
        let mut u = m * (xd_a + (xd_v - v).component_mul(&kd) + e.component_mul(&kp))
            + c * v
            + chain.gravity(q);
        if let Some(fc) = &comp {
            u += fc.torque(v);
        }
        let err = q.compose(&xd.point.inverse());
        Ok((u, navigation.value(&err)))
    };
    loops::timed(
        s,
        &plant,
        &mut env,
        (q, v),
        columns,
        (clock, limits, suffix),
        law,
        progress,
    )
}

/// The scenario's initial `(q, q̇)` on the chain's joint space.
fn initial_state<const N: usize>(
    s: &Scenario,
    chain: &SerialChain<f64, N>,
) -> Result<(JointSpace<f64, N>, SVector<f64, N>)> {
    let q = joint_vector::<N>(&s.initial.q, "initial.q")?;
    Ok((
        JointSpace::new(q, chain.kinds()),
        joint_vector::<N>(&s.initial.v, "initial.v")?,
    ))
}

/// A chain run's 3-D contact world, if the scenario has a `[contact_3d]` table.
struct Contact {
    #[cfg(feature = "contact")]
    world: crate::contact::spatial::SpatialWorld,
}

impl Contact {
    fn of(s: &Scenario, robot: &crate::model::robot::Robot) -> Result<Option<Self>> {
        match &s.contact_3d {
            None => Ok(None),
            #[cfg(feature = "contact")]
            // Obstacles in the part's frame go where the part is.
            Some(_) => match s.contact_3d_in_base_frame()? {
                Some(spec) => Ok(Some(Contact {
                    world: crate::contact::spatial::SpatialWorld::new_in(
                        &spec,
                        robot,
                        &s.base_dir,
                    )?,
                })),
                None => Ok(None),
            },
            #[cfg(not(feature = "contact"))]
            Some(_) => {
                let _ = robot;
                Err(SimError::Setting(
                    "the scenario has a [contact_3d] table, but pvfc-sim was built without its `contact` feature".into(),
                ))
            }
        }
    }

    /// The contact torque `F_e` on the arm at `(q, q̇)`, and what the log keeps of it.
    fn forces<const N: usize>(
        &self,
        t: f64,
        q: &JointSpace<f64, N>,
        v: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SpatialContact)> {
        #[cfg(feature = "contact")]
        {
            let c = self.world.contact(t, q.coords().as_slice(), v.as_slice())?;
            Ok((SVector::from_column_slice(&c.torque), c))
        }
        #[cfg(not(feature = "contact"))]
        {
            let _ = (t, q, v);
            Ok((SVector::zeros(), SpatialContact::default()))
        }
    }
}

/// One sample of the contact columns of a URDF arm at `q` (the contact `c`, zero without a
/// world).
fn log_sample<const N: usize>(
    ct: &mut ContactTrace,
    chain: &SerialChain<f64, N>,
    q: &JointSpace<f64, N>,
    c: &SpatialContact,
    work: &Work,
    nominal_speed: f64,
) {
    let tool = chain.kinematics(q.coords()).link_poses[N - 1]
        .compose(chain.tool())
        .translation;
    let torque = if c.torque.len() == N {
        c.torque.clone()
    } else {
        vec![0.0; N]
    };
    ct.push_sample(
        &ContactSample {
            force: c.force.as_slice(),
            normal_force: c.normal_force,
            depth: c.depth,
            torque: &torque,
            tool: tool.as_slice(),
        },
        work,
        nominal_speed,
    );
}

/// A URDF arm's surroundings for the generic loops ([`crate::run::loops`]): its 3-D contact
/// world, if any, whether a disturbance acts, and the chain for the tool's position in the
/// log.
struct Spatial<'a, const N: usize> {
    world: Option<Contact>,
    disturbed: bool,
    chain: &'a SerialChain<f64, N>,
}

impl<'a, const N: usize> Spatial<'a, N> {
    /// The surroundings of scenario `s`'s arm: its `[contact_3d]` world, if any.
    fn of(s: &Scenario, system: &ArmSystem, chain: &'a SerialChain<f64, N>) -> Result<Self> {
        Ok(Spatial {
            world: Contact::of(s, &system.robot)?,
            // An impact is the environment's too; every run with faults keeps the audit.
            disturbed: s.plant.disturbance.is_some() || !s.faults.is_empty(),
            chain,
        })
    }

    /// The contact columns' workspace dimension when the run keeps them: with a world, or
    /// with a disturbance or faults (their work is the environment's, in `work_contact`, and
    /// the audit says whether the faults made the controller create energy).
    fn columns(&self) -> Option<usize> {
        (self.world.is_some() || self.disturbed).then_some(3)
    }
}

impl<const N: usize> Surroundings<JointSpace<f64, N>, N> for Spatial<'_, N> {
    type Contact = (SVector<f64, N>, SpatialContact);

    fn contact(
        &mut self,
        t: f64,
        q: &JointSpace<f64, N>,
        v: &SVector<f64, N>,
    ) -> Result<Self::Contact> {
        match &self.world {
            Some(w) => w.forces(t, q, v),
            None => Ok((SVector::zeros(), SpatialContact::default())),
        }
    }

    fn torque(c: &Self::Contact) -> SVector<f64, N> {
        c.0
    }

    fn normal_force(c: &Self::Contact) -> f64 {
        c.1.normal_force
    }

    fn log(
        &self,
        ct: &mut ContactTrace,
        q: &JointSpace<f64, N>,
        c: &Self::Contact,
        work: &Work,
        nominal_speed: f64,
    ) -> Result<()> {
        log_sample(ct, self.chain, q, &c.1, work, nominal_speed);
        Ok(())
    }
}
