//! A pace learned lap over lap: per-stretch scales of a pace profile on a closed contour,
//! each moved once a lap by what the drives' command did on its stretch.
//!
//! A closed contour repeats; where the drives saturated on one lap they will on the next at
//! the same pace, and where they had margin they will again. Each of `K` evenly spaced knots
//! `τ_k = k·P/K` of the period `P` keeps, while `τ` is nearest to it, the peak share
//! `û_k = max u` and the mean excess `ē_k = ∫ max(0, u − 1) dt / ∫ dt` of the largest share
//! `u = maxᵢ |Tᵢ| / Lᵢ` of a limit the (unclamped) command uses. When `τ` has left both
//! stretches the knot's scale shapes, its scale `s_k` moves:
//!
//! - over a limit (`ē_k > 0`): `s_k ← s_k · max(1 − fall, 1/√(1 + ē_k))`: the pace asked
//!   `1 + ē_k` of what the drive gives, and where inertia dominates the torque of a pace scaled
//!   by `s` grows as `s²`;
//! - under the target (`û_k < u₀`): `s_k ← s_k · min(1 + rise, √(u₀ / û_k))`, and for each
//!   neighbour `j = k ± 1` no higher than `max(s_j, s_k) · min(1 + rise, √(u₀ / û_j))` (`û_j`
//!   from its last visit), never lower than `s_k`: the pace's gradient between two knots
//!   costs torque on both their stretches (`τ̈` has a term `σ² s ds/dτ`), so a knot rising
//!   above a slower neighbour does so by that neighbour's margin too (without it, fast
//!   stretches climbing beside a slow one drive the stretch between into the limit lap after
//!   lap: `docs/design/drive-limited-pace.md`, stop 72);
//! - in between it holds;
//!
//! within `[floor, 1]`, and no higher than a neighbour's scale plus `slope`; a knot that fell
//! pulls its neighbours down to within `slope` of it, both ways round, so that the learned pace
//! never asks for a sharper change than that (the braking into a slow stretch costs torque
//! too). The knots of the stretch `τ` is in are never moved: the pace the robot follows does
//! not jump.
//!
//! The start from rest does not repeat, so nothing is learned from it: learning begins once
//! `τ` has crossed a whole stretch with the command within the limits or more slowly than the
//! stretch before (the robot has caught up with the field), or has gone a whole period.
//!
//! A knot's scale never rises above its **cap** (1 until [`PaceProfile::set_caps`] sets the
//! caps, as a [`super::MissLearner`] does from the torque the model misses); a scale above a
//! new cap comes down to it when `τ` next leaves its stretch.
//!
//! The pace is `σ(τ) · s(τ)`, `s` piecewise linear between the knots. Passivity does not
//! depend on it: the coupling is workless for any field (eq. 27).

use super::PaceProfile;
use crate::error::{Error, ErrorKind, Result};
use crate::scalar::cast;
use crate::Real;

/// The rule of a [`LearnedPace`] (see the [module](self) for what each bound does).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaceLearning<T: Real> {
    /// The peak share of a limit `u₀` below which a scale rises, in (0, 1].
    pub target: T,
    /// The largest fraction a scale falls in one lap, in [0, 1).
    pub fall: T,
    /// The largest fraction a scale rises in one lap (finite, ≥ 0).
    pub rise: T,
    /// The largest difference between the scales of neighbouring knots, in (0, 1].
    pub slope: T,
    /// The least scale, in (0, 1].
    pub floor: T,
}

impl<T: Real> PaceLearning<T> {
    /// The rule, checked: `InvalidParameter` for a bound outside its range.
    pub fn new(target: T, fall: T, rise: T, slope: T, floor: T) -> Result<Self> {
        let rule = PaceLearning {
            target,
            fall,
            rise,
            slope,
            floor,
        };
        let unit = |x: T| x.is_finite() && x > T::zero() && x <= T::one();
        let ok = unit(target)
            && unit(slope)
            && unit(floor)
            && fall.is_finite()
            && fall >= T::zero()
            && fall < T::one()
            && rise.is_finite()
            && rise >= T::zero();
        if ok {
            Ok(rule)
        } else {
            Err(Error::new(
                ErrorKind::InvalidParameter,
                "PaceLearning: target, slope and floor in (0, 1]; fall in [0, 1); rise finite \
                 and ≥ 0",
            ))
        }
    }
}

