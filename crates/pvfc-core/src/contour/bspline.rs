//! A smooth periodic curve through waypoints on any Lie group: the uniform cumulative cubic
//! B-spline (Kim, Kim & Shin 1995), C² on the group, with closed-form body derivatives.

use super::{check_period, Contour, ContourSample};
use crate::error::{Error, ErrorKind, Result};
use crate::lie::{LieGroup, Tangent};
use crate::scalar::cast;
use crate::Real;
use core::marker::PhantomData;

/// A closed, C² curve on `G` through (or near) `n ≥ 3` key points, one every `spacing` units
/// of `τ`, period `n·spacing`. `K` is the capacity: `n = K` for the array constructors
/// ([`through`](Self::through)), `3 ≤ n ≤ K` for the slice ones
/// ([`through_slice`](Self::through_slice)), so that a number of waypoints known at run time
/// needs no allocation and no new type.
///
/// On the segment `τ ∈ [i h, (i+1) h)`, `u = τ/h − i`, with control points `C_k` and
/// `Ω_k = log(C_k⁻¹ C_{k+1})` (indices modulo `K`):
///
/// `x_d(τ) = C_{i−1} · exp(B̃₁(u) Ω_{i−1}) · exp(B̃₂(u) Ω_i) · exp(B̃₃(u) Ω_{i+1})`
///
/// (indices modulo `n`) with the cumulative cubic basis `B̃₁ = (5 + 3u − 3u² + u³)/6`, `B̃₂ = (1 + 3u + 3u² − 2u³)/6`,
/// `B̃₃ = u³/6`. Body velocity and its derivative follow by the recursion
/// `ω_j = Ad_{A_j⁻¹} ω_{j−1} + B̃_j' Ω`, `ω̇_j = Ad_{A_j⁻¹} ω̇_{j−1} − B̃_j' [Ω, Ad_{A_j⁻¹} ω_{j−1}] + B̃_j'' Ω`.
///
/// [`through`](Self::through) finds the control points for which the curve passes through
/// given waypoints at `τ = k·h`; on the torus and `ℝⁿ` that is the periodic cubic
/// interpolating spline. On the torus, consecutive points are joined the short way round
/// (the group logarithm wraps to `(−π, π]`).
///
/// ```
/// use pvfc_core::contour::{Contour, PeriodicBSpline};
/// use pvfc_core::lie::{LieGroup, Torus};
/// use nalgebra::Vector2;
/// let square = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
///     .map(|(a, b)| Torus::<f64, 2>::new(Vector2::new(a, b)));
/// let curve = PeriodicBSpline::through(square, 1.5).unwrap();
/// assert!(curve.point(3.0).distance(&square[2]) < 1e-10); // waypoint 2 at τ = 2·1.5
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PeriodicBSpline<T: Real, G: LieGroup<T, D>, const D: usize, const K: usize> {
    control: [G; K],
    delta: [Tangent<T, D>; K],
    len: usize,
    spacing: T,
    _t: PhantomData<T>,
}

impl<T: Real, G: LieGroup<T, D>, const D: usize, const K: usize> PeriodicBSpline<T, G, D, K> {
    /// The spline with the given control points (the curve passes near, not through, them).
    pub fn from_control_points(control: [G; K], spacing: T) -> Result<Self> {
        Self::from_control_slice(&control, spacing)
    }

    /// As [`from_control_points`](Self::from_control_points) with `3 ≤ n ≤ K` points.
    pub fn from_control_slice(points: &[G], spacing: T) -> Result<Self> {
        let n = points.len();
        check_capacity(n, K)?;
        check_control(points, spacing)?;
        let mut control = [G::identity(); K];
        control[..n].copy_from_slice(points);
        let mut delta = [Tangent::zeros(); K];
        spline_segment_logs(&control[..n], &mut delta);
        Ok(PeriodicBSpline {
            control,
            delta,
            len: n,
            spacing,
            _t: PhantomData,
        })
    }

    /// The spline through the waypoints `W_k` at `τ = k·spacing`: the control points are found
    /// by the fixed-point iteration `C_k ← C_k·exp(log(x_d(k h)⁻¹ W_k))` (for abelian groups a
    /// Jacobi iteration with contraction factor ≤ 2/3). A `NoConvergence` error is returned if
    /// the waypoints are too coarse: the interpolating control points overshoot the waypoints
    /// (up to 3× on an alternating pattern), and must stay less than π apart on SO(3) and the
    /// torus, where the logarithm is discontinuous beyond.
    pub fn through(waypoints: [G; K], spacing: T) -> Result<Self> {
        Self::through_slice(&waypoints, spacing)
    }

