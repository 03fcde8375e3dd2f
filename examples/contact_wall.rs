//! A wall across the contour: PVFC against a timed tracker, the Rust twin of
//! `examples/python/contact_wall.py`.
//!
//! ```text
//! cargo run --release --example contact_wall
//! ```

use pvfc::sim::run::run_scenario;
use pvfc::sim::scenario::presets;
use pvfc::sim::trace::metrics::contact_summary;

fn main() -> Result<(), pvfc::sim::SimError> {
    let scenario = presets::contact_wall();
    for run in run_scenario(&scenario, &mut |_| {})? {
        if let Some(s) = contact_summary(&run) {
            println!(
                "{}: peak force {:.0} N, energy pumped into the wall {:.1} J, audit residual {:.1e} of {:.1} J",
                run.name, s.peak_force, s.energy_pumped, s.audit, s.energy_scale
            );
        }
    }
    Ok(())
}
