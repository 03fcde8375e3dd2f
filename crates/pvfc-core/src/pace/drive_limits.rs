//! The fastest pace the drives allow along a contour: the time-optimal parameterisation of
//! the contour under per-joint torque limits (Bobrow, Dubowsky & Gibson 1985; the
//! reachability form of TOPP-RA, Pham & Pham 2018), on a periodic grid of `τ`, without
//! allocation.
//!
//! Moving along the contour, `q̇ = ξ_d(τ) τ̇` and `q̈ = ξ_d τ̈ + ξ_d' τ̇²` (body coordinates),
//! so the torque the motion needs is affine in `u = τ̈` and `x = τ̇²`:
//!
//! `T(τ) = a(τ) u + b(τ) x + c(τ)`, `a = M ξ_d`, `b = M ξ_d' + C(x_d, ξ_d) ξ_d`,
//! `c = g(x_d) + f ∘ sign(ξ_d)`
//!
//! (`g` when the controller compensates gravity, `f` its friction compensation, both torques
//! the drive must deliver on top of the coupling's). Viscous friction `B q̇ = B ξ_d √x` adds a
//! term in `√x` (`d(τ) √x`, `d = B ξ_d`): the torque is then no longer affine in `x`, and the
//! passes below stay exact for the bounds they test at each `x` (each bound is computed at the
//! `x` it is asked for) but the bisection on `x` assumes the admissible `x` still form an
//! interval from 0, which holds while `b x + d √x` is monotone in `x` on each joint (always when
//! `b` and `d` have the same sign). Each joint's limit `|T_i| ≤ h L_i`, with a
//! headroom `h ∈ (0, 1]` kept for the correction of errors, bounds `u` between two affine
//! functions of `x`. On a grid `τ_j = jΔ` with `x_{j+1} = x_j + 2Δ u_j`, the profile is:
//! 1. the largest `x_j` at which some `u` is admissible (the maximum-velocity curve), capped by
//!    the rate asked for;
//! 2. a backward pass: the largest `x_j` from which an admissible deceleration reaches
//!    `x_{j+1}` or below;
//! 3. a forward pass: `x_{j+1} ≤ x_j + 2Δ u_max(x_j)`.
//!
//! Both passes go round the closed contour until nothing changes (at most three laps each).
//! [`drive_limited_rates_with_miss`] adds, at each point, a torque the model misses (measured
//! on the plant along the contour) to what the drives must deliver.
//! The admissible set of `(x, u)` at each point is convex, so each bound is found by
//! bisection on `x`.

use crate::contour::Contour;
use crate::error::{ensure_finite, Error, ErrorKind, Result};
use crate::lie::{LieGroup, Tangent};
use crate::mechanics::MechanicalSystem;
use crate::scalar::cast;
use crate::Real;

/// The torque the drives can give the contour's motion (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriveLimits<T: Real, const D: usize> {
    torque: Tangent<T, D>,
    headroom: T,
    friction: Tangent<T, D>,
    viscous: Tangent<T, D>,
    gravity: bool,
}

impl<T: Real, const D: usize> DriveLimits<T, D> {
    /// Per-joint torque limits `L_i` (finite, > 0), all of them for the motion (headroom 1),
    /// no friction or gravity compensation.
    pub fn new(torque: Tangent<T, D>) -> Result<Self> {
        ensure_finite(torque.iter(), "DriveLimits: torque limits")?;
        if torque.iter().any(|l| *l <= T::zero()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "DriveLimits: torque limits must be > 0",
            ));
        }
        Ok(DriveLimits {
            torque,
            headroom: T::one(),
            friction: Tangent::zeros(),
            viscous: Tangent::zeros(),
            gravity: false,
        })
    }

    /// The share `h ∈ (0, 1]` of each limit the motion along the contour may use; the rest is
    /// kept for the coupling's correction of errors and for what the model misses.
    pub fn with_headroom(mut self, headroom: T) -> Result<Self> {
        if !(headroom.is_finite() && headroom > T::zero() && headroom <= T::one()) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "DriveLimits: the headroom must be in (0, 1]",
            ));
        }
        self.headroom = headroom;
        Ok(self)
    }

    /// The controller's friction compensation `f_i ≥ 0` (eq. 35), which the drives deliver on
    /// top of the motion's torque.
    pub fn with_friction_compensation(mut self, friction: Tangent<T, D>) -> Result<Self> {
        non_negative(
            &friction,
            "DriveLimits: friction compensation",
            "DriveLimits: friction compensation must be ≥ 0",
        )?;
        self.friction = friction;
        Ok(self)
    }

    /// Viscous friction `B = diag(b_i)`, `b_i ≥ 0`, that the drives overcome on top of the
    /// motion's torque (`B q̇`; a plant's, when the least lap time on it is asked for).
    pub fn with_viscous_friction(mut self, viscous: Tangent<T, D>) -> Result<Self> {
        non_negative(
            &viscous,
            "DriveLimits: viscous friction",
            "DriveLimits: viscous friction must be ≥ 0",
        )?;
        self.viscous = viscous;
        Ok(self)
    }

    /// Whether the drives also hold the robot against gravity (`g(q)` of the model).
    pub fn with_gravity(mut self, gravity: bool) -> Self {
        self.gravity = gravity;
        self
    }

    /// The limits `L_i`.
    pub fn torque(&self) -> &Tangent<T, D> {
        &self.torque
    }

    /// The headroom `h`.
    pub fn headroom(&self) -> T {
        self.headroom
    }
}

