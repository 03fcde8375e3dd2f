//! Part programs (G-code) read into tool paths: the geometry against paths built another way
//! (the rounded polygon, the circle, points transformed by hand), the modal words (planes,
//! units, incremental coordinates and centres, R arcs), the feed, and every refusal with its
//! line and column.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pvfc_control::error::SimError;
use pvfc_control::model::cartesian::{CartesianSpec, PoseSpec};
use pvfc_control::model::gcode::{PartProgram, ProgramError};
use pvfc_control::model::path_orientation::PathFrame;
use pvfc_control::model::tool_path::ToolPath;
use std::f64::consts::{PI, TAU};
use std::path::Path;

fn path(text: &str) -> ToolPath {
    PartProgram::parse(text)
        .and_then(|p| p.tool_path())
        .unwrap_or_else(|e| panic!("{e:?}\n{text}"))
}

fn error(text: &str) -> ProgramError {
    match PartProgram::parse(text).and_then(|p| p.tool_path()) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e,
    }
}

/// The largest distance from `m` points of `a` to the path `b`.
fn farthest(a: &ToolPath, b: &ToolPath, m: usize) -> f64 {
    (0..m)
        .map(|k| {
            b.closest(&a.point(a.length() * k as f64 / m as f64))
                .distance
        })
        .fold(0.0, f64::max)
}

const RECTANGLE: &str = "G21 G90 G17\nG0 X5 Y0\nG1 X35 F600\nG3 X40 Y5 I0 J5\nG1 Y15\nG3 X35 Y20 I-5 J0\nG1 X5\nG3 X0 Y15 I0 J-5\nG1 Y5\nG3 X5 Y0 I5 J0\nG0 Z10\nM30\n";

#[test]
fn a_rounded_rectangle_is_the_rounded_polygon_of_its_corners() {
    let program = path(RECTANGLE);
    let corners =
        [[0.0, 0.0], [0.04, 0.0], [0.04, 0.02], [0.0, 0.02]].map(|[x, y]| Vector3::new(x, y, 0.0));
    let polygon = ToolPath::rounded_polygon(&corners, 0.005).unwrap();
    assert!((program.length() - polygon.length()).abs() < 1e-15);
    assert!(farthest(&program, &polygon, 4000) < 1e-15);
    assert!(farthest(&polygon, &program, 4000) < 1e-15);
    // Counter-clockwise (G3 corners): the same direction as the polygon.
    assert!((program.tangent(0.001) - Vector3::x()).norm() < 1e-15);
}

#[test]
fn centres_by_r_incremental_moves_absolute_centres_and_inches_give_the_same_path() {
    let reference = path(RECTANGLE);
    let by_r = RECTANGLE
        .replace("I0 J5", "R5")
        .replace("I-5 J0", "R5")
        .replace("I0 J-5", "R5")
        .replace("I5 J0", "R5");
    let incremental = "G21 G91\nG0 X5 Y0\nG1 X30 F600\nG3 X5 Y5 I0 J5\nG1 Y10\nG3 X-5 Y5 I-5 J0\nG1 X-30\nG3 X-5 Y-5 I0 J-5\nG1 Y-10\nG3 X5 Y-5 I5 J0\n";
    let absolute_centres = "G21 G90 G90.1\nG0 X5 Y0\nG1 X35 F600\nG3 X40 Y5 I35 J5\nG1 Y15\nG3 X35 Y20 I35 J15\nG1 X5\nG3 X0 Y15 I5 J15\nG1 Y5\nG3 X5 Y0 I5 J5\n";
    let scale = |x: f64| format!("{}", x / 25.4);
    let inches = format!(
        "G20 G90\nG0 X{a} Y0\nG1 X{b} F{f}\nG3 X{c} Y{a} I0 J{a}\nG1 Y{d}\nG3 X{b} Y{e} I-{a} J0\nG1 X{a}\nG3 X0 Y{d} I0 J-{a}\nG1 Y{a}\nG3 X{a} Y0 I{a} J0\n",
        a = scale(5.0),
        b = scale(35.0),
        c = scale(40.0),
        d = scale(15.0),
        e = scale(20.0),
        f = scale(600.0),
    );
    for text in [
        by_r.as_str(),
        incremental,
        absolute_centres,
        inches.as_str(),
    ] {
        let p = path(text);
        assert!((p.length() - reference.length()).abs() < 1e-12, "{text}");
        assert!(farthest(&p, &reference, 2000) < 1e-12, "{text}");
        let program = PartProgram::parse(text).unwrap();
        let feed = program.moves[0].feed.unwrap();
        assert!(
            (feed - 0.01).abs() < 1e-15,
            "600 mm/min is 0.01 m/s, got {feed}"
        );
    }
}

