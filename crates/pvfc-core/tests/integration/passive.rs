//! The passive digital controller (`pvfc_core::passive`): its energy balance over one held
//! period against a finely integrated plant, at random states, periods, limits and external
//! torques; its errors; its convergence to the ZOH controller as the period goes to zero.

use nalgebra::Vector2;
use proptest::prelude::*;
use pvfc_core::passive::PassiveController;
use pvfc_core::prelude::*;

use crate::common;
use common::held::{kinetic, plant};

type Field = SuspendedField<
    f64,
    Torus<f64, 2>,
    Lissajous<f64, 2>,
    TorusNavigation<f64, 2>,
    ExponentialPacing<f64>,
    2,
>;
type Passive = PassiveController<f64, Torus<f64, 2>, Scara<f64>, Field, 2>;

fn controller(energy: f64, gamma: f64) -> Controller<f64, Torus<f64, 2>, Scara<f64>, Field, 2> {
    let field = SuspendedField::new(
        Lissajous::<f64, 2>::paper(),
        TorusNavigation::paper(Vector2::new(1.0, 1.0)).unwrap(),
        ExponentialPacing::new(5.0).unwrap(),
    );
    let law = PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(1.0, energy).unwrap(),
        gamma,
    )
    .unwrap();
    Controller::new(law)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// Over random states, periods, limits, add-ons and external torques, two steps of the
    /// controller around one held period: the robot's kinetic energy plus the storage changes
    /// by exactly the environment's work plus the add-ons' (to the plant integrator's error),
    /// and the storage is the internal states' energy.
    #[test]
    fn one_period_creates_no_energy(
        q in prop::array::uniform2(-3.0f64..3.0),
        v in prop::array::uniform2(-2.0f64..2.0),
        tau in 0.0f64..6.0,
        tau_dot in -1.0f64..1.0,
        flywheel in 0.5f64..12.0,
        h in 1e-4f64..2e-2,
        limit in prop::option::of(0.5f64..20.0),
        fe in prop::array::uniform2(-5.0f64..5.0),
        add_ons in any::<bool>(),
        positions_only in any::<bool>(),
    ) {
        let mut c = controller(100.0, 0.5).with_state(InternalState {
            tau, tau_dot, flywheel_speed: flywheel, laps: 0,
        });
        if add_ons {
            c = c
                .with_nominal_speed(NominalSpeed::new(0.5, 1.0).unwrap())
                .with_friction_compensation(FrictionCompensation::new(Vector2::new(2.0, 3.0)).unwrap().with_band(0.1).unwrap());
        }
        let mut ctl: Passive = PassiveController::new(c);
        if let Some(l) = limit {
            ctl = ctl.with_torque_limits(Vector2::new(l, l)).unwrap();
        }
        let (q0, v0) = (Torus::new(Vector2::from(q)), Vector2::from(v));
        let vel = (!positions_only).then_some(&v0);
        let first = ctl.step(&q0, vel, None, h).unwrap();
        prop_assert!(first.torque.iter().all(|t| limit.is_none_or(|l| t.abs() <= l)));
        let s0 = first.energy.storage;
        let fe = Vector2::from(fe);
        let (q1, v1) = plant(q0, v0, first.torque + fe, h, 200);
        let second = ctl.step(&q1, Some(&v1), None, h).unwrap();
        let env = fe.dot(&(q1.angles() - q0.angles()));
        let before = kinetic(&q0, &v0) + s0;
        let after = kinetic(&q1, &v1) + second.energy.storage;
        let residual = after - before - env - second.energy.add_ons;
        prop_assert!(residual.abs() <= 1e-9 * (1.0 + before), "residual {residual:e} of {before}");
        // The storage is what the internal states hold (it did not run dry here).
        let st = second.state;
        let held = 0.5 * (st.tau_dot * st.tau_dot + st.flywheel_speed * st.flywheel_speed);
        if second.energy.storage >= 0.0 {
            prop_assert!((held - second.energy.storage).abs() <= 1e-9 * (1.0 + held));
        }
    }
}