/// `NonFinite` (`what`) for a non-finite entry, `InvalidParameter` (`negative`) for a
/// negative one.
fn non_negative<T: Real, const D: usize>(
    v: &Tangent<T, D>,
    what: &'static str,
    negative: &'static str,
) -> Result<()> {
    ensure_finite(v.iter(), what)?;
    if v.iter().any(|x| *x < T::zero()) {
        return Err(Error::new(ErrorKind::InvalidParameter, negative));
    }
    Ok(())
}

/// The torque of the motion at one point of the contour, `T = a u + b x + d √x + c` with
/// `u = τ̈`, `x = τ̇²`, and the limits `h L` it must stay within (module documentation): a
/// row of the plan, computed once from the model and the contour so that a plan can be made
/// again ([`drive_limited_rates_on_rows`]) or a step's torque compared with it
/// ([`MotionRow::torque`]) without evaluating the model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionRow<T: Real, const D: usize> {
    a: Tangent<T, D>,
    b: Tangent<T, D>,
    c: Tangent<T, D>,
    d: Tangent<T, D>,
    limit: Tangent<T, D>,
}

impl<T: Real, const D: usize> MotionRow<T, D> {
    /// The row at `τ` of `contour`, from `system`'s model and `limits` (gravity and friction
    /// compensation in `c`, the limits times the headroom).
    pub fn at<G, Sys, X>(system: &Sys, contour: &X, limits: &DriveLimits<T, D>, tau: T) -> Self
    where
        G: LieGroup<T, D>,
        Sys: MechanicalSystem<T, G, D>,
        X: Contour<T, G, D>,
    {
        Self::with_miss(system, contour, limits, tau, None)
    }

    fn with_miss<G, Sys, X>(
        system: &Sys,
        contour: &X,
        limits: &DriveLimits<T, D>,
        tau: T,
        miss: Option<&Tangent<T, D>>,
    ) -> Self
    where
        G: LieGroup<T, D>,
        Sys: MechanicalSystem<T, G, D>,
        X: Contour<T, G, D>,
    {
        let s = contour.sample(tau);
        let (m, c) = system.inertia_and_coriolis(&s.point, &s.velocity);
        let mut offset = Tangent::zeros();
        if limits.gravity {
            offset += system.gravity(&s.point);
        }
        if let Some(miss) = miss {
            offset += miss;
        }
        for i in 0..D {
            let v = s.velocity[i];
            if v > T::zero() {
                offset[i] += limits.friction[i];
            } else if v < T::zero() {
                offset[i] -= limits.friction[i];
            }
        }
        MotionRow {
            a: m * s.velocity,
            b: m * s.acceleration + c * s.velocity,
            c: offset,
            d: limits.viscous.component_mul(&s.velocity),
            limit: limits.torque * limits.headroom,
        }
    }

    /// The torque the model says the motion needs at `τ̈ = tau_ddot`, `τ̇ = tau_dot ≥ 0`:
    /// `a τ̈ + b τ̇² + d τ̇ + c`.
    pub fn torque(&self, tau_ddot: T, tau_dot: T) -> Tangent<T, D> {
        self.a * tau_ddot + self.b * (tau_dot * tau_dot) + self.d * tau_dot + self.c
    }

    /// The row with `miss` added to what the drives deliver at any pace.
    fn plus(&self, miss: &Tangent<T, D>) -> Self {
        MotionRow {
            c: self.c + miss,
            ..*self
        }
    }

