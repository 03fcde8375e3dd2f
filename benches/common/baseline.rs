//! The baseline that benchmark groups measure beside their own benchmarks, and the ratios to
//! it printed after the run: absolute times differ between machines (and between runs on a
//! shared one), ratios to a baseline measured in the same run much less.

use criterion::{measurement::WallTime, BenchmarkGroup};
use nalgebra::Vector2;
use pvfc::prelude::*;
use pvfc::sim::scenario::presets::pelican_example;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::SystemTime;

/// The baseline's name in every group that measures it.
pub const BASELINE: &str = "scara_lissajous_f64_baseline";

/// The paper's SCARA control step (Pelican arm, Lissajous contour, self-pacing), f64, 1000
/// steps from a fresh controller, as the benchmark [`BASELINE`] of the group `g`.
pub fn scara_step_baseline(g: &mut BenchmarkGroup<'_, WallTime>) {
    let scara = pelican_example()
        .controller()
        .expect("the example is valid");
    let q = Torus::new(Vector2::new(0.1, 0.2));
    g.bench_function(BASELINE, |b| {
        b.iter(|| {
            let mut ctl = scara;
            for k in 0..1000 {
                let v = Vector2::new(0.3, 0.001 * k as f64);
                black_box(ctl.step(black_box(&q), black_box(&v), 1e-3).expect("valid"));
            }
        })
    });
}

/// Where criterion keeps its results: `CRITERION_HOME`, else `criterion` beside the
/// benchmark binary's `release/deps` (the cargo target directory).
fn criterion_home() -> Option<PathBuf> {
    if let Some(home) = std::env::var_os("CRITERION_HOME") {
        return Some(PathBuf::from(home));
    }
    let exe = std::env::current_exe().ok()?;
    Some(exe.ancestors().nth(3)?.join("criterion"))
}

/// The median (ns) criterion wrote for `group/bench` at or after `since`.
fn median(group: &str, bench: &str, since: SystemTime) -> Option<f64> {
    let path = criterion_home()?
        .join(group)
        .join(bench)
        .join("new")
        .join("estimates.json");
    let written = std::fs::metadata(&path).ok()?.modified().ok()?;
    if written < since {
        return None;
    }
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
    json["median"]["point_estimate"].as_f64()
}

/// Prints, for each of `groups`, every benchmark measured in this run (since `since`) as its
/// median and its ratio to the group's [`BASELINE`] of the same run.
pub fn print_ratios(groups: &[&str], since: SystemTime) {
    let Some(home) = criterion_home() else {
        return;
    };
    for group in groups {
        let Some(base) = median(group, BASELINE, since) else {
            continue;
        };
        println!(
            "{group}: medians and ratios to {BASELINE} ({:.1} µs) of this run",
            base / 1e3
        );
        let Ok(entries) = std::fs::read_dir(home.join(group)) else {
            continue;
        };
        let mut rows: Vec<(String, f64)> = entries
            .filter_map(|e| {
                let name = e.ok()?.file_name().into_string().ok()?;
                (name != BASELINE && name != "report")
                    .then(|| Some((name.clone(), median(group, &name, since)?)))
                    .flatten()
            })
            .collect();
        rows.sort_by(|a, b| a.0.cmp(&b.0));
        for (name, m) in rows {
            println!("  {name}: {:.1} µs, ×{:.2}", m / 1e3, m / base);
        }
    }
}