#[test]
fn bad_input_is_a_typed_error_and_changes_nothing() {
    let mut ctl: Passive = PassiveController::new(controller(50.0, 1.0).starting_at_rest(0.0));
    let q = Torus::new(Vector2::new(0.1, 0.2));
    ctl.step(&q, None, None, 1e-3).unwrap();
    let before = ctl;
    let nan = Vector2::new(f64::NAN, 0.0);
    for (q, v, u, dt, kind) in [
        (q, None, None, 0.0, ErrorKind::InvalidParameter),
        (q, None, None, f64::INFINITY, ErrorKind::InvalidParameter),
        (Torus::new(nan), None, None, 1e-3, ErrorKind::NonFinite),
        (q, Some(&nan), None, 1e-3, ErrorKind::NonFinite),
        (q, None, Some(&nan), 1e-3, ErrorKind::NonFinite),
    ] {
        assert_eq!(ctl.step(&q, v, u, dt).unwrap_err().kind(), kind);
        assert_eq!(ctl, before, "an error changed the controller");
    }
    let c = PassiveController::new(controller(50.0, 1.0));
    assert!(c.with_torque_limits(Vector2::new(1.0, 0.0)).is_err());
    assert!(c.with_torque_limits(Vector2::new(1.0, f64::NAN)).is_err());
    assert!(c.with_velocity_filter(-1.0).is_err());
    assert!(c.with_reserve(f64::NAN).is_err());
    assert!(c
        .with_encoder_resolution(Vector2::new(-1e-5, 1e-5))
        .is_err());
}

/// Without a measured velocity and `T_f = 0`, the law sees the backward difference of the
/// positions (wrapped across ±π).
#[test]
fn the_velocity_estimate_is_the_backward_difference() {
    let mut ctl: Passive = PassiveController::new(controller(50.0, 1.0).starting_at_rest(0.0));
    let h = 1e-3;
    let q0 = Torus::new(Vector2::new(3.1, -0.5));
    let q1 = Torus::new(Vector2::new(-3.1, -0.49));
    ctl.step(&q0, None, None, h).unwrap();
    let out = ctl.step(&q1, None, None, h).unwrap();
    let expect = Vector2::new(2.0 * std::f64::consts::PI - 6.2, 0.01) / h;
    assert!((out.velocity - expect).amax() < 1e-9, "{:?}", out.velocity);
}

/// The tank: with a reserve just below the storage, the coupling that would accelerate the
/// robot (drawing from the storage) is scaled down, and the storage stays at the reserve up
/// to the one-period prediction's error.
#[test]
fn a_dry_tank_scales_the_coupling() {
    let c = controller(50.0, 1.0).starting_at_rest(0.0);
    let reserve = 50.0 - 0.01;
    let mut ctl: Passive = PassiveController::new(c).with_reserve(reserve).unwrap();
    let (mut q, mut v) = (Torus::new(Vector2::new(0.5, 1.0)), Vector2::new(0.0, 0.0));
    let h = 1e-3;
    let mut scaled = 0;
    let mut lowest = f64::INFINITY;
    for _ in 0..2000 {
        let out = ctl.step(&q, Some(&v), None, h).unwrap();
        scaled += usize::from(out.energy.scale < 1.0);
        lowest = lowest.min(out.energy.storage);
        (q, v) = plant(q, v, out.torque, h, 10);
    }
    assert!(
        scaled > 100,
        "the tank scaled the coupling at {scaled} steps only"
    );
    assert!(
        lowest > reserve - 1e-4,
        "the storage fell to {lowest} below the reserve {reserve}"
    );
    assert!(
        kinetic(&q, &v) <= 0.01 + 1e-4,
        "the robot got more than the tank could give"
    );
}

/// As the period goes to zero the passive controller becomes the ZOH controller: the energy
/// the projection corrects falls at least as h² per step, and the two runs' contour errors
/// agree.
#[test]
fn the_correction_vanishes_as_the_period_goes_to_zero() {
    let run = |h: f64| {
        let c = controller(50.0, 1.0).starting_at_rest(0.0);
        let mut passive: Passive = PassiveController::new(c);
        let mut zoh = c;
        let (mut q, mut v) = (Torus::new(Vector2::new(0.3, 1.0)), Vector2::zeros());
        let (mut qz, mut vz) = (q, v);
        let mut correction = 0.0f64;
        let steps = (0.5 / h).round() as usize;
        let mut u = (0.0, 0.0);
        for _ in 0..steps {
            let out = passive.step(&q, Some(&v), None, h).unwrap();
            correction = correction.max(out.energy.correction.abs());
            u.0 = out.diagnostics.potential;
            (q, v) = plant(q, v, out.torque, h, 4);
            let oz = zoh.step(&qz, &vz, h).unwrap();
            u.1 = oz.diagnostics.potential;
            (qz, vz) = plant(qz, vz, oz.torque, h, 4);
        }
        (correction, u)
    };
    let (c1, u1) = run(2e-3);
    let (c2, u2) = run(1e-3);
    assert!(
        c2 < c1 / 3.0,
        "max correction per step {c1:e} at 2 ms, {c2:e} at 1 ms"
    );
    for (a, b) in [u1, u2] {
        assert!(
            (a - b).abs() <= 0.05 * a.max(b) + 1e-9,
            "U passive {a:e}, ZOH {b:e}"
        );
    }
}

