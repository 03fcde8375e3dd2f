//! The firmware's host twin: the closed loops of `examples/firmware` (the same `hil.rs`, and
//! the RTIC firmware's `drive.rs`) in f64 and in f32 on the host.
//! `firmware_trace_matches_the_host_twin` and `rtic_trace_matches_the_host_twin` compare the
//! traces the firmwares printed in QEMU (files named by `PVFC_FIRMWARE_TRACE`,
//! `PVFC_RTIC_TRACE`; CI runs them with `scripts/firmware.sh`) with the twins.

#[path = "../examples/firmware/src/hil.rs"]
#[allow(dead_code)]
mod hil;

#[path = "../examples/firmware/src/drive.rs"]
mod drive;

use hil::{Plant, Sample, STEPS, TRACE_EVERY};
use pvfc::prelude::*;
use pvfc_core::nalgebra::Vector2;
use pvfc_core::scalar::cast;

/// The firmware's SysTick handler, step for step, in the scalar `T`.
fn twin<T: Real>() -> Vec<Sample<f64>> {
    let mut ctl = hil::controller::<T>().unwrap();
    let mut plant = Plant::<T>::default();
    let f = |x: T| nalgebra::try_convert::<T, f64>(x).unwrap();
    let mut out = vec![];
    for step in 0..STEPS {
        let (q, v) = (plant.q, plant.v);
        let o = ctl
            .step(&Torus::new(q), &v, cast(hil::DT))
            .expect("no fault on the host");
        if step % TRACE_EVERY == 0 {
            let s = ctl.state();
            let mf = ctl.law().flywheel().inertia();
            out.push(Sample {
                step,
                q: [f(q[0]), f(q[1])],
                torque: [f(o.torque[0]), f(o.torque[1])],
                tau: f(s.unwrapped_tau(ctl.law().field().period())),
                potential: f(o.diagnostics.potential),
                kinetic_energy: f(plant.kinetic_energy()
                    + cast::<T>(0.5)
                        * (s.tau_dot * s.tau_dot + mf * s.flywheel_speed * s.flywheel_speed)),
            });
        }
        let torque: Vector2<T> = o.torque;
        plant.advance(&torque);
    }
    out
}

#[test]
fn the_host_twin_follows_the_contour() {
    let t = twin::<f64>();
    let (first, last) = (t[0], t[t.len() - 1]);
    assert!(
        last.potential < 0.05 * first.potential,
        "U {} -> {}",
        first.potential,
        last.potential
    );
    assert!(last.tau > 1.5, "τ advanced {}", last.tau);
    // Viscous friction is not compensated: κ_a only falls.
    assert!(last.kinetic_energy < first.kinetic_energy);
}

/// Parses the firmware's trace: scaled integers (q in µrad, torque in mN·m, τ in 1e-6,
/// U in 1e-9, κ_a in µJ).
fn parse(text: &str) -> Vec<Sample<f64>> {
    text.lines()
        .filter(|l| l.chars().next().is_some_and(|c| c.is_ascii_digit()))
        .map(|l| {
            let x: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            Sample {
                step: x[0] as usize,
                q: [x[1] * 1e-6, x[2] * 1e-6],
                torque: [x[3] * 1e-3, x[4] * 1e-3],
                tau: x[5] * 1e-6,
                potential: x[6] * 1e-9,
                kinetic_energy: x[7] * 1e-6,
            }
        })
        .collect()
}

/// The largest difference over the run: q (rad), τ, U, κ_a (J).
fn worst(a: &[Sample<f64>], b: &[Sample<f64>]) -> [f64; 4] {
    let mut w = [0.0f64; 4];
    for (x, y) in a.iter().zip(b) {
        assert_eq!(x.step, y.step);
        w[0] = w[0].max((x.q[0] - y.q[0]).abs().max((x.q[1] - y.q[1]).abs()));
        w[1] = w[1].max((x.tau - y.tau).abs());
        w[2] = w[2].max((x.potential - y.potential).abs());
        w[3] = w[3].max((x.kinetic_energy - y.kinetic_energy).abs());
    }
    w
}

