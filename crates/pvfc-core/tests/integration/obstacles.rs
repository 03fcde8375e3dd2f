//! Obstacles through navigation functions (Remark 3): the composed function's critical points,
//! the field's flow around obstacles, and the property suites' coverage of the barrier.

use crate::common;

use common::setups::*;
use common::vec;
use nalgebra::Vector2;
use pvfc_core::obstacle::{ObstacleSet, Obstacles};
use pvfc_core::prelude::*;

/// The composed function `φ(q)` at a fixed `τ` of the Pelican around [`scara_obstacle_set`].
fn phi(field: &impl VelocityField<f64, Torus<f64, 2>, 2>, q: Vector2<f64>, tau: f64) -> f64 {
    let (z, _) = (Vector2::zeros(), 0.0);
    field.sample(&Torus::new(q), &z, tau, 0.0).potential
}

fn params() -> Params {
    Params {
        r: 1.0,
        gamma: 0.05,
        h: [1.0, 1.0, 1.0],
    }
}

/// The contour keeps a clearance from every obstacle (the composition's first condition).
#[test]
fn the_contour_is_clear_of_the_obstacles() {
    for set in [scara_obstacle_set::<f64>(), scara_ball_world(2.0)] {
        let contour = Lissajous::<f64, 2>::paper();
        let smallest = (0..6000)
            .map(|k| {
                let x: Torus<f64, 2> = contour.point(k as f64 * 1e-3);
                set.clearance(x.angles()).unwrap()
            })
            .fold(f64::INFINITY, f64::min);
        println!("the contour's smallest clearance: {smallest:.4}");
        assert!(smallest > 0.05, "{smallest}");
    }
}

/// The local minima of `φ(·, τ)` on a grid of the free joint space (`β > 0`).
fn grid_minima<F>(field: &F, set: &ObstacleSet<f64, 2>, tau: f64) -> Vec<Vector2<f64>>
where
    F: VelocityField<f64, Torus<f64, 2>, 2>,
{
    let n = 160;
    let step = 2.0 * std::f64::consts::PI / n as f64;
    let at = |i: usize, j: usize| {
        Vector2::new(
            -std::f64::consts::PI + i as f64 * step,
            -std::f64::consts::PI + j as f64 * step,
        )
    };
    {
        let values: Vec<Vec<Option<f64>>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let q = at(i, j);
                        (set.barrier(&Torus::new(q), &Vector2::zeros())
                            .unwrap()
                            .0
                            .value
                            > 0.0)
                            .then(|| phi(field, q, tau))
                    })
                    .collect()
            })
            .collect();
        let mut minima = vec![];
        for i in 0..n {
            for j in 0..n {
                let Some(v) = values[i][j] else { continue };
                let lower = (0..9).filter(|k| *k != 4).all(|k| {
                    let (a, b) = ((i + n + k / 3 - 1) % n, (j + n + k % 3 - 1) % n);
                    values[a][b].is_none_or(|w| v <= w)
                });
                if lower {
                    minima.push(at(i, j));
                }
            }
        }
        for m in &minima {
            let (b, _) = set.barrier(&Torus::new(*m), &Vector2::zeros()).unwrap();
            println!(
                "  minimum at {:?}: φ = {:.4}, β = {:.4}, clearance {:.4}",
                m.as_slice(),
                phi(field, *m, tau),
                b.value,
                set.clearance(m).unwrap()
            );
        }
        minima
    }
}

/// Rimon–Koditschek: in a sphere world of the joint space, at several `τ`, `φ` has one local
/// minimum, at the contour's point, on a grid of the free space where `U` is convex
/// (`|E_i| < π/2` on the torus, where it behaves as the squared distance RK's proof assumes).
/// Beyond, `U`'s gradient fades towards its saddles at `E_i = π`, and a ball there can hold a
/// minimum behind it: printed, not asserted.
#[test]
fn the_composed_function_has_one_minimum_in_a_sphere_world() {
    for kappa in [2.0, 4.0] {
        let set = scara_ball_world::<f64>(kappa);
        let field = Law::new(params(), set).field;
        for tau in [0.0, 1.1, 2.5, 4.2] {
            println!("κ = {kappa}, τ = {tau}:");
            let x: Torus<f64, 2> = Lissajous::paper().point(tau);
            let convex = |m: &Vector2<f64>| {
                (m - x.angles())
                    .iter()
                    .all(|e| e.sin().atan2(e.cos()).abs() < std::f64::consts::FRAC_PI_2)
            };
            let minima: Vec<_> = grid_minima(&field, &set, tau)
                .into_iter()
                .filter(convex)
                .collect();
            assert_eq!(minima.len(), 1, "κ = {kappa}, τ = {tau}: {minima:?}");
            assert!((minima[0] - x.angles()).norm() < 0.08);
        }
    }
}