/// Torque limits clamp each joint's command to `±limit` and report it: at states where the
/// law asks for more than the limit on one joint only, that joint is clamped, the other is
/// the unlimited controller's torque, and `saturated` is set; within the limits nothing
/// changes and `saturated` is clear.
#[test]
fn torque_limits_clamp_each_joint_and_report_it() {
    let free = PassiveController::new(controller(50.0, 1.0).starting_at_rest(0.0));
    let (mut clamped_some, mut clear_some) = (false, false);
    for k in 0..40 {
        let q = Torus::new(Vector2::new(0.1 * k as f64 - 2.0, 0.3 - 0.05 * k as f64));
        let v = Vector2::new(0.2 * (k % 7) as f64 - 0.6, 0.1 * (k % 5) as f64 - 0.2);
        let mut unlimited = free; // (a copy)
        let want = unlimited.step(&q, Some(&v), None, 1e-3).unwrap().torque;
        // Joint 0 limited below what the law asks (when it asks anything), joint 1 above it.
        let limits = Vector2::new(0.5 * want[0].abs(), 2.0 * want[1].abs() + 1.0);
        if limits[0] <= 0.0 {
            continue;
        }
        let mut ctl = free.with_torque_limits(limits).unwrap();
        let out = ctl.step(&q, Some(&v), None, 1e-3).unwrap();
        assert_eq!(
            out.torque[0],
            limits[0].copysign(want[0]),
            "joint 0 at step {k}"
        );
        assert_eq!(out.torque[1], want[1], "joint 1 at step {k}");
        assert!(out.energy.saturated);
        clamped_some = true;
        let mut ctl = free
            .with_torque_limits(want.abs() * 2.0 + Vector2::repeat(1.0))
            .unwrap();
        let out = ctl.step(&q, Some(&v), None, 1e-3).unwrap();
        assert_eq!(out.torque, want);
        assert!(!out.energy.saturated);
        clear_some = true;
    }
    assert!(clamped_some && clear_some);
}

// ---- Supervision: faults detected, answered with the safe torque, nothing created ----

use pvfc_core::supervision::{Fault, Supervision};

/// Bounds no clean run of these tests comes near: 10 rad/s, 2,000 rad/s², periods 0.4–3.5 ms.
fn supervision() -> Supervision<f64, 2> {
    Supervision::new(Vector2::new(10.0, 10.0), 4e-4, 3.5e-3)
        .unwrap()
        .with_max_acceleration(Vector2::new(2000.0, 2000.0))
        .unwrap()
}

fn supervised(limits: f64) -> Passive {
    PassiveController::new(controller(50.0, 1.0).starting_at_rest(0.0))
        .with_torque_limits(Vector2::new(limits, limits))
        .unwrap()
        .with_supervision(supervision())
}

/// What the sensors and the drive do to one period of the loop.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Glitch {
    /// The reading of joint `j` is off by `size` (rad).
    Spike(usize, f64),
    /// The reading of joint `j` is NaN.
    NotANumber(usize),
    /// The reading of joint `j` keeps the value it had when the freeze began.
    Freeze(usize),
    /// The period is this long (s); the controller is told so at the next sample.
    Period(f64),
    /// The drive keeps the torque it had (and says so).
    Dropped,
    /// The drive applies the command of the sample before (and says so).
    Late,
    /// The drive clamps the torque to this (N·m; and says so).
    Limit(f64),
    /// The reading of joint `j` is NaN while the drive keeps the torque it had.
    NotANumberDropped(usize),
}

/// The loop of `steps` periods of 1 ms (unless a glitch says otherwise) from the contour's
/// start at rest, with `glitch(k)` at sample `k`. Returns each sample's fault and the energy
/// the controller created up to it: the drive's work on the robot, `Σ u_appliedᵀΔq_true`,
/// less the add-ons' energy it reported, less what its storage gave.
fn run(
    ctl: &mut Passive,
    steps: usize,
    glitch: impl Fn(usize) -> Option<Glitch>,
) -> Vec<(Option<Fault>, f64)> {
    run_with_hidden_work(ctl, steps, glitch).0
}

/// What a run's set-aside energy did (J), and the robot's true speed at its end.
#[derive(Clone, Copy, Debug, Default)]
struct SetAsideBooks {
    /// The most work the drive did on a joint while its reading stood still (what a
    /// frozen encoder hid, paid from what the storage set aside).
    most_hidden: f64,
    /// The most the storage held aside at a sample.
    most_held: f64,
    /// What the storage kept of it in the end (the sum of the steps' net set-aside).
    kept: f64,
    /// The joints' true speeds at the last sample (rad/s).
    final_speed: Vector2<f64>,
}