/// A pace profile `P` times per-stretch scales `s(τ)`, piecewise linear between `K` evenly
/// spaced knots of a period, learned by [`PaceProfile::learn`]. Every scale starts at 1 (the
/// profile unchanged); without a period ([`new`](Self::new)) it does not learn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LearnedPace<T: Real, P, const K: usize> {
    profile: P,
    /// The contour's period `P`, if it learns.
    period: Option<T>,
    scales: [T; K],
    /// The ceilings of the scales, in (0, 1].
    caps: [T; K],
    /// Per knot, over this lap's visit: the peak share, `∫ max(0, u − 1) dt` and `∫ dt`.
    peaks: [T; K],
    excess: [T; K],
    time: [T; K],
    /// Per knot, the peak share its last visit saw (0 before one).
    last_peaks: [T; K],
    /// The stretch `[τ_a, τ_{a+1})` of the last `τ` learned from (`K`: none yet).
    current: usize,
    /// Until learning begins: where the start from rest is.
    start: Start<T>,
}

/// The start from rest, watched until it is over: when `τ` has crossed a whole stretch
/// (entered at one knot, left at the other) with the command within the limits throughout,
/// or more slowly than the stretch before (`τ̇` no longer rising from rest), or has gone a
/// whole period.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Start<T> {
    /// Over: learning has begun.
    over: bool,
    /// The last `τ` read, and how far `τ` has gone since the first reading.
    last: Option<T>,
    travelled: T,
    /// The stretch `τ` is in (`None` before the first reading), whether `τ` entered it at
    /// one of its knots, and whether the command stayed within the limits since.
    stretch: Option<usize>,
    entered: bool,
    within: bool,
    /// The time spent in the stretch `τ` is in, and in the last whole stretch crossed.
    time: T,
    crossed: Option<T>,
}

impl<T: Real> Start<T> {
    fn new() -> Self {
        Start {
            over: false,
            last: None,
            travelled: T::zero(),
            stretch: None,
            entered: false,
            within: true,
            time: T::zero(),
            crossed: None,
        }
    }

    /// Reads a step of `dt` at `τ`, in stretch `a`, with the share `share` of a limit; whether
    /// the start is over (from this step on, everything is learned).
    fn over(&mut self, tau: T, share: T, dt: T, period: T, a: usize) -> bool {
        if self.over {
            return true;
        }
        if let Some(last) = self.last {
            let half = period * cast::<T>(0.5);
            let mut d = tau - last;
            if d > half {
                d -= period;
            } else if d < -half {
                d += period;
            }
            self.travelled += d;
        }
        self.last = Some(tau);
        if self.stretch != Some(a) {
            if self.entered {
                // Crossed a whole stretch: within the limits, or slower than the one before
                // (`τ̇` no longer rises from rest).
                let slower = self.crossed.is_some_and(|before| self.time > before);
                if self.within || slower {
                    self.over = true;
                }
                self.crossed = Some(self.time);
            }
            self.entered = self.stretch.is_some();
            self.within = true;
            self.time = T::zero();
            self.stretch = Some(a);
        }
        self.time += dt;
        if share > T::one() {
            self.within = false;
        }
        if self.travelled.abs() >= period {
            self.over = true;
        }
        self.over
    }
}

/// `τ` in units of `K` evenly spaced knots of the period: `(a, f)` with `x = a + f`, `a < K`,
/// `f ∈ [0, 1)`.
pub(crate) fn knot<T: Real, const K: usize>(period: T, tau: T) -> (usize, T) {
    let n = cast::<T>(K as f64);
    let x = tau / period * n;
    let x = x - (x / n).floor() * n;
    let a = x.floor();
    let f = x - a;
    let a = a.to_i64_checked().unwrap_or(0).rem_euclid(K as i64) as usize;
    (a, f)
}

/// The knot nearest `τ` of `K` evenly spaced over the period.
pub(crate) fn nearest_knot<T: Real, const K: usize>(period: T, tau: T) -> usize {
    let (a, f) = knot::<T, K>(period, tau);
    nearer::<T, K>(a, f)
}

/// Of knots `a` and `a + 1` (of `K`, round the period), the one nearer `a + f`.
fn nearer<T: Real, const K: usize>(a: usize, f: T) -> usize {
    if f < cast::<T>(0.5) {
        a
    } else {
        (a + 1) % K
    }
}

