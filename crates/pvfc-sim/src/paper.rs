//! The paper's experiment (section V) as ready-made types: a two-link arm on the Lissajous
//! contour with eq. (17) navigation and eq. (21) self-pacing.

use nalgebra::Vector2;
use pvfc_core::prelude::*;

/// The velocity field of the experiments.
pub type PaperField = SuspendedField<
    f64,
    Torus<f64, 2>,
    Lissajous<f64, 2>,
    TorusNavigation<f64, 2>,
    ExponentialPacing<f64>,
    2,
>;

/// The controller of the experiments.
pub type PaperController = Controller<f64, Torus<f64, 2>, Scara<f64>, PaperField, 2>;

/// The paper's controller in the passive digital mode (`pvfc_core::passive`).
pub type PaperPassiveController = PassiveController<f64, Torus<f64, 2>, Scara<f64>, PaperField, 2>;

/// Settings the paper does not publish for the core example (Pelican arm, no friction).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperSettings {
    /// Self-pacing parameter `R` of eq. (21).
    pub r: f64,
    /// Navigation weights `h_i` of eq. (17).
    pub h: [f64; 2],
    /// Energy level `Ē` of eq. (6).
    pub energy: f64,
    /// Flywheel inertia `M_F` (the paper: 1).
    pub flywheel_inertia: f64,
    /// Coupling gain `γ` of eq. (7).
    pub gamma: f64,
}

impl Default for PaperSettings {
    fn default() -> Self {
        PaperSettings {
            r: 100.0,
            h: [1.0, 1.0],
            energy: 50.0,
            flywheel_inertia: 1.0,
            gamma: 0.05,
        }
    }
}

/// The controller for the Pelican arm, starting at `τ = 0` with all of `Ē` in the flywheel
/// (`q̇_F = 10 rad/s` for the paper's energy 50 and `M_F = 1`).
pub fn controller(s: &PaperSettings) -> pvfc_core::Result<PaperController> {
    let field = SuspendedField::new(
        Lissajous::paper(),
        TorusNavigation::paper(Vector2::new(s.h[0], s.h[1]))?,
        ExponentialPacing::new(s.r)?,
    );
    let law = PvfcLaw::new(
        Scara::pelican(),
        field,
        Flywheel::new(s.flywheel_inertia, s.energy)?,
        s.gamma,
    )?;
    Ok(Controller::new(law).starting_at_rest(0.0))
}
