//! Each claim of section V as a test with a number (the runs of `pvfc reproduce`, shared).
//! One claim does not come out on our plant and is reported, not asserted: U without
//! compensation is 24–40× (not ~2×) the compensated U (`fig9.vs.fig8.factor`); see the
//! manual's reproduction page.

use pvfc_cli::report::{claims, Claim};
use pvfc_cli::reproduce::run_all;
use pvfc_cli::runs::Runs;
use pvfc_sim::scenario::preset_id::PresetId;
use pvfc_sim::scenario::Mode;
use std::sync::OnceLock;

fn all_claims() -> &'static (Runs, Vec<Claim>) {
    static CELL: OnceLock<(Runs, Vec<Claim>)> = OnceLock::new();
    CELL.get_or_init(|| {
        let runs = run_all(&pvfc_sim::scenario::presets::all(), 2, |_| Box::new(|_| {}))
            .expect("the presets run");
        let c = claims(&runs).expect("every claim can be evaluated");
        (runs, c)
    })
}

fn claim(id: &str) -> &'static Claim {
    all_claims()
        .1
        .iter()
        .find(|c| c.id == id)
        .expect("claim exists")
}

fn assert_holds(id: &str) {
    let c = claim(id);
    assert!(
        c.holds,
        "{}: {} — measured {}",
        c.id, c.statement, c.measured
    );
}

#[test]
fn frictionless_energy_drift_is_below_1e_6_over_60_s() {
    assert_holds("energy.continuous");
    let t = all_claims()
        .0
        .trace(PresetId::Energy(Mode::Continuous))
        .unwrap();
    assert_eq!(t.len(), 60_001, "60 s at 1 kHz");
}

#[test]
fn theorem_2_u_to_zero_and_tau_dot_to_beta_lambda1() {
    assert_holds("theorem2");
}

#[test]
fn remark_1_the_velocity_field_error_converges_at_two_gamma_beta_e_bar() {
    assert_holds("remark1");
}

#[test]
fn under_a_disturbance_the_error_is_bounded_and_shrinks_as_gamma_grows() {
    assert_holds("robustness");
    let runs = pvfc_cli::robustness::disturbed_runs(&all_claims().0).unwrap();
    assert_eq!(runs.len(), 6);
    // The disturbance does work the audit must count: without it the residual would be
    // 7–54 % of κ_a(0), with it integration error.
    assert!(
        runs.iter().all(|d| d.work > 0.05 && d.audit < 1e-6),
        "{runs:?}"
    );
}

#[test]
fn fig6_energy_dissipates_contour_followed_slower_u_grows() {
    assert_holds("fig6");
    assert_holds("fig6.audit");
}

#[test]
fn fig7_self_pacing_holds_tau_and_straightens_the_approach() {
    assert_holds("fig7");
}

#[test]
fn fig8_mean_u_falls_as_r_rises_with_compensation() {
    assert_holds("fig8.pacing");
}

#[test]
fn fig9_mean_u_falls_as_r_rises_without_compensation() {
    assert_holds("fig9.pacing");
}

#[test]
fn fig9_u_is_larger_without_compensation_at_each_r() {
    assert_holds("fig9.vs.fig8");
}

#[test]
fn fig10_u_lower_at_r2_than_r1_and_less_gain_from_2_to_3() {
    assert_holds("fig10");
}

#[test]
fn fig10_at_the_energy_levels_beta_reaches_r_at_the_time_constant_1_over_c() {
    assert_holds("fig10.level");
}

#[test]
fn the_sampled_loop_energy_change_is_reported_and_small() {
    let t = all_claims()
        .0
        .trace(PresetId::Energy(Mode::Sampled))
        .unwrap();
    let drift = pvfc_sim::trace::metrics::energy_drift(t);
    // Not a property of PVFC but of the discretisation: measured 3.8e-4 over 60 s.
    assert!(
        drift > 0.0 && drift < 1e-2,
        "sampled-loop energy drift {drift:e}"
    );
}

#[test]
fn the_passive_digital_controller_closes_its_audit_at_1khz_and_100hz() {
    assert_holds("digital.audit");
}

#[test]
fn the_passive_digital_controller_never_gives_more_than_it_has() {
    assert_holds("digital.passivity");
}

#[test]
fn on_a_drive_the_passive_controller_creates_no_more_than_the_encoder_bound() {
    assert_holds("digital.drive");
}