impl<T: Real, P, const K: usize> LearnedPace<T, P, K> {
    /// `profile` with every scale at 1, not learning.
    pub fn new(profile: P) -> Self {
        LearnedPace {
            profile,
            period: None,
            scales: [T::one(); K],
            caps: [T::one(); K],
            peaks: [T::zero(); K],
            excess: [T::zero(); K],
            time: [T::zero(); K],
            last_peaks: [T::zero(); K],
            current: K,
            start: Start::new(),
        }
    }

    /// `profile` with every scale at 1, learning over a closed contour of period `period`.
    ///
    /// Errors: `InvalidParameter` for a period that is not finite and > 0, or fewer than 3
    /// knots.
    pub fn periodic(profile: P, period: T) -> Result<Self> {
        if !(period.is_finite() && period > T::zero() && K >= 3) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "LearnedPace: the period must be finite and > 0, with at least 3 knots",
            ));
        }
        let mut pace = Self::new(profile);
        pace.period = Some(period);
        Ok(pace)
    }

    /// The period it learns over, if any.
    pub fn period(&self) -> Option<T> {
        self.period
    }

    /// The scales at the knots `τ_k = k·P/K`.
    pub fn scales(&self) -> &[T; K] {
        &self.scales
    }

    /// The ceilings of the scales at the knots.
    pub fn caps(&self) -> &[T; K] {
        &self.caps
    }

    /// The profile before scaling.
    pub fn profile(&self) -> &P {
        &self.profile
    }

    /// The profile before scaling, to replace it on line.
    pub fn profile_mut(&mut self) -> &mut P {
        &mut self.profile
    }

    /// Moves knot `k`'s scale by what its stretch saw, then bounds its neighbours by the
    /// slope, leaving alone the knots `a` and `a + 1` of the stretch `τ` is in.
    fn settle(&mut self, k: usize, a: usize, rule: &PaceLearning<T>) {
        let peak = self.peaks[k];
        let excess = if self.time[k] > T::zero() {
            self.excess[k] / self.time[k]
        } else {
            T::zero()
        };
        self.peaks[k] = T::zero();
        self.excess[k] = T::zero();
        self.time[k] = T::zero();
        self.last_peaks[k] = peak;
        // A knot's rise is bounded by its neighbours' margins too: the pace's gradient
        // between two knots costs torque on both stretches.
        let up = T::one() + rule.rise;
        let margin = |p: T| {
            if p > T::zero() {
                (rule.target / p).sqrt().min(up)
            } else {
                up
            }
        };
        let factor = if excess > T::zero() {
            (T::one() / (T::one() + excess))
                .sqrt()
                .max(T::one() - rule.fall)
        } else if peak < rule.target {
            // Up to a neighbour's level the gradient between them shrinks; above it, the
            // neighbour's margin bounds the rise.
            let s = self.scales[k];
            let by = |j: usize| self.scales[j].max(s) * margin(self.last_peaks[j]) / s;
            margin(peak)
                .min(by((k + K - 1) % K))
                .min(by((k + 1) % K))
                .max(T::one())
        } else {
            T::one()
        };
        let left = self.scales[(k + K - 1) % K] + rule.slope;
        let right = self.scales[(k + 1) % K] + rule.slope;
        let s = (self.scales[k] * factor)
            .min(self.caps[k])
            .min(left)
            .min(right);
        self.scales[k] = s.max(rule.floor);
        let protected = |j: usize| j == a || j == (a + 1) % K;
        for step in [1, K - 1] {
            let mut i = k;
            for _ in 1..K {
                let j = (i + step) % K;
                let bound = self.scales[i] + rule.slope;
                if protected(j) || self.scales[j] <= bound {
                    break;
                }
                self.scales[j] = bound;
                i = j;
            }
        }
    }
}

impl<T: Real, P: PaceProfile<T>, const K: usize> PaceProfile<T> for LearnedPace<T, P, K> {
    #[inline]
    fn pace(&self, tau: T) -> (T, T) {
        let (sigma, dsigma) = self.profile.pace(tau);
        let Some(period) = self.period else {
            return (sigma, dsigma);
        };
        let (a, f) = knot::<T, K>(period, tau);
        let (s0, s1) = (self.scales[a], self.scales[(a + 1) % K]);
        let s = s0 + (s1 - s0) * f;
        let ds = (s1 - s0) * cast::<T>(K as f64) / period;
        (sigma * s, dsigma * s + sigma * ds)
    }

