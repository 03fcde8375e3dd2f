//! The UR5 (6 joints) and the Franka Panda (7) from their URDFs (`models/`, copies of
//! example-robot-data's): the free chain conserves energy under gravity, and PVFC with gravity
//! compensation keeps κ_a constant and converges onto a joint-space contour.

use nalgebra::SVector;
use pvfc::prelude::*;
use pvfc_core::augmented::AugmentedState;
use pvfc_sim::urdf::ChainDescription;
use pvfc_sim::ClosedLoop;
use std::path::Path;

fn arm<const N: usize>(file: &str, tip: &str) -> SerialChain<f64, N> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("models")
        .join(file);
    ChainDescription::from_file(&path, None, Some(tip))
        .unwrap()
        .chain::<N>()
        .unwrap()
}

/// A closed joint-space contour of the UR5 (the waypoints of `scenarios/ur5_waypoints.toml`'s
/// kind, rad).
const UR5_WAYPOINTS: [[f64; 6]; 6] = [
    [0.0, -1.2, 1.4, -1.8, -1.57, 0.0],
    [0.5, -1.0, 1.2, -1.7, -1.4, 0.3],
    [0.8, -1.4, 1.6, -1.6, -1.2, 0.6],
    [0.3, -1.7, 1.9, -1.9, -1.5, 0.2],
    [-0.3, -1.5, 1.7, -2.0, -1.8, -0.3],
    [-0.5, -1.1, 1.3, -1.8, -1.7, -0.4],
];

fn ur5() -> SerialChain<f64, 6> {
    arm("ur5/ur5_robot.urdf", "tool0")
}

fn panda() -> SerialChain<f64, 7> {
    arm("panda/panda.urdf", "panda_hand_tcp")
}