    /// The admissible `u = τ̈` at `x = τ̇²`: `[lo, hi]`, or `None` when there is none.
    fn bounds(&self, x: T) -> Option<(T, T)> {
        let mut lo: Option<T> = None;
        let mut hi: Option<T> = None;
        let root = x.max(T::zero()).sqrt();
        for i in 0..D {
            let rest = self.b[i] * x + self.d[i] * root + self.c[i];
            let (below, above) = (-self.limit[i] - rest, self.limit[i] - rest);
            let a = self.a[i];
            if a == T::zero() {
                if below > T::zero() || above < T::zero() {
                    return None;
                }
                continue;
            }
            let (l, h) = if a > T::zero() {
                (below / a, above / a)
            } else {
                (above / a, below / a)
            };
            lo = Some(lo.map_or(l, |x: T| x.max(l)));
            hi = Some(hi.map_or(h, |x: T| x.min(h)));
        }
        match (lo, hi) {
            (Some(l), Some(h)) if l <= h => Some((l, h)),
            (Some(_), Some(_)) => None,
            // No joint moves with τ̈ (a point where the contour stands still): any u.
            _ => {
                let any = cast::<T>(1e30);
                Some((-any, any))
            }
        }
    }
}

/// The largest `x ∈ [0, top]` with `admissible(x)`, for an admissible set that is an interval
/// containing 0 (`None` when 0 is not admissible).
fn largest<T: Real>(top: T, admissible: impl Fn(T) -> bool) -> Option<T> {
    if !admissible(T::zero()) {
        return None;
    }
    if admissible(top) {
        return Some(top);
    }
    let (mut ok, mut bad) = (T::zero(), top);
    for _ in 0..64 {
        let mid = (ok + bad) * cast::<T>(0.5);
        if mid <= ok || mid >= bad {
            break;
        }
        if admissible(mid) {
            ok = mid;
        } else {
            bad = mid;
        }
    }
    Some(ok)
}

/// The fastest `τ̇` the drives allow at `τ_j = j·period/n` for `n = rates.len()` points of a
/// closed contour of period `period`: on entry `rates[j]` is the rate asked for there (finite
/// and positive), on return the largest rate not above it that the drives can sustain,
/// accelerating and decelerating within their limits (module documentation).
///
/// Errors: `DimensionMismatch` for fewer than 3 points; `NonFinite` or `InvalidParameter`
/// for a bad rate or period; `InvalidParameter` when the drives cannot hold the contour even
/// at rest at some point (gravity or friction compensation beyond a limit).
pub fn drive_limited_rates<T, G, Sys, X, const D: usize>(
    system: &Sys,
    contour: &X,
    limits: &DriveLimits<T, D>,
    period: T,
    rates: &mut [T],
) -> Result<()>
where
    T: Real,
    G: LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    X: Contour<T, G, D>,
{
    plan(system, contour, limits, period, rates, None)
}

/// [`drive_limited_rates`] with the torque the model misses: at each point `τ_j` the drives
/// also deliver `miss[j]` (per joint, signed: what a plant's friction and inertia errors ask of
/// them beyond the model's motion torque there, as measured along the contour), so each limit
/// bounds `T(τ_j) + miss[j]`. With every `miss[j] = 0` the rates are
/// [`drive_limited_rates`]'s.
///
/// Errors: those of [`drive_limited_rates`]; `DimensionMismatch` for a `miss` not of
/// `rates.len()` points; `NonFinite` for a non-finite entry.
pub fn drive_limited_rates_with_miss<T, G, Sys, X, const D: usize>(
    system: &Sys,
    contour: &X,
    limits: &DriveLimits<T, D>,
    period: T,
    rates: &mut [T],
    miss: &[Tangent<T, D>],
) -> Result<()>
where
    T: Real,
    G: LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    X: Contour<T, G, D>,
{
    plan(system, contour, limits, period, rates, Some(miss))
}

/// [`drive_limited_rates_with_miss`] on rows computed once ([`MotionRow::at`] at
/// `τ_j = j·period/n`, `n = rows.len() = rates.len()`): the same three passes, no model
/// evaluated. With `miss` `None` the rates are those [`drive_limited_rates`] gives on the
/// same points, bit for bit.
///
/// Errors: those of [`drive_limited_rates_with_miss`]; `DimensionMismatch` for `rows` not of
/// `rates.len()` points.
pub fn drive_limited_rates_on_rows<T: Real, const D: usize>(
    rows: &[MotionRow<T, D>],
    miss: Option<&[Tangent<T, D>]>,
    period: T,
    rates: &mut [T],
) -> Result<()> {
    if rows.len() != rates.len() {
        return Err(Error::new(
            ErrorKind::DimensionMismatch,
            "drive_limited_rates_on_rows: one row per point",
        ));
    }
    check(period, rates, miss)?;
    passes(period, rates, |j| match miss {
        Some(m) => rows[j].plus(&m[j]),
        None => rows[j],
    })
}

