//! The paper's reproduction: every preset run, and what the runs produce (MCAP logs, the
//! summary table of the claims).

use crate::report;
use crate::runs::Runs;
use pvfc_sim::error::{Result, SimError};
use pvfc_sim::run::run_scenario_with;
use pvfc_sim::scenario::Scenario;
use pvfc_sim::scenario::System;
use std::path::{Path, PathBuf};

/// Runs every scenario; `progress(name)` gives the callback for each run.
pub fn run_all(
    scenarios: &[Scenario],
    mut progress: impl FnMut(&str) -> Box<dyn FnMut(f64)>,
) -> Result<Runs> {
    let mut runs = Runs::default();
    for s in scenarios {
        let mut p = progress(&s.name);
        let system = System::build(s)?;
        for t in run_scenario_with(s, &system, &mut *p)? {
            runs.runs.insert(t.name.clone(), (s.clone(), t));
        }
        runs.systems.insert(s.name.clone(), system);
    }
    Ok(runs)
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| SimError::io(path, e))
}

/// Writes an MCAP log per run into `dir/logs`, its plot channels at `rate` (Hz; `None`: every
/// sample, see [`pvfc_sim::log::LogOptions`]); returns the files.
pub fn write_logs(runs: &Runs, dir: &Path, rate: Option<f64>) -> Result<Vec<PathBuf>> {
    let logs = dir.join("logs");
    std::fs::create_dir_all(&logs).map_err(|e| SimError::io(&logs, e))?;
    runs.runs
        .iter()
        .map(|(name, (s, t))| {
            let p = logs.join(format!("{name}.mcap"));
            let scene = pvfc_sim::log::scene::Scene::of_system(s, &*runs.system(s)?, t)?;
            let options = pvfc_sim::log::LogOptions {
                scene: scene.as_ref(),
                rate,
            };
            pvfc_sim::log::write_mcap_with(t, &options, &p)?;
            Ok(p)
        })
        .collect()
}

/// Evaluates the claims and writes `summary.md` and `summary.csv` into `dir`.
pub fn write_summary(runs: &Runs, dir: &Path) -> Result<Vec<report::Claim>> {
    let claims = report::claims(runs)?;
    let mut md = String::from("# pvfc reproduce: the claims of section V\n\n");
    md.push_str(&report::markdown(&claims));
    write(&dir.join("summary.md"), &md)?;
    write(&dir.join("summary.csv"), &report::csv(&claims))?;
    Ok(claims)
}
