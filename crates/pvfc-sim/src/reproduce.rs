//! Running scenarios and writing what they produce: MCAP logs, figures, the summary table.

use crate::arm::ArmSystem;
use crate::error::{Result, SimError};
use crate::report::{self, Runs};
use crate::scenario::Scenario;
use crate::simulate::{simulate, simulate_timed, Trace};
use std::path::{Path, PathBuf};

/// Runs one scenario: the PVFC loop, and the timed baseline if the scenario asks for one
/// (at PVFC's mean `τ̇` over its last 12 s unless the scenario fixes the rate).
pub fn run_scenario(s: &Scenario, progress: &mut dyn FnMut(f64)) -> Result<Vec<Trace>> {
    let system = if s.is_chain() {
        Some(ArmSystem::build(s)?)
    } else {
        None
    };
    run_scenario_with(s, system.as_ref(), progress)
}

/// [`run_scenario`] with a URDF arm's system already built (`None` for the SCARA): the URDF
/// is read and a Cartesian path solved once for both runs.
pub fn run_scenario_with(
    s: &Scenario,
    system: Option<&ArmSystem>,
    progress: &mut dyn FnMut(f64),
) -> Result<Vec<Trace>> {
    let pvfc = match system {
        Some(sys) => crate::chain_run::simulate_chain_with(s, sys, progress)?,
        None => simulate(s, progress)?,
    };
    let mut out = vec![];
    if let Some(b) = &s.baseline {
        let rate = match b.tau_rate {
            Some(r) => r,
            None => {
                let n = pvfc.len() - 1;
                let from = pvfc
                    .t
                    .iter()
                    .position(|&t| t >= pvfc.t[n] - 12.0)
                    .unwrap_or(0);
                (pvfc.tau[n] - pvfc.tau[from]) / (pvfc.t[n] - pvfc.t[from]).max(f64::EPSILON)
            }
        };
        out.push(match system {
            Some(sys) => crate::chain_run::simulate_timed_chain_with(s, sys, b, rate, &mut |_| {})?,
            None => simulate_timed(s, b, rate, &mut |_| {})?,
        });
    }
    out.insert(0, pvfc);
    Ok(out)
}

/// Runs every scenario; `progress(name)` gives the callback for each run.
pub fn run_all(
    scenarios: &[Scenario],
    mut progress: impl FnMut(&str) -> Box<dyn FnMut(f64)>,
) -> Result<Runs> {
    let mut runs = Runs::default();
    for s in scenarios {
        let mut p = progress(&s.name);
        let system = if s.is_chain() {
            Some(ArmSystem::build(s)?)
        } else {
            None
        };
        for t in run_scenario_with(s, system.as_ref(), &mut *p)? {
            runs.runs.insert(t.name.clone(), (s.clone(), t));
        }
        if let Some(sys) = system {
            runs.arms.insert(s.name.clone(), sys);
        }
    }
    Ok(runs)
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| SimError::io(path, e))
}

/// Writes an MCAP log per run into `dir/logs`, its plot channels at `rate` (Hz; `None`: every
/// sample, see [`crate::log::LogOptions`]); returns the files.
pub fn write_logs(runs: &Runs, dir: &Path, rate: Option<f64>) -> Result<Vec<PathBuf>> {
    let logs = dir.join("logs");
    std::fs::create_dir_all(&logs).map_err(|e| SimError::io(&logs, e))?;
    runs.runs
        .iter()
        .map(|(name, (s, t))| {
            let p = logs.join(format!("{name}.mcap"));
            let scene = match runs.arm_system(s)? {
                Some(sys) => Some(crate::log::scene::ArmScene::of_run_with(s, &sys, t)?),
                None => None,
            };
            let options = crate::log::LogOptions {
                scene: scene.as_ref(),
                rate,
            };
            crate::log::write_mcap_with(t, &options, &p)?;
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
