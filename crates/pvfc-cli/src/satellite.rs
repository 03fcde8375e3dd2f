//! Section IV-B's satellite in `pvfc reproduce`: PVFC on SO(3), the paper's example of a
//! compact Lie group other than the arm's torus. The run is the preset
//! [`satellite`](pvfc_sim::scenario::presets::satellite); this module gives its claim (its
//! figure is [`crate::body_plot`]).

use crate::runs::Runs;
use pvfc_sim::error::Result;
use pvfc_sim::scenario::preset_id::PresetId;
use pvfc_sim::trace::metrics::{attitude_errors, energy_drift};

/// The satellite's claim: the attitude reaches its contour (Theorem 2 on SO(3)), `τ̇ → βλ₁`,
/// and `κ_a` is constant (Theorem 1).
pub(crate) fn claim(r: &Runs, push: &mut impl FnMut(&str, &str, &str, String, bool)) -> Result<()> {
    let (s, t) = r.run(PresetId::Satellite)?;
    let angle = attitude_errors(t, &s.attitude_contour()?);
    let n = t.len() - 1;
    let from = t.t.iter().position(|&x| x >= t.t[n] - 10.0).unwrap_or(0);
    let u_tail = t.potential[from..].iter().cloned().fold(0.0, f64::max);
    let pace = (from..=n)
        .map(|i| (t.tau_dot[i] - t.beta[i] * t.lambda1[i]).abs())
        .fold(0.0, f64::max);
    let drift = energy_drift(t);
    push(
        "satellite",
        "On SO(3), the satellite of section IV-B: the attitude converges to its contour and τ̇ → βλ₁ (Theorem 2 on a compact Lie group), with κ_a constant (Theorem 1)",
        "a rigid body from 1.52 rad off a rotation at constant rate, P = diag(1, 2, 3) in eq. (26), 30 s continuous: the angle ‖log(R_d(τ)ᵀR)‖ at 0 and 30 s; max U and max |τ̇ − βλ₁| over the last 10 s; max |κ_a − κ_a(0)|/κ_a(0)",
        format!(
            "angle {:.2} → {:.1e} rad; max U = {u_tail:.1e}, max |τ̇ − βλ₁| = {pace:.1e}; κ_a drift {drift:.1e}",
            angle[0], angle[n]
        ),
        angle[n] < 1e-4 && u_tail < 1e-6 && pace < 1e-3 && drift < 1e-6,
    );
    Ok(())
}