#[test]
fn clockwise_circles_in_each_plane_turn_the_right_way() {
    // A full circle of radius 10 mm from (10, 0, 0) about the origin: G2 clockwise seen
    // from the plane's normal; ends where it starts.
    let cases = [
        ("G17", "G2 X10 Y0 I-10 J0", Vector3::z()),
        ("G18", "G2 X10 Z0 I-10 K0", Vector3::y()),
        ("G19", "G2 Y10 Z0 J-10 K0", Vector3::x()),
    ];
    for (plane, arc, normal) in cases {
        let start = if plane == "G19" { "G0 Y10" } else { "G0 X10" };
        let p = path(&format!("{plane}\n{start}\n{arc}\n"));
        assert!((p.length() - TAU * 0.01).abs() < 1e-15, "{plane}");
        let x0 = p.point(0.0);
        let t0 = p.tangent(0.0);
        // Clockwise about the normal: the tangent is −normal × (x0 − centre).
        let expected = -normal.cross(&x0).normalize();
        assert!(
            (t0 - expected).norm() < 1e-12,
            "{plane}: {t0:?} against {expected:?}"
        );
        // Every point on the circle, in the plane.
        for k in 0..100 {
            let x = p.point(p.length() * k as f64 / 100.0);
            assert!((x.norm() - 0.01).abs() < 1e-15 && x.dot(&normal).abs() < 1e-18);
        }
    }
}

#[test]
fn a_negative_radius_takes_the_longer_arc() {
    // A half-disc closed by its diameter: R ±10 between (−10, 0) and (10, 0).
    let short = path("G0 X-10 Y0\nG2 X10 Y0 R10\nG1 X-10\n");
    assert!((short.length() - (PI * 0.01 + 0.02)).abs() < 1e-15);
    // A three-quarter turn: from (10, 0) to (0, 10) counter-clockwise the long way.
    let long = path("G0 X10 Y0\nG3 X0 Y10 R-10\nG1 X10 Y0\n");
    let chord = 0.01 * 2f64.sqrt();
    assert!((long.length() - (1.5 * PI * 0.01 + chord)).abs() < 1e-15);
    // The long way round is about the other centre, (10, 10): its midpoint is 135° on from
    // the start, at (10, 10) + (10, 10)/√2.
    let mid = long.point(0.75 * PI * 0.01);
    let expected = Vector3::new(0.01, 0.01, 0.0) * (1.0 + 1.0 / 2f64.sqrt());
    assert!((mid - expected).norm() < 1e-15, "{mid:?}");
}

#[test]
fn coordinates_keep_their_digits() {
    // 123.4567891 mm is not an f32 (the parser's literal): the path keeps the written digits.
    let p = PartProgram::parse("G0 X0 Y0\nG1 X123.4567891\nG1 Y1\nG1 X0 Y0\n").unwrap();
    let pvfc_control::model::tool_path::Segment::Line { to } = p.moves[0].segment else {
        panic!("a line");
    };
    assert!((to.x - 0.1234567891).abs() < 3e-17, "{}", to.x);
    assert!((f64::from(123.456_79_f32) * 1e-3 - to.x).abs() > 1e-9);
}

