//! Independent linear axes: a Cartesian stage on `ℝⁿ`.

use super::{positive, MechanicalSystem};
use crate::error::Result;
use crate::lie::{Rn, Tangent};
use crate::Real;
use nalgebra::{SMatrix, SVector};

/// `N` decoupled linear axes with moving masses `m_i`: `M = diag(m)`, `C = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearStage<T: Real, const N: usize> {
    mass: SVector<T, N>,
}

impl<T: Real, const N: usize> LinearStage<T, N> {
    /// Axes with masses `m_i > 0` (kg).
    pub fn new(mass: SVector<T, N>) -> Result<Self> {
        for m in mass.iter() {
            positive(*m, "LinearStage: every mass must be finite and > 0")?;
        }
        Ok(LinearStage { mass })
    }
}

impl<T: Real, const N: usize> MechanicalSystem<T, Rn<T, N>, N> for LinearStage<T, N> {
    #[inline]
    fn inertia(&self, _q: &Rn<T, N>) -> SMatrix<T, N, N> {
        SMatrix::from_diagonal(&self.mass)
    }

    #[inline]
    fn coriolis(&self, _q: &Rn<T, N>, _v: &Tangent<T, N>) -> SMatrix<T, N, N> {
        SMatrix::zeros()
    }
}