/// The largest differences (`worst`) of a firmware's trace against the f64 and the f32 twins,
/// and of the f32 twin against the f64 one, printed.
fn compare(
    name: &str,
    fw: &[Sample<f64>],
    host64: &[Sample<f64>],
    host32: &[Sample<f64>],
) -> [[f64; 4]; 3] {
    let w = [worst(fw, host64), worst(fw, host32), worst(host32, host64)];
    for (what, d) in [
        (format!("{name} vs host f64"), w[0]),
        (format!("{name} vs host f32"), w[1]),
        ("host f32 vs host f64".to_string(), w[2]),
    ] {
        println!(
            "{what}: max |Δq| {:.2e} rad, |Δτ| {:.2e}, |ΔU| {:.2e}, |Δκ| {:.2e} J",
            d[0], d[1], d[2], d[3]
        );
    }
    w
}

#[test]
#[ignore = "needs the firmware's trace: scripts/firmware.sh runs it"]
fn firmware_trace_matches_the_host_twin() {
    let path = std::env::var("PVFC_FIRMWARE_TRACE").expect("PVFC_FIRMWARE_TRACE names the trace");
    let fw = parse(&std::fs::read_to_string(&path).unwrap());
    assert_eq!(
        fw.len(),
        STEPS / TRACE_EVERY,
        "the firmware printed every sample"
    );
    let host64 = twin::<f64>();
    let host32 = twin::<f32>();
    let [vs64, vs32, _] = compare("firmware", &fw, &host64, &host32);
    // The printed trace is quantised (1 µrad, 1e-6 in τ, 1e-9 in U, 1 µJ). The target and the
    // host in f32 run the same arithmetic but for the square root (the host's hardware one,
    // the target's `Real::sqrt_fast`): measured ≤ 1.2e-6 rad, about the print's resolution;
    // bound 1e-5 rad.
    // Against f64: f32 rounding (6e-8 relative per operation) through a loop that converges
    // onto the contour, where errors do not grow: measured 2.7e-5 rad over 10 s; bound 2e-4 rad
    // (relative 1.5e-4 of the arm's ~1.3 rad excursion), and 2e-4 in τ.
    assert!(vs32[0] < 1e-5, "q: firmware vs host f32 {:e} rad", vs32[0]);
    assert!(vs64[0] < 2e-4, "q: firmware vs host f64 {:e} rad", vs64[0]);
    assert!(vs64[1] < 2e-4, "τ: firmware vs host f64 {:e}", vs64[1]);
    assert!(vs64[3] < 2e-2, "κ_a: firmware vs host f64 {:e} J", vs64[3]);
}

/// The RTIC firmware's control task, period for period, in the scalar `T`: the setpoints
/// applied at the periods `setpoints` gives (the firmware's `cmd` lines, or its script).
fn rtic_twin<T: Real>(
    setpoints: &[(u32, drive::Setpoint)],
) -> (Vec<Sample<f64>>, Vec<Option<ErrorKind>>) {
    drive_twin::<T, T>(setpoints)
}