/// Section IV-B: the satellite on SO(3) reaches its attitude contour with κ_a constant.
#[test]
fn the_satellite_reaches_its_attitude_contour() {
    assert_holds("satellite");
}

/// Fig. 1 under friction (80 % compensated), unsaturated: PVFC at the coupling rate
/// `γβĒ = 400/s` stays nearer the contour than the timed tracker (ω_n = 20 rad/s) at its
/// mean speed.
#[test]
fn under_friction_pvfc_is_nearer_the_contour_than_the_timed_tracker() {
    assert_holds("fig1");
}

#[test]
fn the_passive_controller_tracks_as_the_continuous_one() {
    assert_holds("digital.tracking");
}

/// Fig. 1 on saturating drives, the SCARA on both contours: wherever the timed tracker is at a
/// limit in over 5 % of its samples, PVFC (with the drive-limited pace) is at most a third as
/// far from the contour, slower than demanded, never stopping and itself at a limit in under
/// 5 % of its samples; at every demanded speed it is both nearer and faster than the
/// speed-scaling tracker; the claims `fig1.saturated` and `fig1.saturated.lissajous` hold.
#[test]
fn on_saturating_drives_the_timed_tracker_leaves_the_contour_and_pvfc_slows_down() {
    use pvfc_cli::speed_sweep::sweep;
    use pvfc_sim::scenario::preset_id::Fig1Contour;
    for contour in Fig1Contour::ALL {
        let w = sweep(&all_claims().0, contour).expect("the sweep's runs");
        let mut saturating = 0;
        for i in 0..w.pvfc.len() {
            let (p, t, c) = (&w.pvfc[i], &w.timed[i], &w.scaled[i]);
            let at = format!("{contour:?} at r = {}", p.demanded);
            assert!(
                p.saturated < 0.05,
                "{at}: PVFC at a limit in {}",
                p.saturated
            );
            if t.saturated > 0.05 {
                saturating += 1;
                assert!(
                    p.error.0 <= t.error.0 / 3.0,
                    "{at}: {:?} vs {:?}",
                    p.error,
                    t.error
                );
                assert!(p.tau_rate < p.demanded && p.slowest > 0.1, "{at}: {p:?}");
            }
            assert!(
                p.error.0 <= c.error.0,
                "{at}: {:?} vs {:?}",
                p.error,
                c.error
            );
            assert!(
                p.tau_rate > c.tau_rate,
                "{at}: τ̇ {} vs {}",
                p.tau_rate,
                c.tau_rate
            );
        }
        assert!(saturating >= 3, "{contour:?}: the timed tracker saturates");
    }
    for id in ["fig1.saturated", "fig1.saturated.lissajous"] {
        assert_holds(id);
    }
}

#[test]
fn every_claim_is_evaluated_and_the_table_renders() {
    let c = &all_claims().1;
    assert_eq!(
        c.len(),
        29,
        "19 claims of sections II–V (Fig. 1 on saturating drives on a circle and on the Lissajous curve, Fig. 10 at its energy levels, Remark 1's rate, the robustness under a disturbance, the satellite on SO(3) and Figs. 8–9 with stiction among them), 6 of contact, 4 of the digital controller"
    );
    let md = pvfc_cli::report::markdown(c);
    assert_eq!(md.lines().count(), 2 + c.len());
    let csv = pvfc_cli::report::csv(c);
    assert_eq!(csv.lines().count(), 1 + c.len());
}

// Contact: the claims of `pvfc reproduce` about the contact scenarios.

#[test]
fn contact_energy_audit_is_integration_error_only() {
    assert_holds("contact.audit");
}

#[test]
fn contact_pvfc_never_gives_the_world_more_than_it_has() {
    assert_holds("contact.passivity");
}

#[test]
fn contact_timed_baseline_pushes_harder_than_pvfc() {
    assert_holds("contact.baseline");
}

#[test]
fn contact_sampled_controller_is_reported() {
    assert_holds("contact.sampled");
    assert!(claim("contact.sampled")
        .measured
        .contains("at the first touch"));
}

#[test]
fn contact_force_schedule_keeps_the_deburring_force_under_its_limit() {
    assert_holds("contact.deburr");
}

#[test]
fn contact_contour_is_followed_again_after_release() {
    assert_holds("contact.recovery");
}
