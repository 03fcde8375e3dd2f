//! `pvfc`: reproduce the paper's section V, or run one scenario.

use clap::{Parser, Subcommand};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use pvfc_cli::plot;
use pvfc_cli::reproduce::{run_all, write_logs, write_summary, Progress};
use pvfc_sim::scenario::presets;
use pvfc_sim::scenario::{RobotSpec, Scenario, System};
use pvfc_sim::SimError;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "pvfc",
    version,
    about = "Passive Velocity Field Control: the paper's experiments in simulation"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run every scenario of section V; write figures, MCAP logs and the summary table.
    Reproduce {
        /// Output directory.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// Skip the MCAP logs.
        #[arg(long)]
        no_logs: bool,
        /// The logs' plot channels at this rate (Hz); 0 writes every sample (1 kHz). The
        /// claims and figures always use every sample.
        #[arg(long, default_value_t = 100.0)]
        log_rate: f64,
        /// Threads (default: every core of this machine); the results do not depend on it.
        #[arg(long)]
        threads: Option<usize>,
    },
    /// Run one scenario file; write its MCAP log(s).
    Run {
        /// The scenario (TOML).
        scenario: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// The log's plot channels at this rate (Hz); 0 (the default) writes every sample.
        #[arg(long, default_value_t = 0.0)]
        log_rate: f64,
    },
    /// Run a scenario's plant against a drive across a serial line (hardware in the loop),
    /// in lockstep: each control period the encoders' counts go to the drive and its torque
    /// comes back. The drive's controller replaces the scenario's; the scenario's
    /// `[[operator]]` commands go in the frames. Writes `logs/NAME-hil.mcap` (and with
    /// `--twin`, the scenario's own drive on the same plant as `logs/NAME.mcap`, compared).
    #[cfg(unix)]
    Hil {
        /// The scenario (TOML): the plant, the encoders' counts per turn, the operator.
        scenario: PathBuf,
        /// A Unix socket the drive listens on (a QEMU guest's `-serial unix:PATH,server=on`).
        #[arg(long, conflicts_with = "qemu", required_unless_present = "qemu")]
        socket: Option<PathBuf>,
        /// A firmware (ELF) to run here in `qemu-system-arm -machine netduinoplus2`, its
        /// USART1 the line.
        #[arg(long)]
        qemu: Option<PathBuf>,
        /// Output directory.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// How long an answer is awaited before the frame is sent again (ms).
        #[arg(long, default_value_t = 300)]
        timeout_ms: u64,
        /// Flip one bit of this period's first frame: the drive must refuse it.
        #[arg(long)]
        corrupt_at: Option<u32>,
        /// Also run the scenario's own passive drive on the same plant, and compare.
        #[arg(long)]
        twin: bool,
    },
    /// Run a study (sweep or Monte Carlo) in parallel: its table `NAME.csv` (one row per run:
    /// its parameters and metrics, or its error), the same table as an Arrow IPC file
    /// `NAME.arrow` (pandas' `read_feather`, Polars' `read_ipc`) and a figure per metric. An
    /// interrupted sweep run again continues where it stopped.
    Sweep {
        /// The study (TOML).
        study: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "results")]
        out: PathBuf,
        /// Threads (default: every core of this machine).
        #[arg(long)]
        threads: Option<usize>,
        /// Stop after this many new runs (a later sweep completes the table).
        #[arg(long)]
        limit: Option<usize>,
        /// Skip the figures.
        #[arg(long)]
        no_figures: bool,
        /// Run this controller instead of the study's own (`pvfc`, `timed`,
        /// `speed_scaling`: the base's baseline tracker) on the same runs; the table is
        /// then NAME-CONTROLLER.
        #[arg(long)]
        controller: Option<String>,
    },
    /// Write the built-in scenarios as TOML files.
    Presets {
        /// Output directory.
        #[arg(long, default_value = "scenarios")]
        out: PathBuf,
    },
}

fn bar(bars: &MultiProgress, name: &str) -> Progress {
    let pb = bars.add(ProgressBar::new(1000));
    let style = ProgressStyle::with_template("{prefix:>28} [{bar:40}] {percent:>3}% {elapsed}")
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
    pb.set_style(style);
    pb.set_prefix(name.to_string());
    Box::new(move |f: f64| {
        pb.set_position((f * 1000.0) as u64);
        if f >= 1.0 {
            pb.finish();
        }
    })
}

