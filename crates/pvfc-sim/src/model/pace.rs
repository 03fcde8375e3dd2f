//! The drive-limited pace of a controller (`pvfc_core::pace`): the fastest rate `τ̇(τ)` the
//! drives allow along a closed contour, computed on a fine grid and held as a smooth profile
//! `σ(τ)` of [`PACE_KNOTS`] knots that stays at or below it.

use crate::error::{Result, SimError};
use pvfc_core::contour::Contour;
use pvfc_core::lie::LieGroup;
use pvfc_core::mechanics::MechanicalSystem;
use pvfc_core::pace::{drive_limited_rates, DriveLimits, PaceTable, Paced};
use pvfc_core::pacing::ExponentialPacing;

/// The knots of a controller's pace profile.
pub const PACE_KNOTS: usize = 256;

/// The points per period on which the drive-limited rates are computed (16 per knot).
pub const PACE_GRID: usize = 16 * PACE_KNOTS;

/// A controller's pace profile: none (the paper's uniform pace) or a table.
pub type PaceProfileTable = Option<PaceTable<f64, PACE_KNOTS>>;

/// The self-pacing of the simulator's fields: eq. (21) with an optional pace profile.
pub type FieldPacing = Paced<ExponentialPacing<f64>, PaceProfileTable>;

/// Eq. (21)'s self-pacing with parameter `r`, at the uniform pace.
pub fn uniform_pacing(r: f64) -> Result<FieldPacing> {
    Ok(Paced::new(ExponentialPacing::new(r)?, None))
}

/// The profile `σ = τ̇_max(τ) / β` for a field run at energy level `β` (`beta`, the rate `τ̇`
/// it would make on the contour at `σ = 1`), where `τ̇_max ≤ β` is the fastest rate the drives
/// allow (`limits`) along `contour` of period `period`, for the model `system`.
pub fn drive_limited_pace<G, Sys, X, const D: usize>(
    system: &Sys,
    contour: &X,
    limits: &DriveLimits<f64, D>,
    period: f64,
    beta: f64,
) -> Result<PaceTable<f64, PACE_KNOTS>>
where
    G: LieGroup<f64, D>,
    Sys: MechanicalSystem<f64, G, D>,
    X: Contour<f64, G, D>,
{
    if !(beta.is_finite() && beta > 0.0) {
        return Err(SimError::Setting(format!(
            "the pace's energy level β = {beta}: finite and > 0"
        )));
    }
    let mut rates = vec![beta; PACE_GRID];
    drive_limited_rates(system, contour, limits, period, &mut rates)?;
    if let Some((j, r)) = rates.iter().enumerate().find(|(_, r)| **r <= 1e-6 * beta) {
        return Err(SimError::Setting(format!(
            "the drives cannot move along the contour at τ = {:.4} (fastest rate there {r:.3e})",
            j as f64 * period / PACE_GRID as f64
        )));
    }
    Ok(PaceTable::below(&rates, beta, PACE_KNOTS, period)?)
}
