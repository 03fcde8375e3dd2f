//! Obstacles in the joint space: balls, ellipsoids and rounded boxes of joint coordinates.

use super::{step_barrier, Barrier};
use crate::error::{ensure_finite, Error, ErrorKind, Result};
use crate::lie::Tangent;
use crate::Real;
use nalgebra::SVector;

/// A region of joint coordinates to keep out of: the superellipsoid
/// `r(q) = (Σ ((q_i − c_i)/a_i)^{2p})^{1/2p} ≤ 1` with centre `c`, semi-axes `a` and
/// exponent `p ≥ 1` (`p = 1` an ellipsoid, a ball when the semi-axes are equal; a large `p` a
/// box with rounded corners, smooth everywhere).
///
/// Its clearance is `ℓ(q) = (r(q) − 1)·a_min` (the distance to a ball's surface; for other
/// shapes a distance of the same order), and its barrier `β = σ(ℓ/w)` with the smooth step
/// `σ` and the influence width `w`: `β = 0` on the surface, `1` at a clearance of `w` and
/// beyond.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointRegion<T: Real, const N: usize> {
    center: SVector<T, N>,
    inverse_axes: SVector<T, N>,
    smallest_axis: T,
    exponent: i32,
    influence: T,
}

impl<T: Real, const N: usize> JointRegion<T, N> {
    /// The region with centre `c`, semi-axes `a_i > 0`, exponent `p ≥ 1` and influence width
    /// `w > 0`, in the joint coordinates of the contour (unwrapped angles).
    pub fn new(center: SVector<T, N>, semi_axes: SVector<T, N>, p: u8, w: T) -> Result<Self> {
        ensure_finite(center.iter(), "JointRegion: centre")?;
        ensure_finite(semi_axes.iter(), "JointRegion: semi-axes")?;
        ensure_finite([w].iter(), "JointRegion: influence width")?;
        if semi_axes.iter().any(|a| *a <= T::zero()) || w <= T::zero() || p == 0 || p > 8 {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "JointRegion: the semi-axes and the influence width must be > 0, the exponent in 1..=8",
            ));
        }
        Ok(JointRegion {
            center,
            inverse_axes: semi_axes.map(|a| T::one() / a),
            smallest_axis: semi_axes.min(),
            exponent: 2 * i32::from(p),
            influence: w,
        })
    }

    /// A ball of radius `r` about `c`.
    pub fn ball(center: SVector<T, N>, radius: T, w: T) -> Result<Self> {
        Self::new(center, SVector::repeat(radius), 1, w)
    }

    /// `r(q)` and `∂r/∂q`, with `u_i = (q_i − c_i)/a_i`, `m = Σ u_i^P`, `r = m^{1/P}`,
    /// `∂r/∂q_i = r^{1−P} u_i^{P−1} / a_i`.
    #[inline]
    fn radius(&self, q: &SVector<T, N>) -> (T, SVector<T, N>, SVector<T, N>) {
        let u = (q - self.center).component_mul(&self.inverse_axes);
        let pw = self.exponent;
        let m = u.iter().fold(T::zero(), |acc, ui| acc + ui.powi(pw));
        let r = m.powf(T::one() / crate::scalar::cast(f64::from(pw)));
        let r_safe = r.max(crate::scalar::cast(1e-12));
        let dr = u
            .map(|ui| ui.powi(pw - 1))
            .component_mul(&self.inverse_axes)
            * r_safe.powi(1 - pw);
        (r, u, dr)
    }

    /// The clearance `ℓ(q)`: negative inside.
    pub fn clearance(&self, q: &SVector<T, N>) -> T {
        (self.radius(q).0 - T::one()) * self.smallest_axis
    }

    /// `β = σ(ℓ/w)`, `dβ`, and their rates along `v`.
    ///
    /// `d/dt ∂r/∂q_i = (1−P) r^{−P} ṙ u_i^{P−1}/a_i + r^{1−P} (P−1) u_i^{P−2} u̇_i / a_i`,
    /// `u̇_i = v_i/a_i`, `ṙ = ∂r·v`.
    pub fn barrier(&self, q: &SVector<T, N>, v: &Tangent<T, N>) -> Barrier<T, N> {
        let (r, u, dr) = self.radius(q);
        let scale = self.smallest_axis / self.influence;
        if (r - T::one()) * scale >= T::one() {
            return Barrier::free();
        }
        let pw = self.exponent;
        let p_minus_1: T = crate::scalar::cast(f64::from(pw - 1));
        let r_safe = r.max(crate::scalar::cast(1e-12));
        let r_dot = dr.dot(v);
        let u_dot = v.component_mul(&self.inverse_axes);
        let dr_dot = u
            .map(|ui| ui.powi(pw - 1))
            .component_mul(&self.inverse_axes)
            * (-p_minus_1 * r_safe.powi(-pw) * r_dot)
            + u.zip_map(&u_dot, |ui, udi| ui.powi(pw - 2) * udi)
                .component_mul(&self.inverse_axes)
                * (p_minus_1 * r_safe.powi(1 - pw));
        step_barrier(
            (r - T::one()) * scale,
            &(dr * scale),
            r_dot * scale,
            &(dr_dot * scale),
        )
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn the_barrier_matches_finite_differences() {
        let region = JointRegion::new(
            Vector3::<f64>::new(0.2, -0.1, 0.4),
            Vector3::new(0.5, 0.3, 0.4),
            2,
            0.6,
        )
        .unwrap();
        let (q, v, h) = (
            Vector3::<f64>::new(0.6, 0.2, 0.1),
            Vector3::new(0.4, -0.9, 0.3),
            1e-6,
        );
        let b = region.barrier(&q, &v);
        assert!(
            b.value > 0.0 && b.value < 1.0,
            "inside the influence: {}",
            b.value
        );
        for i in 0..3 {
            let mut dq = Vector3::zeros();
            dq[i] = h;
            let fd = (region.barrier(&(q + dq), &v).value - region.barrier(&(q - dq), &v).value)
                / (2.0 * h);
            assert!((fd - b.differential[i]).abs() < 1e-8);
        }
        let p = region.barrier(&(q + v * h), &v);
        let m = region.barrier(&(q - v * h), &v);
        assert!(((p.value - m.value) / (2.0 * h) - b.value_rate).abs() < 1e-8);
        assert!(
            ((p.differential - m.differential) / (2.0 * h) - b.differential_rate).norm() < 1e-7
        );
    }

    #[test]
    fn a_ball_measures_the_distance_and_is_free_beyond_its_influence() {
        let ball = JointRegion::<f64, 3>::ball(Vector3::new(1.0, 0.0, 0.0), 0.5, 0.2).unwrap();
        let q = Vector3::<f64>::new(1.0, 0.8, 0.0);
        assert!((ball.clearance(&q) - 0.3).abs() < 1e-15);
        assert_eq!(ball.barrier(&q, &Vector3::zeros()), Barrier::free());
        let on = Vector3::<f64>::new(1.5, 0.0, 0.0);
        assert!(ball.barrier(&on, &Vector3::zeros()).value.abs() < 1e-15);
        assert!(JointRegion::ball(Vector3::zeros(), 0.0, 0.1).is_err());
        assert!(JointRegion::ball(Vector3::new(f64::NAN, 0.0, 0.0), 1.0, 0.1).is_err());
    }
}