#[test]
fn every_refusal_names_its_line_and_column() {
    let cases: &[(&str, usize, usize, &str)] = &[
        ("G0 X0 Y0\nG1 X10\nG5 X3\n", 3, 1, "G5: not supported"),
        (
            "G0 X0\nG1 X10 A5\nG1 X0\n",
            2,
            8,
            "the word A is not supported",
        ),
        (
            "G0 X0\nG1 X10\nG1 Y10\nG1 X0 Y0 Z1\n",
            4,
            1,
            "does not close",
        ),
        (
            "G0 X0\nG1 X10\nG0 X20\nG1 X0\n",
            4,
            1,
            "rapid move (G0) between cutting moves",
        ),
        ("G0 X10 Y0\nG3 X10 Y0 Z5 I-10 J0\n", 2, 1, "helical"),
        ("G0 X10 Y0\nG3 X0 Y10 I-10 J1\nG1 X10 Y0\n", 2, 1, "radius"),
        (
            "G0 X10 Y0\nG3 X0 Y10\nG1 X10 Y0\n",
            2,
            1,
            "needs its centre",
        ),
        (
            "G0 X10 Y0\nG3 X0 Y10 R1\nG1 X10 Y0\n",
            2,
            1,
            "shorter than half the chord",
        ),
        ("G0 X10 Y0\nG3 X0 Y10 I-10 R10\n", 2, 1, "not both"),
        (
            "G0 X10 Y0\nG3 X0 Y10 I-10 K1\n",
            2,
            1,
            "along the plane's normal",
        ),
        ("G0 X0\nG1 X#1\n", 2, 4, "expected: number"),
        ("G0 X0\n  G1 X10 X20\n", 2, 10, "X given twice"),
        ("G0 X0\nG1 G2 X10\n", 2, 4, "two motion codes"),
        ("G0 X0\nM98 P100\n", 2, 1, "M98: not supported"),
        ("G0 X1\nG0 X2\n", 1, 1, "no cutting move"),
        ("G0 X0\nG1 X10 I5\n", 2, 1, "on a straight move"),
        ("G0 X0\nG64\nG1 X10\n", 2, 1, "G64 needs P"),
        (
            "G0 X0\nG1 X10\nG64 P0 G1 Y5\n",
            3,
            1,
            "the tolerance must be > 0",
        ),
        ("G0 X0\nG1 X10 P2\n", 2, 8, "only as G64's tolerance"),
        ("G0 X0\nG64 P1 P2\n", 2, 8, "P given twice"),
        // Found by fuzzing (fuzz/fuzz_targets/gcode.rs): the parser's code number overflows.
        (
            "G0 X0\nG1 X10\n (G1) G2000000000000 X0\n",
            3,
            7,
            "code number this large",
        ),
        (
            "G0 X0\nG1 X10\nM 4294967302\n",
            3,
            1,
            "code number this large",
        ),
    ];
    for &(text, line, column, fragment) in cases {
        let e = error(text);
        assert!(
            e.line == line && e.column == column && e.message.contains(fragment),
            "{text:?}: got line {}, column {}: {}; expected {line}:{column} with {fragment:?}",
            e.line,
            e.column,
            e.message
        );
    }
}

#[test]
fn a_parse_error_is_named_where_it_is() {
    let e = error("G0 X0\nG1 X10 Y\nG1 X0\n");
    assert_eq!(e.line, 2, "{e:?}");
}

#[test]
fn rapid_moves_only_place_the_start_and_retract() {
    let p = PartProgram::parse(
        "G0 X5 Y5 Z20\nG0 Z0\nG1 X15\nG1 Y15\nG1 X5\nG1 Y5\nG0 Z20\nG0 X0 Y0\nM30\n",
    )
    .unwrap();
    assert_eq!(p.start, Vector3::new(0.005, 0.005, 0.0));
    assert_eq!(p.moves.len(), 4);
    assert!((p.tool_path().unwrap().length() - 0.04).abs() < 1e-15);
}

#[test]
fn a_scenario_reads_its_part_program_in_the_parts_frame() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenarios");
    let part = PoseSpec {
        xyz: [0.45, -0.15, 0.30],
        rpy: [0.0, 0.0, 0.1],
    };
    let spec = CartesianSpec {
        gcode: Some("parts/bracket.nc".into()),
        part: Some(part),
        ..Default::default()
    };
    let placed = spec.path(&dir).unwrap();
    let in_part = path(&std::fs::read_to_string(dir.join("parts/bracket.nc")).unwrap());
    // The exact length: straight 820 mm, four 30 mm and four 10 mm quarter circles.
    let exact = 0.820 + 2.0 * PI * 0.030 + 2.0 * PI * 0.010;
    assert!(
        (in_part.length() - exact).abs() < 1e-12,
        "{}",
        in_part.length()
    );
    assert!((placed.length() - exact).abs() < 1e-12);
    let pose = Isometry3::from_parts(
        Translation3::new(0.45, -0.15, 0.30),
        UnitQuaternion::from_euler_angles(0.0, 0.0, 0.1),
    );
    for k in 0..500 {
        let s = exact * k as f64 / 500.0;
        let by_hand = pose.transform_point(&in_part.point(s).into()).coords;
        assert!((placed.point(s) - by_hand).norm() < 1e-15);
    }
    // A missing file names its path; a bad program names the file, line and column.
    let missing = CartesianSpec {
        gcode: Some("parts/none.nc".into()),
        ..Default::default()
    };
    assert!(
        matches!(missing.path(&dir), Err(SimError::Io { path, .. }) if path.ends_with("parts/none.nc"))
    );
    let both = CartesianSpec {
        gcode: Some("parts/bracket.nc".into()),
        points: vec![[0.0; 3]; 3],
        ..Default::default()
    };
    assert!(both
        .path(&dir)
        .unwrap_err()
        .to_string()
        .contains("exactly one of"));
}

