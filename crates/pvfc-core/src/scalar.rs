//! The scalar type every pvfc computation is generic over, and the few elementary functions
//! the control step needs in a faster form than `libm` gives them.

use nalgebra::{ComplexField, RealField};

mod sealed {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A real scalar usable by pvfc: `f32` (microcontrollers with a single-precision FPU) or `f64`.
///
/// This is [`nalgebra::RealField`] plus `Copy`, and a fused `sin_cos` for the control step.
/// It is sealed: implemented for `f32` and `f64` only.
pub trait Real: RealField + Copy + sealed::Sealed {
    /// `(sin x, cos x)` with one argument reduction and two short polynomials (fdlibm's
    /// kernels for `f64`, Cephes' for `f32`, evaluated in the type itself so that an
    /// `f32`-only FPU never touches `f64`). Within 2 ulp of the correctly rounded values for
    /// `|x| ≤ 10⁵` (`f64`) or `|x| ≤ 10³` (`f32`); outside that range, and for NaN and ±∞, it
    /// falls back to the standard `sin` and `cos`.
    ///
    /// ```
    /// use pvfc_core::Real;
    /// let (s, c) = 0.5f64.sin_cos_fast();
    /// assert!((s - 0.5f64.sin()).abs() < 1e-16 && (c - 0.5f64.cos()).abs() < 1e-16);
    /// ```
    fn sin_cos_fast(self) -> (Self, Self);

    /// `√x` as cheap as the platform allows. `f64`, and `f32` with the `std` feature: the
    /// standard (hardware) square root. `f32` without `std` (microcontrollers): a Cortex-M4F
    /// has a `VSQRT.F32` instruction but neither `core` nor `libm` emits it on stable Rust, and
    /// libm's bitwise `sqrtf` costs ~50 instructions; this is [`sqrt_newton_f32`], the
    /// reciprocal square root's bit-level estimate refined by two Newton steps and one step on
    /// the root, in `f32` (≤ 2 ulp, tested against the correctly rounded root over every
    /// argument in [1, 4) and random ones, measured ≤ 1 ulp; 0 for 0, NaN for negative or NaN,
    /// ∞ for ∞).
    fn sqrt_fast(self) -> Self;

    /// `self` rounded towards zero as an `i64` when it is finite and `|self| < 2⁶³`, computed
    /// in the type itself (no `f64` on an `f32` target).
    fn to_i64_checked(self) -> Option<i64>;

    /// `eˣ` inline, without a call. `f32`: Cephes' `expf` (Cody–Waite reduction by `ln 2` in
    /// two parts, a degree-5 polynomial, the power of two put in the exponent bits), within
    /// 2 ulp of the correctly rounded value for `|x| ≤ 87` (tested); outside that range (where
    /// the result would be subnormal or overflow), and for NaN, the standard `exp`, out of
    /// line. `f64`: the standard `exp`.
    ///
    /// Why: self-pacing (eq. 21) takes one `exp` per step; inline, the paper's SCARA step
    /// executes 29 instructions fewer on a Cortex-M4F and 10 fewer on x86-64 than with the
    /// call (measured; a call also makes x86-64 save every live vector register).
    ///
    /// ```
    /// use pvfc_core::Real;
    /// assert!((1.0f32.exp_fast() - core::f32::consts::E).abs() <= f32::EPSILON * 3.0);
    /// assert_eq!((-200.0f32).exp_fast(), 0.0);
    /// ```
    fn exp_fast(self) -> Self;

