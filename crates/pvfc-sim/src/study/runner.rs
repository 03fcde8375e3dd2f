//! Running a study: each run's loop (PVFC's, or a baseline tracker's) and the metrics kept of
//! it, in parallel on this machine's threads. A run that fails, or panics, is a row with its error; the study goes on.

use crate::run::{simulate_system, simulate_tracker};
use crate::scenario::System;
use crate::study::metrics::{Metric, RunView};
use crate::study::spec::StudyRun;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::mpsc;

/// One row of a study's table: a run's index, the values of its axes, and its metrics, or
/// the error that ended it.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyRow {
    /// The run's index in the study.
    pub index: usize,
    /// The values of the axes, in the spec's order.
    pub parameters: Vec<f64>,
    /// The metrics, in the study's order; `None` where a metric does not apply (or the run
    /// failed).
    pub metrics: Vec<Option<f64>>,
    /// Why the run failed, if it did.
    pub error: Option<String>,
}

/// Runs one run of a study (its controller's loop) and computes `metrics` of it. Never fails:
/// an error, or a panic, is the row's `error`.
pub fn run_one(run: &StudyRun, metrics: &[&Metric]) -> StudyRow {
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(
        || -> crate::Result<Vec<Option<f64>>> {
            let s = &run.scenario;
            let system = System::build(s)?;
            let trace = match (run.controller.tracker(), &s.baseline) {
                (Some(tracker), Some(b)) => {
                    let rate = b.tau_rate.ok_or_else(|| {
                        crate::SimError::Setting("baseline.tau_rate: not given".into())
                    })?;
                    simulate_tracker(s, &system, b, rate, tracker, &mut |_| {})?
                }
                (Some(_), None) => {
                    return Err(crate::SimError::Setting(
                        "a tracker's run needs [baseline]".into(),
                    ))
                }
                (None, _) => simulate_system(s, &system, &mut |_| {})?,
            };
            RunView::new(s, &trace, system.chain().map(|a| &a.robot)).values(metrics)
        },
    ));
    let (values, error) = match outcome {
        Ok(Ok(values)) => (values, None),
        Ok(Err(e)) => (vec![None; metrics.len()], Some(e.to_string())),
        Err(panic) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic".into());
            (
                vec![None; metrics.len()],
                Some(format!("the run panicked: {what}")),
            )
        }
    };
    StudyRow {
        index: run.index,
        parameters: run.parameters.iter().map(|(_, v)| *v).collect(),
        metrics: values,
        error,
    }
}

/// The number of threads a study runs on by default: every core of this machine.
pub fn default_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Runs `runs` on `threads` threads (at least one), handing each row to `on_row` on the
/// calling thread as it finishes (so in the order they finish, not by index). `on_row`
/// returns `false` to stop: runs under way finish, no new run starts.
pub fn run_study(
    runs: &[StudyRun],
    metrics: &[&Metric],
    threads: usize,
    on_row: &mut dyn FnMut(StudyRow) -> bool,
) {
    let next = AtomicUsize::new(0);
    let stop = std::sync::atomic::AtomicBool::new(false);
    let (send, receive) = mpsc::channel::<StudyRow>();
    std::thread::scope(|scope| {
        for _ in 0..threads.clamp(1, runs.len().max(1)) {
            let send = send.clone();
            let (next, stop) = (&next, &stop);
            scope.spawn(move || {
                while !stop.load(Ordering::Relaxed) {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(run) = runs.get(i) else { break };
                    if send.send(run_one(run, metrics)).is_err() {
                        break;
                    }
                }
            });
        }
        drop(send);
        for row in receive {
            if !on_row(row) {
                stop.store(true, Ordering::Relaxed);
            }
        }
    });
}
