//! `pvfc hil`: a scenario's plant against a drive across a serial line (hardware in the loop,
//! [`pvfc_sim::run::link`]): the line a Unix socket, one a QEMU guest's USART is connected to
//! (started here from a firmware's ELF, or by the user); the run's MCAP log, the line's
//! figures, and the host twin (the scenario's own passive drive on the same plant) beside it.

use pvfc_sim::run::link::{LinkDrive, LinkOptions, LinkReport};
use pvfc_sim::scenario::{Scenario, System};
use pvfc_sim::trace::Trace;
use pvfc_sim::SimError;
use std::os::unix::net::UnixStream;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Where the drive is.
#[derive(Clone, Debug, PartialEq)]
pub enum DriveAt {
    /// A Unix socket a drive (a QEMU guest's USART) listens on.
    Socket(PathBuf),
    /// A firmware ELF run here in `qemu-system-arm -machine netduinoplus2`, its USART1 on a
    /// socket in `dir`.
    Qemu {
        /// The firmware.
        elf: PathBuf,
        /// Where the socket and QEMU's log go.
        dir: PathBuf,
    },
}

/// What a run across the line gave.
#[derive(Debug)]
pub struct HilRun {
    /// The plant's trace, the drive's torques (its internal states NaN: on the drive).
    pub trace: Trace,
    /// What happened on the line.
    pub report: LinkReport,
    /// Wall time (s).
    pub seconds: f64,
}

/// QEMU, ended when the run ends, however it ends.
struct Qemu(std::process::Child);

impl Drop for Qemu {
    fn drop(&mut self) {
        self.0.kill().ok();
        self.0.wait().ok();
    }
}

/// Connects to `socket`, trying for `within`.
fn connect(socket: &Path, within: Duration) -> Result<UnixStream, SimError> {
    let start = Instant::now();
    loop {
        match UnixStream::connect(socket) {
            Ok(s) => return Ok(s),
            Err(e) if start.elapsed() > within => {
                return Err(SimError::Io {
                    path: socket.to_path_buf(),
                    source: e,
                })
            }
            Err(_) => std::thread::sleep(Duration::from_millis(20)),
        }
    }
}

/// Runs scenario `s` (its system `system`) against the drive at `at`, each answer awaited for
/// `timeout` before the frame is sent again.
pub fn run(
    s: &Scenario,
    system: &System,
    at: &DriveAt,
    timeout: Duration,
    options: LinkOptions,
) -> Result<HilRun, SimError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| SimError::Io { path, source }
    };
    let (socket, _qemu) = match at {
        DriveAt::Socket(p) => (p.clone(), None),
        DriveAt::Qemu { elf, dir } => {
            std::fs::create_dir_all(dir).map_err(io(dir))?;
            let socket = dir.join("usart1.sock");
            let _ = std::fs::remove_file(&socket);
            let log = dir.join("qemu.log");
            let out = std::fs::File::create(&log).map_err(io(&log))?;
            let err = out.try_clone().map_err(io(&log))?;
            let child = std::process::Command::new("qemu-system-arm")
                .args(["-machine", "netduinoplus2", "-nographic"])
                .args(["-semihosting-config", "enable=on,target=native"])
                .arg("-serial")
                .arg(format!("unix:{},server=on,wait=on", socket.display()))
                .arg("-kernel")
                .arg(elf)
                .stdout(out)
                .stderr(err)
                .spawn()
                .map_err(io(Path::new("qemu-system-arm")))?;
            (socket, Some(Qemu(child)))
        }
    };
    let mut line = connect(&socket, Duration::from_secs(20))?;
    line.set_read_timeout(Some(timeout)).map_err(io(&socket))?;
    let start = Instant::now();
    let mut drive = LinkDrive::new(s, &mut line, options)?;
    let trace = pvfc_sim::run::simulate_system_over(s, system, &mut drive, &mut |_| {})?;
    Ok(HilRun {
        trace,
        report: drive.into_report(),
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// The largest difference of joint angle (rad) and of torque between two traces, over the
/// samples both have.
pub fn largest_difference(a: &Trace, b: &Trace) -> (f64, f64) {
    let worst = |x: &[f64], y: &[f64]| {
        x.iter()
            .zip(y)
            .map(|(u, v)| (u - v).abs())
            .fold(0.0, f64::max)
    };
    (
        worst(a.q.as_flat(), b.q.as_flat()),
        worst(a.torque.as_flat(), b.torque.as_flat()),
    )
}