/// [`run`], and what its set-aside energy did.
fn run_with_hidden_work(
    ctl: &mut Passive,
    steps: usize,
    glitch: impl Fn(usize) -> Option<Glitch>,
) -> (Vec<(Option<Fault>, f64)>, SetAsideBooks) {
    let h = 1e-3;
    let mut books_of = SetAsideBooks::default();
    let (mut q, mut v) = (Torus::new(Vector2::new(0.0, 0.0)), Vector2::zeros());
    let (mut dt, mut applied, mut last_command) = (h, Vector2::zeros(), Vector2::zeros());
    let (mut work, mut add_ons, mut b0) = (0.0, 0.0, None);
    // The drive's true work on each joint over the last period, and over the stretch
    // its reading has stood still (what the set-aside energy has paid for so far).
    let (mut last_work, mut hidden) = (Vector2::<f64>::zeros(), Vector2::<f64>::zeros());
    let mut stretch_time = Vector2::<f64>::zeros();
    let mut out = Vec::new();
    let mut frozen = None;
    for k in 0..steps {
        let g = glitch(k);
        let mut reading = *q.angles();
        match g {
            Some(Glitch::Spike(j, size)) => reading[j] += size,
            Some(Glitch::NotANumber(j) | Glitch::NotANumberDropped(j)) => reading[j] = f64::NAN,
            Some(Glitch::Freeze(j)) => reading[j] = *frozen.get_or_insert(reading[j]),
            _ => {}
        }
        if !matches!(g, Some(Glitch::Freeze(_))) {
            frozen = None;
        }
        let report = (k > 0).then_some(&applied);
        let step = ctl.step(&Torus::new(reading), None, report, dt).unwrap();
        // The controller's books: its storage and what is set aside that the motion since
        // the reading stood still has not used beyond what the balances accounted.
        let aside = ctl.set_aside();
        let mut books = step.energy.storage;
        for j in 0..2 {
            // The stretch's periods are those over which its time grew.
            hidden[j] = if aside.time[j] == 0.0 {
                0.0
            } else if aside.time[j] > stretch_time[j] {
                hidden[j] + last_work[j]
            } else {
                hidden[j]
            };
            stretch_time[j] = aside.time[j];
            books += (aside.energy[j] - (hidden[j] - aside.accounted[j])).max(0.0);
            books_of.most_hidden = books_of.most_hidden.max(hidden[j]);
        }
        books_of.most_held = books_of.most_held.max(aside.energy.sum());
        books_of.final_speed = v;
        books_of.kept += step.energy.set_aside;
        let b = *b0.get_or_insert(books);
        add_ons += step.energy.add_ons;
        out.push((step.fault, work - add_ons - (b - books)));
        // The drive.
        applied = match g {
            Some(Glitch::Dropped | Glitch::NotANumberDropped(_)) => applied,
            Some(Glitch::Late) => last_command,
            Some(Glitch::Limit(l)) => step.torque.map(|t| t.clamp(-l, l)),
            _ => step.torque,
        };
        last_command = step.torque;
        let period = match g {
            Some(Glitch::Period(p)) => p,
            _ => h,
        };
        let (q1, v1) = plant(q, v, applied, period, 10);
        let dq = q1.angles() - q.angles();
        last_work = applied.component_mul(&dq);
        work += applied.dot(&dq);
        (q, v, dt) = (q1, v1, period);
    }
    (out, books_of)
}

/// The most a run's books rose over any stretch: `max_{s ≤ t} (c_t − c_s)` of the energy
/// created `c` ([`run`]).
fn created_over_any_stretch(run: &[(Option<Fault>, f64)]) -> f64 {
    let (mut low, mut most) = (f64::INFINITY, 0.0f64);
    for (_, c) in run {
        low = low.min(*c);
        most = most.max(c - low);
    }
    most
}

#[test]
fn on_clean_signals_supervision_changes_nothing() {
    let mut plain: Passive = PassiveController::new(controller(50.0, 1.0).starting_at_rest(0.0))
        .with_torque_limits(Vector2::new(20.0, 20.0))
        .unwrap();
    let mut watched = supervised(20.0);
    let a = run(&mut plain, 1500, |_| None);
    let b = run(&mut watched, 1500, |_| None);
    assert_eq!(a, b);
    assert!(b.iter().all(|(f, _)| f.is_none()));
}

