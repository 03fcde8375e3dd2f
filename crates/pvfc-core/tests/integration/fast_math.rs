//! The fast elementary functions of `Real` (`sin_cos_fast`, `sqrt_fast`, `exp_fast`) against the
//! standard library, over random arguments.

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
        // f64: the standard library's sin and cos.
        prop_assert_eq!(x.sin_cos_fast(), (x.sin(), x.cos()));
        // f32: reduced in f32 (no libm fallback): on the circle, and close to the f64 values
        // of the same f32 argument while |y| ≤ 10⁵.
        let y = (x * 1e-7) as f32;
        let (s, c) = y.sin_cos_fast();
        prop_assert!((s * s + c * c - 1.0).abs() < 1e-5);
        let yd = y as f64;
        prop_assert!((s as f64 - yd.sin()).abs() < 1e-5 && (c as f64 - yd.cos()).abs() < 1e-5, "{y}");
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

/// The distance of two `f32` in units in the last place.
fn ulps(a: f32, b: f32) -> i64 {
    (a.to_bits() as i64 - b.to_bits() as i64).abs()
}

/// Marsaglia's xorshift64: the next pseudo-random state (reproducible arguments).
fn xorshift(state: &mut u64) {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
}

/// The `f32` square root of `no_std` targets against the correctly rounded one: within 2 ulp
/// over random normal and subnormal arguments and over every argument in [1, 4), exact special
/// values.
#[test]
fn sqrt_newton_f32_is_within_two_ulp() {
    use pvfc_core::scalar::sqrt_newton_f32;
    let mut worst = 0;
    let mut state = 0x2545_f491_4f6c_dd1du64;
    for _ in 0..200_000 {
        xorshift(&mut state);
        let x = f32::from_bits((state as u32) & 0x7f7f_ffff); // finite, positive
        worst = worst.max(ulps(sqrt_newton_f32(x), x.sqrt()));
    }
    // Every f32 in [1, 4): the estimate's error repeats with each factor of 4 (the exponent's
    // parity and the mantissa), so this covers every normal argument's case.
    for bits in 1.0f32.to_bits()..4.0f32.to_bits() {
        let x = f32::from_bits(bits);
        worst = worst.max(ulps(sqrt_newton_f32(x), x.sqrt()));
    }
    for x in [
        1e-45f32,
        1e-40,
        1.0,
        2.0,
        4.0,
        0.25,
        f32::MAX,
        f32::MIN_POSITIVE,
    ] {
        worst = worst.max(ulps(sqrt_newton_f32(x), x.sqrt()));
    }
    assert!(worst <= 2, "worst {worst} ulp");
    assert_eq!(sqrt_newton_f32(0.0), 0.0);
    assert_eq!(sqrt_newton_f32(-0.0).to_bits(), (-0.0f32).to_bits());
    assert!(
        sqrt_newton_f32(-1.0).is_nan()
            && sqrt_newton_f32(-1e-40).is_nan()
            && sqrt_newton_f32(f32::NAN).is_nan()
    );
    assert_eq!(sqrt_newton_f32(f32::INFINITY), f32::INFINITY);
}

/// Large `f32` arguments are reduced in `f32` (no libm fallback): close to the f64 reference.
#[test]
fn f32_sin_cos_of_large_arguments_stay_accurate() {
    use pvfc_core::Real;
    for k in 0..20_000 {
        let x = 1.0e3f32 + k as f32 * 1.2345;
        let (s, c) = x.sin_cos_fast();
        let xd = x as f64;
        assert!((s as f64 - xd.sin()).abs() < 2e-6, "sin({x})");
        assert!((c as f64 - xd.cos()).abs() < 2e-6, "cos({x})");
    }
    let (s, c) = f32::INFINITY.sin_cos_fast();
    assert!(s.is_nan() && c.is_nan());
}

/// The inline `f32` exponential against the correctly rounded one (the `f64` exponential
/// rounded to `f32`): within 2 ulp over random and evenly spaced arguments of its fast range,
/// the standard `exp` outside it, exact special values; `f64` is the standard `exp`.
#[test]
fn exp_fast_is_within_two_ulp() {
    let reference = |x: f32| (x as f64).exp() as f32;
    let mut worst = 0;
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    for i in 0..400_000 {
        xorshift(&mut state);
        // Half uniform on [−87, 87], half log-spread small arguments of both signs.
        let u = (state >> 40) as f32 / (1u64 << 24) as f32;
        let x = if i % 2 == 0 {
            (u * 2.0 - 1.0) * 87.0
        } else {
            let sign = if state & 1 == 0 { 1.0 } else { -1.0 };
            sign * 10f32.powf(-30.0 * u)
        };
        worst = worst.max(ulps(x.exp_fast(), reference(x)));
    }
    for k in -87_000..=87_000 {
        let x = k as f32 * 1e-3;
        worst = worst.max(ulps(x.exp_fast(), reference(x)));
    }
    assert!(worst <= 2, "worst {worst} ulp");
    // Outside the fast range: the standard library's exp.
    for x in [
        87.5f32,
        88.7,
        89.0,
        -87.5,
        -100.0,
        -103.0,
        -200.0,
        f32::INFINITY,
    ] {
        assert_eq!(x.exp_fast(), x.exp(), "{x}");
    }
    assert_eq!(f32::NEG_INFINITY.exp_fast(), 0.0);
    assert!(f32::NAN.exp_fast().is_nan() && f64::NAN.exp_fast().is_nan());
    assert_eq!(0.0f32.exp_fast(), 1.0);
    for x in [-700.0, -3.5, 0.0, 1e-9, 2.0, 700.0] {
        assert_eq!(x.exp_fast(), f64::exp(x));
    }
}

/// One entry: finite (ordinary, the largest, subnormal, ±0) or not (±∞, NaN).
fn entry() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -1.0e6..1.0e6f64,
        1 => Just(f64::MAX),
        1 => Just(-f64::MAX),
        1 => Just(5e-324),
        1 => Just(-0.0),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(f64::NAN),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    /// `all_finite` (a sum of `xᵢ·0`, no branch per entry) says what a check of each entry
    /// says, in f64 and f32 (where f64's extremes become ±∞ or 0), however many entries.
    #[test]
    fn all_finite_is_each_entry_finite(xs in proptest::collection::vec(entry(), 0..9)) {
        let each = xs.iter().all(|x| x.is_finite());
        prop_assert_eq!(pvfc_core::scalar::all_finite(xs.iter()), each, "{:?}", xs);
        let ys: Vec<f32> = xs.iter().map(|&x| x as f32).collect();
        let each = ys.iter().all(|y| y.is_finite());
        prop_assert_eq!(pvfc_core::scalar::all_finite(ys.iter()), each, "{:?}", ys);
        // In two parts: every entry of both.
        let (a, b) = xs.split_at(xs.len() / 2);
        prop_assert_eq!(
            pvfc_core::scalar::all_finite_in(a.iter(), b.iter()),
            xs.iter().all(|x| x.is_finite()),
            "{:?} | {:?}", a, b
        );
    }
}