/// The passes of [`drive_limited_rates`], with the missed torques if any.
fn plan<T, G, Sys, X, const D: usize>(
    system: &Sys,
    contour: &X,
    limits: &DriveLimits<T, D>,
    period: T,
    rates: &mut [T],
    miss: Option<&[Tangent<T, D>]>,
) -> Result<()>
where
    T: Real,
    G: LieGroup<T, D>,
    Sys: MechanicalSystem<T, G, D>,
    X: Contour<T, G, D>,
{
    check(period, rates, miss)?;
    let step = period / cast::<T>(rates.len() as f64);
    passes(period, rates, |j| {
        let tau = step * cast::<T>(j as f64);
        MotionRow::with_miss(system, contour, limits, tau, miss.map(|m| &m[j]))
    })
}

/// Checks a plan's inputs: at least 3 rates, each finite and > 0, a finite period > 0, and a
/// finite missed torque per point if any.
fn check<T: Real, const D: usize>(
    period: T,
    rates: &[T],
    miss: Option<&[Tangent<T, D>]>,
) -> Result<()> {
    let n = rates.len();
    if n < 3 {
        return Err(Error::new(
            ErrorKind::DimensionMismatch,
            "drive_limited_rates: at least 3 points",
        ));
    }
    ensure_finite(rates.iter(), "drive_limited_rates: rates")?;
    if rates.iter().any(|r| *r <= T::zero()) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            "drive_limited_rates: every rate asked for must be > 0",
        ));
    }
    if !(period.is_finite() && period > T::zero()) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            "drive_limited_rates: the period must be finite and > 0",
        ));
    }
    if let Some(miss) = miss {
        if miss.len() != n {
            return Err(Error::new(
                ErrorKind::DimensionMismatch,
                "drive_limited_rates_with_miss: one missed torque per point",
            ));
        }
        ensure_finite(
            miss.iter().flat_map(|m| m.iter()),
            "drive_limited_rates_with_miss: missed torques",
        )?;
    }
    Ok(())
}

/// The three passes (module documentation) on the rows `row(j)` of the points
/// `τ_j = j·period/n`, `n = rates.len()`, inputs checked.
fn passes<T: Real, const D: usize>(
    period: T,
    rates: &mut [T],
    row: impl Fn(usize) -> MotionRow<T, D>,
) -> Result<()> {
    let n = rates.len();
    let step = period / cast::<T>(n as f64);
    let two_step = step + step;
    let at_rest = || {
        Error::new(
            ErrorKind::InvalidParameter,
            "drive_limited_rates: the drives cannot hold the contour at rest (gravity or friction compensation beyond a torque limit)",
        )
    };
    // 1. The maximum-velocity curve, capped by the rates asked for (x = τ̇²).
    for (j, r) in rates.iter_mut().enumerate() {
        let rj = row(j);
        *r = largest(*r * *r, |x| rj.bounds(x).is_some()).ok_or_else(at_rest)?;
    }
    // 2. Backward: from x_j an admissible deceleration must reach x_{j+1} or below.
    for _ in 0..3 {
        let mut changed = false;
        for j in (0..n).rev() {
            let rj = row(j);
            let next = rates[(j + 1) % n];
            let x = largest(rates[j], |x| {
                rj.bounds(x)
                    .is_some_and(|(lo, _)| x + two_step * lo <= next)
            })
            .unwrap_or(T::zero());
            if x < rates[j] {
                rates[j] = x;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    // 3. Forward: from x_j the largest admissible acceleration bounds x_{j+1}.
    for _ in 0..3 {
        let mut changed = false;
        for j in 0..n {
            let rj = row(j);
            let reach = match rj.bounds(rates[j]) {
                Some((_, hi)) => rates[j] + two_step * hi,
                None => rates[j],
            };
            let k = (j + 1) % n;
            if reach < rates[k] {
                rates[k] = reach.max(T::zero());
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    for r in rates.iter_mut() {
        *r = r.max(T::zero()).sqrt();
    }
    Ok(())
}