#[cfg(unix)]
fn hil(
    path: &Path,
    out: &Path,
    socket: Option<PathBuf>,
    qemu: Option<PathBuf>,
    timeout: std::time::Duration,
    corrupt_at: Option<u32>,
    twin: bool,
) -> Result<(), SimError> {
    use pvfc_cli::hil::{largest_difference, run, DriveAt};
    let s = Scenario::from_file(path)?;
    mkdir(out)?;
    let at = match (socket, qemu) {
        (Some(p), _) => DriveAt::Socket(p),
        (None, Some(elf)) => DriveAt::Qemu {
            elf,
            dir: out.join("qemu"),
        },
        (None, None) => {
            return Err(SimError::Setting(
                "pvfc hil: give --socket or --qemu".into(),
            ))
        }
    };
    let system = System::build(&s)?;
    let options = pvfc_sim::run::link::LinkOptions {
        corrupt_at,
        ..Default::default()
    };
    let hil = run(&s, &system, &at, timeout, options)?;
    let r = &hil.report;
    let (median, largest) = r.round_trip();
    println!(
        "{}: {} periods in {:.1} s; frames sent {}, sent again {}, corrupted on purpose {}, unread by the drive {}, late answers {}; round trip median {:.0} µs, largest {:.0} µs",
        s.name,
        r.periods,
        hil.seconds,
        r.sent,
        r.resent,
        r.corrupted,
        r.unread,
        r.late,
        median * 1e6,
        largest * 1e6
    );
    let mut runs = pvfc_cli::runs::Runs::default();
    let mut hil_trace = hil.trace;
    hil_trace.name = format!("{}-hil", s.name);
    if twin {
        let t = pvfc_sim::run::simulate_system(&s, &system, &mut |_| {})?;
        let (dq, du) = largest_difference(&hil_trace, &t);
        println!(
            "{}: against the host twin (the scenario's drive on the same plant): largest |Δq| {dq:.2e} rad, |Δtorque| {du:.2e} N·m",
            s.name
        );
        runs.runs.insert(t.name.clone(), (s.clone(), t));
    }
    runs.runs
        .insert(hil_trace.name.clone(), (s.clone(), hil_trace));
    for f in write_logs(&runs, out, None)? {
        println!("wrote {}", f.display());
    }
    match r.fault {
        Some((period, code)) => Err(SimError::Link {
            period,
            message: format!("the drive latched fault {code}"),
        }),
        None => Ok(()),
    }
}

fn mkdir(p: &Path) -> Result<(), SimError> {
    std::fs::create_dir_all(p).map_err(|e| SimError::Io {
        path: p.to_path_buf(),
        source: e,
    })
}

