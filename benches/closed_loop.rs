//! 10 s of closed loop at 1 kHz (the paper's Fig. 8, R = 100: arm, friction, compensation,
//! nominal speed), as the simulator runs it:
//! * continuous: controller states integrated with the plant, RK4 at 1 kHz (10,000 steps);
//! * sampled: controller at 1 kHz with zero-order hold, plant RK4 at 10 kHz (the default).

#[path = "common/baseline.rs"]
mod baseline;
#[path = "common/machine.rs"]
mod machine;

use criterion::{criterion_group, Criterion};
use pvfc::sim::run::simulate;
use pvfc::sim::scenario::presets;
use pvfc::sim::scenario::Mode;
use std::hint::black_box;

fn closed_loop(c: &mut Criterion) {
    let mut g = c.benchmark_group("closed_loop_10s_1kHz");
    g.sample_size(30);
    baseline::scara_step_baseline(&mut g);
    let mut cont = presets::fig8(100);
    cont.duration = 10.0;
    cont.simulation.mode = Mode::Continuous;
    cont.simulation.plant_substeps = 1;
    g.bench_function("continuous_rk4", |b| {
        b.iter(|| simulate(black_box(&cont), &mut |_| {}).expect("valid"))
    });
    let mut samp = presets::fig8(100);
    samp.duration = 10.0;
    g.bench_function("sampled_plant_10kHz", |b| {
        b.iter(|| simulate(black_box(&samp), &mut |_| {}).expect("valid"))
    });
    g.finish();
}

criterion_group!(benches, closed_loop);
fn main() {
    machine::print_machine();
    let start = std::time::SystemTime::now();
    benches();
    Criterion::default().configure_from_args().final_summary();
    baseline::print_ratios(&["closed_loop_10s_1kHz"], start);
}
