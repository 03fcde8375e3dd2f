//! The SCARA's forward dynamics by the closed-form 2×2 Cholesky solve give what nalgebra's
//! general Cholesky gives, bit for bit, over random matrices (well and badly conditioned, and
//! not positive definite) and random states, in f64 and f32.

use nalgebra::{Matrix2, Vector2};
use proptest::prelude::*;
use pvfc_core::mechanics::cholesky_solve2;
use pvfc_core::prelude::*;

fn general<T: pvfc_core::Real>(m: &Matrix2<T>, b: &Vector2<T>) -> Option<Vector2<T>> {
    m.cholesky().map(|c| c.solve(b))
}

fn same_bits(a: Option<Vector2<f64>>, b: Option<Vector2<f64>>) -> bool {
    match (a, b) {
        (None, None) => true,
        // Equal as numbers (a zero's sign aside) and as bits otherwise.
        (Some(a), Some(b)) => a
            .iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits() || (*x == 0.0 && *y == 0.0)),
        _ => false,
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn the_2x2_solve_is_nalgebras(
        a in -1e3f64..1e3, c in -1e3f64..1e3, d in -1e3f64..1e3,
        scale in -12i32..12, b0 in -1e3f64..1e3, b1 in -1e3f64..1e3,
    ) {
        let k = 10f64.powi(scale);
        // Symmetric; positive definite or not as the draw falls.
        let m = Matrix2::new(a * k, c * k, c * k, d * k);
        let b = Vector2::new(b0, b1);
        prop_assert!(same_bits(cholesky_solve2(&m, &b), general(&m, &b)), "{m} {b}");
        // A positive definite one from a random factor (nearly singular at times).
        let l = Matrix2::new(a.abs() + 1e-9, 0.0, c, d.abs() * 1e-6 + 1e-12);
        let spd = l * l.transpose();
        prop_assert!(same_bits(cholesky_solve2(&spd, &b), general(&spd, &b)), "{spd} {b}");
        let (m32, b32) = (spd.cast::<f32>(), b.cast::<f32>());
        let (x, y) = (cholesky_solve2(&m32, &b32), general(&m32, &b32));
        prop_assert!(same_bits(x.map(|v| v.cast()), y.map(|v| v.cast())), "{m32} {b32}");
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
            prop_assert!(same_bits(got, expected), "{got:?} {expected:?}");
        }
    }
}
