//! The fused `sin_cos_fast` against the standard library, over random arguments.

use proptest::prelude::*;
use pvfc_core::Real;

proptest! {
    #![proptest_config(ProptestConfig::with_cases(100_000))]

    #[test]
    fn f64_within_two_ulp_of_one(x in -1.0e5..1.0e5f64) {
        let (s, c) = x.sin_cos_fast();
        // |sin|, |cos| ≤ 1: 2 ulp of 1 is 4.4e-16 absolute.
        prop_assert!((s - x.sin()).abs() <= 4.5e-16, "sin({x}) = {s} vs {}", x.sin());
        prop_assert!((c - x.cos()).abs() <= 4.5e-16, "cos({x}) = {c} vs {}", x.cos());
    }

    #[test]
    fn f64_small_arguments_are_relatively_accurate(x in -1.0..1.0f64, e in -30i32..0) {
        let x = x * 10f64.powi(e);
        let (s, c) = x.sin_cos_fast();
        prop_assert!((s - x.sin()).abs() <= 2.0 * f64::EPSILON * x.sin().abs(), "sin({x})");
        prop_assert!((c - x.cos()).abs() <= 2.0 * f64::EPSILON, "cos({x})");
    }

    #[test]
    fn f32_within_two_ulp_of_one(x in -1.0e3..1.0e3f32) {
        let (s, c) = x.sin_cos_fast();
        let (rs, rc) = ((x as f64).sin(), (x as f64).cos());
        prop_assert!((s as f64 - rs).abs() <= 2.4e-7, "sin({x}) = {s} vs {rs}");
        prop_assert!((c as f64 - rc).abs() <= 2.4e-7, "cos({x}) = {c} vs {rc}");
    }

    #[test]
    fn outside_the_fast_range_it_falls_back(x in 1.0e5..1.0e12f64) {
        prop_assert_eq!(x.sin_cos_fast(), (x.sin(), x.cos()));
        let y = (x * 1e-2) as f32;
        prop_assert_eq!(y.sin_cos_fast(), (y.sin(), y.cos()));
    }
}

#[test]
fn special_values() {
    for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let (s, c) = x.sin_cos_fast();
        assert!(s.is_nan() && c.is_nan());
    }
    for x in [f32::NAN, f32::INFINITY] {
        let (s, c) = x.sin_cos_fast();
        assert!(s.is_nan() && c.is_nan());
    }
    assert_eq!(0.0f64.sin_cos_fast(), (0.0, 1.0));
    let (s, c) = std::f64::consts::FRAC_PI_2.sin_cos_fast();
    assert!((s - 1.0).abs() < 1e-16 && c.abs() < 1e-16);
}