    /// The smallest self-pacing gain `λ₁ = exp(−R U)` the law keeps; below it `λ₁` is 0
    /// ([`crate::pacing::ExponentialPacing`]). `f32`: `2⁻⁴⁰ ≈ 9·10⁻¹³`. At a large error
    /// `exp(−R U)` is tiny, and the law multiplies it with itself, with `τ̇` and with the
    /// rates (`λ₁²`, `λ₁ U̇ R`): in `f32` those products fall below `2⁻¹²⁶` into subnormal
    /// numbers, which an Intel core handles by a microcode assist of ~100 cycles each (the
    /// SCARA's `f32` step took 2.1× its `f64` time on an Intel Xeon, measured; 0.9× with
    /// flush-to-zero set). Above `2⁻⁴⁰` their products stay normal; below it the feed-forward
    /// it scales is less than `f32`'s resolution of the correction term squared, and the
    /// contour's progress `τ̇ ∝ λ₁` is nil to the eye. `f64`: 0 (no cut): its exponent range
    /// keeps the step's products normal, and its speed does not change with flush-to-zero
    /// (measured).
    const PACING_FLOOR: Self;
}

/// Maps the reduced argument's kernel values to the quadrant `n mod 4`.
#[inline(always)]
fn quadrant<T: core::ops::Neg<Output = T>>(q: u32, s: T, c: T) -> (T, T) {
    match q & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

// The constants are fdlibm's and Cephes' as published; each parses to the intended value.
#[allow(clippy::excessive_precision)]
impl Real for f64 {
    const PACING_FLOOR: f64 = 0.0;

    #[inline]
    fn sqrt_fast(self) -> f64 {
        ComplexField::sqrt(self)
    }

    #[inline]
    fn exp_fast(self) -> f64 {
        ComplexField::exp(self)
    }

    #[inline]
    fn to_i64_checked(self) -> Option<i64> {
        (self.is_finite() && self.abs() < 9.223_372_036_854_775e18).then_some(self as i64)
    }

    #[inline]
    fn sin_cos_fast(self) -> (f64, f64) {
        let x = self;
        if x.is_nan() || x.abs() > 1.0e5 {
            return (ComplexField::sin(x), ComplexField::cos(x));
        }
        // n = round(x·2/π) by the 1.5·2⁵² trick; r = x − n·π/2 in three parts (Cody–Waite),
        // each product exact for |n| < 2²⁰.
        const SHIFT: f64 = 6_755_399_441_055_744.0;
        const FRAC_2_PI: f64 = core::f64::consts::FRAC_2_PI;
        const P1: f64 = 1.570_796_326_734_125_614_17e0;
        const P2: f64 = 6.077_100_506_303_965_976_6e-11;
        const P3: f64 = 2.022_266_248_711_166_455_8e-21;
        let t = x * FRAC_2_PI + SHIFT;
        let q = t.to_bits() as u32;
        let n = t - SHIFT;
        let r = ((x - n * P1) - n * P2) - n * P3;
        // fdlibm's __kernel_sin and __kernel_cos on [−π/4, π/4].
        const S1: f64 = -1.666_666_666_666_663_243_48e-1;
        const S2: f64 = 8.333_333_333_322_489_461_24e-3;
        const S3: f64 = -1.984_126_982_985_794_931_34e-4;
        const S4: f64 = 2.755_731_370_707_006_767_89e-6;
        const S5: f64 = -2.505_076_025_340_686_341_95e-8;
        const S6: f64 = 1.589_690_995_211_550_102_21e-10;
        const C1: f64 = 4.166_666_666_666_660_190_37e-2;
        const C2: f64 = -1.388_888_888_887_410_957_49e-3;
        const C3: f64 = 2.480_158_728_947_672_941_78e-5;
        const C4: f64 = -2.755_731_435_139_066_330_35e-7;
        const C5: f64 = 2.087_572_321_298_174_827_90e-9;
        const C6: f64 = -1.135_964_755_778_819_482_65e-11;
        let z = r * r;
        let w = z * z;
        let rs = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
        let s = r + z * r * (S1 + z * rs);
        let rc = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
        let hz = 0.5 * z;
        let one_minus = 1.0 - hz;
        let c = one_minus + (((1.0 - one_minus) - hz) + z * rc);
        quadrant(q, s, c)
    }
}

#[allow(clippy::excessive_precision)]
impl Real for f32 {
    const PACING_FLOOR: f32 = 9.094_947e-13; // 2⁻⁴⁰

    #[inline]
    fn sqrt_fast(self) -> f32 {
        #[cfg(feature = "std")]
        {
            ComplexField::sqrt(self)
        }
        #[cfg(not(feature = "std"))]
        {
            sqrt_newton_f32(self)
        }
    }

    #[inline]
    fn to_i64_checked(self) -> Option<i64> {
        (self.is_finite() && self.abs() < 9.223_372e18).then_some(self as i64)
    }

    #[inline]
    fn exp_fast(self) -> f32 {
        // One comparison, false for NaN too, keeps the usual case on the inline path.
        if self.abs() <= 87.0 {
            exp_cephes_f32(self)
        } else {
            exp_far_f32(self)
        }
    }

    #[inline]
    fn sin_cos_fast(self) -> (f32, f32) {
        // One comparison, false for NaN and ±∞ too, keeps the usual case on the inline path.
        if self.abs() <= 1.0e3 {
            sin_cos_kernel_f32(self)
        } else {
            sin_cos_far_f32(self)
        }
    }
}

/// [`Real::sin_cos_fast`] for `|x| > 10³`, NaN and ±∞: reduced by whole turns first, kept out
/// of line so that the inline fast path stays short.
#[cold]
#[inline(never)]
#[allow(clippy::excessive_precision)]
fn sin_cos_far_f32(mut x: f32) -> (f32, f32) {
    if !x.is_finite() {
        return (f32::NAN, f32::NAN);
    }
    // Reduced by whole turns in f32 (2π in three parts of 8, 12 and 24 bits, Cody–Waite), so
    // that an f32 target never links libm's f64-based sinf/cosf. The first two products are
    // exact while |k| < 2¹² (|x| < 2.5·10⁴); beyond, accuracy degrades slowly with |x|
    // (measured ≤ 1e-5 up to 10⁵; by 2²⁴ x has no fractional digits left, and no f32
    // evaluation means much).
    const TURN_1: f32 = 6.281_25;
    const TURN_2: f32 = 1.935_005_187_988_281_2e-3;
    const TURN_3: f32 = 3.019_916_050_561_733e-7;
    let k = (x * core::f32::consts::FRAC_1_PI * 0.5).round();
    x = ((x - k * TURN_1) - k * TURN_2) - k * TURN_3;
    sin_cos_kernel_f32(x)
}

/// `(sin x, cos x)` of a finite `x` reduced by quarter turns (`|x|` up to ~10³ keeps the
/// reduction's products exact): Cephes' `sinf` and `cosf` kernels.
#[inline(always)]
#[allow(clippy::excessive_precision)]
fn sin_cos_kernel_f32(x: f32) -> (f32, f32) {
    const SHIFT: f32 = 12_582_912.0;
    const FRAC_2_PI: f32 = core::f32::consts::FRAC_2_PI;
    // π/2 in three parts with few significant bits (Cephes' DP1..DP3, doubled).
    const P1: f32 = 1.570_312_5;
    const P2: f32 = 4.837_512_969_970_703_125e-4;
    const P3: f32 = 7.549_789_954_891_882_16e-8;
    let t = x * FRAC_2_PI + SHIFT;
    let q = t.to_bits();
    let n = t - SHIFT;
    let r = ((x - n * P1) - n * P2) - n * P3;
    // Cephes' sinf and cosf polynomials on [−π/4, π/4]. For |r| < 2⁻¹² they round to
    // (r, 1) exactly (r³/6 is below half an ulp of r, r²/2 below half an ulp of 1), so on x86
    // z is taken as 0 there: else r², r³ and z² underflow into subnormal numbers for tiny r
    // (a contour near τ = 0, as self-pacing holds it at a large error), each a microcode
    // assist of ~100 cycles on Intel cores. Elsewhere (an Arm FPU takes subnormals at full
    // speed) the comparison and its branch are left out: the same values.
    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    let z = if r.abs() < 2.441_406_3e-4 { 0.0 } else { r * r };
    #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
    let z = r * r;
    let s = ((-1.951_529_589_1e-4 * z + 8.332_160_873_6e-3) * z - 1.666_665_461_1e-1) * z * r + r;
    let c = ((2.443_315_711_809_948e-5 * z - 1.388_731_625_493_765e-3) * z
        + 4.166_664_568_298_827e-2)
        * z
        * z
        - 0.5 * z
        + 1.0;
    quadrant(q, s, c)
}

/// Cephes' `expf` for `|x| ≤ 87` (the fast path of [`Real::exp_fast`]).
#[inline(always)]
#[allow(clippy::excessive_precision)]
fn exp_cephes_f32(x: f32) -> f32 {
    // n = round(x / ln 2) by the 1.5·2²³ shift: t's low mantissa bits hold n.
    const SHIFT: f32 = 12_582_912.0;
    // ln 2 = C1 − C2 (Cephes): C1 has 9 significant bits, so n·C1 is exact for |n| ≤ 126.
    const C1: f32 = 0.693_359_375;
    const C2: f32 = -2.121_944_4e-4;
    let t = x * core::f32::consts::LOG2_E + SHIFT;
    let n = t - SHIFT;
    let k = (t.to_bits() as i32).wrapping_sub(SHIFT.to_bits() as i32);
    let r = (x - n * C1) - n * C2;
    // Cephes' expf polynomial on [−ln2/2, ln2/2].
    let p = (((((1.987_569_15e-4 * r + 1.398_199_950_7e-3) * r + 8.333_451_907_3e-3) * r
        + 4.166_579_589_4e-2)
        * r
        + 1.666_666_545_9e-1)
        * r
        + 5.000_000_120_1e-1)
        * (r * r)
        + r
        + 1.0;
    // |x| ≤ 87: |n| ≤ 126, so 2ⁿ is a normal number.
    p * f32::from_bits(((k + 127) as u32) << 23)
}

/// `exp_fast`'s range where the result is subnormal, overflows or is NaN: the standard `exp`,
/// kept out of line so that the inline fast path stays short.
#[cold]
#[inline(never)]
fn exp_far_f32(x: f32) -> f32 {
    ComplexField::exp(x)
}

/// `√x` for `f32` without hardware support reachable from stable Rust: the bit-level estimate
/// of `1/√x`, two Newton steps, then `x·(1/√x)` with one correction step on the root. A
/// normal positive finite `x` (the control step's case) takes one integer comparison; zero,
/// subnormals, ∞, negative numbers and NaN go out of line.
#[inline]
pub fn sqrt_newton_f32(x: f32) -> f32 {
    // Normal, positive and finite: the bits lie in [0x0080_0000, 0x7f7f_ffff].
    if x.to_bits().wrapping_sub(0x0080_0000) < 0x7f00_0000 {
        sqrt_newton_normal(x)
    } else {
        sqrt_newton_special(x)
    }
}

/// [`sqrt_newton_f32`] of a normal positive finite `x`. The estimate is within 3.5 % of
/// `1/√x`; each Newton step squares the relative error (1.8e-3, then 4.6e-6), and the step
/// on the root, `r ← r + (x − r²)·y/2`, takes `r = x·y` to within rounding.
#[inline(always)]
fn sqrt_newton_normal(x: f32) -> f32 {
    let half = 0.5 * x;
    let mut y = f32::from_bits(0x5f37_5a86 - (x.to_bits() >> 1));
    y *= 1.5 - half * y * y;
    y *= 1.5 - half * y * y;
    let r = x * y;
    r + 0.5 * y * (x - r * r)
}

/// [`sqrt_newton_f32`] of everything else: negative or NaN → NaN; ±0 → ±0; ∞ → ∞;
/// subnormals scaled into the normal range first (`√(2²⁴ x) = 2¹² √x`).
#[cold]
#[inline(never)]
fn sqrt_newton_special(x: f32) -> f32 {
    if x.is_nan() || x < 0.0 {
        f32::NAN
    } else if x == 0.0 || x == f32::INFINITY {
        x
    } else {
        sqrt_newton_normal(x * 16_777_216.0) * (1.0 / 4096.0)
    }
}

/// Converts an `f64` constant into the scalar type `T` (exact for `f64`, rounded for `f32`).
///
/// ```
/// let half: f32 = pvfc_core::scalar::cast(0.5);
/// assert_eq!(half, 0.5f32);
/// ```
#[inline(always)]
pub fn cast<T: Real>(x: f64) -> T {
    nalgebra::convert(x)
}

/// `true` when every entry of the slice-like iterator is finite (neither NaN nor infinite).
///
/// With a floating-point unit, without a branch per entry: `x·0` is `±0` for a finite `x`
/// and NaN for ±∞ or NaN, and a sum of zeros stays zero while one NaN makes it NaN, so the
/// sum of the products is zero exactly when every entry is finite (no overflow: nothing but
/// zeros is ever added). One multiply–add per entry and one comparison, against an absolute
/// value, a comparison and a branch per entry (on the Cortex-M4F, 70 of the SCARA step's
/// instructions were its finite checks). Where floating point is in software (Arm's soft-float
/// ABI, RISC-V without `F`), each entry's own test, a few integer instructions on its bits.
#[inline]
pub fn all_finite<'a, T: Real + 'a>(xs: impl IntoIterator<Item = &'a T>) -> bool {
    all_finite_in(xs, core::iter::empty())
}

/// Whether this target computes in software floating point (Arm's soft-float ABI, RISC-V
/// without `F`), where a product costs a call into the runtime's routines.
const SOFT_FLOAT: bool = cfg!(any(
    all(target_arch = "arm", not(target_abi = "eabihf")),
    all(
        any(target_arch = "riscv32", target_arch = "riscv64"),
        not(target_feature = "f")
    )
));

/// [`all_finite`] of two parts at once (one comparison for both with a floating-point unit;
/// each entry's own test in software floating point).
#[inline]
pub fn all_finite_in<'a, 'b, T: Real + 'a + 'b>(
    a: impl IntoIterator<Item = &'a T>,
    b: impl IntoIterator<Item = &'b T>,
) -> bool {
    if SOFT_FLOAT {
        return a.into_iter().all(|x| x.is_finite()) && b.into_iter().all(|x| x.is_finite());
    }
    // Two loops, not a chain: a chained iterator's `next` is not unrolled (measured on the
    // Cortex-M4F).
    let mut zero = T::zero();
    for x in a {
        zero += *x * T::zero();
    }
    for x in b {
        zero += *x * T::zero();
    }
    zero == T::zero()
}