#[test]
fn a_spike_is_answered_with_zero_torque_and_the_loop_resumes() {
    let mut ctl = supervised(20.0);
    let run = run(&mut ctl, 800, |k| {
        (k == 500 || k == 600).then_some(Glitch::Spike(1, if k == 500 { 0.3 } else { -0.02 }))
    });
    assert_eq!(run[500].0, Some(Fault::Speed { joint: 1 }));
    assert_eq!(run[600].0, Some(Fault::Speed { joint: 1 }));
    assert!(run.iter().filter(|(f, _)| f.is_some()).count() == 2);
    for (k, (_, created)) in run.iter().enumerate() {
        assert!(*created <= 1e-9, "{created:e} J created at sample {k}");
    }
}

#[test]
fn a_fault_step_returns_the_safe_torque_and_charges_the_unseen_work() {
    let mut ctl = supervised(20.0);
    let mut q = Torus::new(Vector2::new(0.0, 0.0));
    let mut last = ctl.step(&q, None, None, 1e-3).unwrap();
    for _ in 0..50 {
        q = Torus::new(q.angles() + Vector2::new(1e-3, -5e-4));
        last = ctl.step(&q, None, None, 1e-3).unwrap();
    }
    let before = ctl;
    let nan = Torus::new(Vector2::new(f64::NAN, 0.0));
    let f = ctl.step(&nan, None, None, 1e-3).unwrap();
    assert_eq!(f.fault, Some(Fault::NonFinite));
    assert_eq!(f.torque, Vector2::zeros());
    // The charge: from the last increment's speed w = (1, −0.5) rad/s, each joint's
    // `u w h + |u| ā h (e_w/2 + h/2)` (ā = 2,000 rad/s²), never more than the speed bound's
    // `|u| v̄ h` (v̄ = 10 rad/s) nor below zero.
    let (h, w) = (1e-3, Vector2::new(1.0, -0.5));
    let bound: f64 = (0..2)
        .map(|j| {
            let u = last.torque[j];
            (u * w[j] * h + u.abs() * 2000.0 * h * (0.5 * h + 0.5 * h))
                .min(u.abs() * 10.0 * h)
                .max(0.0)
        })
        .sum();
    assert!(
        (f.energy.unseen - bound).abs() <= 1e-12 * bound.max(1e-3),
        "{} {bound}",
        f.energy.unseen
    );
    let speed_bound = (last.torque[0].abs() + last.torque[1].abs()) * 10.0 * h;
    assert!(bound < 0.5 * speed_bound, "{bound} {speed_bound}");
    assert!(f.energy.storage <= before.storage() - bound + 1e-12);
    assert_eq!(
        f.state.tau,
        before.controller().state().tau,
        "τ advanced at a fault"
    );
    // Zero torque is held: the next good reading is balanced at zero work.
    q = Torus::new(q.angles() + Vector2::new(2e-3, -1e-3));
    let next = ctl.step(&q, None, None, 1e-3).unwrap();
    assert_eq!(next.fault, None);
    assert_eq!(next.energy.to_robot, 0.0);
    // The velocity estimate spans both periods.
    assert!((next.velocity - Vector2::new(1.0, -0.5)).norm() < 1e-9);
    // The period: out of bounds is a fault with the exact balance.
    q = Torus::new(q.angles() + Vector2::new(5e-3, 0.0));
    let late = ctl.step(&q, None, None, 5e-3).unwrap();
    assert_eq!(late.fault, Some(Fault::Period));
    // Joint 1's reading stood still over the period: the most its torque can have done
    // unseen, at its speed bound (10 rad/s), is set aside.
    let aside = (next.torque[1] - next.add_on[1]).abs() * 10.0 * 5e-3;
    assert!(aside > 0.0);
    assert!((late.energy.set_aside - aside).abs() <= 1e-15 * aside.max(1.0));
    assert_eq!(late.energy.unseen, 0.0);
    assert!((late.energy.to_robot - next.torque.dot(&Vector2::new(5e-3, 0.0))).abs() < 1e-15);
    for dt in [f64::NAN, 0.0, -1.0, f64::INFINITY, 1e-4] {
        assert_eq!(
            ctl.step(&q, None, None, dt).unwrap().fault,
            Some(Fault::Period)
        );
    }
}

/// The sample between 0.3 and 0.9 s at which joint 0 is slowest on the clean loop (1 ms):
/// where a frozen encoder is not seen.
fn slowest_sample_of_joint_0() -> usize {
    let h = 1e-3;
    let mut probe = supervised(20.0);
    let (mut q, mut v) = (Torus::new(Vector2::new(0.0, 0.0)), Vector2::<f64>::zeros());
    let mut speed = Vec::new();
    for _ in 0..900 {
        let out = probe.step(&q, None, None, h).unwrap();
        speed.push(v[0].abs());
        (q, v) = plant(q, v, out.torque, h, 10);
    }
    (300..900)
        .min_by(|a, b| speed[*a].total_cmp(&speed[*b]))
        .unwrap()
}