/// The drive in the scalar `T` against the plant in the scalar `P`, period for period, the
/// setpoints applied at the periods `setpoints` gives: its samples and each period's latched
/// fault.
fn drive_twin<T: Real, P: Real>(
    setpoints: &[(u32, drive::Setpoint)],
) -> (Vec<Sample<f64>>, Vec<Option<ErrorKind>>) {
    let mut drive = drive::Drive::<T>::new().unwrap();
    let mut plant = Plant::<P>::default();
    let f = |x: T| nalgebra::try_convert::<T, f64>(x).unwrap();
    let g = |x: P| nalgebra::try_convert::<P, f64>(x).unwrap();
    let mut setpoint = drive::Setpoint::STOPPED;
    let (mut out, mut faults) = (vec![], vec![]);
    for step in 0..STEPS as u32 {
        if let Some((_, s)) = setpoints.iter().find(|(at, _)| *at == step) {
            setpoint = *s;
        }
        let o = drive.period(setpoint, drive::encoder_counts(&plant.q));
        faults.push(o.fault);
        if step % TRACE_EVERY as u32 == 0 {
            let c = drive.controller().controller();
            out.push(Sample {
                step: step as usize,
                q: [g(plant.q[0]), g(plant.q[1])],
                torque: [f(o.torque[0]), f(o.torque[1])],
                tau: f(c.state().unwrapped_tau(c.law().field().period())),
                potential: o.potential.map_or(f64::NAN, f),
                kinetic_energy: g(plant.kinetic_energy()),
            });
        }
        plant.advance(&o.torque.map(|x| cast::<P>(f(x))));
    }
    // The drive keeps the first fault it latched.
    assert_eq!(drive.fault(), faults.iter().flatten().next().copied());
    (out, faults)
}

/// The script's commands as the setpoints the firmware applies, at the periods it sends them.
fn script_setpoints() -> Vec<(u32, drive::Setpoint)> {
    let mut s = drive::Setpoint::STOPPED;
    drive::SCRIPT
        .iter()
        .map(|(at, c)| {
            s = s.after(*c);
            (*at, s)
        })
        .collect()
}

/// Mean kinetic energy of the arm over the samples in `[from, to)` (J).
fn mean_kinetic(t: &[Sample<f64>], from: usize, to: usize) -> f64 {
    let s: Vec<f64> = t
        .iter()
        .filter(|x| (from..to).contains(&x.step))
        .map(|x| x.kinetic_energy)
        .collect();
    s.iter().sum::<f64>() / s.len() as f64
}

#[test]
fn the_rtic_drive_obeys_the_operator() {
    let (t, faults) = rtic_twin::<f64>(&script_setpoints());
    assert!(faults.iter().all(Option::is_none), "no fault");
    let at = |step: usize| t[step / TRACE_EVERY];
    // Stopped until the start: the safe torque, the arm at rest.
    assert!(t[..2]
        .iter()
        .all(|x| x.torque == [0.0; 2] && x.q == [0.0; 2]));
    // Started at r = 1: the arm reaches for the contour (U falls by 10× before 4 s).
    assert!(
        at(3900).potential < 0.1 * at(200).potential,
        "U {} -> {}",
        at(200).potential,
        at(3900).potential
    );
    // r = 2 speeds it up, r = 0 brakes it: the arm's mean kinetic energy over each phase,
    // against the same run without that command.
    let without = |i: usize| {
        let mut s = script_setpoints();
        let speed = s[i - 1].1.speed;
        s[i].1.speed = speed;
        s[i + 1..]
            .iter_mut()
            .for_each(|x| x.1.speed = speed.max(x.1.speed));
        rtic_twin::<f64>(&s).0
    };
    let (fast, kept) = (
        mean_kinetic(&t, 5_000, 7_000),
        mean_kinetic(&without(1), 5_000, 7_000),
    );
    println!("r = 2 from 4 s: {fast:.3e} J over 5–7 s, {kept:.3e} J at r = 1");
    assert!(
        fast > 1.5 * kept,
        "r = 2: {fast:.2e} J against {kept:.2e} J at r = 1"
    );
    let (braked, kept) = (
        mean_kinetic(&t, 8_500, 9_500),
        mean_kinetic(&without(2), 8_500, 9_500),
    );
    println!("r = 0 from 7 s: {braked:.3e} J over 8.5–9.5 s, {kept:.3e} J at r = 2");
    assert!(
        braked < 0.5 * kept,
        "r = 0: {braked:.2e} J against {kept:.2e} J at r = 2"
    );
    // Stopped again: the safe torque.
    assert!(t[95..]
        .iter()
        .all(|x| x.torque == [0.0; 2] && x.potential.is_nan()));
}

