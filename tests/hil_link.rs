#![cfg(unix)]
//! `pvfc hil`'s host side without QEMU: the RTIC firmware's drive (`examples/firmware`'s
//! `drive.rs`, in f64) answers on a socket pair from a thread, as the firmware's USART task
//! does, and pvfc-sim's plant runs against it across the line (`LinkDrive`). The run must
//! equal the same scenario with its own passive drive on the host (`scenarios/hil_scara.toml`
//! describes the firmware's drive), and a frame corrupted on purpose must be refused, counted
//! and sent again.

#[path = "../examples/firmware/src/hil.rs"]
#[allow(dead_code)]
mod hil;

#[path = "../examples/firmware/src/drive.rs"]
#[allow(dead_code)]
mod drive;

use pvfc_link::{Actuate, Decoder, DriveState, Sense};
use pvfc_sim::run::link::{LinkDrive, LinkOptions};
use pvfc_sim::scenario::{Scenario, System};
use std::io::{Read, Write};
use std::os::unix::net::UnixStream;
use std::time::Duration;

/// The firmware's answer loop on `line`: each `Sense` read is one period of the drive (a
/// period answered before is answered again with the same frame); a frame it cannot read is
/// counted and not answered. Ends when the host closes the line; returns the drive's count of
/// unread frames.
fn firmware(mut line: UnixStream) -> u32 {
    let mut drive = drive::Drive::<f64>::new().unwrap();
    let mut setpoint = drive::Setpoint::STOPPED;
    let mut decoder = Decoder::<Sense>::new();
    let mut errors = 0u32;
    let mut last: Option<(u32, Vec<u8>)> = None;
    let mut byte = [0u8; 1];
    while let Ok(1) = line.read(&mut byte) {
        match decoder.push(byte[0]) {
            Some(Ok(sense)) => {
                if let Some((seq, frame)) = &last {
                    if *seq == sense.seq {
                        line.write_all(frame).unwrap();
                        continue;
                    }
                }
                if let Some(c) = sense.command {
                    setpoint = setpoint.after(c);
                }
                let period = drive.period(setpoint, [sense.counts[0], sense.counts[1]]);
                let state = match (drive.fault(), setpoint.run) {
                    (Some(_), _) => DriveState::Fault(1),
                    (None, true) => DriveState::Running,
                    (None, false) => DriveState::Stopped,
                };
                let answer = Actuate {
                    seq: sense.seq,
                    torque: period.torque.iter().map(|&t| t as f32).collect(),
                    state,
                    errors,
                };
                let mut frame = [0u8; pvfc_link::MAX_FRAME];
                let n = pvfc_link::encode(&answer, &mut frame).unwrap();
                line.write_all(&frame[..n]).unwrap();
                last = Some((sense.seq, frame[..n].to_vec()));
            }
            Some(Err(_)) => errors += 1,
            None => {}
        }
    }
    errors
}

/// The scenario, its system, and a line whose host end awaits an answer for `timeout_ms`.
fn setting(timeout_ms: u64) -> (Scenario, System, UnixStream, UnixStream) {
    let s = scenario();
    let system = System::build(&s).unwrap();
    let (host, device) = UnixStream::pair().unwrap();
    host.set_read_timeout(Some(Duration::from_millis(timeout_ms)))
        .unwrap();
    (s, system, host, device)
}

fn scenario() -> Scenario {
    Scenario::from_file(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/hil_scara.toml"
    )))
    .unwrap()
}