    fn set_scale(&mut self, scale: T) -> bool {
        self.profile.set_scale(scale)
    }

    /// Sets the ceilings of the `K` scales (each finite, in (0, 1]); `false` (nothing changed)
    /// for another count or a bad entry.
    fn set_caps(&mut self, caps: &[T]) -> bool {
        let ok = caps.len() == K
            && caps
                .iter()
                .all(|c| c.is_finite() && *c > T::zero() && *c <= T::one());
        if ok {
            self.caps.copy_from_slice(caps);
        }
        ok
    }

    /// Records the step's share of a limit at `τ`; when `τ` enters a new stretch, the knot
    /// whose stretches it has left moves (see the [module](self)). `false` without a period
    /// or for a `τ`, `share` or `dt` that is not finite (nothing recorded).
    fn learn(&mut self, tau: T, share: T, dt: T, rule: &PaceLearning<T>) -> bool {
        let Some(period) = self.period else {
            return false;
        };
        if !(tau.is_finite() && share.is_finite() && dt.is_finite() && dt >= T::zero()) {
            return false;
        }
        let (a, f) = knot::<T, K>(period, tau);
        // The start from rest does not repeat: nothing is learned from it.
        if !self.start.over(tau, share, dt, period, a) {
            return true;
        }
        if a != self.current {
            if self.current < K {
                self.settle((a + K - 1) % K, a, rule);
            }
            self.current = a;
        }
        let nearest = nearer::<T, K>(a, f);
        if share > self.peaks[nearest] {
            self.peaks[nearest] = share;
        }
        if share > T::one() {
            self.excess[nearest] += (share - T::one()) * dt;
        }
        self.time[nearest] += dt;
        true
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;
    use crate::pace::UniformPace;

    const K: usize = 16;

    fn rule() -> PaceLearning<f64> {
        PaceLearning::new(0.9, 0.3, 0.1, 0.1, 0.2).unwrap()
    }

    /// Laps of a unit period at `τ̇ = 1`, the share `share(τ mod 1)` at every step; checks at
    /// every step that learning never moves the pace at the `τ` it is at.
    fn laps(p: &mut LearnedPace<f64, UniformPace, K>, n: usize, share: impl Fn(f64) -> f64) {
        let dt = 1e-3;
        let mut tau = 0.0;
        for _ in 0..(n as f64 / dt) as usize {
            let before = p.pace(tau);
            assert!(p.learn(tau, share(tau % 1.0), dt, &rule()));
            assert_eq!(p.pace(tau), before, "the pace jumped at τ = {tau}");
            tau += dt;
        }
    }

    fn slope_holds(s: &[f64; K], slope: f64, skip: &[usize]) -> bool {
        (0..K).all(|k| {
            let j = (k + 1) % K;
            skip.contains(&k) || skip.contains(&j) || (s[k] - s[j]).abs() <= slope + 1e-12
        })
    }

    #[test]
    fn a_stretch_over_the_limit_slows_on_the_next_lap_and_nowhere_far_from_it() {
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        // Half again the limit over [0.5, 0.6), well under it elsewhere.
        let share = |x: f64| if (0.5..0.6).contains(&x) { 1.5 } else { 0.5 };
        laps(&mut p, 3, share);
        let s = *p.scales();
        // Knots 8 and 9 (τ = 0.5, 0.5625) saw the excess: each lap at most 30 % lower.
        for k in [8, 9] {
            assert!(
                s[k] < 0.95 && s[k] >= 0.7f64.powi(3) - 1e-12,
                "knot {k}: {}",
                s[k]
            );
        }
        // The far side of the contour kept the planned pace.
        for k in [0, 1, 15] {
            assert_eq!(s[k], 1.0, "knot {k}");
        }
        // Within [floor, 1], and neighbours within the slope (the stretch τ is in aside).
        assert!(s.iter().all(|x| (0.2..=1.0).contains(x)));
        assert!(slope_holds(&s, 0.1, &[0, 1]), "{s:?}");
    }

    #[test]
    fn with_margin_again_the_scales_rise_back_to_the_plan() {
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        laps(
            &mut p,
            6,
            |x| if (0.25..0.5).contains(&x) { 3.0 } else { 0.5 },
        );
        let low = p.scales()[5];
        assert!(low < 0.5, "{low}");
        // Rising by at most 10 % a lap: from `low` to 1 takes ln(1/low)/ln(1.1) laps.
        let needed = ((1.0 / low).ln() / 1.1f64.ln()).ceil() as usize;
        laps(&mut p, needed - 2, |_| 0.5);
        assert!(p.scales()[5] < 1.0, "rose faster than 10 % a lap");
        laps(&mut p, 4, |_| 0.5);
        assert!(p.scales().iter().all(|&s| s == 1.0), "{:?}", p.scales());
    }

    #[test]
    fn a_knot_rises_no_faster_than_its_neighbours_margins_allow() {
        // The pace's gradient between two knots costs torque on both stretches: a knot beside
        // one near the target rises by that one's margin, not by its own.
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        let nearest = |x: f64| ((x * K as f64).round() as usize) % K;
        laps(&mut p, 3, |x| {
            if (7..=9).contains(&nearest(x)) {
                1.5
            } else {
                0.3
            }
        });
        assert!(
            p.scales()[7] < 0.9 && p.scales()[9] < 0.9,
            "{:?}",
            p.scales()
        );
        // Knot 8 just under the target (0.9): √(0.9/0.895) a lap; its neighbours see 0.3.
        // (The first lap still remembers the 1.5 of the laps before.)
        let share = |x: f64| if nearest(x) == 8 { 0.895 } else { 0.3 };
        laps(&mut p, 1, share);
        let before = *p.scales();
        laps(&mut p, 1, share);
        let after = *p.scales();
        let margin = (0.9f64 / 0.895).sqrt();
        for k in [7, 8, 9] {
            assert!(
                after[k] <= before[k] * margin + 1e-12,
                "knot {k}: {before:?} -> {after:?}"
            );
            assert!(
                after[k] > before[k],
                "knot {k} did not rise: {before:?} -> {after:?}"
            );
        }
        // (By its own margin alone knot 7 would rise 10 %, to 0.600: the slope allows 0.646.)
    }

    #[test]
    fn the_start_from_rest_teaches_nothing() {
        // Over the limit on the whole first lap while `τ̇` rises from rest (a start that never
        // catches up): nothing moves until a whole period has gone.
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        let (rule, dt) = (rule(), 1e-3);
        let mut t = 0.0;
        while t * t / 2.0 < 1.0 - 1e-9 {
            assert!(p.learn(t * t / 2.0, 3.0, dt, &rule));
            t += dt;
        }
        assert!(p.scales().iter().all(|&s| s == 1.0), "{:?}", p.scales());
        // The same excess on a later lap slows its stretch.
        laps(
            &mut p,
            2,
            |x| if (0.5..0.6).contains(&x) { 3.0 } else { 0.5 },
        );
        assert!(
            p.scales()[8] < 1.0 && p.scales()[9] < 1.0,
            "{:?}",
            p.scales()
        );

        // Over the limit while `τ̇` rises, then at a `τ̇` that wobbles about 1: learning begins
        // in the first lap, once a whole stretch is crossed more slowly than the one before.
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        let (mut tau, mut rate) = (0.0f64, 0.0f64);
        while tau < 0.95 {
            assert!(p.learn(tau, 3.0, dt, &rule));
            tau += rate * (1.0 + 0.05 * (40.0 * tau).sin()) * dt;
            rate = f64::min(rate + 0.01, 1.0);
        }
        assert!(
            p.scales().iter().any(|&s| s < 1.0),
            "nothing learned: {:?}",
            p.scales()
        );

        // Over the limit while `τ̇` rises from rest to 1 (until τ = 0.2), then at that `τ̇`:
        // learning begins once `τ̇` has stopped rising, and what passes the limit later in the
        // same lap is learned.
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        let (mut tau, mut rate) = (0.0f64, 0.0f64);
        while tau < 1.0 {
            let share = if rate < 1.0 || (0.6..0.65).contains(&tau) {
                3.0
            } else {
                0.5
            };
            assert!(p.learn(tau, share, dt, &rule));
            tau += rate * dt;
            rate = f64::min(rate + 2.5 * dt, 1.0);
        }
        let s = p.scales();
        assert!(
            s[0..3].iter().all(|&x| x == 1.0),
            "the start was learned: {s:?}"
        );
        assert!(s[10] < 1.0, "the later excess was not learned: {s:?}");
    }

    #[test]
    fn caps_bound_the_scales_and_take_effect_as_tau_leaves_each_knot() {
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        laps(&mut p, 2, |_| 0.5);
        assert!(p.scales().iter().all(|&s| s == 1.0));
        let mut caps = [1.0; K];
        for c in &mut caps[4..8] {
            *c = 0.5;
        }
        // Wrong counts and bad entries are refused and change nothing.
        assert!(!p.set_caps(&caps[..K - 1]));
        assert!(!p.set_caps(&[f64::NAN; K]));
        assert!(!p.set_caps(&[1.5; K]));
        assert_eq!(p.caps(), &[1.0; K]);
        assert!(p.set_caps(&caps));
        // With margin everywhere the scales would rise to 1; the caps hold them (the laps
        // check at every step that the pace does not jump when they take effect).
        laps(&mut p, 3, |_| 0.5);
        let s = *p.scales();
        for k in 4..8 {
            assert_eq!(s[k], 0.5, "knot {k}: {s:?}");
        }
        // The neighbours come down within the slope, the far side is untouched.
        assert!(slope_holds(&s, 0.1, &[]), "{s:?}");
        assert_eq!(s[14], 1.0);
        // Caps back at 1: the scales rise again, by at most `rise` a lap.
        assert!(p.set_caps(&[1.0; K]));
        laps(&mut p, 1, |_| 0.5);
        assert!(
            p.scales()[5] > 0.5 && p.scales()[5] <= 0.55 + 1e-12,
            "{:?}",
            p.scales()
        );
    }

    #[test]
    fn a_peak_between_the_target_and_the_limit_holds_the_pace() {
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        laps(&mut p, 2, |x| if x < 0.5 { 2.0 } else { 0.5 });
        let held = *p.scales();
        laps(&mut p, 3, |_| 0.95);
        // Knots 2..6 are away from the stretch τ ends in: none moved.
        assert_eq!(p.scales()[2..6], held[2..6]);
    }

    #[test]
    fn the_unlearned_pace_is_the_profile_itself() {
        let table = crate::pace::PaceTable::<f64, 8>::new(&[1.0, 0.5, 0.7, 0.9], 4.0).unwrap();
        let learned = LearnedPace::<f64, _, K>::periodic(table, 4.0).unwrap();
        let plain = LearnedPace::<f64, _, K>::new(table);
        for i in 0..100 {
            let tau = i as f64 * 0.173;
            assert_eq!(learned.pace(tau), table.pace(tau));
            assert_eq!(plain.pace(tau), table.pace(tau));
        }
    }

    #[test]
    fn bad_rules_and_bad_readings_are_refused() {
        assert!(PaceLearning::new(0.0, 0.3, 0.1, 0.1, 0.2).is_err());
        assert!(PaceLearning::new(0.9, 1.0, 0.1, 0.1, 0.2).is_err());
        assert!(PaceLearning::new(0.9, 0.3, f64::NAN, 0.1, 0.2).is_err());
        assert!(PaceLearning::new(0.9, 0.3, 0.1, 0.0, 0.2).is_err());
        assert!(PaceLearning::new(0.9, 0.3, 0.1, 0.1, 1.5).is_err());
        assert!(LearnedPace::<f64, _, K>::periodic(UniformPace, 0.0).is_err());
        assert!(LearnedPace::<f64, _, K>::periodic(UniformPace, f64::INFINITY).is_err());
        // Without a period nothing is learned; a non-finite reading is not recorded.
        let mut p = LearnedPace::<f64, _, K>::new(UniformPace);
        assert!(!p.learn(0.1, 2.0, 1e-3, &rule()));
        let mut p = LearnedPace::<f64, _, K>::periodic(UniformPace, 1.0).unwrap();
        assert!(!p.learn(0.1, f64::NAN, 1e-3, &rule()));
        assert!(!p.learn(f64::NAN, 0.5, 1e-3, &rule()));
        assert!(p.learn(0.1, 0.5, 1e-3, &rule()));
    }
}
