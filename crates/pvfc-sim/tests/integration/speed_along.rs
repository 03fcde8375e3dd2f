//! The speed an arm makes along its contour (`trace::metrics::speed_along_contour`), which the
//! speed–accuracy figure of Fig. 1 on saturating drives plots: on the contour it is the pace
//! of `x_d(τ)`, `τ̇ |x_d'(τ)|`; an arm that stays off the contour or goes back and forth makes
//! about nothing, whatever the pace of its reference.

use nalgebra::Vector2;
use pvfc_sim::run::{simulate, simulate_timed};
use pvfc_sim::scenario::preset_id::Fig1Contour;
use pvfc_sim::scenario::presets::fig1_saturated;
use pvfc_sim::trace::metrics::{contour_closest, contour_distance, speed_along_contour};

/// PVFC on the circle of Fig. 1 on saturating drives at `r = 1` (below the limits): the arm is
/// on the contour, and the speed it makes along it is its `τ̇` times the circle's
/// `|x_d'| = 2π/6` per unit of `τ`.
#[test]
fn on_the_contour_it_is_the_pace_of_the_reference() {
    let s = fig1_saturated(Fig1Contour::Circle, 100);
    let t = simulate(&s, &mut |_| {}).expect("valid run");
    let contour = s.contour().expect("a Lissajous contour");
    let start = t.t.iter().position(|&x| x >= 20.0).expect("40 s run");
    let range = start..t.len();
    let along = speed_along_contour(&t, &contour, s.period(), range);
    let tau_rate = (t.tau[t.len() - 1] - t.tau[start]) / (t.t[t.len() - 1] - t.t[start]);
    let pace = tau_rate * std::f64::consts::TAU / 6.0;
    assert!(
        (along - pace).abs() < 0.02 * pace,
        "along {along}, pace {pace}"
    );
}

/// The timed tracker on the paper's Lissajous curve at `r = 4`, its drives saturated: it ends
/// near the figure-eight's crossing at the origin (on the contour, so its distance to the
/// contour is small), going back and forth; its reference runs at `4 |x_d'|`, and the speed
/// it makes along the contour is a small fraction of that.
#[test]
fn a_stalled_tracker_makes_no_speed() {
    let s = fig1_saturated(Fig1Contour::Lissajous, 400);
    let b = s.baseline.clone().expect("a timed baseline");
    let t = simulate_timed(&s, &b, 4.0, &mut |_| {}).expect("valid run");
    let contour = s.contour().expect("a Lissajous contour");
    let start = t.t.iter().position(|&x| x >= 28.0).expect("40 s run");
    let along = speed_along_contour(&t, &contour, s.period(), start..t.len());
    // The reference's mean pace over a period: 4 × (mean |x_d'| over τ).
    let mean_tangent: f64 = (0..600)
        .map(|k| contour.coordinates(s.period() * k as f64 / 600.0)[1].norm())
        .sum::<f64>()
        / 600.0;
    let reference = 4.0 * mean_tangent;
    assert!(
        along.abs() < 0.05 * reference,
        "along {along}, reference {reference}"
    );
    let q = Vector2::from_column_slice(&t.q[t.len() - 1]);
    assert!(q.norm() < 0.3, "the tracker ends near the crossing: {q}");
    assert!(contour_distance(&contour, s.period(), &q) < 0.1);
}

/// The nearest point is a point of the contour at the distance returned.
#[test]
fn the_nearest_point_is_on_the_contour() {
    let s = fig1_saturated(Fig1Contour::Lissajous, 100);
    let contour = s.contour().expect("a Lissajous contour");
    for q in [[0.3, 0.2], [-0.9, 1.4], [1.2, -0.1], [0.0, 0.0]] {
        let q = Vector2::from(q);
        let (tau, d) = contour_closest(&contour, s.period(), &q);
        let p = contour.coordinates(tau)[0];
        assert!(((q - p).norm() - d).abs() < 1e-12);
        // No point of a fine grid is nearer.
        let nearest = (0..20_000)
            .map(|k| (q - contour.coordinates(s.period() * k as f64 / 20_000.0)[0]).norm())
            .fold(f64::INFINITY, f64::min);
        assert!(d <= nearest + 1e-9, "{d} against {nearest}");
    }
}