/// A joint's encoder freezes while the joint is too slow for the acceleration bound to tell
/// (no fault is reported): the controller pushes a joint it believes still. Over each period
/// its reading stands still, the storage sets aside the most the torque can have done unseen
/// (`|c| v̄ h`), so no energy is created at any sample; when the encoder reads again, the
/// jump is rejected, the next reading confirms it, and the books are settled.
#[test]
fn an_undetected_freeze_creates_nothing_and_is_settled_when_the_encoder_reads_again() {
    // The freeze starts where joint 0 is slowest between 0.3 and 0.9 s.
    let start = slowest_sample_of_joint_0();
    let mut ctl = supervised(20.0);
    let (run, books) = run_with_hidden_work(&mut ctl, start + 200, |k| {
        (k >= start && k < start + 40).then_some(Glitch::Freeze(0))
    });
    let stretch = created_over_any_stretch(&run);
    assert!(stretch <= 1e-9, "{stretch:e} J created over a stretch");
    for (k, (_, created)) in run.iter().enumerate() {
        assert!(*created <= 1e-9, "{created:e} J created at sample {k}");
    }
    assert!(
        run[start..start + 40].iter().all(|(f, _)| f.is_none()),
        "the freeze was detected: not a test of an undetected one"
    );
    // Not a test of nothing: the frozen joint moved under its torque unseen, and that work
    // (the debt of a controller without the set-aside) was paid from what was set aside.
    assert!(
        books.most_hidden > 1e-6,
        "the freeze hid no work ({:e} J): not a test of the set-aside",
        books.most_hidden
    );
    // And what was set aside came back, less the bound on the stretch's work: here 2.8 of
    // the 7.6 J held are kept for 1.3 J of hidden work (the bound knows the stretch's
    // motion and torques, not how the joint moved between).
    assert!(
        books.kept <= 0.7 * books.most_held,
        "{books:?}: too little came back"
    );
    assert!(
        run[start + 40..].iter().any(|(f, _)| f.is_some()),
        "the catch-up was not seen"
    );
    let (_, settled) = run[run.len() - 1];
    assert!(settled <= 1e-9, "{settled:e} J still owed");
}

/// The readings are lost (NaN) while the drive keeps its torque: each period is charged the
/// most that torque can have done unseen, and when the readings come back, the balance over
/// the gap is not taken in credit (the robot may have given energy back meanwhile: the
/// charges already paid more than the gap's work, and a credit after them would show as
/// energy created since the gap began).
#[test]
fn a_gap_in_the_readings_is_not_settled_in_credit() {
    let mut worst: f64 = 0.0;
    for start in [300, 420, 555, 610, 777, 901] {
        let mut ctl = supervised(20.0);
        let run = run(&mut ctl, start + 100, |k| {
            (k >= start && k < start + 20).then_some(Glitch::NotANumberDropped(1))
        });
        assert!(run[start..start + 20].iter().all(|(f, _)| f.is_some()));
        worst = worst.max(created_over_any_stretch(&run));
    }
    assert!(worst <= 1e-9, "{worst:e} J created over a stretch");
}

/// A spike right after an undetected freeze, long enough to be taken for the frozen
/// encoder's catch-up (17 samples of −0.3 rad; the property test below found the kind), is
/// not trusted with the stretch's motion: what was set aside for the freeze comes back only
/// after the readings have moved cleanly for as long as the stretch lasted, by which time
/// the jump back has undone the spike. (Trusted at once, 90 mJ came back that the hidden
/// motion had used.)
#[test]
fn a_spike_taken_for_a_catch_up_gives_nothing_back() {
    let mut ctl = supervised(5.0);
    let (run, books) = run_with_hidden_work(&mut ctl, 700, |k| {
        if (433..462).contains(&k) {
            Some(Glitch::Freeze(1))
        } else if (462..479).contains(&k) {
            Some(Glitch::Spike(1, -0.3))
        } else {
            None
        }
    });
    assert!(books.most_hidden > 1e-3, "{books:?}: nothing hidden");
    let stretch = created_over_any_stretch(&run);
    assert!(stretch <= 1e-9, "{stretch:e} J created over a stretch");
    for (k, (_, created)) in run.iter().enumerate() {
        assert!(*created <= 1e-9, "{created:e} J created at sample {k}");
    }
}

