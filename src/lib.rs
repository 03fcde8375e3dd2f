//! # pvfc
//!
//! Passive Velocity Field Control (Li & Horowitz) for contour following. This umbrella crate
//! re-exports the `no_std` core ([`core`], also usable alone as `pvfc-core` on a
//! microcontroller) and the simulation crate ([`sim`]); it also holds the project's
//! cross-crate tests, benchmarks and examples.

#![forbid(unsafe_code)]
#![warn(missing_docs)]
// Library code never unwraps: bad input is an error value.
#![warn(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

pub use pvfc_core as core;
pub use pvfc_core::prelude;
pub use pvfc_sim as sim;

/// The paper's experiment (section V) as a ready-made controller: the Pelican SCARA on the
/// Lissajous contour, eq. (17) navigation, eq. (21) self-pacing, a flywheel of inertia 1.
pub mod paper {
    use nalgebra::Vector2;
    use pvfc_core::prelude::*;

    /// The controller type of the paper's experiment.
    pub type PaperController = Controller<
        f64,
        Torus<f64, 2>,
        Scara<f64>,
        SuspendedField<
            f64,
            Torus<f64, 2>,
            Lissajous<f64, 2>,
            TorusNavigation<f64, 2>,
            ExponentialPacing<f64>,
            2,
        >,
        2,
    >;

    /// Settings the paper does not publish; chosen here and documented in the README.
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

    /// Builds the controller, starting at `τ = 0` with all of `Ē` in the flywheel
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
}
