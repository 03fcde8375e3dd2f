//! The paper's reproduction: every preset run, and what the runs produce (MCAP logs, the
//! summary table of the claims).

use crate::report;
use crate::runs::Runs;
use pvfc_sim::error::{Result, SimError};
use pvfc_sim::run::run_scenario_with;
use pvfc_sim::scenario::Scenario;
use pvfc_sim::scenario::System;
use std::panic::AssertUnwindSafe;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The error of a run that panicked (a bug: reported, never carried on).
fn panicked(name: &str) -> SimError {
    SimError::Scenario {
        path: name.into(),
        message: "the run panicked".into(),
    }
}

/// The callback of one scenario's runs: their progress, a fraction in [0, 1].
pub type Progress = Box<dyn FnMut(f64) + Send>;

/// Runs every scenario on `threads` threads (at least one; each scenario's runs on one
/// thread, so the traces do not depend on the count); `progress(name)` gives the callback for
/// each scenario, on the thread that runs it. The first scenario (in the slice's order) that
/// fails gives the error.
pub fn run_all<F>(scenarios: &[Scenario], threads: usize, progress: F) -> Result<Runs>
where
    F: Fn(&str) -> Progress + Sync,
{
    type Done = (usize, Result<(System, Vec<pvfc_sim::trace::Trace>)>);
    let next = AtomicUsize::new(0);
    let workers = threads.clamp(1, scenarios.len().max(1));
    let mut done: Vec<Done> = std::thread::scope(|scope| {
        let handles: Vec<_> = (0..workers)
            .map(|_| {
                scope.spawn(|| {
                    let mut mine = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        let Some(s) = scenarios.get(i) else {
                            break mine;
                        };
                        let mut p = progress(&s.name);
                        let r = std::panic::catch_unwind(AssertUnwindSafe(|| {
                            System::build(s).and_then(|system| {
                                run_scenario_with(s, &system, &mut *p).map(|t| (system, t))
                            })
                        }))
                        .unwrap_or_else(|_| Err(panicked(&s.name)));
                        mine.push((i, r));
                    }
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().map_err(|_| panicked("reproduce")))
            .collect::<Result<Vec<_>>>()
    })?
    .into_iter()
    .flatten()
    .collect();
    done.sort_by_key(|(i, _)| *i);
    let mut runs = Runs::default();
    for (i, r) in done {
        let (system, traces) = r?;
        let s = &scenarios[i];
        for t in traces {
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
