//! Faults in the loop (issue "Faults survived", item 3): the SCARA and the UR5 under the
//! supervised passive controller meet every kind of `[[faults]]` event
//! (`scenarios/scara_faults.toml`, `scenarios/ur5_faults.toml`). The supervision finds the
//! faults it can see, the controller creates no energy meanwhile (the run's audit, within the
//! encoders' boundary term), and after each fault it returns to the contour.

use pvfc_sim::plant::faults::FaultKind;
use pvfc_sim::run::simulate;
use pvfc_sim::scenario::Scenario;
use pvfc_sim::trace::Trace;
use std::path::PathBuf;

fn scenario(name: &str) -> Scenario {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios")
        .join(name);
    Scenario::from_file(&p).unwrap()
}

/// The first sample at or after `t`.
fn at(tr: &Trace, t: f64) -> usize {
    tr.t.iter().position(|x| *x >= t - 1e-12).unwrap()
}

/// What the encoders' rounding can hide beyond their charge: the sum by parts' boundary
/// terms, `Σ_i δ_i L_i` for the resolution `δ` and the torque limits `L` (J).
fn boundary(s: &Scenario) -> f64 {
    let p = s.controller.passive.as_ref().unwrap();
    let delta = std::f64::consts::TAU / p.encoder_counts.unwrap();
    p.torque_limit.iter().map(|l| delta * l).sum()
}

/// Runs `name` and checks, for every fault event: what the supervision reports in its
/// window, that the audit does not rise over it by more than the encoders' boundary term,
/// that `U` is back below ten times its level of the half second before within
/// `recovery` seconds of the window's end (and stays there 0.2 s), and over the whole run
/// that the audit (the energy the controller created) never exceeds the encoders' boundary
/// term.
fn survives(name: &str, recovery: f64) {
    let s = scenario(name);
    let tr = simulate(&s, &mut |_| {}).unwrap();
    let audit = tr.contact.as_ref().unwrap().audit_residual(&tr.energy);
    let created = audit.iter().cloned().fold(f64::MIN, f64::max);
    assert!(
        created <= boundary(&s),
        "{name}: {created:e} J created (bound {:e})",
        boundary(&s)
    );
    for e in &s.faults {
        let k0 = at(&tr, e.at);
        let end = at(&tr, e.at + e.duration.max(1e-3));
        let seen: Vec<f64> = tr.fault[k0..=end + 1].to_vec();
        let want = match e.kind {
            FaultKind::EncoderSpike => Some(3.0),
            FaultKind::NonFinite => Some(1.0),
            FaultKind::EncoderFreeze => Some(5.0),
            FaultKind::MissedPeriod => Some(2.0),
            _ => None,
        };
        match want {
            Some(code) => assert!(
                seen.contains(&code),
                "{name}: {:?} at {} not reported ({seen:?})",
                e.kind,
                e.at
            ),
            None => assert!(
                seen.iter().all(|c| *c == 0.0),
                "{name}: {:?} at {} reported as {seen:?}",
                e.kind,
                e.at
            ),
        }
        if e.kind == FaultKind::NonFinite {
            // Every sample of the window, with the safe torque.
            for k in k0..end {
                assert_eq!(tr.fault[k], 1.0, "{name}: NaN at t = {}", tr.t[k]);
                assert!(tr.torque.get(k).unwrap().iter().all(|u| *u == 0.0));
            }
        }
        // The audit only falls over a run (the encoders' charge drains the storage): what a
        // fault could create shows as a rise from the sample before it.
        let rise = audit[k0..at(&tr, e.at + e.duration + 0.5)]
            .iter()
            .map(|a| a - audit[k0 - 1])
            .fold(f64::MIN, f64::max);
        assert!(
            rise <= boundary(&s),
            "{name}: {:?} at {}: the audit rose by {rise:e} J",
            e.kind,
            e.at
        );
        let pre = tr.potential[at(&tr, e.at - 0.5)..k0]
            .iter()
            .cloned()
            .fold(0.0, f64::max);
        let back = (end..tr.t.len()).find(|&k| {
            tr.potential[k..(k + 200).min(tr.t.len())]
                .iter()
                .all(|u| *u <= 10.0 * pre)
        });
        let back = back.map(|b| tr.t[b] - tr.t[end]);
        assert!(
            back.is_some_and(|b| b <= recovery),
            "{name}: {:?} at {}: U back below 10 × {pre:e} after {back:?} s",
            e.kind,
            e.at
        );
    }
    assert_eq!(tr.fault[tr.t.len() - 1], 0.0);
}

