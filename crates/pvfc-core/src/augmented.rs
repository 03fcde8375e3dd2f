//! Vectors and states of the augmented system `q_a = (q, τ, q_F)` (eq. 4 on the suspended
//! system of eq. 14), stored in blocks so that no `(D+2)`-sized matrix is ever needed.

use crate::lie::{LieGroup, Tangent};
use crate::Real;
use core::ops::{Add, Mul, Neg, Sub};
use nalgebra::{SMatrix, SVector};

/// A (co)vector of the augmented system: robot block (`D` entries, body coordinates), the
/// suspended coordinate `τ`, and the fictitious flywheel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AugmentedVector<T: Real, const D: usize> {
    /// The robot's entries.
    pub robot: SVector<T, D>,
    /// The entry of the contour parameter `τ`.
    pub tau: T,
    /// The entry of the flywheel.
    pub flywheel: T,
}

impl<T: Real, const D: usize> AugmentedVector<T, D> {
    /// From the three blocks.
    #[inline]
    pub fn new(robot: SVector<T, D>, tau: T, flywheel: T) -> Self {
        AugmentedVector {
            robot,
            tau,
            flywheel,
        }
    }

    /// The zero vector.
    #[inline]
    pub fn zeros() -> Self {
        Self::new(SVector::zeros(), T::zero(), T::zero())
    }

    /// The Euclidean pairing `aᵀb` (a covector acting on a vector).
    #[inline]
    pub fn dot(&self, other: &Self) -> T {
        self.robot.dot(&other.robot) + self.tau * other.tau + self.flywheel * other.flywheel
    }

    /// The Euclidean norm.
    #[inline]
    pub fn norm(&self) -> T {
        self.dot(self).sqrt()
    }

    /// `true` when every entry is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        crate::scalar::all_finite_in(self.robot.iter(), [&self.tau, &self.flywheel])
    }

    /// The entries as one column `(robot, τ, flywheel)`; `A` must equal `D + 2`
    /// (`None` otherwise: stable Rust cannot write `D + 2` as a type).
    pub fn to_column<const A: usize>(&self) -> Option<SVector<T, A>> {
        if A != D + 2 {
            return None;
        }
        let mut out = SVector::<T, A>::zeros();
        for i in 0..D {
            out[i] = self.robot[i];
        }
        out[D] = self.tau;
        out[D + 1] = self.flywheel;
        Some(out)
    }

    /// The outer product `a bᵀ` as an `A × A` matrix, `A = D + 2`.
    pub fn outer<const A: usize>(&self, other: &Self) -> Option<SMatrix<T, A, A>> {
        Some(self.to_column::<A>()? * other.to_column::<A>()?.transpose())
    }
}

impl<T: Real, const D: usize> Add for AugmentedVector<T, D> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(
            self.robot + o.robot,
            self.tau + o.tau,
            self.flywheel + o.flywheel,
        )
    }
}

impl<T: Real, const D: usize> Sub for AugmentedVector<T, D> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(
            self.robot - o.robot,
            self.tau - o.tau,
            self.flywheel - o.flywheel,
        )
    }
}

impl<T: Real, const D: usize> Neg for AugmentedVector<T, D> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::new(-self.robot, -self.tau, -self.flywheel)
    }
}

impl<T: Real, const D: usize> Mul<T> for AugmentedVector<T, D> {
    type Output = Self;
    #[inline]
    fn mul(self, s: T) -> Self {
        Self::new(self.robot * s, self.tau * s, self.flywheel * s)
    }
}

/// The full state of the closed loop: the robot's configuration and body velocity, and the
/// controller's three internal states `τ`, `τ̇` and the flywheel speed `q̇_F` (section III-B:
/// the flywheel angle itself is never needed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AugmentedState<T: Real, G, const D: usize> {
    /// Robot configuration `q`.
    pub q: G,
    /// Robot velocity `q̇` in body coordinates.
    pub v: Tangent<T, D>,
    /// Contour parameter `τ`.
    pub tau: T,
    /// Its rate `τ̇`.
    pub tau_dot: T,
    /// Flywheel speed `q̇_F`.
    pub flywheel_speed: T,
}

impl<T: Real, G: LieGroup<T, D>, const D: usize> AugmentedState<T, G, D> {
    /// The augmented velocity `q̇_a = (q̇, τ̇, q̇_F)`.
    #[inline]
    pub fn velocity(&self) -> AugmentedVector<T, D> {
        AugmentedVector::new(self.v, self.tau_dot, self.flywheel_speed)
    }

    /// `true` when every entry is finite.
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.q.is_finite()
            && crate::scalar::all_finite_in(
                self.v.iter(),
                [&self.tau, &self.tau_dot, &self.flywheel_speed],
            )
    }
}
