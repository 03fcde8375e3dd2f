//! The closed loop run, once for every robot: generic over the configuration group `G`, the
//! plant `Sys` and the dimension `N`, so that the planar SCARA (`Torus<2>`, `Scara`, planar
//! contact) and any URDF arm (`JointSpace<N>`, `SerialChain<N>`, 3-D contact) run through the
//! same code. What differs is given: the controller ([`Stepper`]: `Controller::step` or the
//! passive one) for the sampled-data loop, the closed loop for the continuous one, and what
//! the robot touches ([`Surroundings`]).
//!
//! The works `[contact, friction, controller add-ons, gravity]` are integrated by the RK4
//! quadrature of the stages' powers, so the audit `κ_a − κ_a(0) − ΣW` is integration error.

use crate::contact::ForceSchedule;
use crate::error::{Result, SimError};
use crate::plant::disturbance::{torque_of, Disturbance};
use crate::plant::faults::{impact_torque, FaultState};
use crate::plant::friction::JointFriction;
use crate::run::integrate::{ClosedLoop, Derivative};
use crate::run::path_clock::PathClock;
use crate::run::stepper::{Sample, Stepper};
use crate::scenario::{BaselineSpec, Scenario};
use crate::trace::{ContactTrace, Row, Trace, Work};
use nalgebra::SVector;
use pvfc_core::augmented::AugmentedState;
use pvfc_core::prelude::*;

/// The coordinates a trace logs for a configuration (the torus's unwrapped angles, the joint
/// space's coordinates, an attitude's rotation vector).
pub(crate) trait Coordinates<const N: usize> {
    /// The coordinates.
    fn coordinates(&self) -> SVector<f64, N>;
}

impl<const N: usize> Coordinates<N> for Torus<f64, N> {
    fn coordinates(&self) -> SVector<f64, N> {
        *self.angles()
    }
}

impl<const N: usize> Coordinates<N> for JointSpace<f64, N> {
    fn coordinates(&self) -> SVector<f64, N> {
        *self.coords()
    }
}

/// An attitude `R` as its rotation vector `r`, `R = exp(r̂)`, `‖r‖ ≤ π`.
impl Coordinates<3> for So3<f64> {
    fn coordinates(&self) -> SVector<f64, 3> {
        self.log()
    }
}

/// What the robot touches: the contact at `(t, q, q̇)` (a function of its arguments: the loops
/// call it at every integration stage), its joint torque `F_e`, and the sample the trace
/// keeps of it.
pub(crate) trait Surroundings<G, const N: usize> {
    /// One evaluation of the contact.
    type Contact;
    /// The contact at time `t` and state `(q, q̇)`.
    fn contact(&mut self, t: f64, q: &G, v: &SVector<f64, N>) -> Result<Self::Contact>;
    /// Its joint torque `F_e`.
    fn torque(c: &Self::Contact) -> SVector<f64, N>;
    /// Its total normal force (what the force schedule reads).
    fn normal_force(c: &Self::Contact) -> f64;
    /// One sample of the contact columns: the contact, the works so far, the nominal speed.
    fn log(
        &self,
        ct: &mut ContactTrace,
        q: &G,
        c: &Self::Contact,
        work: &Work,
        nominal_speed: f64,
    ) -> Result<()>;
}

/// A run's force schedule and nominal speed: sets `r` of (36) from the normal force; `true`
/// when `r` changed (what was evaluated with the old `r` must be evaluated again).
fn schedule(
    s: &Scenario,
    nominal: Option<&mut NominalSpeed<f64>>,
    normal_force: f64,
) -> Result<bool> {
    let r0 = s.controller.nominal_speed.map(|n| n.r);
    match (force_schedule(s), r0, nominal) {
        (Some(sch), Some(r0), Some(ns)) => {
            let r = sch.speed(r0, normal_force);
            let changed = r != ns.speed();
            ns.set_speed(r)?;
            Ok(changed)
        }
        _ => Ok(false),
    }
}

/// The scenario's force schedule: of its planar `[contact]` or its `[contact_3d]`.
fn force_schedule(s: &Scenario) -> Option<ForceSchedule> {
    s.contact
        .as_ref()
        .and_then(|c| c.force_schedule)
        .or_else(|| s.contact_3d.as_ref().and_then(|c| c.force_schedule))
}