#[test]
fn the_scara_survives_every_fault() {
    survives("scara_faults.toml", 1.0);
}

#[test]
fn the_ur5_survives_every_fault() {
    survives("ur5_faults.toml", 1.0);
}

#[test]
fn faults_need_the_passive_controller_and_round_trip() {
    let s = scenario("scara_faults.toml");
    let mut zoh = s.clone();
    zoh.controller.passive = None;
    let e = zoh.validate().unwrap_err().to_string();
    assert!(
        e.contains("faults") && e.contains("controller.passive"),
        "{e}"
    );
    let again = Scenario::from_toml(&s.to_toml().unwrap(), "again.toml".as_ref()).unwrap();
    assert_eq!(again.faults, s.faults);
    let mut bad = s.clone();
    bad.faults[2].joint = 7;
    let e = bad.validate().unwrap_err().to_string();
    assert!(e.contains("faults[2].joint"), "{e}");
}

#[test]
fn the_field_energy_bound_is_read_and_checked_by_name() {
    let s = scenario("ur5_faults.toml");
    assert_eq!(s.controller.field_energy_bound, Some(0.2));
    assert!(s.to_toml().unwrap().contains("field_energy_bound = 0.2"));
    for share in [0.0, 1.0, 1.5, -0.1, f64::NAN, f64::INFINITY] {
        let mut bad = s.clone();
        bad.controller.field_energy_bound = Some(share);
        let e = bad.validate().unwrap_err().to_string();
        assert!(e.contains("controller.field_energy_bound"), "{share}: {e}");
    }
}

#[test]
fn the_campaign_keeps_the_recovery_after_each_kind_of_fault() {
    use pvfc_sim::study::metrics::{metric, RunView};
    use pvfc_sim::trace::metrics::recovery_time;
    let s = scenario("scara_faults.toml");
    let tr = simulate(&s, &mut |_| {}).unwrap();
    let view = RunView::new(&s, &tr, None);
    let slowest = metric("recovery_time").unwrap().of(&view).unwrap();
    let mut kinds = Vec::new();
    for e in &s.faults {
        let name = format!(
            "recovery_{}",
            toml::Value::try_from(e.kind).unwrap().as_str().unwrap()
        );
        let per_kind = metric(&name).unwrap().of(&view);
        // The scenario has one event of each kind: its own recovery, if it ends a second
        // before the run does (else it cannot be judged).
        if e.at + e.duration + 1.0 > s.duration {
            assert_eq!(per_kind, None, "{name}");
            continue;
        }
        let own = recovery_time(&tr, e.at, e.duration, 1.0 / s.controller.rate, 0.2);
        assert_eq!(per_kind, own, "{name}");
        assert!(per_kind.unwrap() <= slowest, "{name}");
        kinds.push(per_kind.unwrap());
    }
    assert!(kinds.len() >= 8, "{kinds:?}");
    assert_eq!(kinds.iter().cloned().fold(0.0, f64::max), slowest);
    // A run without faults has none.
    let mut clean = s.clone();
    clean.faults.clear();
    let tr = simulate(&clean, &mut |_| {}).unwrap();
    let view = RunView::new(&clean, &tr, None);
    assert_eq!(metric("recovery_impact").unwrap().of(&view), None);
}