/// A spike of two samples on a joint whose reading stands still is not a frozen encoder's
/// catch-up: a jump the joint could not have made at its speed bound (10 rad/s) while its
/// reading stood still (3 ms here: 0.03 rad against 0.3) is rejected at both samples, and the
/// true reading after it is taken at once. (Taken for a catch-up, the spike would become the
/// controller's position, and the truth after it would be rejected for 30 ms.)
#[test]
fn a_spike_of_two_samples_is_not_a_catch_up() {
    let start = slowest_sample_of_joint_0();
    let mut ctl = supervised(20.0);
    let run = run(&mut ctl, start + 60, |k| {
        if (start..start + 3).contains(&k) {
            Some(Glitch::Freeze(0))
        } else if (start + 3..start + 5).contains(&k) {
            Some(Glitch::Spike(0, 0.3))
        } else {
            None
        }
    });
    assert!(
        run[start..start + 3].iter().all(|(f, _)| f.is_none()),
        "the freeze was detected: the reading did not stand still unseen"
    );
    for (k, (fault, _)) in run.iter().enumerate().take(start + 5).skip(start + 3) {
        assert!(
            matches!(fault, Some(Fault::Speed { joint: 0 })),
            "sample {k}: {fault:?}"
        );
    }
    for (k, (fault, created)) in run.iter().enumerate().skip(start + 5) {
        assert_eq!(
            *fault, None,
            "sample {k}: the true reading after the spike was rejected"
        );
        assert!(*created <= 1e-9, "{created:e} J created at sample {k}");
    }
}

#[test]
fn a_frozen_encoder_is_latched_until_it_moves() {
    let mut ctl = supervised(20.0);
    // Joint 0 at 4 rad/s: it cannot stop within a millisecond at 2,000 rad/s².
    let mut q = Torus::new(Vector2::new(0.0, 0.0));
    for _ in 0..20 {
        ctl.step(&q, None, None, 1e-3).unwrap();
        q = Torus::new(q.angles() + Vector2::new(4e-3, 0.0));
    }
    let stuck = Torus::new(q.angles() - Vector2::new(4e-3, 0.0));
    ctl.step(&stuck, None, None, 1e-3).unwrap();
    for k in 0..30 {
        let out = ctl.step(&stuck, None, None, 1e-3).unwrap();
        assert_eq!(out.fault, Some(Fault::Frozen { joint: 0 }), "sample {k}");
        assert_eq!(out.torque, Vector2::zeros());
    }
    // It moves again, by what 4 rad/s can do in the time since the last good reading.
    let moved = Torus::new(stuck.angles() + Vector2::new(0.05, 0.0));
    assert_eq!(ctl.step(&moved, None, None, 1e-3).unwrap().fault, None);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Random glitches of every kind the controller detects or the drive reports, and frozen
    /// encoders (seen or not), over 1.2 s of the SCARA's loop: the energy the controller
    /// created (the drive's true work less the add-ons' reported energy and what its books
    /// gave) is at most rounding at every sample and over every stretch, and the loop ends
    /// with no fault (unless a joint is truly beyond its speed bound).
    #[test]
    fn faults_create_no_energy(
        events in prop::collection::vec(
            (50usize..1000, 0usize..8, 1usize..30, 0usize..2, 0.05f64..1.0, any::<bool>()),
            1..12,
        ),
        limit in 5.0f64..30.0,
    ) {
        let glitch = |k: usize| {
            events.iter().find(|e| k >= e.0 && k < e.0 + e.2).map(|&(_, kind, _, j, size, sign)| {
                let size = if sign { size } else { -size };
                match kind {
                    0 => Glitch::Spike(j, size),
                    1 => Glitch::NotANumber(j),
                    2 => Glitch::Period(5e-4 + 2.5e-3 * size),
                    3 => Glitch::Period(4e-3 + 4e-3 * size.abs()),
                    4 => Glitch::Dropped,
                    5 => Glitch::Late,
                    6 => Glitch::Freeze(j),
                    _ => Glitch::Limit(limit * size.abs()),
                }
            })
        };
        let mut ctl = supervised(limit);
        let (run, books) = run_with_hidden_work(&mut ctl, 1200, glitch);
        for (k, (_, created)) in run.iter().enumerate() {
            prop_assert!(*created <= 1e-9, "{created:e} J created at sample {k}");
        }
        let stretch = created_over_any_stretch(&run);
        prop_assert!(stretch <= 1e-9, "{stretch:e} J created over a stretch");
        // The loop ends with no fault, unless the drive's faults drove a joint beyond its
        // speed bound (10 rad/s): the supervision then rightly reports it, and zero torque on
        // this frictionless plant never slows it (a dropped command holding 12 N·m for 10 ms
        // does it to the light second link).
        let beyond = books.final_speed.iter().any(|v| v.abs() > 10.0);
        prop_assert!(
            run[1199].0.is_none() || beyond,
            "the loop ends at fault {:?} with the joints at {:?} rad/s",
            run[1199].0,
            books.final_speed
        );
    }
}