#[test]
fn a_fault_latches_the_safe_torque() {
    // A corrupted command (a speed that is not a number) at 3 s, a good one after it.
    let mut setpoints = script_setpoints();
    let bad = drive::Setpoint {
        run: true,
        speed: f32::NAN,
    };
    setpoints.insert(1, (3_000, bad));
    setpoints.insert(
        2,
        (
            3_001,
            drive::Setpoint {
                run: true,
                speed: 1.0,
            },
        ),
    );
    let (t, faults) = rtic_twin::<f64>(&setpoints);
    let latched: Vec<usize> = faults
        .iter()
        .enumerate()
        .filter_map(|(i, f)| f.map(|_| i))
        .collect();
    assert_eq!(latched, [3_000], "latched once, at the bad command");
    assert_eq!(faults[3_000], Some(ErrorKind::NonFinite));
    assert!(
        t[30..]
            .iter()
            .all(|x| x.torque == [0.0; 2] && x.potential.is_nan()),
        "the safe torque from then on"
    );
    assert!(t[29].torque != [0.0; 2]);
}

/// Parses the RTIC firmware's `cmd STEP RUN SPEED_e3` lines.
fn parse_commands(text: &str) -> Vec<(u32, drive::Setpoint)> {
    text.lines()
        .filter_map(|l| l.strip_prefix("cmd "))
        .map(|l| {
            let x: Vec<i64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            (
                x[0] as u32,
                drive::Setpoint {
                    run: x[1] == 1,
                    speed: x[2] as f32 * 1e-3,
                },
            )
        })
        .collect()
}

#[test]
#[ignore = "needs the RTIC firmware's trace: scripts/firmware.sh runs it"]
fn rtic_trace_matches_the_host_twin() {
    let path = std::env::var("PVFC_RTIC_TRACE").expect("PVFC_RTIC_TRACE names the trace");
    let text = std::fs::read_to_string(&path).unwrap();
    let fw = parse(&text);
    let commands = parse_commands(&text);
    assert_eq!(
        fw.len(),
        STEPS / TRACE_EVERY,
        "the firmware printed every sample"
    );
    // Each command lands at the period the script sends it (QEMU counting instructions), or a
    // period or two later if the host kept QEMU from running the operator's task in time.
    let script = script_setpoints();
    assert_eq!(commands.len(), script.len(), "one setpoint per command");
    for (got, sent) in commands.iter().zip(&script) {
        assert!(
            got.1 == sent.1 && (sent.0..=sent.0 + 2).contains(&got.0),
            "{got:?} for {sent:?}"
        );
    }
    assert!(text.contains("0 messages dropped, no fault"));
    let (host64, _) = rtic_twin::<f64>(&commands);
    let (host32, _) = rtic_twin::<f32>(&commands);
    // U is printed as -1 where the controller was not stepped; the twin has NaN there.
    let finite = |t: &[Sample<f64>]| -> Vec<Sample<f64>> {
        t.iter()
            .map(|x| Sample {
                potential: if x.potential.is_finite() {
                    x.potential
                } else {
                    -1e-9
                },
                ..*x
            })
            .collect()
    };
    let (host64, host32) = (finite(&host64), finite(&host32));
    let [vs64, vs32, f32_vs_f64] = compare("rtic", &fw, &host64, &host32);
    // The same arithmetic as the host's f32 but for the square root (the target's
    // `Real::sqrt_fast`): measured 6.8e-6 rad (the print's resolution is 1e-6); bound 1e-5.
    assert!(vs32[0] < 1e-5, "q: firmware vs host f32 {:e} rad", vs32[0]);
    // Against f64 the encoders' counts amplify rounding (an angle one count apart rounds to
    // another count, and the loop runs on from there): the firmware is as far from the f64
    // twin as the host's own f32 twin is, within 10 %.
    assert!(
        vs64[0] <= 1.1 * f32_vs_f64[0] + 1e-5,
        "q: firmware vs host f64 {:e} rad, host f32 vs f64 {:e} rad",
        vs64[0],
        f32_vs_f64[0]
    );
}