    /// As [`through`](Self::through) with `3 ≤ n ≤ K` waypoints.
    pub fn through_slice(waypoints: &[G], spacing: T) -> Result<Self> {
        let n = waypoints.len();
        check_capacity(n, K)?;
        let mut control = [G::identity(); K];
        let mut delta = [Tangent::zeros(); K];
        let mut next = [G::identity(); K];
        spline_through(
            waypoints,
            spacing,
            &mut control[..n],
            &mut delta[..n],
            &mut next[..n],
        )?;
        Ok(PeriodicBSpline {
            control,
            delta,
            len: n,
            spacing,
            _t: PhantomData,
        })
    }

    /// The control points.
    pub fn control_points(&self) -> &[G] {
        &self.control[..self.len]
    }

    /// The number of key points `n`.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always `false`: a spline has at least 3 points.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The spacing `h` of the knots in `τ`.
    pub fn spacing(&self) -> T {
        self.spacing
    }
}

impl<T: Real, G: LieGroup<T, D>, const D: usize, const K: usize> Contour<T, G, D>
    for PeriodicBSpline<T, G, D, K>
{
    #[inline]
    fn sample(&self, tau: T) -> ContourSample<T, G, D> {
        SplineView::new(
            &self.control[..self.len],
            &self.delta[..self.len],
            self.spacing,
        )
        .sample(tau)
    }

    fn period(&self) -> Option<T> {
        Some(self.spacing * cast(self.len as f64))
    }
}

/// The spline's arithmetic on borrowed storage: `n ≥ 1` control points `C_k` and their segment
/// logarithms `Ω_k = log(C_k⁻¹ C_{k+1})` (indices modulo `n`), one knot every `spacing` of
/// `τ`. [`PeriodicBSpline`] evaluates itself through it; a spline kept elsewhere (on the heap,
/// where a capacity of many waypoints should not pass through the stack) uses it with its own
/// storage, and so computes the same values to the bit.
#[derive(Clone, Copy, Debug)]
pub struct SplineView<'a, T: Real, G, const D: usize> {
    control: &'a [G],
    delta: &'a [Tangent<T, D>],
    spacing: T,
}

impl<'a, T: Real, G: LieGroup<T, D>, const D: usize> SplineView<'a, T, G, D> {
    /// The view of `control` and `delta` (the shorter's length counts; at least one point).
    pub fn new(control: &'a [G], delta: &'a [Tangent<T, D>], spacing: T) -> Self {
        let n = control.len().min(delta.len());
        SplineView {
            control: &control[..n],
            delta: &delta[..n],
            spacing,
        }
    }

    /// `x_d(τ)` and its body derivatives (see [`PeriodicBSpline`] for the formulas); the
    /// identity at rest if the view is empty.
    pub fn sample(&self, tau: T) -> ContourSample<T, G, D> {
        let n = self.control.len();
        if n == 0 {
            return ContourSample {
                point: G::identity(),
                velocity: Tangent::<T, D>::zeros(),
                acceleration: Tangent::<T, D>::zeros(),
            };
        }
        let s = tau / self.spacing;
        let floor = s.floor();
        let u = s - floor;
        let kf: T = cast(n as f64);
        // Segment index modulo n, for negative τ too.
        let seg = floor - (floor / kf).floor() * kf;
        let i = (seg.to_i64_checked().unwrap_or(0).max(0) as usize) % n; // in T: no f64 on f32 targets
        let (u2, u3) = (u * u, u * u * u);
        let sixth: T = cast(1.0 / 6.0);
        let (three, two, five, six): (T, T, T, T) = (cast(3.0), cast(2.0), cast(5.0), cast(6.0));
        let b = [
            (five + three * u - three * u2 + u3) * sixth,
            (T::one() + three * u + three * u2 - two * u3) * sixth,
            u3 * sixth,
        ];
        let h = self.spacing;
        let db = [
            (three - six * u + three * u2) * sixth / h,
            (three + six * u - six * u2) * sixth / h,
            u2 * cast::<T>(0.5) / h,
        ];
        let ddb = [
            (u - T::one()) / (h * h),
            (T::one() - two * u) / (h * h),
            u / (h * h),
        ];
        let mut point = self.control[(i + n - 1) % n];
        let mut w = Tangent::<T, D>::zeros();
        let mut dw = Tangent::<T, D>::zeros();
        for j in 0..3 {
            let omega = self.delta[(i + n - 1 + j) % n];
            let a = G::exp(&(omega * b[j]));
            let w_prev = a.adjoint_inverse_apply(&w);
            dw = a.adjoint_inverse_apply(&dw) - G::lie_bracket(&omega, &w_prev) * db[j]
                + omega * ddb[j];
            w = w_prev + omega * db[j];
            point = point.compose(&a);
        }
        ContourSample {
            point,
            velocity: w,
            acceleration: dw,
        }
    }
}