/// Restores the default action of `SIGPIPE` (Rust's runtime ignores it), so that
/// `pvfc … | head` ends quietly when the reader goes away, as other command-line tools do,
/// instead of panicking on the failed write.
#[cfg(unix)]
#[allow(unsafe_code)]
fn quiet_broken_pipe() {
    // SAFETY: `signal` with `SIG_DFL` only resets a disposition; it is called first thing in
    // `main`, before any other thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(unix))]
fn quiet_broken_pipe() {}

fn main() -> ExitCode {
    quiet_broken_pipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Reproduce {
            out,
            no_logs,
            log_rate,
            threads,
        } => reproduce(&out, (!no_logs).then_some(log_rate), threads),
        Command::Run {
            scenario,
            out,
            log_rate,
        } => run(&scenario, &out, log_rate),
        Command::Sweep {
            study,
            out,
            threads,
            limit,
            no_figures,
            controller,
        } => sweep(
            &study,
            &out,
            threads,
            limit,
            !no_figures,
            controller.as_deref(),
        ),
        Command::Presets { out } => write_presets(&out),
        #[cfg(unix)]
        Command::Hil {
            scenario,
            socket,
            qemu,
            out,
            timeout_ms,
            corrupt_at,
            twin,
        } => hil(
            &scenario,
            &out,
            socket,
            qemu,
            std::time::Duration::from_millis(timeout_ms),
            corrupt_at,
            twin,
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// A log rate from the command line: 0 means every sample.
/// Checked before anything runs, so that a bad rate loses no run.
fn log_rate(rate: f64) -> Result<Option<f64>, SimError> {
    if !(rate.is_finite() && rate >= 0.0) {
        return Err(SimError::Setting(format!(
            "--log-rate {rate}: a finite rate ≥ 0 (Hz; 0 logs every sample)"
        )));
    }
    Ok((rate != 0.0).then_some(rate))
}

/// `log_rate`: `None` skips the logs.
fn reproduce(out: &Path, log_rate_hz: Option<f64>, threads: Option<usize>) -> Result<(), SimError> {
    let log_rate_hz = match log_rate_hz {
        Some(r) => Some(log_rate(r)?),
        None => None,
    };
    mkdir(out)?;
    let mut scenarios = presets::all();
    scenarios.extend(presets::arms_3d()?);
    scenarios.extend(presets::tool_paths()?);
    let threads = threads.unwrap_or_else(pvfc_sim::study::runner::default_threads);
    let bars = MultiProgress::new();
    let runs = run_all(&scenarios, threads, |name| bar(&bars, name))?;
    if let Some(rate) = log_rate_hz {
        let files = write_logs(&runs, out, rate)?;
        println!(
            "wrote {} MCAP logs to {}",
            files.len(),
            out.join("logs").display()
        );
    }
    let figs = plot::all_figures(&runs, out)?;
    for f in &figs {
        println!("wrote {}", f.display());
    }
    let claims = write_summary(&runs, out)?;
    println!(
        "wrote {} and summary.csv\n",
        out.join("summary.md").display()
    );
    for c in &claims {
        println!(
            "[{}] {:<20} {}",
            if c.holds { "holds" } else { "does not hold" },
            c.id,
            c.measured
        );
    }
    Ok(())
}

fn sweep(
    study: &Path,
    out: &Path,
    threads: Option<usize>,
    limit: Option<usize>,
    figures: bool,
    controller: Option<&str>,
) -> Result<(), SimError> {
    let controller = controller
        .map(str::parse::<pvfc_sim::study::spec::StudyController>)
        .transpose()?;
    let threads = threads.unwrap_or_else(pvfc_sim::study::runner::default_threads);
    let pb = ProgressBar::new(0);
    pb.set_style(
        ProgressStyle::with_template(
            "{prefix:>20} [{bar:40}] {pos}/{len} runs {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    pb.set_prefix(
        study
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
    );
    let o = pvfc_cli::sweep::sweep_with(
        study,
        controller,
        out,
        threads,
        limit,
        &mut |done, total| {
            pb.set_length(total as u64);
            pb.set_position(done as u64);
        },
    )?;
    pb.finish();
    println!(
        "{}: {} runs ({} ran now on {threads} threads in {:.1} s, {:.2} runs/s; {} from the table; {} failed): {} and {}",
        o.spec.name,
        o.rows.len(),
        o.ran,
        o.seconds,
        o.ran as f64 / o.seconds.max(1e-9),
        o.resumed,
        o.failed(),
        o.csv.display(),
        o.arrow.display()
    );
    for r in o.rows.iter().filter(|r| r.error.is_some()) {
        println!("run {}: {}", r.index, r.error.as_deref().unwrap_or(""));
    }
    if figures {
        for f in pvfc_cli::study_plot::study_figures(&o.spec, &o.rows, out)? {
            println!("wrote {}", f.display());
        }
    }
    Ok(())
}

fn run(path: &Path, out: &Path, rate: f64) -> Result<(), SimError> {
    let rate = log_rate(rate)?;
    let s = Scenario::from_file(path)?;
    for d in &s.deprecations {
        eprintln!("warning: {}: {d}", path.display());
    }
    mkdir(out)?;
    let runs = run_all(std::slice::from_ref(&s), 1, |name| {
        bar(&MultiProgress::new(), name)
    })?;
    for f in write_logs(&runs, out, rate)? {
        println!("wrote {}", f.display());
    }
    for (name, (s, t)) in &runs.runs {
        let n = t.len() - 1;
        println!(
            "{name}: t = {:.1} s, τ = {:.3}, U = {:.3e}, β = {:.4}, κ_a = {:.3} J, mean U over the last pass = {}",
            t.t[n],
            t.tau[n],
            t.potential[n],
            t.beta[n],
            t.energy[n],
            pvfc_sim::trace::metrics::mean_potential_over_pass(t, s.period())
                .map(|u| format!("{u:.3e}"))
                .unwrap_or_else(|| "(no complete pass)".into())
        );
        let system = runs.system(s)?;
        let budget = match system.chain() {
            Some(sys) => pvfc_sim::trace::path_budget::path_budget(s, &sys.robot, t)?,
            None => None,
        };
        if let Some(c) = pvfc_sim::trace::clearance::clearance(s, &system, t)? {
            println!(
                "{name}: obstacles: smallest clearance {:.4} at t = {:.2} s (m between the robot's spheres and the world's shapes; joint units to joint-space regions)",
                c.smallest, c.time
            );
        }
        if let Some(b) = budget {
            println!("{name}: tool path: {b}");
        }
        if let Some(sys) = system.chain() {
            if let Some(speeds) = pvfc_sim::trace::feed_speeds::feed_speeds(s, &sys.robot, t)? {
                let each: Vec<String> = speeds
                    .iter()
                    .map(|x| {
                        format!(
                            "{:.0}–{:.0} mm: {:.1} ({:+.1} %)",
                            x.span.0 * 1e3,
                            x.span.1 * 1e3,
                            x.median * 1e3,
                            100.0 * x.error()
                        )
                    })
                    .collect();
                println!(
                    "{name}: speed on each stretch against its feed (median mm/s): {}",
                    each.join(", ")
                );
            }
        }
        let summary = pvfc_sim::trace::metrics::contact_summary(t);
        match (&*system, summary) {
            (System::RigidBody(ctl), c) => {
                let contour = ctl.law().field().contour();
                let angle = pvfc_sim::trace::metrics::attitude_errors(t, contour);
                println!(
                    "{name}: attitude error ‖log(R_d(τ)ᵀR)‖ {:.3} → {:.2e} rad",
                    angle[0], angle[n]
                );
                // A rigid body touches nothing: its environment is the disturbance.
                if let Some(c) = c {
                    println!(
                        "{name}: disturbance: energy pumped into it {:.3} J, its work {:+.3} J, audit residual {:.1e} of {:.3} J",
                        c.energy_pumped, c.work_contact, c.audit, c.energy_scale
                    );
                }
            }
            (System::Scara(_) | System::SerialChain(_), Some(c)) => {
                // With a disturbance torque, the environment is the contact and the disturbance.
                let environment = if s.plant.disturbance.is_some() {
                    "the environment (contact and disturbance)"
                } else {
                    "the contact"
                };
                println!(
                    "{name}: contact: peak force {:.1} N, energy pumped into {environment} {:.3} J, work of the environment {:+.3} J, audit residual {:.1e} of {:.3} J",
                    c.peak_force, c.energy_pumped, c.work_contact, c.audit, c.energy_scale
                );
            }
            (System::Scara(_) | System::SerialChain(_), None) => {}
        }
        if !s.faults.is_empty() {
            if let Some(f) = pvfc_sim::trace::metrics::fault_summary(t) {
                let [nan, period, speed, accel, frozen] = f.samples;
                println!(
                    "{name}: faults: {} events; samples at fault: non-finite {nan}, period {period}, speed {speed}, acceleration {accel}, frozen {frozen}; energy created at most {:.1e} J",
                    s.faults.len(),
                    f.created
                );
            }
        }
    }
    if s.contact.is_some() {
        let p = out.join(format!("{}.png", s.name));
        plot::contact_figure(&runs, &s.name, &p)?;
        println!("wrote {}", p.display());
    }
    let figures = match s.plant.robot {
        RobotSpec::Scara(_) => Vec::new(),
        RobotSpec::SerialChain(_) => plot::chain_figures(&runs, out)?,
        RobotSpec::RigidBody(_) => plot::body_figures(&runs, out)?,
    };
    for p in figures {
        println!("wrote {}", p.display());
    }
    Ok(())
}

fn write_presets(out: &Path) -> Result<(), SimError> {
    mkdir(out)?;
    for s in presets::all() {
        let p = out.join(format!("{}.toml", s.name));
        let text = format!("# {}\n{}", s.description, s.to_toml()?);
        std::fs::write(&p, text).map_err(|e| SimError::Io {
            path: p.clone(),
            source: e,
        })?;
        println!("wrote {}", p.display());
    }
    Ok(())
}