/// What the host saw of a hardware-in-the-loop run.
#[derive(Debug, Default)]
struct Line {
    /// Frames sent, frames sent again after no answer, frames corrupted on purpose.
    sent: usize,
    resent: usize,
    corrupted: usize,
    /// The frames the drive could not read during the run (its count at the end, less at boot).
    drive_errors: u32,
    /// The drive's answer to a period sent after a skipped one (the run over): its state and
    /// torque.
    after_gap: Option<(pvfc_link::DriveState, [f32; 2])>,
}

/// Period `k` of the host's plant: a sample every `TRACE_EVERY` periods (the angles and the
/// torque), then one period at `torque`.
fn advance(plant: &mut Plant<f64>, k: u32, torque: Vector2<f64>, out: &mut Vec<Sample<f64>>) {
    if k.is_multiple_of(TRACE_EVERY as u32) {
        out.push(Sample {
            step: k as usize,
            q: [plant.q[0], plant.q[1]],
            torque: [torque[0], torque[1]],
            ..Sample::default()
        });
    }
    plant.advance(&torque);
}

/// The host's frame of period `seq`: the plant's encoder counts and `command`; its bytes and
/// their length.
fn sense_frame(
    seq: u32,
    plant: &Plant<f64>,
    command: Option<drive::Command>,
) -> ([u8; pvfc_link::MAX_FRAME], usize) {
    let sense = pvfc_link::Sense {
        seq,
        counts: drive::encoder_counts(&plant.q).iter().copied().collect(),
        command,
    };
    let mut frame = [0u8; pvfc_link::MAX_FRAME];
    let n = pvfc_link::encode(&sense, &mut frame).unwrap();
    (frame, n)
}

/// The period at which the host corrupts its frame on purpose (one bit flipped).
const CORRUPT_AT: u32 = 5_000;