/// The feeds along the path: one stretch per cutting move, end to end over the path's
/// length, each at its move's F (units per minute to m/s), a move before the first F at the
/// fallback, looked up by arc length (wrapped) and by the closest point.
#[test]
fn feeds_are_the_speeds_of_their_stretches() {
    use pvfc_control::model::feeds::FeedProfile;
    let text = RECTANGLE
        .replace("G1 X35 F600", "G1 X35")
        .replace("G1 Y15\n", "G1 Y15 F1200\n");
    let program = PartProgram::parse(&text).unwrap();
    let tool_path = program.tool_path().unwrap();
    assert!(FeedProfile::from_program(&program, tool_path.clone(), None).is_err());
    let feeds = FeedProfile::from_program(&program, tool_path.clone(), Some(0.5))
        .unwrap()
        .expect("F words");
    let stretches: Vec<_> = feeds.stretches().collect();
    assert_eq!(stretches.len(), 8);
    assert_eq!(stretches[0].0, 0.0);
    assert!((stretches[7].1 - tool_path.length()).abs() < 1e-15);
    for w in stretches.windows(2) {
        assert_eq!(w[0].1, w[1].0);
    }
    let speeds: Vec<f64> = stretches.iter().map(|s| s.2).collect();
    assert_eq!(speeds[..2], [0.5, 0.5]);
    assert!(
        speeds[2..].iter().all(|v| (v - 0.02).abs() < 1e-15),
        "{speeds:?}"
    );
    // The first line is 30 mm: 29 mm in, and one pass later, it is at the fallback.
    assert_eq!(feeds.speed_along(0.029), 0.5);
    assert_eq!(feeds.speed_along(0.029 + tool_path.length()), 0.5);
    assert!((feeds.speed_along(0.031 + 0.5 * PI * 0.005 + 0.001) - 0.02).abs() < 1e-15);
    assert!((feeds.speed_at(&Vector3::new(0.040 + 1e-4, 0.010, 0.0)) - 0.02).abs() < 1e-15);
    assert_eq!(feeds.speed_at(&Vector3::new(0.020, -1e-4, 0.0)), 0.5);
    // A program without F has no feeds.
    let bare = PartProgram::parse(&RECTANGLE.replace(" F600", "")).unwrap();
    assert!(
        FeedProfile::from_program(&bare, bare.tool_path().unwrap(), Some(0.5))
            .unwrap()
            .is_none()
    );
}

/// Found by fuzzing (fuzz/fuzz_targets/gcode.rs, CI): a code number past `u32` after carriage
/// returns (which the gcode crate's lexer skips) overflowed inside the crate; it is an error
/// naming the code, as with spaces.
#[test]
fn a_code_number_past_u32_after_carriage_returns_is_an_error() {
    let bytes: &[u8] = b"G20 G9G2G20 G\r\r999900000\xbf00000000000295170617\nG0 X1 3 \x131 Z0 G9G2G20 G\r\r999999999992999999999999959\r9\r\r\r\r\r11!G18 X1 3 X1 Z-1 R-2 F2992999Z-\xff\xff\xffH13\x0b\x000\n!0\n";
    let text = String::from_utf8_lossy(bytes);
    let e = error(&text);
    assert!(e.message.contains("code number this large"), "{e:?}");
    let e = error("G0 X0\nG1 X10\nG\r\r\t 999999999999\n");
    assert!(
        e.line == 3 && e.message.contains("G: a code number this large"),
        "{e:?}"
    );
}

/// The largest turn of the path's direction where one piece meets the next (rad).
fn largest_kink(p: &ToolPath) -> f64 {
    let l = p.length();
    let starts = p.piece_starts();
    starts[..starts.len() - 1]
        .iter()
        .map(|&s| p.tangent((s - 1e-9 * l).rem_euclid(l)).angle(&p.tangent(s)))
        .fold(0.0, f64::max)
}