/// The segment logarithms `Ω_k = log(C_k⁻¹ C_{k+1})` of the control points (indices modulo
/// `n`) into `delta` (its first `n`).
pub fn spline_segment_logs<T: Real, G: LieGroup<T, D>, const D: usize>(
    control: &[G],
    delta: &mut [Tangent<T, D>],
) {
    let n = control.len();
    for (k, d) in delta.iter_mut().enumerate().take(n) {
        *d = control[k].inverse().compose(&control[(k + 1) % n]).log();
    }
}

/// The interpolating spline through `waypoints` (`n ≥ 3` of them, at `τ = k·spacing`) on
/// storage of the caller's: on return `control` (`n`) holds its control points and `delta`
/// (`n`) their segment logarithms; `next` is room for `n` points. The same fit, checks and
/// errors as [`PeriodicBSpline::through`] (which calls it): the fixed-point iteration
/// `C_k ← C_k·exp(log(x_d(k h)⁻¹ W_k))` from `C_k = W_k`, a `NoConvergence` error if the
/// waypoints are too coarse. Evaluate the result with [`SplineView`].
pub fn spline_through<T: Real, G: LieGroup<T, D>, const D: usize>(
    waypoints: &[G],
    spacing: T,
    control: &mut [G],
    delta: &mut [Tangent<T, D>],
    next: &mut [G],
) -> Result<()> {
    let n = waypoints.len();
    check_control(waypoints, spacing)?;
    if control.len() != n || delta.len() != n || next.len() != n {
        return Err(Error::new(
            ErrorKind::DimensionMismatch,
            "PeriodicBSpline: room for the control points, their logarithms and the next ones must be one per waypoint",
        ));
    }
    control.copy_from_slice(waypoints);
    spline_segment_logs(control, delta);
    let tolerance = T::default_epsilon() * cast(64.0);
    // The next control points; they equal the spline's at each iteration's start.
    next.copy_from_slice(control);
    for _ in 0..2000 {
        let mut worst = T::zero();
        let view = SplineView::new(control, delta, spacing);
        for (k, c) in next.iter_mut().enumerate() {
            let at: T = spacing * cast(k as f64);
            let residual = view.sample(at).point.inverse().compose(&waypoints[k]).log();
            worst = worst.max(residual.norm());
            *c = c.compose(&G::exp(&residual));
        }
        if !worst.is_finite() {
            break;
        }
        // Neighbouring control points more than ~π apart make the logarithm jump: the
        // waypoints are too coarse for an interpolating spline on this group.
        let spread = (0..n)
            .map(|k| G::chart_extent(&next[k].inverse().compose(&next[(k + 1) % n]).log()))
            .fold(T::zero(), |a, b| a.max(b));
        if spread > cast::<T>(0.9 * core::f64::consts::PI) {
            return Err(Error::new(
                ErrorKind::NoConvergence,
                "PeriodicBSpline::through: waypoints too far apart (control points would be ≥ 0.9π apart); add waypoints",
            ));
        }
        if worst <= tolerance {
            return Ok(());
        }
        if !next.iter().all(|c| c.is_finite()) {
            return Err(Error::new(
                ErrorKind::NonFinite,
                "PeriodicBSpline: control points",
            ));
        }
        control.copy_from_slice(next);
        spline_segment_logs(control, delta);
    }
    Err(Error::new(
        ErrorKind::NoConvergence,
        "PeriodicBSpline::through: control points did not converge",
    ))
}

/// At most `capacity` points.
fn check_capacity(n: usize, capacity: usize) -> Result<()> {
    if n > capacity {
        return Err(Error::new(
            ErrorKind::DimensionMismatch,
            "PeriodicBSpline: more points than the spline's capacity K",
        )
        .with_value(n as f64));
    }
    Ok(())
}

/// At least 3 finite points, and a spacing finite and > 0.
fn check_control<T: Real, G: LieGroup<T, D>, const D: usize>(
    points: &[G],
    spacing: T,
) -> Result<()> {
    if points.len() < 3 {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            "PeriodicBSpline: needs at least 3 points",
        ));
    }
    check_period(spacing, "PeriodicBSpline: spacing must be finite and > 0")?;
    if !points.iter().all(|c| c.is_finite()) {
        return Err(Error::new(
            ErrorKind::NonFinite,
            "PeriodicBSpline: control points",
        ));
    }
    Ok(())
}