/// A step that fails right after a frozen encoder's catch-up is confirmed changes nothing:
/// the settlement is put back, and the same reading then settles it.
#[test]
fn a_failed_step_at_a_catch_up_changes_nothing() {
    let h = 1e-3;
    let start = slowest_sample_of_joint_0();
    // The loop of `run`, the drive applying what it was told, with joint 0's encoder frozen
    // over [start, start + 40): the truth read again at start + 40 is rejected, and the
    // reading at start + 41 confirms it.
    let mut ctl = supervised(20.0);
    let (mut q, mut v) = (Torus::new(Vector2::new(0.0, 0.0)), Vector2::<f64>::zeros());
    let mut applied = Vector2::zeros();
    let mut frozen = None;
    for k in 0..start + 41 {
        let mut reading = *q.angles();
        if (start..start + 40).contains(&k) {
            reading[0] = *frozen.get_or_insert(reading[0]);
        }
        let report = (k > 0).then_some(&applied);
        let out = ctl.step(&Torus::new(reading), None, report, h).unwrap();
        applied = out.torque;
        (q, v) = plant(q, v, applied, h, 10);
    }
    let reading = Torus::new(*q.angles());
    let mut settled = ctl;
    let ok = settled.step(&reading, None, Some(&applied), h).unwrap();
    assert!(
        ok.fault.is_none() && ok.energy.to_robot > 0.0,
        "the catch-up is not confirmed here: not a test of its undo ({ok:?})"
    );
    // A torque report whose work overflows what the storage can hold fails the step.
    let before = ctl;
    let m = f64::MAX;
    let huge = [[m, m], [-m, -m], [m, -m], [-m, m]]
        .map(Vector2::from)
        .into_iter()
        .find(|u| {
            let mut c = ctl;
            c.step(&reading, None, Some(u), h).is_err()
        })
        .expect("no torque report overflows: not a test of the undo");
    assert!(ctl.step(&reading, None, Some(&huge), h).is_err());
    assert_eq!(ctl, before, "a failed step changed the controller");
    // The same reading then settles the catch-up as it would have.
    assert_eq!(ctl.step(&reading, None, Some(&applied), h).unwrap(), ok);
}

/// A drive that gives less than the add-ons' torque (a lowered limit, a kept older command):
/// the add-ons' torque counts first, up to what was applied, and the coupling's storage pays
/// only for the rest; where the drive applied the command, the books are the command's.
#[test]
fn an_add_on_torque_the_drive_did_not_give_is_not_paid_from_the_storage() {
    let with_friction = || {
        PassiveController::new(
            controller(50.0, 1.0)
                .starting_at_rest(0.0)
                .with_friction_compensation(
                    FrictionCompensation::new(Vector2::new(2.0, 2.0)).unwrap(),
                ),
        )
    };
    let mut ctl: Passive = with_friction();
    let mut q = Torus::new(Vector2::new(0.0, 0.0));
    let mut last = ctl.step(&q, None, None, 1e-3).unwrap();
    for _ in 0..40 {
        q = Torus::new(q.angles() + Vector2::new(1e-3, -5e-4));
        last = ctl.step(&q, None, None, 1e-3).unwrap();
    }
    let (a, command) = (last.add_on, last.torque);
    assert!(
        a.iter().all(|x| x.abs() > 1.0),
        "friction compensation at work: {a}"
    );
    let dq = Vector2::new(1e-3, -5e-4);
    let next = Torus::new(q.angles() + dq);
    // The drive applied half the add-ons' torque on each joint: all of it is theirs.
    let mut short = ctl;
    let half = a * 0.5;
    let out = short.step(&next, None, Some(&half), 1e-3).unwrap();
    assert_eq!(out.energy.to_robot, 0.0);
    assert!((out.energy.add_ons - half.dot(&dq)).abs() < 1e-15);
    // Against the add-ons' side on joint 0: nothing of it is theirs there.
    let mut against = ctl;
    let other = Vector2::new(-a[0], a[1] * 0.5);
    let out = against.step(&next, None, Some(&other), 1e-3).unwrap();
    assert!((out.energy.to_robot - other[0] * dq[0]).abs() < 1e-15);
    // The command applied: the coupling's share is the command less the add-ons'.
    let mut full = ctl;
    let out = full.step(&next, None, Some(&command), 1e-3).unwrap();
    assert!((out.energy.to_robot - (command - a).dot(&dq)).abs() < 1e-15);
    assert!((out.energy.add_ons - a.dot(&dq)).abs() < 1e-15);
}
