//! The firmware's host twin: the closed loop of `examples/firmware` (the same `hil.rs`) in
//! f64 and in f32 on the host. `firmware_trace_matches_the_host_twin` compares the trace the
//! firmware printed in QEMU (file named by `PVFC_FIRMWARE_TRACE`; CI runs it with
//! `scripts/firmware.sh`) with the twins.

#[path = "../examples/firmware/src/hil.rs"]
#[allow(dead_code)]
mod hil;

use hil::{Plant, Sample, STEPS, TRACE_EVERY};
use pvfc::prelude::*;
use pvfc_core::nalgebra::Vector2;
use pvfc_core::scalar::cast;

/// The firmware's SysTick handler, step for step, in the scalar `T`.
fn twin<T: Real>() -> Vec<Sample<f64>> {
    let mut ctl = hil::controller::<T>().unwrap();
    let mut plant = Plant::<T>::default();
    let f = |x: T| nalgebra::try_convert::<T, f64>(x).unwrap();
    let mut out = vec![];
    for step in 0..STEPS {
        let (q, v) = (plant.q, plant.v);
        let o = ctl
            .step(&Torus::new(q), &v, cast(hil::DT))
            .expect("no fault on the host");
        if step % TRACE_EVERY == 0 {
            let s = ctl.state();
            let mf = ctl.law().flywheel().inertia();
            out.push(Sample {
                step,
                q: [f(q[0]), f(q[1])],
                torque: [f(o.torque[0]), f(o.torque[1])],
                tau: f(s.unwrapped_tau(ctl.law().field().period())),
                potential: f(o.diagnostics.potential),
                kinetic_energy: f(plant.kinetic_energy()
                    + cast::<T>(0.5)
                        * (s.tau_dot * s.tau_dot + mf * s.flywheel_speed * s.flywheel_speed)),
            });
        }
        let torque: Vector2<T> = o.torque;
        plant.advance(&torque);
    }
    out
}

#[test]
fn the_host_twin_follows_the_contour() {
    let t = twin::<f64>();
    let (first, last) = (t[0], t[t.len() - 1]);
    assert!(
        last.potential < 0.05 * first.potential,
        "U {} -> {}",
        first.potential,
        last.potential
    );
    assert!(last.tau > 1.5, "τ advanced {}", last.tau);
    // Viscous friction is not compensated: κ_a only falls.
    assert!(last.kinetic_energy < first.kinetic_energy);
}

/// Parses the firmware's trace: scaled integers (q in µrad, torque in mN·m, τ in 1e-6,
/// U in 1e-9, κ_a in µJ).
fn parse(text: &str) -> Vec<Sample<f64>> {
    text.lines()
        .filter(|l| l.chars().next().is_some_and(|c| c.is_ascii_digit()))
        .map(|l| {
            let x: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            Sample {
                step: x[0] as usize,
                q: [x[1] * 1e-6, x[2] * 1e-6],
                torque: [x[3] * 1e-3, x[4] * 1e-3],
                tau: x[5] * 1e-6,
                potential: x[6] * 1e-9,
                kinetic_energy: x[7] * 1e-6,
            }
        })
        .collect()
}

/// The largest difference over the run: q (rad), τ, U, κ_a (J).
fn worst(a: &[Sample<f64>], b: &[Sample<f64>]) -> [f64; 4] {
    let mut w = [0.0f64; 4];
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.step, y.step);
        w[0] = w[0].max((x.q[0] - y.q[0]).abs().max((x.q[1] - y.q[1]).abs()));
        w[1] = w[1].max((x.tau - y.tau).abs());
        w[2] = w[2].max((x.potential - y.potential).abs());
        w[3] = w[3].max((x.kinetic_energy - y.kinetic_energy).abs());
    }
    w
}

