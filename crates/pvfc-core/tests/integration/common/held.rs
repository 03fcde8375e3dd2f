//! The SCARA (the paper's Pelican arm) over one held period, for the passive controller's
//! energy balance: RK4 in substeps under a constant torque, frictionless.

use nalgebra::Vector2;
use pvfc_core::prelude::*;

/// The plant over one held period `h`: RK4 in `n` substeps under the torque `u`.
pub fn plant(
    q: Torus<f64, 2>,
    v: Vector2<f64>,
    u: Vector2<f64>,
    h: f64,
    n: usize,
) -> (Torus<f64, 2>, Vector2<f64>) {
    let arm = Scara::<f64>::pelican();
    let dt = h / n as f64;
    let (mut q, mut v) = (q, v);
    let acc = |q: &Torus<f64, 2>, v: &Vector2<f64>| arm.acceleration(q, v, &u).unwrap();
    for _ in 0..n {
        let a1 = acc(&q, &v);
        let (q2, v2) = (q.retract(&v, 0.5 * dt), v + a1 * (0.5 * dt));
        let a2 = acc(&q2, &v2);
        let (q3, v3) = (q.retract(&v2, 0.5 * dt), v + a2 * (0.5 * dt));
        let a3 = acc(&q3, &v3);
        let (q4, v4) = (q.retract(&v3, dt), v + a3 * dt);
        let a4 = acc(&q4, &v4);
        q = q.retract(&((v + v2 * 2.0 + v3 * 2.0 + v4) / 6.0), dt);
        v += (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (dt / 6.0);
    }
    (q, v)
}

/// The arm's kinetic energy `½q̇ᵀM(q)q̇`.
pub fn kinetic(q: &Torus<f64, 2>, v: &Vector2<f64>) -> f64 {
    Scara::<f64>::pelican().kinetic_energy(q, v)
}

/// A passive step at `(q, v)` over the period `h`: `(torque, storage, add-ons' work)`.
pub type Step<'a> = dyn FnMut(&Torus<f64, 2>, &Vector2<f64>, f64) -> (Vector2<f64>, f64, f64) + 'a;

/// `warm` periods of `h` (so that whatever the controller adapts has moved), then the
/// balance of one held period: the kinetic energy plus the storage after, minus before, minus
/// the add-ons' work, and the energy before.
pub fn held_balance(
    step: &mut Step<'_>,
    q: Torus<f64, 2>,
    v: Vector2<f64>,
    h: f64,
    warm: usize,
) -> (f64, f64) {
    let (mut q0, mut v0) = (q, v);
    for _ in 0..warm {
        let (u, _, _) = step(&q0, &v0, h);
        (q0, v0) = plant(q0, v0, u, h, 20);
    }
    let (u, s0, _) = step(&q0, &v0, h);
    let (q1, v1) = plant(q0, v0, u, h, 200);
    let (_, s1, add_ons) = step(&q1, &v1, h);
    let before = kinetic(&q0, &v0) + s0;
    let after = kinetic(&q1, &v1) + s1;
    (after - before - add_ons, before)
}
