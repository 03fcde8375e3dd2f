//! Running a scenario of a serial arm read from a URDF (`[plant] urdf = …`): the sampled-data
//! or continuous PVFC loop for any number of joints (1 to 8), with gravity in the plant,
//! joint friction, and the controller's gravity and friction compensation.

use crate::arm::{arm_controller, ArmControllerN, ArmField, ArmSystem};
use crate::contact::spatial::SpatialContact;
use crate::error::{Result, SimError};
use crate::friction::JointFriction;
use crate::integrate::{ClosedLoop, Derivative};
use crate::scenario::{joint_vector, BaselineSpec, Mode, Scenario};
use crate::simulate::{plant_rk4, timing, ContactSample, ContactTrace, Row, Trace, Work};
use crate::stepper::{PassiveDrive, Stepper};
use crate::with_dof;
use nalgebra::SVector;
use pvfc_core::augmented::AugmentedState;
use pvfc_core::prelude::*;

/// Runs the PVFC loop of a URDF arm's scenario. `progress` is called with the fraction done.
pub fn simulate_chain(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Trace> {
    simulate_chain_with(s, &ArmSystem::build(s)?, progress)
}

/// [`simulate_chain`] with the scenario's system already built.
pub fn simulate_chain_with(
    s: &Scenario,
    system: &ArmSystem,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let robot = &system.robot;
    with_dof!(robot.dof(), N => {
        let chain = SerialChain::<f64, N>::try_from(robot.model())?;
        run::<N>(s, chain, system, progress)
    }, otherwise Err(SimError::Setting(format!(
        "robot {}: {} joints; pvfc supports 1 to 8", robot.description().name, robot.dof()
    ))))
}

fn run<const N: usize>(
    s: &Scenario,
    chain: SerialChain<f64, N>,
    system: &ArmSystem,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let base: ArmControllerN<N> = arm_controller(chain, &system.settings)?;
    let flywheel = *base.law().flywheel();
    let ctl = base.with_state(InternalState {
        tau: s.initial.tau,
        tau_dot: s.initial.tau_dot,
        flywheel_speed: s
            .initial
            .flywheel_speed
            .unwrap_or_else(|| flywheel.speed_for_unit_beta()),
        laps: 0,
    });
    let friction = s.plant.friction.clone();
    let (dt, h, n) = timing(s)?;
    let kinds = chain.kinds();
    let q = JointSpace::new(joint_vector::<N>(&s.initial.q, "initial.q")?, kinds);
    let v = joint_vector::<N>(&s.initial.v, "initial.v")?;
    let mut trace = Trace::with_capacity(s.name.clone(), N, n + 1);
    let mut world = Contact::of(s, &system.robot)?;
    let mut contact = world
        .is_some()
        .then(|| ContactTrace::with_capacity(n + 1, N, 3));
    match s.simulation.mode {
        Mode::Sampled => match &s.controller.passive {
            None => sampled(
                s,
                &chain,
                ctl,
                (q, v),
                &mut world,
                &mut trace,
                &mut contact,
                progress,
            )?,
            Some(spec) => {
                let circular = kinds.map(|k| k == JointKind::Circular);
                let drive = PassiveDrive::new(ctl, spec, circular)?;
                sampled(
                    s,
                    &chain,
                    drive,
                    (q, v),
                    &mut world,
                    &mut trace,
                    &mut contact,
                    progress,
                )?
            }
        },
        Mode::Continuous => {
            let sys = ClosedLoop::matched(ctl);
            let i = *sys.controller.state();
            let mut st = AugmentedState {
                q,
                v,
                tau: i.tau,
                tau_dot: i.tau_dot,
                flywheel_speed: i.flywheel_speed,
            };
            let mut sys = sys;
            let mut work = Work::default();
            for k in 0..=n {
                let t = k as f64 * dt;
                let mut first = stage(&sys, &world, &friction, t, &st)?;
                if let Some(r) = schedule(s, sys.controller.nominal_speed_mut(), &first.contact)? {
                    if r.changed {
                        first = stage(&sys, &world, &friction, t, &st)?;
                    }
                }
                let r = sys
                    .controller
                    .nominal_speed_mut()
                    .map_or(0.0, |n| n.speed());
                trace.push(Row {
                    t,
                    q: st.q.coords().as_slice(),
                    v: st.v.as_slice(),
                    tau: st.tau,
                    tau_dot: st.tau_dot,
                    flywheel_speed: st.flywheel_speed,
                    beta: first.beta,
                    potential: first.potential,
                    lambda1: first.lambda1,
                    lambda2: first.lambda2,
                    torque: first.torque.as_slice(),
                    energy: sys.kinetic_energy(&st),
                    friction_power: first.power[1],
                });
                if let (Some(ct), Some(w)) = (contact.as_mut(), &world) {
                    w.log(ct, &chain, &st.q, &first.contact, &work, r)?;
                }
                if k == n {
                    break;
                }
                for j in 0..s.simulation.plant_substeps {
                    let t0 = t + j as f64 * h;
                    if j > 0 {
                        first = stage(&sys, &world, &friction, t0, &st)?;
                    }
                    let mut p = [first.power; 4];
                    st = sys.rk4_with_stages(&st, &first.derivative, h, |i, c, x| {
                        let e = stage(&sys, &world, &friction, t0 + c, x)?;
                        p[i] = e.power;
                        Ok::<_, SimError>(e.derivative)
                    })?;
                    work.add(h, &p);
                }
                if k % 1000 == 0 {
                    progress(k as f64 / n as f64);
                }
            }
        }
    }
    trace.contact = contact;
    progress(1.0);
    Ok(trace)
}

/// The timed-trajectory baseline for a URDF arm: computed torque + PD tracking `x_d(τ(t))`,
/// `τ(t) = τ₀ + rate·t`, with gravity compensation,
/// `T = M(q)(ẍ_d + K_d(ẋ_d − q̇) + K_p(x_d − q)) + C(q, q̇) q̇ + g(q)` (+ the scenario's
/// friction compensation), on the same plant, friction and 3-D contact, held for each
/// controller period.
pub fn simulate_timed_chain(
    s: &Scenario,
    b: &BaselineSpec,
    tau_rate: f64,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    simulate_timed_chain_with(s, &ArmSystem::build(s)?, b, tau_rate, progress)
}

/// [`simulate_timed_chain`] with the scenario's system already built.
pub fn simulate_timed_chain_with(
    s: &Scenario,
    system: &ArmSystem,
    b: &BaselineSpec,
    tau_rate: f64,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    if !tau_rate.is_finite() {
        return Err(SimError::Setting("baseline: τ rate must be finite".into()));
    }
    let robot = &system.robot;
    with_dof!(robot.dof(), N => {
        let chain = SerialChain::<f64, N>::try_from(robot.model())?;
        timed::<N>(s, b, tau_rate, chain, system, progress)
    }, otherwise Err(SimError::Setting(format!(
        "robot {}: {} joints; pvfc supports 1 to 8", robot.description().name, robot.dof()
    ))))
}

fn timed<const N: usize>(
    s: &Scenario,
    b: &BaselineSpec,
    tau_rate: f64,
    chain: SerialChain<f64, N>,
    system: &ArmSystem,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace> {
    let settings = &system.settings;
    let ctl: ArmControllerN<N> = arm_controller(chain, settings)?;
    let field = ctl.law().field();
    let friction = s.plant.friction.clone();
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
    let (dt, h, n) = timing(s)?;
    let kinds = chain.kinds();
    let mut q = JointSpace::new(joint_vector::<N>(&s.initial.q, "initial.q")?, kinds);
    let mut v = joint_vector::<N>(&s.initial.v, "initial.v")?;
    let world = Contact::of(s, &system.robot)?;
    let mut trace = Trace::with_capacity(format!("{}-timed", s.name), N, n + 1);
    let mut contact = world
        .is_some()
        .then(|| ContactTrace::with_capacity(n + 1, N, 3));
    let mut work = Work::default();
    for k in 0..=n {
        let t = k as f64 * dt;
        let tau = s.initial.tau + tau_rate * t;
        let xd = field.contour().sample(tau);
        let (xd_v, xd_a) = (
            xd.velocity * tau_rate,
            xd.acceleration * (tau_rate * tau_rate),
        );
        let e = xd.point.coords() - q.coords();
        let (m, c) = chain.inertia_and_coriolis(&q, &v);
        let mut u = m * (xd_a + (xd_v - v).component_mul(&kd) + e.component_mul(&kp))
            + c * v
            + chain.gravity(&q);
        if let Some(fc) = &comp {
            u += fc.torque(&v);
        }
        let err = q.compose(&xd.point.inverse());
        trace.push(Row {
            t,
            q: q.coords().as_slice(),
            v: v.as_slice(),
            tau,
            tau_dot: tau_rate,
            flywheel_speed: 0.0,
            beta: 0.0,
            potential: field.navigation().value(&err),
            lambda1: 1.0,
            lambda2: 1.0,
            torque: u.as_slice(),
            energy: chain.kinetic_energy(&q, &v),
            friction_power: friction.torque(&v).dot(&v),
        });
        let (fc0, c0) = match world.as_ref() {
            Some(w) => w.forces(t, &q, &v)?,
            None => (SVector::zeros(), SpatialContact::default()),
        };
        if let (Some(ct), Some(w)) = (contact.as_mut(), world.as_ref()) {
            w.log(ct, &chain, &q, &c0, &work, 0.0)?;
        }
        if k == n {
            break;
        }
        (q, v) = hold(
            s,
            &chain,
            world.as_ref(),
            (q, v),
            (t, h),
            (&u, true),
            &fc0,
            &mut work,
        )?;
        if k % 1000 == 0 {
            progress(k as f64 / n as f64);
        }
    }
    trace.contact = contact;
    progress(1.0);
    Ok(trace)
}

/// A chain run's 3-D contact world, if the scenario has a `[contact_3d]` table.
struct Contact {
    #[cfg(feature = "contact")]
    world: crate::contact::spatial::SpatialWorld,
}

impl Contact {
    fn of(s: &Scenario, robot: &crate::robot::Robot) -> Result<Option<Self>> {
        match &s.contact_3d {
            None => Ok(None),
            #[cfg(feature = "contact")]
            Some(spec) => Ok(Some(Contact {
                world: crate::contact::spatial::SpatialWorld::new_in(spec, robot, &s.base_dir)?,
            })),
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

    /// One sample of the contact columns.
    fn log<const N: usize>(
        &self,
        ct: &mut ContactTrace,
        chain: &SerialChain<f64, N>,
        q: &JointSpace<f64, N>,
        c: &SpatialContact,
        work: &Work,
        nominal_speed: f64,
    ) -> Result<()> {
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
        Ok(())
    }
}

/// One evaluation of a chain's closed loop with its contact: the rate, what the log needs,
/// and the powers `[contact, friction, controller add-ons, gravity]` on the arm.
struct Stage<const N: usize> {
    derivative: Derivative<f64, N>,
    contact: SpatialContact,
    torque: SVector<f64, N>,
    beta: f64,
    potential: f64,
    lambda1: f64,
    lambda2: f64,
    power: [f64; 4],
}

fn stage<const N: usize>(
    sys: &ClosedLoop<
        f64,
        JointSpace<f64, N>,
        SerialChain<f64, N>,
        SerialChain<f64, N>,
        ArmField<N>,
        N,
    >,
    world: &Option<Contact>,
    friction: &JointFriction,
    t: f64,
    st: &AugmentedState<f64, JointSpace<f64, N>, N>,
) -> Result<Stage<N>> {
    let (fc, contact) = match world {
        Some(w) => w.forces(t, &st.q, &st.v)?,
        None => (SVector::zeros(), SpatialContact::default()),
    };
    let ff = friction.torque(&st.v);
    let (torque, c) = sys.controller.evaluate(st)?;
    let derivative = sys.rate(st, &torque, &(ff + fc))?;
    let addon = torque - c.torque;
    let controller =
        addon.robot.dot(&st.v) + addon.tau * st.tau_dot + addon.flywheel * st.flywheel_speed;
    let gravity = -sys.plant.gravity(&st.q).dot(&st.v);
    Ok(Stage {
        derivative,
        contact,
        torque: torque.robot,
        beta: c.beta,
        potential: c.field.potential,
        lambda1: c.field.lambda1,
        lambda2: c.field.lambda2,
        power: [fc.dot(&st.v), ff.dot(&st.v), controller, gravity],
    })
}

/// The sampled-data loop of a chain: the controller (`Controller::step` or the passive one) at
/// its rate with zero-order hold, the plant (with gravity, friction and its 3-D contact, if
/// any) in RK4 substeps. With contact, the works are integrated by the RK4 quadrature of the
/// stages' powers and the add-ons' work is what the controller accounts.
#[allow(clippy::too_many_arguments)]
fn sampled<const N: usize, S: Stepper<JointSpace<f64, N>, N>>(
    s: &Scenario,
    chain: &SerialChain<f64, N>,
    mut ctl: S,
    (mut q, mut v): (JointSpace<f64, N>, SVector<f64, N>),
    world: &mut Option<Contact>,
    trace: &mut Trace,
    contact: &mut Option<ContactTrace>,
    progress: &mut dyn FnMut(f64),
) -> Result<()> {
    let friction = s.plant.friction.clone();
    let (dt, h, n) = timing(s)?;
    let period = s.period();
    let mut work = Work::default();
    for k in 0..=n {
        let t = k as f64 * dt;
        let (fc0, c0) = match world.as_ref() {
            Some(w) => w.forces(t, &q, &v)?,
            None => (SVector::zeros(), SpatialContact::default()),
        };
        schedule(s, ctl.nominal_speed_mut(), &c0)?;
        let r = ctl.nominal_speed_mut().map_or(0.0, |n| n.speed());
        let out = ctl.sample(&q, &v, dt)?;
        work.0[2] += out.add_ons_ended;
        trace.push(Row::of_sample(
            t,
            (q.coords().as_slice(), v.as_slice()),
            &out,
            period,
            chain.kinetic_energy(&q, &v),
            friction.torque(&v).dot(&v),
        ));
        if let (Some(ct), Some(w)) = (contact.as_mut(), world.as_ref()) {
            w.log(ct, chain, &q, &c0, &work, r)?;
        }
        if k == n {
            break;
        }
        work.0[2] += out.add_ons_next;
        (q, v) = hold(
            s,
            chain,
            world.as_ref(),
            (q, v),
            (t, h),
            (&out.torque, false),
            &fc0,
            &mut work,
        )?;
        if k % 1000 == 0 {
            progress(k as f64 / n as f64);
        }
    }
    Ok(())
}

/// The outcome of scheduling the nominal speed on the contact force.
struct Scheduled {
    /// Whether `r` changed (a stage evaluated before must be evaluated again).
    changed: bool,
}

/// Sets the nominal speed `r` of (36) from the contact's normal force when the scenario's
/// `[contact_3d]` schedules it (`force_schedule`); `None` when it does not.
fn schedule(
    s: &Scenario,
    nominal: Option<&mut NominalSpeed<f64>>,
    contact: &SpatialContact,
) -> Result<Option<Scheduled>> {
    let sch = s.contact_3d.as_ref().and_then(|c| c.force_schedule);
    let r0 = s.controller.nominal_speed.map(|n| n.r);
    let (Some(sch), Some(r0), Some(ns)) = (sch, r0, nominal) else {
        return Ok(None);
    };
    let r = sch.speed(r0, contact.normal_force);
    let changed = r != ns.speed();
    ns.set_speed(r)?;
    Ok(Some(Scheduled { changed }))
}

/// Holds the motor torque `u` over one controller period from time `t`: the plant (gravity,
/// friction, its 3-D contact) in RK4 substeps of `h`, the works `[contact, friction, motor,
/// gravity]` integrated by the stages' powers. The motor's power is counted only when asked
/// (the timed baseline's; PVFC's add-ons are what its controller accounts). `fc0` is the
/// contact torque at the sample, the first stage of the period.
#[allow(clippy::too_many_arguments)]
fn hold<const N: usize>(
    s: &Scenario,
    chain: &SerialChain<f64, N>,
    world: Option<&Contact>,
    (mut q, mut v): (JointSpace<f64, N>, SVector<f64, N>),
    (t, h): (f64, f64),
    (u, count_motor): (&SVector<f64, N>, bool),
    fc0: &SVector<f64, N>,
    work: &mut Work,
) -> Result<(JointSpace<f64, N>, SVector<f64, N>)> {
    let friction = &s.plant.friction;
    for j in 0..s.simulation.plant_substeps {
        let t0 = t + j as f64 * h;
        let mut p = [[0.0; 4]; 4];
        (q, v) = plant_rk4(chain, &q, &v, h, |i, c, q, v| {
            let ff = friction.torque(v);
            // The first stage of the period is the sample itself: its contact is known.
            let fc = match world {
                Some(_) if i == 0 && j == 0 => *fc0,
                Some(w) => w.forces(t0 + c, q, v)?.0,
                None => SVector::zeros(),
            };
            let motor = if count_motor { u.dot(v) } else { 0.0 };
            p[i] = [fc.dot(v), ff.dot(v), motor, -chain.gravity(q).dot(v)];
            Ok(u + ff + fc)
        })?;
        work.add(h, &p);
    }
    Ok((q, v))
}
