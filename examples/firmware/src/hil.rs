//! The hardware-in-the-loop stand-in shared by the firmware (f32) and its host twin (f64,
//! `tests/firmware_twin.rs` at the workspace root): the paper's controller with friction
//! compensation, and a Pelican SCARA plant with Coulomb and viscous friction integrated by
//! semi-implicit Euler. Generic over the scalar, `no_std`, no allocation.

use pvfc_core::mechanics::MechanicalSystem;
use pvfc_core::nalgebra::{Matrix2, Vector2};
use pvfc_core::prelude::*;
use pvfc_core::scalar::cast;

/// Control periods in a run (10 s at 1 kHz).
pub const STEPS: usize = 10_000;
/// The control period (s).
pub const DT: f64 = 1e-3;
/// Plant steps per control period (the plant at 10 kHz).
pub const SUBSTEPS: usize = 10;
/// One trace sample every this many control periods.
pub const TRACE_EVERY: usize = 100;

/// The controller: Pelican SCARA, the paper's Lissajous contour, `h = (1, 1)`, `R = 100`,
/// `Ē = 50`, `M_F = 1`, `γ = 0.05`, from rest at `τ = 0`, with friction compensation (35)
/// `(2, 3) N·m` whose sign is a linear ramp within ±0.1 rad/s (no chatter at `q̇ ≈ 0`; the
/// plant's own Coulomb friction has the same ramp, so the compensation matches it and only the
/// viscous part is left).
///
/// Known-good constants: the `Err` branches cannot be taken; a firmware still maps them to a
/// fault rather than unwrapping.
pub fn controller<T: Real>() -> Result<ScaraLissajousController<T>, pvfc_core::Error> {
    let friction =
        FrictionCompensation::new(Vector2::new(cast(2.0), cast(3.0)))?.with_band(cast(0.1))?;
    Ok(ScaraLissajousController::pelican_example()?.with_friction_compensation(friction))
}

/// The simulated arm: Pelican SCARA, Coulomb `(2.0, 3.0) N·m` regularised linearly within
/// ±0.1 rad/s, viscous `0.1 N·m·s/rad`, from rest at `q = (0, 0)`. (A ramp of ±0.01 rad/s is
/// a damper of 300 N·m·s/rad on a forearm of ~0.013 kg·m²: a time constant of 4e-5 s, shorter
/// than the 1e-4 s Euler step, and the plant model went numerically stiff.)
pub struct Plant<T: Real> {
    arm: Scara<T>,
    /// Joint angles.
    pub q: Vector2<T>,
    /// Joint velocities.
    pub v: Vector2<T>,
}

impl<T: Real> Default for Plant<T> {
    fn default() -> Self {
        Plant {
            arm: Scara::pelican(),
            q: Vector2::zeros(),
            v: Vector2::zeros(),
        }
    }
}

impl<T: Real> Plant<T> {
    fn friction(v: &Vector2<T>) -> Vector2<T> {
        let coulomb = Vector2::new(cast::<T>(2.0), cast(3.0));
        let (band, viscous): (T, T) = (cast(0.1), cast(0.1));
        Vector2::from_fn(|i, _| {
            let s = (v[i] / band).max(-T::one()).min(T::one());
            -(coulomb[i] * s + viscous * v[i])
        })
    }

    /// Holds `torque` over one control period: `SUBSTEPS` semi-implicit Euler steps.
    pub fn advance(&mut self, torque: &Vector2<T>) {
        let h: T = cast(DT / SUBSTEPS as f64);
        for _ in 0..SUBSTEPS {
            let q = Torus::new(self.q);
            let (m, c) = self.arm.inertia_and_coriolis(&q, &self.v);
            let rhs = torque + Self::friction(&self.v) - c * self.v;
            let det = m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)];
            let inv = Matrix2::new(m[(1, 1)], -m[(0, 1)], -m[(1, 0)], m[(0, 0)]) / det;
            self.v += inv * rhs * h;
            self.q += self.v * h;
        }
    }

    /// `½ q̇ᵀ M q̇`.
    pub fn kinetic_energy(&self) -> T {
        self.arm.kinetic_energy(&Torus::new(self.q), &self.v)
    }
}

/// One trace sample: after `step` control periods.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample<T> {
    /// Control periods done.
    pub step: usize,
    /// Joint angles.
    pub q: [T; 2],
    /// The torque applied over the period that starts here.
    pub torque: [T; 2],
    /// `τ` (unwrapped).
    pub tau: T,
    /// `U(E)`.
    pub potential: T,
    /// `κ_a`.
    pub kinetic_energy: T,
}

impl Sample<f32> {
    /// The sample as the firmwares print it: scaled 32-bit integers, so that no float
    /// formatting and no 64-bit division is linked (step; q in µrad; torque in mN·m; τ in
    /// 1e-6; U in 1e-9, −1 where the controller was not stepped; the kinetic energy in µJ).
    pub fn printed(&self) -> Printed {
        let potential = if self.potential.is_finite() {
            (self.potential * 1e9) as i32
        } else {
            -1
        };
        Printed([
            self.step as i32,
            (self.q[0] * 1e6) as i32,
            (self.q[1] * 1e6) as i32,
            (self.torque[0] * 1e3) as i32,
            (self.torque[1] * 1e3) as i32,
            (self.tau * 1e6) as i32,
            potential,
            (self.kinetic_energy * 1e6) as i32,
        ])
    }
}

/// A trace line's integers, written separated by spaces.
pub struct Printed(pub [i32; 8]);

impl core::fmt::Display for Printed {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        for (i, x) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(" ")?;
            }
            write!(f, "{x}")?;
        }
        Ok(())
    }
}