#[test]
fn the_firmwares_drive_across_the_line_runs_the_scenarios_drive() {
    let (s, system, mut host, device) = setting(50);
    let answering = std::thread::spawn(move || firmware(device));
    let options = LinkOptions {
        corrupt_at: Some(5_000),
        ..Default::default()
    };
    let mut link = LinkDrive::new(&s, &mut host, options).unwrap();
    let across = pvfc_sim::run::simulate_system_over(&s, &system, &mut link, &mut |_| {}).unwrap();
    let report = link.into_report();
    drop(host);
    let unread = answering.join().unwrap();
    // The twin: the scenario's own passive drive (pvfc-sim's) on the same plant.
    let twin = pvfc_sim::run::simulate_system(&s, &system, &mut |_| {}).unwrap();
    let worst = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
    };
    let dq = worst(across.q.as_flat(), twin.q.as_flat());
    let apart = across
        .torque
        .as_flat()
        .iter()
        .zip(twin.torque.as_flat())
        .filter(|(a, b)| (*a - *b).abs() > 1e-4)
        .count();
    let du = worst(across.torque.as_flat(), twin.torque.as_flat());
    println!(
        "across the line: {} periods, frames sent {}, sent again {}, unread {unread}; against the twin |Δq| {dq:.2e} rad, |Δtorque| {du:.2e} N·m, {apart} torques apart by over 1e-4 N·m",
        report.periods, report.sent, report.resent
    );
    assert_eq!(across.len(), twin.len());
    assert_eq!(report.periods as usize, across.len());
    // The corrupted frame: refused by the drive, sent again by the host; nothing else lost.
    assert_eq!(
        (report.corrupted, report.resent, report.unread, unread),
        (1, 1, 1, 1)
    );
    assert_eq!(report.fault, None);
    // The drive moved the arm (started at 0.2 s, stopped at 9.5 s), and the scenario's drive
    // is the firmware's: the same run but for the torque's f32 on the wire. That rounding
    // moves the arm by far less than an encoder count (4.8e-5 rad), but where the arm sits on
    // a count's edge the two drives read neighbouring counts, and the velocity estimate (one
    // count in a period: 0.048 rad/s) moves that period's torque: measured 3.3e-7 rad, 68 of
    // 20,002 torques apart by over 1e-4 N·m, the largest 0.041 N·m.
    let moved = across.q.iter().map(|q| q[1].abs()).fold(0.0, f64::max);
    assert!(moved > 0.5, "the arm moved {moved} rad");
    assert!(dq < 1e-5, "|Δq| {dq:e} rad");
    assert!(
        apart * 100 < across.torque.as_flat().len() && du < 0.1,
        "{apart} torques apart, the largest by {du:e} N·m"
    );
}

#[test]
fn a_drive_that_stops_answering_ends_the_run_with_its_period() {
    let (s, system, mut host, device) = setting(5);
    // Answers the first 100 periods, then reads and stays silent.
    let silent = std::thread::spawn(move || {
        let mut line = device;
        let mut decoder = Decoder::<Sense>::new();
        let mut byte = [0u8; 1];
        while let Ok(1) = line.read(&mut byte) {
            if let Some(Ok(sense)) = decoder.push(byte[0]) {
                if sense.seq < 100 {
                    let answer = Actuate {
                        seq: sense.seq,
                        torque: [0.0f32, 0.0].into_iter().collect(),
                        state: DriveState::Stopped,
                        errors: 0,
                    };
                    let mut frame = [0u8; pvfc_link::MAX_FRAME];
                    let n = pvfc_link::encode(&answer, &mut frame).unwrap();
                    line.write_all(&frame[..n]).unwrap();
                }
            }
        }
    });
    let mut link = LinkDrive::new(&s, &mut host, LinkOptions::default()).unwrap();
    let e = pvfc_sim::run::simulate_system_over(&s, &system, &mut link, &mut |_| {})
        .unwrap_err()
        .to_string();
    assert_eq!(link.report().periods, 100);
    drop(link);
    drop(host);
    silent.join().unwrap();
    assert!(
        e.contains("period 100") && e.contains("no answer after 11 frames"),
        "{e}"
    );
}

#[test]
fn the_scenarios_operator_is_the_firmwares_script() {
    let s = scenario();
    let mut operator = pvfc_sim::scenario::operator::Operator::new(&s.operator, 1e-3)
        .unwrap()
        .unwrap();
    let sent: Vec<(u32, pvfc_link::Command)> = (0..10_000u32)
        .filter_map(|k| operator.due(u64::from(k)).map(|c| (k, c)))
        .collect();
    assert_eq!(sent, drive::SCRIPT);
}

#[test]
fn faults_of_the_hosts_drive_are_refused_across_the_line() {
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/scenarios/hil_scara.toml"
    ));
    let text = std::fs::read_to_string(path).unwrap()
        + "\n[[faults]]\nkind = \"encoder_freeze\"\nat = 4.0\nduration = 0.02\njoint = 0\n";
    let s = Scenario::parse(&text, path, path.parent().unwrap().to_path_buf()).unwrap();
    let (mut host, _device) = UnixStream::pair().unwrap();
    let e = LinkDrive::new(&s, &mut host, LinkOptions::default())
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("[[faults]]"), "{e}");
}
