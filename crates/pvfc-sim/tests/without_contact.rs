//! Built without the `contact` feature (`cargo test -p pvfc-sim --no-default-features`): a
//! scenario with `[contact]` is a clear error, and the others still run. (An integration test,
//! so that the contact module does not import the presets and the simulation.)
#![cfg(not(feature = "contact"))]

use pvfc_sim::run::simulate;
use pvfc_sim::scenario::presets;
use pvfc_sim::SimError;

#[test]
fn a_contact_scenario_is_a_clear_error_without_the_feature() {
    let s = presets::contact_wall();
    match simulate(&s, &mut |_| {}) {
        Err(SimError::Setting(m)) => assert!(m.contains("`contact` feature"), "{m}"),
        other => panic!("expected a setting error, got {other:?}"),
    }
    let mut s = presets::fig6();
    s.duration = 0.1;
    assert!(simulate(&s, &mut |_| {}).is_ok());
}