const SHARP_RECTANGLE: &str =
    "G21 G90 G17 G64 P0.1\nG0 X0 Y0\nG1 X40 F600\nG1 Y20\nG1 X0 F300\nG1 Y0\nM30\n";

#[test]
fn g64_blends_each_sharp_corner_by_the_arc_that_leaves_it_by_the_tolerance() {
    let program = PartProgram::parse(SHARP_RECTANGLE).unwrap();
    let blended: Vec<bool> = program.moves.iter().map(|m| m.blended).collect();
    assert_eq!(
        blended,
        [false, true, false, true, false, true, false, true]
    );
    let p = program.tool_path().unwrap();
    // A right angle's blend leaves the corner by r (√2 − 1): r = 0.1 mm / (√2 − 1); the path
    // is the rectangle's rounded polygon of that radius, starting where the closing corner's
    // blend ends.
    let r = 0.1e-3 / (2f64.sqrt() - 1.0);
    let corners =
        [[0.0, 0.0], [0.04, 0.0], [0.04, 0.02], [0.0, 0.02]].map(|[x, y]| Vector3::new(x, y, 0.0));
    let polygon = ToolPath::rounded_polygon(&corners, r).unwrap();
    assert!((p.length() - polygon.length()).abs() < 1e-15);
    assert!(farthest(&p, &polygon, 4000) < 1e-15);
    assert!(farthest(&polygon, &p, 4000) < 1e-15);
    assert!((p.point(0.0) - Vector3::new(r, 0.0, 0.0)).norm() < 1e-15);
    for c in &corners {
        let d = p.closest(c).distance;
        assert!(
            (d - 0.1e-3).abs() < 1e-12,
            "the corner {c:?} is {d} m off the path"
        );
    }
    assert!(largest_kink(&p) < 1e-6, "{}", largest_kink(&p));
    // The blend's feed is the lower of its two moves': 600 and 300 mm/min at the second
    // corner, 600 where the program has one feed.
    let feeds: Vec<f64> = program
        .moves
        .iter()
        .map(|m| m.feed.unwrap() * 6e4)
        .collect();
    let expected = [600.0, 600.0, 600.0, 300.0, 300.0, 300.0, 300.0, 300.0];
    for (f, e) in feeds.iter().zip(expected) {
        assert!((f - e).abs() < 1e-9, "{feeds:?}");
    }
    // The same program without G64 keeps its corners, kinks of 90°.
    let sharp = path(&SHARP_RECTANGLE.replace(" G64 P0.1", ""));
    assert!((largest_kink(&sharp) - PI / 2.0).abs() < 1e-6);
    assert!((sharp.length() - 0.12).abs() < 1e-15);
    // The tool's frame along the path (a lead of 0.2 rad) needs a direction that does not
    // jump: the blended program has one, the sharp one is refused at its first corner.
    let normal = Vector3::z();
    assert!(PathFrame::new(&p, normal, 0.2, 0.0).is_ok());
    let e = PathFrame::new(&sharp, normal, 0.2, 0.0).unwrap_err();
    assert!(
        e.contains("turns sharply by 90.0°") && e.contains("G64"),
        "{e}"
    );
}

#[test]
fn a_blend_takes_at_most_half_of_each_move() {
    // A tolerance far above the sides: each side is shared by two blends and taken whole, so
    // a 1 mm square becomes the circle of 0.5 mm through its sides' midpoints.
    let p = path("G64 P5\nG0 X0 Y0\nG1 X1\nG1 Y1\nG1 X0\nG1 Y0\n");
    assert!((p.length() - TAU * 0.5e-3).abs() < 1e-15, "{}", p.length());
    let centre = Vector3::new(0.5e-3, 0.5e-3, 0.0);
    for k in 0..64 {
        let x = p.point(p.length() * k as f64 / 64.0);
        assert!(((x - centre).norm() - 0.5e-3).abs() < 1e-15);
    }
    assert!(largest_kink(&p) < 1e-6);
    // A short side limits its two blends: 10 × 1 mm at P0.5, the short sides taken whole.
    let q = path("G64 P0.5\nG0 X0 Y0\nG1 X10\nG1 Y1\nG1 X0\nG1 Y0\n");
    let r = 0.5e-3; // the half side's tangent length at 90°
    assert!((q.length() - (2.0 * (10e-3 - 2.0 * r) + TAU * r)).abs() < 1e-15);
    assert!(largest_kink(&q) < 1e-6);
}

