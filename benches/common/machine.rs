//! What machine a benchmark ran on, printed with its results: figures from different CPUs
//! (Intel and AMD differ, e.g. on subnormal numbers) are not comparable, ratios measured in
//! the same run are.

/// The CPU's model name (`/proc/cpuinfo` on Linux), and the number of logical CPUs.
pub fn cpu() -> String {
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| std::env::consts::ARCH.to_string());
    let n = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!("{model}, {n} logical CPUs")
}

/// Prints the machine line every benchmark starts its own report with.
pub fn print_machine() {
    println!("machine: {}", cpu());
}