/// Total energy `½ vᵀ M v + V(q)` of the free chain, `V = −Σ m_i gᵀ c_i`.
fn energy<const N: usize>(
    c: &SerialChain<f64, N>,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> f64 {
    let k = c.kinematics(q);
    let potential: f64 = (0..N)
        .map(|i| {
            let l = &c.links()[i];
            -l.mass
                * c.gravity_vector()
                    .dot(&k.link_poses[i].transform_point(&l.com))
        })
        .sum();
    0.5 * v.dot(&(c.dynamics(q, v).0 * v)) + potential
}

/// The free chain (no torque) falling under gravity for 10 s, RK4 at 4 kHz. (The fall is
/// chaotic: at 2 kHz the Panda's error moved between 7e-8 and 1.8e-7 with rounding-level
/// changes of the model; the error is RK4's, 4th order in the step.)
fn free_fall<const N: usize>(c: &SerialChain<f64, N>) -> f64 {
    let q0 = c.configuration(SVector::from_fn(|i, _| 0.3 * (i as f64 + 1.0).sin()));
    let mut x = (q0, SVector::<f64, N>::zeros());
    let acc = |q: &JointSpace<f64, N>, v: &SVector<f64, N>| {
        c.acceleration(q, v, &SVector::zeros()).unwrap()
    };
    let e0 = energy(c, x.0.coords(), &x.1);
    let dt = 2.5e-4;
    let mut worst: f64 = 0.0;
    let mut scale: f64 = 1.0;
    for _ in 0..40_000 {
        let (q, v) = x;
        let k1 = (v, acc(&q, &v));
        let s2 = (q.retract(&k1.0, dt / 2.0), v + k1.1 * (dt / 2.0));
        let k2 = (s2.1, acc(&s2.0, &s2.1));
        let s3 = (q.retract(&k2.0, dt / 2.0), v + k2.1 * (dt / 2.0));
        let k3 = (s3.1, acc(&s3.0, &s3.1));
        let s4 = (q.retract(&k3.0, dt), v + k3.1 * dt);
        let k4 = (s4.1, acc(&s4.0, &s4.1));
        x = (
            q.retract(&(k1.0 + k2.0 * 2.0 + k3.0 * 2.0 + k4.0), dt / 6.0),
            v + (k1.1 + k2.1 * 2.0 + k3.1 * 2.0 + k4.1) * (dt / 6.0),
        );
        let ke = 0.5 * x.1.dot(&(c.dynamics(x.0.coords(), &x.1).0 * x.1));
        scale = scale.max(ke);
        worst = worst.max((energy(c, x.0.coords(), &x.1) - e0).abs());
    }
    // Relative to the largest kinetic energy the fall reached.
    worst / scale
}

#[test]
fn free_chains_conserve_energy_under_gravity() {
    let ur5 = free_fall(&ur5());
    let panda = free_fall(&panda());
    println!("free fall, 10 s, RK4 at 4 kHz: |ΔE|/max KE: UR5 {ur5:.1e}, Panda {panda:.1e}");
    assert!(ur5 < 1e-7, "UR5 energy drift {ur5:e}");
    assert!(panda < 1e-7, "Panda energy drift {panda:e}");
}

/// The integration step (RK4). The κ_a drift is the integrator's truncation error: measured
/// 2.7e-7, 1.7e-8 and 1.1e-9 (UR5) at 1, 0.5 and 0.25 ms, a factor 16 per halving (4th order).
const DT: f64 = 2.5e-4;

type ArmField<const N: usize, const K: usize> = SuspendedField<
    f64,
    JointSpace<f64, N>,
    PeriodicBSpline<f64, JointSpace<f64, N>, N, K>,
    JointNavigation<f64, N>,
    ExponentialPacing<f64>,
    N,
>;
type ArmCtl<const N: usize, const K: usize> =
    Controller<f64, JointSpace<f64, N>, SerialChain<f64, N>, ArmField<N, K>, N>;
type ArmLoop<const N: usize, const K: usize> = ClosedLoop<
    f64,
    JointSpace<f64, N>,
    SerialChain<f64, N>,
    SerialChain<f64, N>,
    ArmField<N, K>,
    N,
>;

/// PVFC through `K` joint waypoints (one per unit of `τ`), `h = 4`, `R = 50`, `Ē = 40`,
/// `γ = 1`, with gravity compensation.
fn arm_controller<const N: usize, const K: usize>(
    chain: SerialChain<f64, N>,
    waypoints: [[f64; N]; K],
) -> ArmCtl<N, K> {
    let kinds = chain.kinds();
    let pts = waypoints.map(|w| JointSpace::new(SVector::from(w), kinds));
    let field = SuspendedField::new(
        PeriodicBSpline::through(pts, 1.0).unwrap(),
        JointNavigation::new(SVector::repeat(4.0), kinds).unwrap(),
        ExponentialPacing::new(50.0).unwrap(),
    );
    let law = PvfcLaw::new(chain, field, Flywheel::new(1.0, 40.0).unwrap(), 1.0).unwrap();
    Controller::new(law).with_gravity_compensation()
}

/// PVFC with gravity compensation through `K` waypoints, frictionless, from rest off the
/// contour: (max |κ_a − κ_a(0)|/κ_a(0), U(0), U at 10 s).
fn pvfc_run<const N: usize, const K: usize>(
    chain: SerialChain<f64, N>,
    waypoints: [[f64; N]; K],
) -> (f64, f64, f64) {
    let kinds = chain.kinds();
    let ctl = arm_controller(chain, waypoints);
    let lp: ArmLoop<N, K> = ClosedLoop::matched(ctl);
    let first = SVector::from(waypoints[0]);
    let mut s = AugmentedState {
        q: JointSpace::new(first + SVector::repeat(0.25), kinds),
        v: SVector::zeros(),
        tau: 0.0,
        tau_dot: 0.0,
        flywheel_speed: (2.0f64 * 40.0).sqrt(),
    };
    let nav = |s: &AugmentedState<f64, JointSpace<f64, N>, N>| {
        lp.controller.evaluate(s).unwrap().1.field.potential
    };
    let k0 = lp.kinetic_energy(&s);
    let u0 = nav(&s);
    let mut drift: f64 = 0.0;
    let steps = (10.0 / DT).round() as usize;
    for _ in 0..steps {
        s = lp.rk4_step(&s, DT, &SVector::zeros()).unwrap();
        drift = drift.max((lp.kinetic_energy(&s) - k0).abs() / k0);
    }
    (drift, u0, nav(&s))
}

#[test]
fn pvfc_on_the_ur5_and_the_panda_is_passive_and_converges() {
    let ur5 = pvfc_run(ur5(), UR5_WAYPOINTS);
    let panda = pvfc_run(
        panda(),
        [
            [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8],
            [0.4, -0.1, 0.2, -2.0, 0.2, 2.1, 1.0],
            [0.7, -0.4, 0.3, -1.8, 0.1, 1.8, 1.2],
            [0.3, -0.7, 0.1, -2.3, -0.2, 1.7, 0.9],
            [-0.3, -0.5, -0.2, -2.5, -0.1, 2.0, 0.6],
            [-0.5, -0.2, -0.3, -2.1, 0.2, 2.2, 0.5],
        ],
    );
    println!("UR5: drift {:.1e}, U {:.2e} -> {:.2e}", ur5.0, ur5.1, ur5.2);
    println!(
        "Panda: drift {:.1e}, U {:.2e} -> {:.2e}",
        panda.0, panda.1, panda.2
    );
    for (name, (drift, u0, u_end)) in [("UR5", ur5), ("Panda", panda)] {
        assert!(drift <= 1e-8, "{name}: κ_a drift {drift:e}");
        assert!(u_end < 1e-3 * u0, "{name}: U {u0:e} -> {u_end:e}");
    }
}

/// The passive digital controller (`pvfc_core::passive`) on the UR5 with gravity and gravity
/// compensation, frictionless, from rest off the contour, at 1 kHz, 250 Hz and 100 Hz; the plant
/// RK4 at 20 kHz. At every sample, the arm's energy (kinetic + potential) plus the controller's
/// storage changes by exactly the add-ons' work (here the gravity compensation's,
/// `g(q_k)ᵀΔq`), to the plant integrator's error; `U` converges. `Controller::step` beside it.
#[test]
fn the_passive_controller_on_the_ur5_closes_its_audit_with_gravity() {
    let chain = ur5();
    let kinds = chain.kinds();
    let waypoints = UR5_WAYPOINTS;
    let base = arm_controller(chain, waypoints).starting_at_rest(0.0);
    let plant_dt = 5e-5;
    for rate in [1000.0f64, 250.0, 100.0] {
        let dt = 1.0 / rate;
        let sub = (dt / plant_dt).round() as usize;
        let run = |passive: bool| {
            let mut pc = pvfc_core::passive::PassiveController::new(base);
            let mut zoh = base;
            let mut q = JointSpace::new(SVector::from(waypoints[0]) + SVector::repeat(0.25), kinds);
            let mut v = SVector::<f64, 6>::zeros();
            let kappa0 = pc.storage();
            let e0 = energy(&chain, q.coords(), &v) + kappa0;
            let mut add_ons = 0.0;
            let mut worst: f64 = 0.0;
            let mut u_first = None;
            let mut u_last = 0.0;
            for _ in 0..(3.0 * rate) as usize {
                let (torque, storage, u) = if passive {
                    let out = pc.step(&q, Some(&v), None, dt).unwrap();
                    add_ons += out.energy.add_ons;
                    (out.torque, out.energy.storage, out.diagnostics.potential)
                } else {
                    let pre = *zoh.state();
                    let out = zoh.step(&q, &v, dt).unwrap();
                    // The ZOH controller's add-on (gravity compensation) at the sample,
                    // rectangle rule as the SCARA's sampled loop counts it.
                    let g = chain.gravity_torque(q.coords());
                    add_ons += g.dot(&v) * dt;
                    let s = 0.5 * (pre.tau_dot.powi(2) + pre.flywheel_speed.powi(2));
                    (out.torque, s, out.diagnostics.potential)
                };
                let e = energy(&chain, q.coords(), &v) + storage;
                worst = worst.max((e - e0 - add_ons).abs() / kappa0);
                u_first.get_or_insert(u);
                u_last = u;
                for _ in 0..sub {
                    (q, v) = rk4(&chain, &q, &v, &torque, plant_dt);
                }
            }
            (worst, u_first.unwrap_or(0.0), u_last)
        };
        let (audit, u0, u_end) = run(true);
        let (zoh_audit, _, _) = run(false);
        println!(
            "UR5 at {rate} Hz: passive audit {audit:.1e}, ZOH {zoh_audit:.1e} of κ_a(0); U {u0:.2e} -> {u_end:.2e}"
        );
        assert!(audit <= 1e-8, "{rate} Hz: audit {audit:e}");
        assert!(u_end < 1e-2 * u0, "{rate} Hz: U {u0:e} -> {u_end:e}");
    }
}

/// One RK4 step of the chain under a held torque (gravity in the plant).
fn rk4<const N: usize>(
    c: &SerialChain<f64, N>,
    q: &JointSpace<f64, N>,
    v: &SVector<f64, N>,
    u: &SVector<f64, N>,
    h: f64,
) -> (JointSpace<f64, N>, SVector<f64, N>) {
    let acc = |q: &JointSpace<f64, N>, v: &SVector<f64, N>| c.acceleration(q, v, u).unwrap();
    let a1 = acc(q, v);
    let (q2, v2) = (q.retract(v, 0.5 * h), v + a1 * (0.5 * h));
    let a2 = acc(&q2, &v2);
    let (q3, v3) = (q.retract(&v2, 0.5 * h), v + a2 * (0.5 * h));
    let a3 = acc(&q3, &v3);
    let (q4, v4) = (q.retract(&v3, h), v + a3 * h);
    let a4 = acc(&q4, &v4);
    (
        q.retract(&((v + v2 * 2.0 + v3 * 2.0 + v4) / 6.0), h),
        v + (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0),
    )
}

/// Damped-least-squares inverse kinematics on the UR5 (position and pose) and the Panda
/// (position, with a pull towards a rest posture): reachable targets from perturbed seeds
/// converge to 1e-9 m; an unreachable one is a `NoConvergence` error carrying the distance
/// left; the manipulability vanishes at the UR5's elbow singularity.
#[test]
fn inverse_kinematics_reaches_what_it_can_and_says_what_it_cannot() {
    use pvfc::core::mechanics::{IkSettings, IkTarget};
    let ur = ur5();
    let s = IkSettings::default();
    let mut worst: f64 = 0.0;
    for k in 0..50 {
        let x = k as f64;
        let q_star = SVector::<f64, 6>::from_fn(|i, _| 1.2 * (0.7 * x + 1.3 * i as f64).sin());
        let seed = q_star + SVector::from_fn(|i, _| 0.2 * (2.1 * x + i as f64).cos());
        let target = ur.tool_pose(&q_star);
        let q = ur
            .inverse_kinematics(&IkTarget::Position(target.translation), &seed, &s)
            .unwrap();
        worst = worst.max((ur.tool_pose(&q).translation - target.translation).norm());
        let q = ur
            .inverse_kinematics(&IkTarget::Pose(target), &seed, &s)
            .unwrap();
        let reached = ur.tool_pose(&q);
        worst = worst.max((reached.translation - target.translation).norm());
        assert!(
            (reached.rotation - target.rotation).amax() < 1e-8,
            "pose {k}"
        );
    }
    assert!(worst <= 1e-9, "IK position error {worst:e}");
    let far = ur.inverse_kinematics(
        &IkTarget::Position(nalgebra::Vector3::new(5.0, 0.0, 0.0)),
        &SVector::repeat(0.3),
        &s,
    );
    let e = far.unwrap_err();
    assert_eq!(e.kind(), pvfc::core::ErrorKind::NoConvergence);
    assert!(e.value().unwrap() > 3.0, "{e}");
    // The planar two-link arm's manipulability in closed form, l₁ l₂ |sin q₂| (0 stretched).
    let scara = arm::<2>("scara.urdf", "tool");
    for q2 in [0.0, 0.4, 1.5, -2.5] {
        let m = scara.manipulability(&SVector::from([0.7, q2]));
        assert!(
            (m - 0.4 * 0.35 * f64::sin(q2).abs()).abs() < 1e-12,
            "q2 = {q2}: {m}"
        );
    }

    // The Panda (7 joints): with a pull towards a rest posture it reaches the target and stays
    // nearer the rest than without.
    let panda = panda();
    let rest = SVector::<f64, 7>::from([0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8]);
    let target = panda.tool_pose(&SVector::from([0.3, -0.1, 0.2, -2.0, 0.1, 2.1, 1.0]));
    let free = panda
        .inverse_kinematics(
            &IkTarget::Position(target.translation),
            &rest,
            &IkSettings::default(),
        )
        .unwrap();
    let pulled = panda
        .inverse_kinematics(
            &IkTarget::Position(target.translation),
            &rest,
            &IkSettings {
                rest: Some((rest, 0.1)),
                ..IkSettings::default()
            },
        )
        .unwrap();
    assert!((panda.tool_pose(&pulled).translation - target.translation).norm() <= 1e-9);
    assert!((pulled - rest).norm() <= (free - rest).norm() + 1e-12);
}
