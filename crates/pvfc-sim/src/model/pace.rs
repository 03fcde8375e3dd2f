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

/// A controller's drive-limited pace, as plain data: the field slows along the contour to
/// the fastest pace the drives allow.
#[derive(Clone, Debug, PartialEq)]
pub struct DrivePace {
    /// Per-joint torque limits (N·m or N, each > 0).
    pub torque_limit: Vec<f64>,
    /// The share of each limit the motion along the contour may use, in (0, 1].
    pub headroom: f64,
    /// The energy level `β` the controller runs at (the rate `τ̇` it makes on the contour
    /// where nothing limits it).
    pub level: f64,
}

impl DrivePace {
    /// The limits of an `N`-joint controller that adds `friction` compensation (eq. 35) and,
    /// if `gravity`, its model's `g(q)` to the coupling's torque.
    pub fn limits<const N: usize>(
        &self,
        friction: Option<&[f64]>,
        gravity: bool,
    ) -> Result<DriveLimits<f64, N>> {
        let setting = |what: String| SimError::Setting(what);
        let limit = super::fixed::<N>(&self.torque_limit, "pace.torque_limit")?;
        let mut limits = DriveLimits::new(limit)
            .map_err(|e| setting(format!("pace.torque_limit: {e}")))?
            .with_headroom(self.headroom)
            .map_err(|e| setting(format!("pace.headroom = {}: {e}", self.headroom)))?
            .with_gravity(gravity);
        if let Some(f) = friction {
            let f = super::fixed::<N>(f, "friction_compensation")?;
            limits = limits.with_friction_compensation(f)?;
        }
        Ok(limits)
    }

    /// The pace profile of `system` along `contour` (period `period`) under these limits.
    pub fn profile<G, Sys, X, const N: usize>(
        &self,
        system: &Sys,
        contour: &X,
        period: f64,
        friction: Option<&[f64]>,
        gravity: bool,
    ) -> Result<PaceTable<f64, PACE_KNOTS>>
    where
        G: LieGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        X: Contour<f64, G, N>,
    {
        let limits = self.limits::<N>(friction, gravity)?;
        drive_limited_pace(system, contour, &limits, period, self.level)
    }
}

impl DrivePace {
    /// The least time of one lap of `contour` (period `period`) that the drives allow at
    /// full use of their limits (headroom 1, whatever this pace keeps): the time-optimal
    /// parameterisation's lap, `∫ dτ / τ̇_max(τ)` on [`PACE_GRID`] points, against which a
    /// controller's lap time is measured.
    pub fn minimum_lap<G, Sys, X, const N: usize>(
        &self,
        system: &Sys,
        contour: &X,
        period: f64,
        friction: Option<&[f64]>,
        gravity: bool,
    ) -> Result<f64>
    where
        G: LieGroup<f64, N>,
        Sys: MechanicalSystem<f64, G, N>,
        X: Contour<f64, G, N>,
    {
        let full = DrivePace {
            headroom: 1.0,
            ..self.clone()
        };
        let limits = full.limits::<N>(friction, gravity)?;
        // A rate no drive reaches: the profile is then the drives' alone.
        let mut rates = vec![1e6; PACE_GRID];
        drive_limited_rates(system, contour, &limits, period, &mut rates)?;
        Ok(lap_time(&rates, period))
    }
}

/// The time of one lap at the rates `rates` (`τ̇` at evenly spaced points over `period`),
/// `Σ 2Δ / (τ̇_j + τ̇_{j+1})` (the rate's square moving linearly in `τ`, as the profile's
/// steps assume, is close to this for a fine grid); infinite if the rate is 0 somewhere.
pub fn lap_time(rates: &[f64], period: f64) -> f64 {
    let n = rates.len();
    let step = period / n as f64;
    (0..n)
        .map(|j| 2.0 * step / (rates[j] + rates[(j + 1) % n]))
        .sum()
}

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