#[test]
fn g61_keeps_sharp_the_corners_after_it_and_arcs_stay_as_they_are() {
    // Blending from the first move to the third only: two corners blended (after X40 and
    // after Y20); the corners into and out of the G61 moves stay sharp.
    let program =
        PartProgram::parse("G0 X0 Y0\nG64 P0.1 G1 X40\nG1 Y20\nG1 X0\nG61 G1 Y0\n").unwrap();
    let blended = program.moves.iter().filter(|m| m.blended).count();
    assert_eq!(blended, 2);
    let p = program.tool_path().unwrap();
    assert!((largest_kink(&p) - PI / 2.0).abs() < 1e-6);
    // Nor is a G61 lens (two arcs meeting at right angles), nor a reversal (out and back along one line).
    let lens = PartProgram::parse("G61\nG0 X0 Y0\nG3 X10 Y0 I5 J5\nG3 X0 Y0 I-5 J-5\n").unwrap();
    assert!(lens.moves.iter().all(|m| !m.blended));
    assert!((largest_kink(&lens.tool_path().unwrap()) - PI / 2.0).abs() < 1e-6);
    let back = PartProgram::parse("G64 P0.1\nG0 X0 Y0\nG1 X10\nG1 X0\n").unwrap();
    assert!(back.moves.iter().all(|m| !m.blended));
}

#[test]
fn a_blended_program_is_the_same_in_inches_and_in_a_turned_plane() {
    // P in the program's units: inches with G20.
    let mm = path("G21 G64 P0.254\nG0 X0 Y0\nG1 X25.4\nG1 Y12.7\nG1 X0\nG1 Y0\n");
    let inch = path("G20 G64 P0.01\nG0 X0 Y0\nG1 X1\nG1 Y0.5\nG1 X0\nG1 Y0\n");
    assert!((mm.length() - inch.length()).abs() < 1e-15);
    assert!(farthest(&mm, &inch, 2000) < 1e-15);
    // In the ZX plane (G18) the blends turn about Y, the path the XY one's turned.
    let zx = path("G18 G64 P0.254\nG0 Z0 X0\nG1 Z25.4\nG1 X12.7\nG1 Z0\nG1 X0\n");
    assert!((zx.length() - mm.length()).abs() < 1e-15);
    assert!(largest_kink(&zx) < 1e-6);
}

/// The distance from `x` to the path `p`.
fn off(p: &ToolPath, x: Vector3<f64>) -> f64 {
    p.closest(&x).distance
}

/// Checks the blended `program` of the sharp `text`: no kink at any piece's start, each of
/// `corners` left by `tolerance` (the largest fillet within it, to 0.1 %), and every point of
/// either path within the tolerance of the other.
fn blended_within(program: &PartProgram, text: &str, corners: &[Vector3<f64>], tolerance: f64) {
    let blended = program.tool_path().unwrap();
    let sharp = path(text);
    assert!(
        largest_kink(&blended) < 1e-6,
        "{text}: {}",
        largest_kink(&blended)
    );
    for (i, c) in corners.iter().enumerate() {
        let d = off(&blended, *c);
        assert!(
            d <= tolerance * (1.0 + 1e-9) && d >= 0.999 * tolerance,
            "{text}: corner {i} left by {d:e}"
        );
    }
    assert!(farthest(&blended, &sharp, 4000) <= tolerance * (1.0 + 1e-9));
    assert!(farthest(&sharp, &blended, 4000) <= tolerance * (1.0 + 1e-9));
}