/// The field's flow (`q̇ = V_G`, `τ̇ = V_I`, RK4) from `q` at `τ = 0` for 40 s: the smallest
/// clearance on the way and `φ` at the end.
fn flow<F>(field: &F, set: &ObstacleSet<f64, 2>, start: Vector2<f64>) -> (f64, f64)
where
    F: VelocityField<f64, Torus<f64, 2>, 2>,
{
    let v = |q: Vector2<f64>, tau: f64| {
        let s = field.sample(&Torus::new(q), &Vector2::zeros(), tau, 0.0);
        (s.velocity, s.velocity_tau)
    };
    let (mut q, mut tau, h) = (start, 0.0, 4e-3);
    let mut smallest = f64::INFINITY;
    for _ in 0..10_000 {
        let (k1, t1) = v(q, tau);
        let (k2, t2) = v(q + k1 * (h / 2.0), tau + t1 * h / 2.0);
        let (k3, t3) = v(q + k2 * (h / 2.0), tau + t2 * h / 2.0);
        let (k4, t4) = v(q + k3 * h, tau + t3 * h);
        q += (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        tau += (t1 + 2.0 * t2 + 2.0 * t3 + t4) * h / 6.0;
        smallest = smallest.min(set.clearance(&q).unwrap());
    }
    (smallest, phi(field, q, tau))
}

/// From every start of a grid of the free joint space (the forearm behind the post and the
/// ball included), the field's flow reaches the contour around the obstacles and keeps their
/// margin, in the task-space world and in the sphere world.
#[test]
fn flows_from_everywhere_reach_the_contour_around_the_obstacles() {
    for (name, set, margin) in [
        ("task space", scara_obstacle_set::<f64>(), 0.01),
        ("sphere world", scara_ball_world(2.0), 0.0),
    ] {
        let field = Law::new(params(), set).field;
        let (mut starts, mut worst_clearance, mut worst_phi) = (0, f64::INFINITY, 0.0_f64);
        for i in 0..8 {
            for j in 0..8 {
                let q = vec([-2.9 + i as f64 * 0.8, -2.9 + j as f64 * 0.8]);
                if set.clearance(&q).unwrap() < margin + 0.02 {
                    continue;
                }
                let (clearance, end) = flow(&field, &set, q);
                assert!(
                    clearance > margin,
                    "{name}: from {q:?}: clearance {clearance}"
                );
                assert!(end < 1e-6, "{name}: from {q:?}: φ = {end} at the end");
                starts += 1;
                worst_clearance = worst_clearance.min(clearance);
                worst_phi = worst_phi.max(end);
            }
        }
        println!("{name}: {starts} starts, smallest clearance {worst_clearance:.4}, largest final φ {worst_phi:.1e}");
        assert!(starts > 40);
    }
}

/// The property suites of `control_law.rs` draw states where the barrier acts.
#[test]
fn the_property_suites_meet_the_barrier() {
    let set = scara_obstacle_set::<f64>();
    let mut acting = 0;
    let total = 2000;
    for k in 0..total {
        let a = (k as f64 * 0.618_033_988_7).fract();
        let b = (k as f64 * 0.754_877_666_2).fract();
        let q = Torus::new(vec([(2.0 * a - 1.0) * 3.1, (2.0 * b - 1.0) * 3.1]));
        let (barrier, _) = set.barrier(&q, &Vector2::zeros()).unwrap();
        if barrier.value < 1.0 {
            acting += 1;
        }
    }
    println!("the barrier acts at {acting} of {total} states");
    assert!(acting * 10 > total, "{acting} of {total}");
}

/// The paper's field around a set.
struct Law<F> {
    field: F,
}

impl Law<()> {
    #[allow(clippy::new_ret_no_self)]
    fn new(p: Params, set: ObstacleSet<f64, 2>) -> Law<impl VelocityField<f64, Torus<f64, 2>, 2>> {
        Law {
            field: (*scara_lissajous::<f64>(p).field()).with_obstacles(set),
        }
    }
}