#[test]
#[ignore = "needs the firmware's trace: scripts/firmware.sh runs it"]
fn firmware_trace_matches_the_host_twin() {
    let path = std::env::var("PVFC_FIRMWARE_TRACE").expect("PVFC_FIRMWARE_TRACE names the trace");
    let fw = parse(&std::fs::read_to_string(&path).unwrap());
    assert_eq!(
        fw.len(),
        STEPS / TRACE_EVERY,
        "the firmware printed every sample"
    );
    let host64 = twin::<f64>();
    let host32 = twin::<f32>();
    let vs64 = worst(&fw, &host64);
    let vs32 = worst(&fw, &host32);
    let f32_vs_f64 = worst(&host32, &host64);
    println!(
        "firmware vs host f64: max |Δq| {:.2e} rad, |Δτ| {:.2e}, |ΔU| {:.2e}, |Δκ_a| {:.2e} J",
        vs64[0], vs64[1], vs64[2], vs64[3]
    );
    println!(
        "firmware vs host f32: max |Δq| {:.2e} rad, |Δτ| {:.2e}, |ΔU| {:.2e}, |Δκ_a| {:.2e} J",
        vs32[0], vs32[1], vs32[2], vs32[3]
    );
    println!(
        "host f32 vs host f64: max |Δq| {:.2e} rad, |Δτ| {:.2e}, |ΔU| {:.2e}, |Δκ_a| {:.2e} J",
        f32_vs_f64[0], f32_vs_f64[1], f32_vs_f64[2], f32_vs_f64[3]
    );
    // The printed trace is quantised (1 µrad, 1e-6 in τ, 1e-9 in U, 1 µJ). The target and the
    // host in f32 run the same arithmetic but for the square root (the host's hardware one,
    // the target's `Real::sqrt_fast`): measured ≤ 1.2e-6 rad, about the print's resolution;
    // bound 1e-5 rad.
    // Against f64: f32 rounding (6e-8 relative per operation) through a loop that converges
    // onto the contour, where errors do not grow: measured 2.7e-5 rad over 10 s; bound 2e-4 rad
    // (relative 1.5e-4 of the arm's ~1.3 rad excursion), and 2e-4 in τ.
    assert!(vs32[0] < 1e-5, "q: firmware vs host f32 {:e} rad", vs32[0]);
    assert!(vs64[0] < 2e-4, "q: firmware vs host f64 {:e} rad", vs64[0]);
    assert!(vs64[1] < 2e-4, "τ: firmware vs host f64 {:e}", vs64[1]);
    assert!(vs64[3] < 2e-2, "κ_a: firmware vs host f64 {:e} J", vs64[3]);
}

#[path = "../examples/firmware/src/ur5.rs"]
mod ur5;

/// The firmware's UR5 constants are what the URDF reader gives for `models/ur5` (tip `tool0`).
#[test]
fn the_firmware_ur5_constants_match_the_urdf() {
    let d = pvfc_sim::urdf::ChainDescription::from_file(
        std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/ur5/ur5_robot.urdf"
        )),
        None,
        Some("tool0"),
    )
    .unwrap();
    let m3 = |m: &[[f64; 3]; 3]| nalgebra::Matrix3::from_fn(|i, j| m[i][j]);
    for (j, (r, t, a)) in d.joints.iter().zip(ur5::JOINTS) {
        assert_eq!(j.joint.origin.rotation, m3(&r));
        assert_eq!(j.joint.origin.translation, nalgebra::Vector3::from(t));
        assert_eq!(j.joint.axis, nalgebra::Vector3::from(a));
    }
    for (l, (m, c, i)) in d.links.iter().zip(ur5::LINKS) {
        assert_eq!(
            (l.mass, l.com, l.inertia),
            (m, nalgebra::Vector3::from(c), m3(&i))
        );
    }
    assert_eq!(d.tool.rotation, m3(&ur5::TOOL.0));
    assert_eq!(d.tool.translation, nalgebra::Vector3::from(ur5::TOOL.1));
}
