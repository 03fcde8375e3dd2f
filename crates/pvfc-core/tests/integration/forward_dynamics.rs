//! The SCARA's forward dynamics by Cramer's rule give what nalgebra's general Cholesky gives,
//! within the matrix's condition number times a few ε, over random matrices (well and badly
//! conditioned, and not positive definite) and random states, in f64 and f32.

use nalgebra::{Matrix2, Vector2};
use proptest::prelude::*;
use pvfc_core::mechanics::solve_spd2;
use pvfc_core::prelude::*;

fn general<T: pvfc_core::Real>(m: &Matrix2<T>, b: &Vector2<T>) -> Option<Vector2<T>> {
    m.cholesky().map(|c| c.solve(b))
}

/// `κ(M) = λ_max / λ_min = λ_max² / det M` of a symmetric positive definite 2×2 `M` whose
/// determinant is `det` (given: from a factor, it has no cancellation); ∞ if not positive.
fn condition_with(m: &Matrix2<f64>, det: f64) -> f64 {
    let (a, c, d) = (m[(0, 0)], m[(1, 0)], m[(1, 1)]);
    let top = (a + d) / 2.0 + (((a - d) / 2.0).powi(2) + c * c).sqrt();
    if det > 0.0 {
        top * top / det
    } else {
        f64::INFINITY
    }
}

fn condition(m: &Matrix2<f64>) -> f64 {
    condition_with(m, m[(0, 0)] * m[(1, 1)] - m[(1, 0)] * m[(1, 0)])
}

/// `x` within `κ(M) · 8ε` of `y` (norm-wise, relative to `‖y‖`).
fn close(x: Vector2<f64>, y: Vector2<f64>, kappa: f64, eps: f64) -> bool {
    (x - y).norm() <= 8.0 * eps * kappa * y.norm() + f64::MIN_POSITIVE
}

/// Whether `M` is far enough from singular that both tests of definiteness must agree:
/// `det M` beyond the rounding of its two products.
fn decided(m: &Matrix2<f64>) -> bool {
    let (a, c, d) = (m[(0, 0)], m[(1, 0)], m[(1, 1)]);
    (a * d - c * c).abs() > 1e-12 * ((a * d).abs() + c * c)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn the_2x2_solve_is_nalgebras_within_the_condition_number(
        a in -1e3f64..1e3, c in -1e3f64..1e3, d in -1e3f64..1e3,
        scale in -12i32..12, b0 in -1e3f64..1e3, b1 in -1e3f64..1e3,
    ) {
        let k = 10f64.powi(scale);
        // Symmetric; positive definite or not as the draw falls.
        let m = Matrix2::new(a * k, c * k, c * k, d * k);
        let b = Vector2::new(b0, b1);
        let (x, y) = (solve_spd2(&m, &b), general(&m, &b));
        if decided(&m) {
            prop_assert_eq!(x.is_some(), y.is_some(), "{} {}", m, b);
        }
        if let (Some(x), Some(y)) = (x, y) {
            prop_assert!(close(x, y, condition(&m), f64::EPSILON), "{m} {b}: {x} {y}");
        }
        // A positive definite one from a random factor (nearly singular at times).
        let l = Matrix2::new(a.abs() + 1e-9, 0.0, c, d.abs() * 1e-6 + 1e-12);
        let spd = l * l.transpose();
        let kappa = condition_with(&spd, (l[(0, 0)] * l[(1, 1)]).powi(2));
        if let (Some(x), Some(y)) = (solve_spd2(&spd, &b), general(&spd, &b)) {
            prop_assert!(close(x, y, kappa, f64::EPSILON), "{spd} {b}: {x} {y}");
        }
        // f32, on matrices whose condition f32 can hold.
        if kappa < 1e4 {
            let (m32, b32) = (spd.cast::<f32>(), b.cast::<f32>());
            let x = solve_spd2(&m32, &b32);
            prop_assert!(x.is_some(), "{m32}");
            if let (Some(x), Some(y)) = (x, general(&m32, &b32)) {
                prop_assert!(close(x.cast(), y.cast(), kappa, f32::EPSILON as f64), "{m32} {b32}: {x} {y}");
            }
        }
    }

    /// Not positive definite, NaN and the zero matrix are refused.
    #[test]
    fn what_is_not_positive_definite_is_refused(a in 0.1f64..10.0, c in -10f64..10.0) {
        let b = Vector2::new(1.0, -2.0);
        prop_assert!(solve_spd2(&Matrix2::new(-a, c, c, a), &b).is_none());
        prop_assert!(solve_spd2(&Matrix2::new(a, a + c.abs() + 1.0, a + c.abs() + 1.0, a), &b).is_none());
        prop_assert!(solve_spd2(&Matrix2::new(f64::NAN, c, c, a), &b).is_none());
        prop_assert!(solve_spd2(&Matrix2::new(a, c, c, f64::NAN), &b).is_none());
        prop_assert!(solve_spd2(&Matrix2::<f64>::zeros(), &b).is_none());
    }

    #[test]
    fn the_scaras_acceleration_is_the_general_one(
        q1 in -10f64..10.0, q2 in -10f64..10.0, v1 in -20f64..20.0, v2 in -20f64..20.0,
        f1 in -100f64..100.0, f2 in -100f64..100.0,
    ) {
        // The Pelican, and the heavier direct-drive arm of the paper's scenarios.
        let direct_drive = Scara::new(ScaraParameters {
            m1: 15.0, m2: 6.0, l1: 0.4, l2: 0.35, lc1: 0.2, lc2: 0.15, i1: 0.4, i2: 0.15,
        })
        .unwrap();
        for arm in [Scara::<f64>::pelican(), direct_drive] {
            let q = Torus::<f64, 2>::new(Vector2::new(q1, q2));
            let (v, f) = (Vector2::new(v1, v2), Vector2::new(f1, f2));
            let (m, c, g) = arm.inertia_coriolis_gravity(&q, &v);
            let expected = general(&m, &(f - c * v - g));
            let got = arm.acceleration(&q, &v, &f).ok();
            prop_assert!(matches!((got, expected), (Some(x), Some(y)) if close(x, y, condition(&m), f64::EPSILON)), "{got:?} {expected:?}");
        }
    }
}