/// The sampled-data loop: the controller at its rate with zero-order hold, the plant (with
/// its gravity, friction and contact) integrated with RK4 in substeps. The controller's
/// internal states are logged as they are at the sample (those the torque was computed at).
/// The scenario's `[[faults]]` act on the readings, the clock (a period drawn or lengthened:
/// the samples are then where the clock put them) and the drive (the torque held is what the
/// drive made of the command).
/// The add-ons' work is what the controller accounts (the passive one), or for
/// `Controller::step` summed at the samples (rectangle rule): for a loop without add-ons the
/// audit residual is then the sampled controller's own departure from passivity. The contact
/// columns are kept when `columns` gives the workspace's dimension.
#[allow(clippy::too_many_arguments)]
pub(crate) fn sampled<G, Sys, S, E, const N: usize>(
    s: &Scenario,
    plant: &Sys,
    mut ctl: S,
    (mut q, mut v): (G, SVector<f64, N>),
    env: &mut E,
    columns: Option<usize>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace>
where
    G: LieGroup<f64, N> + Coordinates<N>,
    Sys: MechanicalSystem<f64, G, N>,
    S: Stepper<G, N>,
    E: Surroundings<G, N> + ?Sized,
{
    let friction = s.plant.friction.clone();
    let (dt, _, n) = timing(s)?;
    let period = s.period();
    let mut trace = Trace::with_capacity(s.name.clone(), N, n + 1);
    let mut contact = columns.map(|dim| ContactTrace::with_capacity(n + 1, N, dim));
    let mut work = Work::default();
    let mut faults = FaultState::<N>::new(&s.faults, dt);
    let limits = s
        .controller
        .passive
        .as_ref()
        .map(|p| p.torque_limit.as_slice());
    let limits = limits.filter(|l| !l.is_empty());
    // The nominal clock samples at k·dt; a faulty one where its periods add up to.
    let faulty_clock = faults.timing();
    let end = n as f64 * dt;
    let (mut t, mut since) = (0.0, dt);
    let mut hidden = HiddenWork::<N>::default();
    for k in 0.. {
        let c0 = env.contact(t, &q, &v)?;
        schedule(s, ctl.nominal_speed_mut(), E::normal_force(&c0))?;
        let out = ctl.sample(&q, &v, (t, since), &mut faults)?;
        work.0[2] += out.add_ons_ended;
        let coordinates = q.coordinates();
        trace.push(Row::of_sample(
            t,
            (coordinates.as_slice(), v.as_slice()),
            &out,
            period,
            plant.kinetic_energy(&q, &v) + hidden.unused(&out),
            friction.torque(&v).dot(&v),
        ));
        if let Some(ct) = contact.as_mut() {
            let r = ctl.nominal_speed_mut().map_or(0.0, |n| n.speed());
            env.log(ct, &q, &c0, &work, r)?;
        }
        if t >= end {
            break;
        }
        work.0[2] += out.add_ons_next;
        let (u, p) = if faults.any() {
            (faults.drive(t, &out.torque, limits), faults.period(k, t))
        } else {
            (out.torque, dt)
        };
        let before = q;
        (q, v) = hold(
            s,
            plant,
            env,
            (q, v),
            (t, p / s.simulation.plant_substeps as f64),
            (&u, false),
            &E::torque(&c0),
            &mut work,
        )?;
        hidden.held(&u, &before.inverse().compose(&q).log());
        (t, since) = if faulty_clock {
            (t + p, p)
        } else {
            ((k + 1) as f64 * dt, dt)
        };
        if k % 1000 == 0 {
            progress(t / end);
        }
    }
    trace.contact = contact;
    progress(1.0);
    Ok(trace)
}

/// The books of a passive controller's set-aside energy (`PassiveController::set_aside`):
/// per joint, the drive's true work over the periods of the stretch since its reading stood
/// still (those over which the stretch's time grew). The unused rest of what is set aside,
/// `Σ_j max(s_j − (W_j − a_j), 0)` with `a_j` what the balances accounted, is still the
/// controller's energy: the audit counts it in `κ_a` beside the storage, so that energy set
/// aside and given back is not counted as created, and work beyond what was set aside is.
#[derive(Clone, Copy, Debug)]
struct HiddenWork<const N: usize> {
    /// The true work over each joint's stretch (J).
    stretch: SVector<f64, N>,
    /// The stretch's time at the last sample (s).
    time: SVector<f64, N>,
    /// The drive's true work on each joint over the last period held (J).
    last: SVector<f64, N>,
}

impl<const N: usize> Default for HiddenWork<N> {
    fn default() -> Self {
        HiddenWork {
            stretch: SVector::zeros(),
            time: SVector::zeros(),
            last: SVector::zeros(),
        }
    }
}

impl<const N: usize> HiddenWork<N> {
    /// After the sample `out`: the last period's work joins the stretch of each joint whose
    /// stretch's time grew, and a joint with no stretch open starts afresh. Returns the
    /// set-aside energy not yet used (J).
    fn unused(&mut self, out: &Sample<N>) -> f64 {
        let a = &out.set_aside;
        let mut unused = 0.0;
        for j in 0..N {
            if a.time[j] == 0.0 {
                self.stretch[j] = 0.0;
            } else if a.time[j] > self.time[j] {
                self.stretch[j] += self.last[j];
            }
            self.time[j] = a.time[j];
            unused += (a.energy[j] - (self.stretch[j] - a.accounted[j])).max(0.0);
        }
        unused
    }

    /// The torque `u` held over a period in which the joints moved by `dq`.
    fn held(&mut self, u: &SVector<f64, N>, dq: &SVector<f64, N>) {
        self.last = u.component_mul(dq);
    }
}

/// The trackers' loop: at each sample the tracker's command and the navigation function's
/// value, `law((τ, τ̇, τ̈), q, q̇) = (u, U)` with the path time of `clock`, clamped to
/// `limits` (as the drive does) and held over the period on the same plant, friction and
/// contact; the motor's work is counted. The trace is named `NAME` + `suffix`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn timed<G, Sys, E, const N: usize>(
    s: &Scenario,
    plant: &Sys,
    env: &mut E,
    (mut q, mut v): (G, SVector<f64, N>),
    columns: Option<usize>,
    (mut clock, limits, suffix): (PathClock, Option<SVector<f64, N>>, &str),
    mut law: impl FnMut((f64, f64, f64), &G, &SVector<f64, N>) -> Result<(SVector<f64, N>, f64)>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace>
where
    G: LieGroup<f64, N> + Coordinates<N>,
    Sys: MechanicalSystem<f64, G, N>,
    E: Surroundings<G, N> + ?Sized,
{
    let friction = s.plant.friction.clone();
    let (dt, h, n) = timing(s)?;
    let mut trace = Trace::with_capacity(format!("{}{suffix}", s.name), N, n + 1);
    let mut contact = columns.map(|dim| ContactTrace::with_capacity(n + 1, N, dim));
    let mut work = Work::default();
    for k in 0..=n {
        let t = k as f64 * dt;
        let (tau, tau_rate, tau_accel) = clock.at(t);
        let (command, potential) = law((tau, tau_rate, tau_accel), &q, &v)?;
        let u = BaselineSpec::saturate(command, &limits);
        let coordinates = q.coordinates();
        trace.push(Row {
            t,
            q: coordinates.as_slice(),
            v: v.as_slice(),
            tau,
            tau_dot: tau_rate,
            flywheel_speed: 0.0,
            beta: 0.0,
            w_beta: 0.0,
            potential,
            lambda1: 1.0,
            lambda2: 1.0,
            torque: u.as_slice(),
            energy: plant.kinetic_energy(&q, &v),
            friction_power: friction.torque(&v).dot(&v),
            fault: 0.0,
        });
        let c0 = env.contact(t, &q, &v)?;
        if let Some(ct) = contact.as_mut() {
            env.log(ct, &q, &c0, &work, 0.0)?;
        }
        if k == n {
            break;
        }
        // The share of a limit the command used (0 without limits: only a scaled clock reads
        // it, and it needs limits).
        let share = limits.as_ref().map_or(0.0, |l| {
            command
                .iter()
                .zip(l.iter())
                .fold(0.0, |m: f64, (u, l)| m.max(u.abs() / l))
        });
        clock.advance(dt, share);
        (q, v) = hold(
            s,
            plant,
            env,
            (q, v),
            (t, h),
            (&u, true),
            &E::torque(&c0),
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

/// Holds the motor torque `u` over one controller period from time `t`: the plant (gravity,
/// friction, contact and the scenario's disturbance) in RK4 substeps of `h`, the works
/// `[contact, friction, motor, gravity]` integrated by the stages' powers. The motor's power
/// is counted only when asked (the timed baseline's; PVFC's add-ons are what its controller
/// accounts). `fc0` is the contact torque at the sample, the first stage of the period; the
/// contact's work counts the disturbance's (both are the environment).
#[allow(clippy::too_many_arguments)]
pub(crate) fn hold<G, Sys, E, const N: usize>(
    s: &Scenario,
    plant: &Sys,
    env: &mut E,
    (mut q, mut v): (G, SVector<f64, N>),
    (t, h): (f64, f64),
    (u, count_motor): (&SVector<f64, N>, bool),
    fc0: &SVector<f64, N>,
    work: &mut Work,
) -> Result<(G, SVector<f64, N>)>
where
    G: LieGroup<f64, N>,
    Sys: MechanicalSystem<f64, G, N>,
    E: Surroundings<G, N> + ?Sized,
{
    let friction = &s.plant.friction;
    let disturbance = s.plant.disturbance.as_ref();
    for j in 0..s.simulation.plant_substeps {
        let t0 = t + j as f64 * h;
        let mut p = [[0.0; 4]; 4];
        (q, v) = plant_rk4(plant, &q, &v, h, |i, c, q, v| {
            let ff = friction.torque(v);
            // The first stage of the period is the sample itself: its contact is known. The
            // environment's torque is the contact's and the disturbance's.
            let fc = if i == 0 && j == 0 {
                *fc0
            } else {
                E::torque(&env.contact(t0 + c, q, v)?)
            } + torque_of::<N>(disturbance, t0 + c)
                + impact_torque::<N>(&s.faults, t0 + c, 1.0 / s.controller.rate);
            let motor = if count_motor { u.dot(v) } else { 0.0 };
            p[i] = [fc.dot(v), ff.dot(v), motor, -plant.gravity(q).dot(v)];
            Ok(u + ff + fc)
        })?;
        work.add(h, &p);
    }
    Ok((q, v))
}

/// One evaluation of the closed loop with what it touches: the rate, what the log needs,
/// and the powers `[contact, friction, controller add-ons, gravity]` on the augmented system
/// (kept small: the full `Evaluation` is large and moving it costs).
struct Stage<C, const N: usize> {
    contact: C,
    derivative: Derivative<f64, N>,
    torque: SVector<f64, N>,
    beta: f64,
    w_beta: f64,
    potential: f64,
    lambda1: f64,
    lambda2: f64,
    power: [f64; 4],
}

fn stage<G, Sys, F, E, const N: usize>(
    sys: &ClosedLoop<f64, G, Sys, Sys, F, N>,
    env: &mut E,
    (friction, disturbance): (&JointFriction, Option<&Disturbance>),
    t: f64,
    st: &AugmentedState<f64, G, N>,
) -> Result<Stage<E::Contact, N>>
where
    G: LieGroup<f64, N>,
    Sys: MechanicalSystem<f64, G, N>,
    F: VelocityField<f64, G, N>,
    E: Surroundings<G, N> + ?Sized,
{
    let contact = env.contact(t, &st.q, &st.v)?;
    // The environment's torque: the contact's and the disturbance's.
    let fc = E::torque(&contact) + torque_of::<N>(disturbance, t);
    let ff = friction.torque(&st.v);
    // Only the few numbers the stage keeps are taken of the controller's (large) output.
    let (torque, c) = sys.controller.evaluate_then(st, |c| {
        (
            c.torque,
            [
                c.beta,
                c.velocity_field_error_energy(),
                c.field.potential,
                c.field.lambda1,
                c.field.lambda2,
            ],
        )
    })?;
    let (coupling, [beta, w_beta, potential, lambda1, lambda2]) = c;
    let derivative = sys.rate(st, &torque, &(fc + ff))?;
    let addon = torque - coupling;
    let controller =
        addon.robot.dot(&st.v) + addon.tau * st.tau_dot + addon.flywheel * st.flywheel_speed;
    let gravity = -sys.plant.gravity(&st.q).dot(&st.v);
    Ok(Stage {
        power: [fc.dot(&st.v), ff.dot(&st.v), controller, gravity],
        contact,
        derivative,
        torque: torque.robot,
        beta,
        w_beta,
        potential,
        lambda1,
        lambda2,
    })
}

/// The continuous-time loop from `(q, q̇)` and the controller's internal states: the closed
/// loop (the controller's model as the plant, the controller and their contact) integrated
/// with RKMK4 at the plant's step, logged at the controller's rate. With a force schedule,
/// `r` of (36) is set from the contact force at each logged sample.
pub(crate) fn continuous<G, Sys, F, E, const N: usize>(
    s: &Scenario,
    controller: Controller<f64, G, Sys, F, N>,
    (q, v): (G, SVector<f64, N>),
    env: &mut E,
    columns: Option<usize>,
    progress: &mut dyn FnMut(f64),
) -> Result<Trace>
where
    G: LieGroup<f64, N> + Coordinates<N>,
    Sys: MechanicalSystem<f64, G, N> + Clone,
    F: VelocityField<f64, G, N>,
    E: Surroundings<G, N> + ?Sized,
{
    // The plant is the controller's own model; the controller's internal states join the
    // plant's in the integrated state.
    let mut sys = ClosedLoop::matched(controller);
    let i = *sys.controller.state();
    let mut st = AugmentedState {
        q,
        v,
        tau: i.tau,
        tau_dot: i.tau_dot,
        flywheel_speed: i.flywheel_speed,
    };
    let friction = (&s.plant.friction, s.plant.disturbance.as_ref());
    let (dt, h, n) = timing(s)?;
    let mut trace = Trace::with_capacity(s.name.clone(), N, n + 1);
    let mut contact = columns.map(|dim| ContactTrace::with_capacity(n + 1, N, dim));
    let mut work = Work::default();
    for k in 0..=n {
        let t = k as f64 * dt;
        let mut first = stage(&sys, env, friction, t, &st)?;
        let normal = E::normal_force(&first.contact);
        if schedule(s, sys.controller.nominal_speed_mut(), normal)? {
            first = stage(&sys, env, friction, t, &st)?;
        }
        let coordinates = st.q.coordinates();
        trace.push(Row {
            t,
            q: coordinates.as_slice(),
            v: st.v.as_slice(),
            tau: st.tau,
            tau_dot: st.tau_dot,
            flywheel_speed: st.flywheel_speed,
            beta: first.beta,
            w_beta: first.w_beta,
            potential: first.potential,
            lambda1: first.lambda1,
            lambda2: first.lambda2,
            torque: first.torque.as_slice(),
            energy: sys.kinetic_energy(&st),
            friction_power: first.power[1],
            fault: 0.0,
        });
        if let Some(ct) = contact.as_mut() {
            let r = sys
                .controller
                .nominal_speed_mut()
                .map_or(0.0, |n| n.speed());
            env.log(ct, &st.q, &first.contact, &work, r)?;
        }
        if k == n {
            break;
        }
        for j in 0..s.simulation.plant_substeps {
            let t0 = t + j as f64 * h;
            if j > 0 {
                first = stage(&sys, env, friction, t0, &st)?;
            }
            let mut p = [first.power; 4];
            st = sys.rk4_with_stages(&st, &first.derivative, h, |i, c, x| {
                let e = stage(&sys, env, friction, t0 + c, x)?;
                p[i] = e.power;
                Ok::<_, SimError>(e.derivative)
            })?;
            work.add(h, &p);
        }
        if k % 1000 == 0 {
            progress(k as f64 / n as f64);
        }
    }
    trace.contact = contact;
    progress(1.0);
    Ok(trace)
}

/// One RK4 step of the arm alone under the generalized force `force(i, c, q, q̇)` at the
/// stages `i = 0..4` (time offsets `c = 0, h/2, h/2, h`): motor torque, friction, contact.
/// The step is the simulation's one integrator, [`crate::run::integrate::rkmk4`], on `(q, q̇)`
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
    let next = crate::run::integrate::rkmk4(&s, &k1, h, rate)?;
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