/// Corners where a line meets an arc, of both senses: the fillet tangent to both, leaving the
/// corner by the tolerance (the largest within it), the rest of the path where it was.
#[test]
fn g64_blends_a_line_into_an_arc_by_the_fillet_tangent_to_both() {
    let mm = |x: f64, y: f64| Vector3::new(x, y, 0.0) * 1e-3;
    let tolerance = 0.1e-3;
    // A half disc: the line along its diameter, the arc turning the corner's way (the fillet
    // inside the circle), at both ends.
    let disc = "G0 X-10 Y0\nG1 X10\nG3 X-10 Y0 I-10 J0\n";
    // A plate with a round notch in its lower side: the arc turns against the corners (the
    // fillets outside its circle), then four straight corners.
    let notch = "G0 X0 Y0\nG1 X10\nG3 X30 Y0 I10 J0\nG1 X40\nG1 Y20\nG1 X0\nG1 Y0\n";
    for (text, corners) in [
        (disc, vec![mm(10.0, 0.0), mm(-10.0, 0.0)]),
        (
            notch,
            vec![
                mm(10.0, 0.0),
                mm(30.0, 0.0),
                mm(40.0, 0.0),
                mm(40.0, 20.0),
                mm(0.0, 20.0),
                mm(0.0, 0.0),
            ],
        ),
    ] {
        let program = PartProgram::parse(&format!("G64 P0.1\n{text}")).unwrap();
        assert_eq!(
            program.moves.iter().filter(|m| m.blended).count(),
            corners.len(),
            "{text}"
        );
        blended_within(&program, text, &corners, tolerance);
    }
    // The fillet's ends are on the moves it joins: on the half disc, the fillet into the arc
    // touches the circle of radius 10 mm about the origin.
    let program = PartProgram::parse(&format!("G64 P0.1\n{disc}")).unwrap();
    let mut at = program.start;
    for m in &program.moves {
        let to = match m.segment {
            pvfc_control::model::tool_path::Segment::Line { to }
            | pvfc_control::model::tool_path::Segment::Arc { to, .. } => to,
        };
        if m.blended {
            // One end on the diameter (y = 0), the other on the circle.
            let (on_line, on_circle) = if at[1].abs() < 1e-15 {
                (at, to)
            } else {
                (to, at)
            };
            assert!(on_line[1].abs() < 1e-15, "{on_line}");
            assert!((on_circle.norm() - 10e-3).abs() < 1e-15, "{on_circle}");
        }
        at = to;
    }
}

/// Corners where two arcs meet: a lens (both arcs turning the corners' way: the fillet inside
/// both circles) and a scalloped edge (a convex arc into a concave one and back: inside one
/// circle, outside the other). The fillet tangent to both, leaving each corner by the
/// tolerance, its ends on the two circles.
#[test]
fn g64_blends_an_arc_into_an_arc_by_the_fillet_tangent_to_both() {
    let mm = |x: f64, y: f64| Vector3::new(x, y, 0.0) * 1e-3;
    let tolerance = 0.1e-3;
    // The lens: arcs of radius 5√2 mm about (5, ±5) mm, meeting at right angles.
    let lens = "G0 X0 Y0\nG3 X10 Y0 I5 J5\nG3 X0 Y0 I-5 J-5\n";
    // A plate whose top edge is a bump (G3, a half circle of 5 mm about (25, 20) mm) then a dip
    // (G2, a quarter circle of 5√2 mm about (15, 25) mm), meeting at 45° at (20, 20) mm: the
    // fillet outside the bump's circle and inside the dip's.
    let scallops = "G0 X0 Y0\nG1 X30\nG1 Y20\nG3 X20 Y20 I-5 J0\nG2 X10 Y20 I-5 J5\nG1 X0\nG1 Y0\n";
    for (text, corners, circles) in [
        (
            lens,
            vec![mm(10.0, 0.0), mm(0.0, 0.0)],
            vec![
                (mm(5.0, 5.0), 50f64.sqrt() * 1e-3),
                (mm(5.0, -5.0), 50f64.sqrt() * 1e-3),
            ],
        ),
        (
            scallops,
            vec![mm(20.0, 20.0)],
            vec![
                (mm(25.0, 20.0), 5e-3),
                (mm(15.0, 25.0), 50f64.sqrt() * 1e-3),
            ],
        ),
    ] {
        let program = PartProgram::parse(&format!("G64 P0.1\n{text}")).unwrap();
        blended_within(&program, text, &corners, tolerance);
        // Each arc–arc fillet's ends lie on two of the program's circles.
        let on_circle = |x: Vector3<f64>| {
            circles
                .iter()
                .map(|(c, r)| ((x - c).norm() - r).abs())
                .fold(f64::INFINITY, f64::min)
        };
        let mut at = program.start;
        let mut arc_arc = 0;
        for m in &program.moves {
            let to = match m.segment {
                pvfc_control::model::tool_path::Segment::Line { to }
                | pvfc_control::model::tool_path::Segment::Arc { to, .. } => to,
            };
            if m.blended && on_circle(at) < 1e-15 && on_circle(to) < 1e-15 {
                arc_arc += 1;
            }
            at = to;
        }
        assert_eq!(arc_arc, corners.len(), "{text}: arc–arc fillets");
    }
}