/// The RTIC firmware's `hil` binary in QEMU (USART1 on a Unix socket), in lockstep with the
/// host's plant: the operator's script, the encoders' counts, one frame a period each way.
fn hil_run(elf: &str) -> (Vec<Sample<f64>>, Line) {
    use pvfc_link::{Actuate, Decoder, DriveState};
    use std::io::{Read, Write};
    use std::os::unix::net::UnixStream;
    use std::time::{Duration, Instant};
    let dir = std::env::temp_dir().join(format!("pvfc-hil-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let socket = dir.join("usart1.sock");
    let _ = std::fs::remove_file(&socket);
    let log = std::fs::File::create(dir.join("qemu.log")).unwrap();
    /// QEMU, ended when the run ends, however it ends (a failed assertion included).
    struct Qemu(std::process::Child);
    impl Drop for Qemu {
        fn drop(&mut self) {
            self.0.kill().ok();
            self.0.wait().ok();
        }
    }
    let _qemu = Qemu(
        std::process::Command::new("qemu-system-arm")
            .args(["-machine", "netduinoplus2", "-nographic"])
            .args(["-semihosting-config", "enable=on,target=native"])
            .arg("-serial")
            .arg(format!("unix:{},server=on,wait=on", socket.display()))
            .args(["-kernel", elf])
            .stdout(log.try_clone().unwrap())
            .stderr(log)
            .spawn()
            .expect("qemu-system-arm runs"),
    );
    let start = Instant::now();
    let mut stream = loop {
        match UnixStream::connect(&socket) {
            Ok(s) => break s,
            Err(e) if start.elapsed() > Duration::from_secs(20) => panic!("no QEMU socket: {e}"),
            Err(_) => std::thread::sleep(Duration::from_millis(20)),
        }
    };
    stream
        .set_read_timeout(Some(Duration::from_millis(300)))
        .unwrap();
    let mut plant = Plant::<f64>::default();
    let mut decoder = Decoder::<Actuate>::new();
    let mut line = Line::default();
    let mut out = vec![];
    // Sends `frame` (period `seq`) and reads the answer to it (a late answer to an earlier
    // period, after a frame sent again, is passed over); `None` after 300 ms without one.
    let mut answer = |stream: &mut UnixStream, frame: &[u8], seq: u32, line: &mut Line| {
        stream.write_all(frame).unwrap();
        line.sent += 1;
        let mut byte = [0u8; 1];
        loop {
            match stream.read(&mut byte) {
                Ok(1) => match decoder.push(byte[0]) {
                    Some(Ok(a)) if a.seq == seq => return Some(a),
                    Some(Ok(a)) if a.seq < seq => {}
                    Some(r) => panic!("period {seq}: the drive's answer {r:?}"),
                    None => {}
                },
                Ok(_) => panic!("QEMU closed the line"),
                Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => return None,
                Err(e) => panic!("the line: {e}"),
            }
        }
    };
    // The drive boots after QEMU accepts the connection: bytes before its USART is enabled are
    // lost. Period 0 is sent until answered (the arm at rest, stopped: no period changes
    // anything before the script starts it); only then does the run count frames.
    let (frame, n) = sense_frame(0, &plant, None);
    assert!(
        drive::SCRIPT[0].0 > 0,
        "the script's first command comes after period 0"
    );
    let a = loop {
        if let Some(a) = answer(&mut stream, &frame[..n], 0, &mut line) {
            break a;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "the drive never answered"
        );
    };
    let torque = Vector2::new(f64::from(a.torque[0]), f64::from(a.torque[1]));
    advance(&mut plant, 0, torque, &mut out);
    // What the drive could not read while it booted (a frame cut by the USART's start) is not
    // the run's.
    let boot_errors = a.errors;
    line = Line::default();
    for k in 1..STEPS as u32 {
        let command = drive::SCRIPT
            .iter()
            .find(|(at, _)| *at == k)
            .map(|(_, c)| *c);
        let (frame, n) = sense_frame(k, &plant, command);
        // At CORRUPT_AT the first frame sent has one bit flipped: the drive must not answer it.
        let mut corrupt = k == CORRUPT_AT;
        let a = loop {
            let mut bytes = frame;
            if corrupt {
                bytes[2] ^= 0x10;
                line.corrupted += 1;
            }
            match answer(&mut stream, &bytes[..n], k, &mut line) {
                Some(a) if corrupt => panic!("the drive answered a corrupted frame: {a:?}"),
                Some(a) => break a,
                None => {}
            }
            corrupt = false;
            line.resent += 1;
            assert!(
                line.resent < 10,
                "the drive stopped answering at period {k}"
            );
        };
        assert_eq!(a.seq, k, "the answer's period");
        assert!(
            !matches!(a.state, DriveState::Fault(_)),
            "period {k}: {:?}",
            a.state
        );
        line.drive_errors = a.errors - boot_errors;
        let torque = Vector2::new(f64::from(a.torque[0]), f64::from(a.torque[1]));
        advance(&mut plant, k, torque, &mut out);
    }
    // A period skipped (the host ran one without the drive's torque): the drive must latch
    // its link fault and answer with the safe torque.
    let gap = STEPS as u32 + 1;
    let (frame, n) = sense_frame(gap, &plant, None);
    let a = answer(&mut stream, &frame[..n], gap, &mut line).expect("an answer after the gap");
    line.after_gap = Some((a.state, [a.torque[0], a.torque[1]]));
    (out, line)
}

#[test]
#[ignore = "needs QEMU and the RTIC firmware's hil binary: scripts/firmware.sh runs it"]
fn hil_run_matches_the_host_twin() {
    use pvfc_link::DriveState;
    let elf = std::env::var("PVFC_HIL_FIRMWARE").expect("PVFC_HIL_FIRMWARE names the ELF");
    let t0 = std::time::Instant::now();
    let (fw, line) = hil_run(&elf);
    let seconds = t0.elapsed().as_secs_f64();
    // The same loop on the host: the drive in f32 (as on the target, but for the square root)
    // and in f64, the plant in f64 (as the host runs it).
    let script = script_setpoints();
    let (twin, twin64) = (
        drive_twin::<f32, f64>(&script).0,
        drive_twin::<f64, f64>(&script).0,
    );
    let worst = |a: &[Sample<f64>], b: &[Sample<f64>]| {
        let (mut dq, mut dt) = (0.0f64, 0.0f64);
        for (x, y) in a.iter().zip(b) {
            dq = dq.max((x.q[0] - y.q[0]).abs().max((x.q[1] - y.q[1]).abs()));
            dt = dt.max(
                (x.torque[0] - y.torque[0])
                    .abs()
                    .max((x.torque[1] - y.torque[1]).abs()),
            );
        }
        (dq, dt)
    };
    let ((dq, dt), (dq64, dt64)) = (worst(&fw, &twin), worst(&twin, &twin64));
    println!(
        "hil: {} periods in {seconds:.1} s; frames sent {}, sent again {}, corrupted on purpose {}, \
         unread by the drive {}",
        STEPS, line.sent, line.resent, line.corrupted, line.drive_errors
    );
    println!("hil vs host twin (f32 drive): max |Δq| {dq:.2e} rad, max |Δtorque| {dt:.2e} N·m");
    println!("host twin, f32 drive vs f64: max |Δq| {dq64:.2e} rad, max |Δtorque| {dt64:.2e} N·m");
    assert_eq!(fw.len(), twin.len());
    // The one corrupted frame: not answered, counted by the drive, sent again; nothing else lost.
    assert_eq!((line.corrupted, line.resent, line.drive_errors), (1, 1, 1));
    assert_eq!(line.sent, STEPS + 1);
    // A skipped period: the link fault latched, the safe torque.
    assert_eq!(
        line.after_gap,
        Some((DriveState::Fault(255), [0.0, 0.0])),
        "the drive's answer after a skipped period"
    );
    // The same arithmetic but for the square root: the run is far nearer its f32 twin than the
    // f32 twin is to the f64 one (measured 3.8e-5 against 1.3e-3 rad: positions read through
    // encoder counts make rounding matter).
    assert!(
        dq < 0.1 * dq64 && dq < 1e-4,
        "q: hil vs host twin {dq:e} rad (f32 vs f64: {dq64:e})"
    );
}

#[path = "../examples/firmware/src/ur5.rs"]
mod ur5;

/// The firmware's UR5 constants are what the URDF reader gives for `models/ur5` (tip `tool0`).
#[test]
fn the_firmware_ur5_constants_match_the_urdf() {
    let d = pvfc_sim::urdf::ChainDescription::from_file(
        std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/models/ur5/ur5_robot.urdf"
        )),
        None,
        Some("tool0"),
    )
    .unwrap();
    let m3 = |m: &[[f64; 3]; 3]| nalgebra::Matrix3::from_fn(|i, j| m[i][j]);
    for (j, (r, t, a)) in d.joints.iter().zip(ur5::JOINTS) {
        assert_eq!(j.joint.origin.rotation, m3(&r));
        assert_eq!(j.joint.origin.translation, nalgebra::Vector3::from(t));
        assert_eq!(j.joint.axis, nalgebra::Vector3::from(a));
    }
    for (l, (m, c, i)) in d.links.iter().zip(ur5::LINKS) {
        assert_eq!(
            (l.mass, l.com, l.inertia),
            (m, nalgebra::Vector3::from(c), m3(&i))
        );
    }
    assert_eq!(d.tool.rotation, m3(&ur5::TOOL.0));
    assert_eq!(d.tool.translation, nalgebra::Vector3::from(ur5::TOOL.1));
}
