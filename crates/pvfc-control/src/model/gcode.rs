//! A part program (G-code) read into a closed tool path: its cutting moves (G1 lines, G2/G3
//! arcs in the XY, ZX or YZ plane, with centres by I/J/K or by R) as the path's exact pieces,
//! with each move's feed. The text is parsed by the `gcode` crate; this module gives the
//! words their meaning (modal state: motion, plane, units, absolute or incremental
//! coordinates and arc centres, feed) and refuses what it does not support with the line and
//! column of the word.
//!
//! The rules, for a periodic contour:
//! - The contour is the program's cutting moves (G1, G2, G3), from the first to the last.
//!   Rapid moves (G0) before the first cutting move only place the tool (the contour starts
//!   where they leave it, or at the origin), and rapid moves after the last are ignored (a
//!   retract); a rapid move between cutting moves is an error (the contour would jump).
//! - The last cutting move must end where the first began (within 2 µm, or 0.1 % of an
//!   arc's radius for its centre): a contour is closed.
//! - Units: millimetres (G21, the default) or inches (G20); coordinates absolute (G90, the
//!   default) or incremental (G91); arc centres incremental from the arc's start (G91.1, the
//!   default) or absolute (G90.1). A feed F is in units per minute (G94) and holds until
//!   changed.
//! - Helical arcs (an arc that also moves along its plane's normal) are refused.
//! - Corners: `G64 P<tolerance>` blends, from its block on, each corner where two moves
//!   (straight or arcs) meet at an angle by the circular arc (tangent to both) that leaves the
//!   corner by at most the tolerance, taking at most half of either move (so that blends never
//!   overlap); G61 (and G61.1) keeps the corners sharp again (the default). A corner is blended
//!   when both its moves were read in G64; with two tolerances, by the smaller. The blend is a
//!   cutting move of its own ([`ProgramMove::blended`]) at the lower of its two moves' feeds.
//!   Between two lines the blend is the largest arc within the tolerance; between a line and
//!   an arc or between two arcs (in the arcs' plane), the fillet of the largest radius within
//!   it. Corners where a move leaves an arc's plane are kept as they are, as are reversals and
//!   turns below 1e-4 rad.
//! - Accepted and without effect on the path: comments, line numbers (N), tool changes (T),
//!   spindle speeds (S), M0–M9 and M30, G40, G49, G54, G80, G94. Any other word is an error,
//!   and so is a P anywhere but after G64.

use nalgebra::{Unit, Vector3};

use super::tool_path::{arc_sweep, corner_arc, Segment, ToolPath};

/// How far (m) an arc's end may be off its radius, and the last move off the first's start.
pub const PROGRAM_TOLERANCE: f64 = 2e-6;

/// What is wrong with a part program, and where (1-based line and column of the word).
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramError {
    /// The line (1-based).
    pub line: usize,
    /// The column of the word (1-based, in characters).
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

/// One cutting move of a part program.
#[derive(Clone, Debug, PartialEq)]
pub struct ProgramMove {
    /// Its geometry (m, in the program's frame).
    pub segment: Segment,
    /// The feed in force (m/s), if the program set one.
    pub feed: Option<f64>,
    /// The line it is on (1-based); a blend's is its second move's.
    pub line: usize,
    /// A corner's blend (G64) inserted before the move on `line`, not a move of the program.
    pub blended: bool,
}

/// A part program's cutting moves, from where the first begins.
#[derive(Clone, Debug, PartialEq)]
pub struct PartProgram {
    /// Where the first cutting move begins (m).
    pub start: Vector3<f64>,
    /// The cutting moves in order.
    pub moves: Vec<ProgramMove>,
}

impl PartProgram {
    /// Reads a part program's text.
    pub fn parse(source: &str) -> Result<PartProgram, ProgramError> {
        let lines = LineStarts::new(source);
        if let Some((offset, letter)) = oversized_code(source) {
            return Err(lines.error(
                offset,
                format!("{letter}: a code number this large is not G-code"),
            ));
        }
        let program = gcode::parse(source).map_err(|d| {
            let first = d.iter().next();
            let (line, column) = first.map_or((1, 1), |d| lines.at(d.span.start));
            ProgramError {
                line,
                column,
                message: first.map_or("not G-code".into(), |d| d.kind.to_string()),
            }
        })?;
        let mut state = Modal::default();
        let mut moves = Vec::new();
        // Per move, the blending tolerance in force (m; G64 P).
        let mut tolerances = Vec::new();
        let mut start = None;
        let mut after_last_cut = false;
        for block in &program.blocks {
            let mut words = Words::default();
            for code in &block.codes {
                match code {
                    gcode::Code::General(g) => words.general(g, &lines)?,
                    gcode::Code::Miscellaneous(m) => {
                        let n = number(m.number);
                        if !(matches!(n, (0..=9, 0) | (30, 0))) {
                            return Err(lines.error(
                                m.span.start,
                                format!("M{}: not supported", show(m.number)),
                            ));
                        }
                        // An M-code's own words (none used) are not coordinates.
                    }
                    gcode::Code::ToolChange(_) => {}
                    _ => {
                        return Err(lines.error(block.span.start, "an unknown kind of word".into()))
                    }
                }
            }
            for w in &block.word_addresses {
                words.argument(w.letter, &w.value, w.span, &lines)?;
            }
            // Modal settings first (a block may set the units and move).
            state.apply(&words);
            if let Some((true, at)) = words.blending {
                // P in the block's units (a block may set G20/G21 and G64 together).
                match words.tolerance {
                    Some(p) if p > 0.0 => state.blend = Some(p * state.unit),
                    Some(p) => {
                        return Err(lines.error(at, format!("G64 P{p}: the tolerance must be > 0")))
                    }
                    None => {
                        return Err(lines.error(at, "G64 needs P, the distance the path may leave a corner by when it blends it".into()))
                    }
                }
            }
            let Some(motion) =
                words
                    .motion
                    .map(|(m, _)| m)
                    .or(if words.has_axes() { state.motion } else { None })
            else {
                if words.has_axes() || words.has_centre() {
                    return Err(lines.error(
                        block.span.start,
                        "coordinates without a motion mode (G0, G1, G2 or G3)".into(),
                    ));
                }
                continue;
            };
            state.motion = Some(motion);
            let at = words.first_span.unwrap_or(block.span.start);
            let from = state.position;
            let to = state.target(&words);
            let line = lines.at(at).0;
            match motion {
                Motion::Rapid => {
                    if !moves.is_empty() {
                        after_last_cut = true;
                    }
                    state.position = to;
                    continue;
                }
                _ if after_last_cut => {
                    return Err(lines.error(at, "a rapid move (G0) between cutting moves: the contour would jump (rapid moves may only precede the first cut or follow the last)".into()));
                }
                Motion::Line => {
                    if words.has_centre() {
                        return Err(lines.error(at, "I, J, K or R on a straight move".into()));
                    }
                    start.get_or_insert(from);
                    moves.push(ProgramMove {
                        segment: Segment::Line { to },
                        feed: state.feed,
                        line,
                        blended: false,
                    });
                    tolerances.push(state.blend);
                }
                Motion::Clockwise | Motion::CounterClockwise => {
                    let (center, axis) = state
                        .arc(&words, from, to, motion)
                        .map_err(|m| lines.error(at, m))?;
                    start.get_or_insert(from);
                    moves.push(ProgramMove {
                        segment: Segment::Arc { to, center, axis },
                        feed: state.feed,
                        line,
                        blended: false,
                    });
                    tolerances.push(state.blend);
                }
            }
            state.position = to;
        }
        let Some(start) = start else {
            return Err(ProgramError {
                line: 1,
                column: 1,
                message: "no cutting move (G1, G2 or G3)".into(),
            });
        };
        let (start, moves) = blend_corners(start, moves, &tolerances);
        Ok(PartProgram { start, moves })
    }

    /// The closed tool path of the cutting moves; an error names the move's line.
    pub fn tool_path(&self) -> Result<ToolPath, ProgramError> {
        let segments: Vec<Segment> = self.moves.iter().map(|m| m.segment).collect();
        ToolPath::from_segments(self.start, &segments, PROGRAM_TOLERANCE).map_err(|e| {
            ProgramError {
                line: self.moves.get(e.index).map_or(1, |m| m.line),
                column: 1,
                message: e.what,
            }
        })
    }
}

/// A turn below this (rad) is left as it is (a blend of it would have a radius of thousands of
/// its tangent lengths, and no tool feels it); within 1e-6 of π, a reversal (not blended).
const STRAIGHT: f64 = 1e-4;

/// What a move is near a corner: a straight move (its unit direction and length) or an arc
/// (its circle, the axis it turns about and its sweep).
#[derive(Clone, Copy, Debug)]
enum Near {
    Line {
        dir: Vector3<f64>,
        length: f64,
    },
    Arc {
        center: Vector3<f64>,
        radius: f64,
        axis: Unit<Vector3<f64>>,
        sweep: f64,
    },
}

impl Near {
    /// The move from `from` along `segment`, or `None` for a move of no length.
    fn of(from: Vector3<f64>, segment: &Segment) -> Option<Near> {
        match *segment {
            Segment::Line { to } => {
                let d = to - from;
                let length = d.norm();
                (length > 0.0).then(|| Near::Line {
                    dir: d / length,
                    length,
                })
            }
            Segment::Arc { to, center, axis } => {
                let (s, e) = (from - center, to - center);
                let radius = s.norm();
                let sweep = arc_sweep(s, e, &axis, (to - from).norm() <= PROGRAM_TOLERANCE);
                (radius > 0.0).then_some(Near::Arc {
                    center,
                    radius,
                    axis,
                    sweep,
                })
            }
        }
    }

    /// The unit tangent at `x` (a point of the move), in the direction of travel.
    fn tangent(&self, x: Vector3<f64>) -> Vector3<f64> {
        match *self {
            Near::Line { dir, .. } => dir,
            Near::Arc { center, axis, .. } => axis.cross(&(x - center)).normalize(),
        }
    }

    /// The same move travelled backwards (its sweep and length unchanged).
    fn reversed(self) -> Near {
        match self {
            Near::Line { dir, length } => Near::Line { dir: -dir, length },
            Near::Arc {
                center,
                radius,
                axis,
                sweep,
            } => Near::Arc {
                center,
                radius,
                axis: -axis,
                sweep,
            },
        }
    }
}

/// A corner's blend: where it leaves the move into the corner, where it joins the move out of
/// it, the arc between, and how much of each move it takes (a length, or an arc's angle).
#[derive(Clone, Debug)]
struct Blend {
    leaves: Vector3<f64>,
    joins: Vector3<f64>,
    arc: Segment,
    taken_in: f64,
    taken_out: f64,
}

/// The blend at corner `here` from the straight move `line` (its direction `a`, into the
/// corner) to the arc `circle` (out of it), turning about `n` (unit, `a × b` of the corner's
/// tangents), of radius `rho`: the fillet's centre is `rho` from the line, on the inside of the
/// turn, and `R ∓ rho` from the circle's centre (inside the circle where the arc turns the same
/// way as the corner). `None` where no such fillet touches both moves within half of each, or
/// where it leaves the corner by more than `tolerance`.
fn line_to_arc(
    here: Vector3<f64>,
    line: (Vector3<f64>, f64),
    circle: (Vector3<f64>, f64, Unit<Vector3<f64>>, f64),
    n: Unit<Vector3<f64>>,
    rho: f64,
    tolerance: f64,
) -> Option<Blend> {
    let ((a, length), (c, radius, axis, sweep)) = (line, circle);
    let inward = n.cross(&a);
    let reach = radius - axis.dot(&n).signum() * rho;
    if reach <= 0.0 {
        return None;
    }
    // The fillet's centre P + s a + ρ (n × a), |it − c| = R ∓ ρ: the root nearest the corner,
    // which must be before it (s ≤ 0).
    let d0 = here + inward * rho - c;
    let half_b = a.dot(&d0);
    let disc = half_b * half_b - d0.norm_squared() + reach * reach;
    if disc < 0.0 {
        return None;
    }
    let (s1, s2) = (-half_b + disc.sqrt(), -half_b - disc.sqrt());
    let s = if s1.abs() <= s2.abs() { s1 } else { s2 };
    if !(s <= 1e-15 && -s <= 0.5 * length) {
        return None;
    }
    let leaves = here + a * s;
    let center = leaves + inward * rho;
    let out = (center - c).normalize();
    let joins = c + out * radius;
    // The arc's angle from the corner to where the fillet joins it, within half its sweep.
    let taken = arc_angle(c, &axis, here, joins);
    if !within_half(taken, sweep) {
        return None;
    }
    fillet(
        here,
        (leaves, joins),
        (center, rho, n),
        tolerance,
        (-s, taken),
    )
}

/// The angle about `axis` from `from` to `to`, both on a circle about `c`.
fn arc_angle(
    c: Vector3<f64>,
    axis: &Unit<Vector3<f64>>,
    from: Vector3<f64>,
    to: Vector3<f64>,
) -> f64 {
    let (p0, p1) = ((from - c).normalize(), (to - c).normalize());
    p0.cross(&p1).dot(axis).atan2(p0.dot(&p1))
}

/// Whether an arc's angle `taken` to a fillet's end is within half of its `sweep`.
fn within_half(taken: f64, sweep: f64) -> bool {
    taken >= -1e-12 && taken <= 0.5 * sweep
}

/// The blend of corner `here` by the fillet (centre, radius `rho`, axis `n`) from `leaves` to
/// `joins`, taking `taken` of the two moves; `None` if it leaves the corner by more than
/// `tolerance`.
fn fillet(
    here: Vector3<f64>,
    (leaves, joins): (Vector3<f64>, Vector3<f64>),
    (center, rho, n): (Vector3<f64>, f64, Unit<Vector3<f64>>),
    tolerance: f64,
    (taken_in, taken_out): (f64, f64),
) -> Option<Blend> {
    if (here - center).norm() - rho > tolerance {
        return None;
    }
    Some(Blend {
        leaves,
        joins,
        arc: Segment::Arc {
            to: joins,
            center,
            axis: n,
        },
        taken_in: taken_in.max(0.0),
        taken_out: taken_out.max(0.0),
    })
}

/// The blend at corner `here` from move `into` to move `out` (see the [module](self)): the
/// arc tangent to both that leaves the corner by at most `tolerance`, taking at most half of
/// either move; `None` for a turn below [`STRAIGHT`], a reversal, or an arc whose plane is not
/// the corner's.
fn blend(here: Vector3<f64>, into: Near, out: Near, tolerance: f64) -> Option<Blend> {
    let (a, b) = (into.tangent(here), out.tangent(here));
    let turn = a.dot(&b).clamp(-1.0, 1.0).acos();
    if !(STRAIGHT..=std::f64::consts::PI - 1e-6).contains(&turn) {
        return None;
    }
    let n = Unit::new_normalize(a.cross(&b));
    let in_plane = |near: &Near| match near {
        Near::Line { .. } => true,
        Near::Arc { axis, .. } => (axis.dot(&n).abs() - 1.0).abs() <= 1e-9,
    };
    if !(in_plane(&into) && in_plane(&out)) {
        return None;
    }
    let half = 0.5 * turn;
    // Between two lines the arc leaves the corner by r (1/cos(θ/2) − 1); its tangents are
    // r tan(θ/2) long.
    let radius = tolerance / (1.0 / half.cos() - 1.0);
    match (into, out) {
        (Near::Line { length: la, .. }, Near::Line { length: lb, .. }) => {
            let tangent = (radius * half.tan()).min(0.5 * la.min(lb));
            let (center, axis) = corner_arc(here, a, b, turn, tangent);
            let joins = here + b * tangent;
            (center.iter().all(|x| x.is_finite()) && tangent > 0.0).then_some(Blend {
                leaves: here - a * tangent,
                joins,
                arc: Segment::Arc {
                    to: joins,
                    center,
                    axis,
                },
                taken_in: tangent,
                taken_out: tangent,
            })
        }
        (Near::Line { .. }, Near::Arc { .. }) => {
            line_into_arc(here, into, out, n, radius, tolerance)
        }
        (Near::Arc { .. }, Near::Line { .. }) => {
            // The same corner travelled backwards: a line into an arc.
            let b = line_into_arc(here, out.reversed(), into.reversed(), -n, radius, tolerance)?;
            let Segment::Arc { center, .. } = b.arc else {
                return None;
            };
            Some(Blend {
                leaves: b.joins,
                joins: b.leaves,
                arc: Segment::Arc {
                    to: b.leaves,
                    center,
                    axis: n,
                },
                taken_in: b.taken_out,
                taken_out: b.taken_in,
            })
        }
        (
            Near::Arc {
                center: c1,
                radius: r1,
                axis: a1,
                sweep: s1,
            },
            Near::Arc {
                center: c2,
                radius: r2,
                axis: a2,
                sweep: s2,
            },
        ) => largest(radius, |rho| {
            arc_to_arc(here, (c1, r1, a1, s1), (c2, r2, a2, s2), n, rho, tolerance)
        }),
    }
}

/// The blend at corner `here` from the arc `into` to the arc `out` (each its circle's centre,
/// radius, axis and sweep), turning about `n`, of radius `rho`: the fillet's centre is
/// `R₁ ∓ rho` from the first circle's centre and `R₂ ∓ rho` from the second's (inside a circle
/// where its arc turns the corner's way, outside where it turns against it), the one of the
/// two such points nearest the corner. `None` where no such fillet touches both arcs within
/// half of each, or where it leaves the corner by more than `tolerance`.
fn arc_to_arc(
    here: Vector3<f64>,
    into: (Vector3<f64>, f64, Unit<Vector3<f64>>, f64),
    out: (Vector3<f64>, f64, Unit<Vector3<f64>>, f64),
    n: Unit<Vector3<f64>>,
    rho: f64,
    tolerance: f64,
) -> Option<Blend> {
    let ((c1, r1, a1, s1), (c2, r2, a2, s2)) = (into, out);
    let reach1 = r1 - a1.dot(&n).signum() * rho;
    let reach2 = r2 - a2.dot(&n).signum() * rho;
    if reach1 <= 0.0 || reach2 <= 0.0 {
        return None;
    }
    // The two circles of the fillet's possible centres meet where the chord between them
    // crosses the line of centres, `along` from c₁, at `±h` across it (in the corner's plane).
    let d = c2 - c1;
    let distance = d.norm();
    if distance <= 1e-12 * (r1 + r2) {
        return None;
    }
    let e = d / distance;
    let along = (reach1 * reach1 - reach2 * reach2 + distance * distance) / (2.0 * distance);
    let h2 = reach1 * reach1 - along * along;
    if h2 < 0.0 {
        return None;
    }
    let (base, across) = (c1 + e * along, n.cross(&e) * h2.sqrt());
    let (f1, f2) = (base + across, base - across);
    let center = if (f1 - here).norm() <= (f2 - here).norm() {
        f1
    } else {
        f2
    };
    let leaves = c1 + (center - c1).normalize() * r1;
    let joins = c2 + (center - c2).normalize() * r2;
    // Each arc's angle between the corner and the fillet's end, within half its sweep: the
    // first's from where the fillet leaves it to the corner, the second's from the corner on.
    let taken_in = arc_angle(c1, &a1, leaves, here);
    let taken_out = arc_angle(c2, &a2, here, joins);
    if !(within_half(taken_in, s1) && within_half(taken_out, s2)) {
        return None;
    }
    fillet(
        here,
        (leaves, joins),
        (center, rho, n),
        tolerance,
        (taken_in, taken_out),
    )
}

/// The largest fillet ([`line_to_arc`]) at `here` from the straight move `line` into the arc
/// `arc`, turning about `n`; `radius` is the straight corner's (see [`largest`]).
fn line_into_arc(
    here: Vector3<f64>,
    line: Near,
    arc: Near,
    n: Unit<Vector3<f64>>,
    radius: f64,
    tolerance: f64,
) -> Option<Blend> {
    let (
        Near::Line { dir, length },
        Near::Arc {
            center,
            radius: r,
            axis,
            sweep,
        },
    ) = (line, arc)
    else {
        return None;
    };
    largest(radius, |rho| {
        line_to_arc(
            here,
            (dir, length),
            (center, r, axis, sweep),
            n,
            rho,
            tolerance,
        )
    })
}

/// The fillet of the largest radius that `fillet` accepts, by bisection from twice the
/// straight corners' `radius` down (the curvature of an arc moves it by less than that).
fn largest(radius: f64, fillet: impl Fn(f64) -> Option<Blend>) -> Option<Blend> {
    let (mut lo, mut hi) = (0.0, 2.0 * radius);
    if let Some(b) = fillet(hi) {
        return Some(b);
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if fillet(mid).is_some() {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    if lo > 0.0 {
        fillet(lo)
    } else {
        None
    }
}

/// The program's moves with each corner read in G64 blended by an arc (see the
/// [module](self)): `tolerances[j]` is the tolerance in force at move `j`. The closing corner
/// (the last move into the first) counts as a corner too; when it is blended, the contour
/// starts where its blend ends.
fn blend_corners(
    start: Vector3<f64>,
    moves: Vec<ProgramMove>,
    tolerances: &[Option<f64>],
) -> (Vector3<f64>, Vec<ProgramMove>) {
    let n = moves.len();
    if n < 2 || tolerances.iter().all(Option::is_none) {
        return (start, moves);
    }
    let end = |j: usize| match moves[j].segment {
        Segment::Line { to } | Segment::Arc { to, .. } => to,
    };
    let from = |j: usize| if j == 0 { start } else { end(j - 1) };
    let near = |j: usize| Near::of(from(j), &moves[j].segment);
    // The blend at the end of move j (into move j + 1).
    let corner = |j: usize| -> Option<Blend> {
        let k = (j + 1) % n;
        let tolerance = tolerances[j]?.min(tolerances[k]?);
        blend(end(j), near(j)?, near(k)?, tolerance)
    };
    let corners: Vec<Option<Blend>> = (0..n).map(corner).collect();
    let feed = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, y) => y.or(x),
    };
    let mut out = Vec::with_capacity(2 * n);
    for (j, m) in moves.iter().enumerate() {
        let mut m = m.clone();
        let before = &corners[(j + n - 1) % n];
        if let Some(b) = &corners[j] {
            // The move stops where its corner's blend leaves it.
            m.segment = match m.segment {
                Segment::Line { .. } => Segment::Line { to: b.leaves },
                Segment::Arc { center, axis, .. } => Segment::Arc {
                    to: b.leaves,
                    center,
                    axis,
                },
            };
        }
        // A move that its two blends take whole (each half of it) is left out.
        let taken = before.as_ref().map_or(0.0, |b| b.taken_out)
            + corners[j].as_ref().map_or(0.0, |b| b.taken_in);
        let whole = match near(j) {
            Some(Near::Line { length, .. }) => length - taken <= PROGRAM_TOLERANCE,
            Some(Near::Arc { sweep, radius, .. }) => (sweep - taken) * radius <= PROGRAM_TOLERANCE,
            None => false,
        };
        if !whole {
            out.push(m);
        }
        if let Some(b) = &corners[j] {
            let k = (j + 1) % n;
            out.push(ProgramMove {
                segment: b.arc,
                feed: feed(moves[j].feed, moves[k].feed),
                line: moves[k].line,
                blended: true,
            });
        }
    }
    // With the closing corner blended, the contour starts where that blend ends.
    let start = corners[n - 1].as_ref().map_or(start, |b| b.joins);
    if let (
        Some(Blend {
            arc: Segment::Arc { center, axis, .. },
            ..
        }),
        Some(last),
    ) = (&corners[n - 1], out.last_mut())
    {
        // The blend closes the contour exactly where it starts.
        last.segment = Segment::Arc {
            to: start,
            center: *center,
            axis: *axis,
        };
    }
    (start, out)
}

/// Byte offsets where each line starts, for line and column numbers.
struct LineStarts<'a> {
    source: &'a str,
    starts: Vec<usize>,
}

impl<'a> LineStarts<'a> {
    fn new(source: &'a str) -> Self {
        let starts = std::iter::once(0)
            .chain(source.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        LineStarts { source, starts }
    }

    /// The 1-based line and column (in characters) of byte `offset`.
    fn at(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.source.len());
        let line = self.starts.partition_point(|&s| s <= offset).max(1);
        let begin = self.starts[line - 1];
        let column = self
            .source
            .get(begin..offset)
            .map_or(0, |s| s.chars().count());
        (line, column + 1)
    }

    fn error(&self, offset: usize, message: String) -> ProgramError {
        let (line, column) = self.at(offset);
        ProgramError {
            line,
            column,
            message,
        }
    }
}

/// The first G, M or T word whose number is too large for the parser (gcode 0.7 multiplies
/// it by 10 in a `u32`: from 429,496,730 it overflows, a panic in a debug build and another
/// code in a release build), outside comments: its offset and letter.
fn oversized_code(source: &str) -> Option<(usize, char)> {
    let bytes = source.as_bytes();
    let (mut i, mut in_paren) = (0, false);
    while i < bytes.len() {
        let b = bytes[i];
        match b {
            b'(' => in_paren = true,
            b')' => in_paren = false,
            b'\n' => in_paren = false,
            b';' if !in_paren => {
                // A comment to the end of the line.
                while i < bytes.len() && bytes[i] != b'\n' {
                    i += 1;
                }
                continue;
            }
            b'G' | b'g' | b'M' | b'm' | b'T' | b't' if !in_paren => {
                let mut j = i + 1;
                // The gcode crate's lexer skips spaces, tabs and carriage returns between a
                // letter and its number.
                while j < bytes.len() && matches!(bytes[j], b' ' | b'\t' | b'\r') {
                    j += 1;
                }
                let digits = bytes[j..].iter().take_while(|c| c.is_ascii_digit());
                let mut value: u64 = 0;
                for &d in digits {
                    value = value.saturating_mul(10).saturating_add(u64::from(d - b'0'));
                }
                if value >= 100_000_000 {
                    return Some((i, char::from(b).to_ascii_uppercase()));
                }
            }
            _ => {}
        }
        i += 1;
    }
    None
}

/// A G- or M-code's number as (major, minor): G91.1 is (91, 1).
fn number(n: gcode::core::Number) -> (u32, u32) {
    (n.major(), n.minor().map_or(0, |m| m.get()))
}

fn show(n: gcode::core::Number) -> String {
    match number(n) {
        (major, 0) => major.to_string(),
        (major, minor) => format!("{major}.{minor}"),
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Motion {
    Rapid,
    Line,
    Clockwise,
    CounterClockwise,
}

/// The words of one block, as numbers (in the program's units).
#[derive(Default)]
struct Words {
    motion: Option<(Motion, usize)>,
    plane: Option<usize>,
    inches: Option<bool>,
    incremental: Option<bool>,
    incremental_centres: Option<bool>,
    /// X, Y, Z.
    axes: [Option<f64>; 3],
    /// I, J, K.
    centre: [Option<f64>; 3],
    radius: Option<f64>,
    feed: Option<f64>,
    /// G64 (true) or G61 (false), and where.
    blending: Option<(bool, usize)>,
    /// G64's P.
    tolerance: Option<f64>,
    first_span: Option<usize>,
}

impl Words {
    fn has_axes(&self) -> bool {
        self.axes.iter().any(Option::is_some)
    }

    fn has_centre(&self) -> bool {
        self.centre.iter().any(Option::is_some) || self.radius.is_some()
    }

    fn general(
        &mut self,
        g: &gcode::GeneralCode,
        lines: &LineStarts<'_>,
    ) -> Result<(), ProgramError> {
        let at = g.span.start;
        self.first_span.get_or_insert(at);
        let set_motion = |words: &mut Words, m: Motion| match words.motion {
            Some(_) => Err(lines.error(at, "two motion codes in one block".into())),
            None => {
                words.motion = Some((m, at));
                Ok(())
            }
        };
        match number(g.number) {
            (0, 0) => set_motion(self, Motion::Rapid)?,
            (1, 0) => set_motion(self, Motion::Line)?,
            (2, 0) => set_motion(self, Motion::Clockwise)?,
            (3, 0) => set_motion(self, Motion::CounterClockwise)?,
            (17, 0) => self.plane = Some(2),
            (18, 0) => self.plane = Some(1),
            (19, 0) => self.plane = Some(0),
            (20, 0) => self.inches = Some(true),
            (21, 0) => self.inches = Some(false),
            (90, 0) => self.incremental = Some(false),
            (91, 0) => self.incremental = Some(true),
            (90, 1) => self.incremental_centres = Some(false),
            (91, 1) => self.incremental_centres = Some(true),
            (64, 0) => self.blending = Some((true, at)),
            (61, 0 | 1) => self.blending = Some((false, at)),
            (40 | 49 | 54 | 80 | 94, 0) => {}
            _ => {
                return Err(lines.error(at, format!("G{}: not supported", show(g.number))));
            }
        }
        let blends = number(g.number) == (64, 0);
        for a in &g.args {
            if blends && a.letter.eq_ignore_ascii_case(&'P') {
                if self.tolerance.is_some() {
                    return Err(lines.error(a.span.start, "P given twice in one block".into()));
                }
                self.tolerance = Some(literal('P', &a.value, a.span, lines)?);
                continue;
            }
            self.argument(a.letter, &a.value, a.span, lines)?;
        }
        Ok(())
    }

    fn argument(
        &mut self,
        letter: char,
        value: &gcode::Value,
        span: gcode::core::Span,
        lines: &LineStarts<'_>,
    ) -> Result<(), ProgramError> {
        let at = span.start;
        let letter = letter.to_ascii_uppercase();
        let number = literal(letter, value, span, lines)?;
        if letter == 'F' && number <= 0.0 {
            return Err(lines.error(at, format!("F{number}: a feed must be > 0")));
        }
        let slot = match letter {
            'X' => &mut self.axes[0],
            'Y' => &mut self.axes[1],
            'Z' => &mut self.axes[2],
            'I' => &mut self.centre[0],
            'J' => &mut self.centre[1],
            'K' => &mut self.centre[2],
            'R' => &mut self.radius,
            'F' => &mut self.feed,
            'S' | 'T' | 'N' => return Ok(()),
            'P' => {
                return Err(lines.error(
                    at,
                    "P: only as G64's tolerance (G64 P0.05) is P supported".into(),
                ));
            }
            _ => {
                return Err(lines.error(at, format!("{letter}{number}: the word {letter} is not supported (axes X, Y, Z; arcs I, J, K, R; feed F)")));
            }
        };
        if slot.is_some() {
            return Err(lines.error(at, format!("{letter} given twice in one block")));
        }
        *slot = Some(number);
        if letter != 'F' {
            self.first_span.get_or_insert(at);
        }
        Ok(())
    }
}

/// A word's number: the literal's own digits in f64 (the parser keeps an f32: 0.1 µm on a 1 m
/// part), finite.
fn literal(
    letter: char,
    value: &gcode::Value,
    span: gcode::core::Span,
    lines: &LineStarts<'_>,
) -> Result<f64, ProgramError> {
    let at = span.start;
    let letter = letter.to_ascii_uppercase();
    let number = match value {
        gcode::Value::Literal(x) => lines
            .source
            .get(span.start..span.start + span.length)
            .and_then(|w| w.trim().get(1..))
            .and_then(|digits| digits.trim().parse::<f64>().ok())
            .unwrap_or(f64::from(*x)),
        _ => {
            return Err(lines.error(
                at,
                format!("{letter}: variables are not supported, give a number"),
            ));
        }
    };
    if !number.is_finite() {
        return Err(lines.error(at, format!("{letter}: not a finite number")));
    }
    Ok(number)
}

/// The modal state between blocks.
struct Modal {
    motion: Option<Motion>,
    /// The plane's normal axis: 2 for XY (G17), 1 for ZX (G18), 0 for YZ (G19).
    plane: usize,
    /// Metres per program unit.
    unit: f64,
    incremental: bool,
    incremental_centres: bool,
    /// m/s.
    feed: Option<f64>,
    /// The blending tolerance (m; G64 P), or sharp corners (G61, the default).
    blend: Option<f64>,
    /// m.
    position: Vector3<f64>,
}

impl Default for Modal {
    fn default() -> Self {
        Modal {
            motion: None,
            plane: 2,
            unit: 1e-3,
            incremental: false,
            incremental_centres: true,
            feed: None,
            blend: None,
            position: Vector3::zeros(),
        }
    }
}

impl Modal {
    fn apply(&mut self, w: &Words) {
        if let Some(p) = w.plane {
            self.plane = p;
        }
        if let Some(inches) = w.inches {
            self.unit = if inches { 0.0254 } else { 1e-3 };
        }
        if let Some(i) = w.incremental {
            self.incremental = i;
        }
        if let Some(i) = w.incremental_centres {
            self.incremental_centres = i;
        }
        if let Some((false, _)) = w.blending {
            self.blend = None;
        }
        if let Some(f) = w.feed {
            // Units per minute to m/s (F > 0 is checked where the word is read).
            self.feed = Some(f * self.unit / 60.0);
        }
    }

    fn target(&self, w: &Words) -> Vector3<f64> {
        let mut to = self.position;
        for k in 0..3 {
            if let Some(x) = w.axes[k] {
                to[k] = if self.incremental {
                    self.position[k] + x * self.unit
                } else {
                    x * self.unit
                };
            }
        }
        to
    }

    /// An arc's centre and the axis it turns about.
    fn arc(
        &self,
        w: &Words,
        from: Vector3<f64>,
        to: Vector3<f64>,
        motion: Motion,
    ) -> Result<(Vector3<f64>, Unit<Vector3<f64>>), String> {
        let mut normal = Vector3::zeros();
        normal[self.plane] = 1.0;
        let axis = match motion {
            Motion::CounterClockwise => Unit::new_unchecked(normal),
            _ => Unit::new_unchecked(-normal),
        };
        if w.centre[self.plane].is_some() {
            let letter = ['I', 'J', 'K'][self.plane];
            return Err(format!("{letter} is along the plane's normal: the arc's centre is in its plane (G17 XY: I, J; G18 ZX: I, K; G19 YZ: J, K)"));
        }
        let given = w.centre.iter().any(Option::is_some);
        match (given, w.radius) {
            (true, Some(_)) => Err("give the arc's centre by I, J, K or by R, not both".into()),
            (false, None) => Err("an arc needs its centre (I, J, K) or its radius (R)".into()),
            (true, None) => {
                let mut center = if self.incremental_centres {
                    from
                } else {
                    Vector3::zeros()
                };
                for k in 0..3 {
                    if k == self.plane {
                        center[k] = from[k];
                    } else if let Some(c) = w.centre[k] {
                        center[k] += c * self.unit;
                    } else if !self.incremental_centres {
                        center[k] = from[k];
                    }
                }
                Ok((center, axis))
            }
            (false, Some(r)) => {
                let r = r * self.unit;
                let mut chord = to - from;
                chord[self.plane] = 0.0;
                let d = chord.norm();
                if d == 0.0 {
                    return Err("an arc by R must end elsewhere than it starts (a full circle needs I, J, K)".into());
                }
                let half = 0.5 * d;
                if r.abs() < half * (1.0 - 1e-9) {
                    return Err(format!(
                        "R = {:.6} m is shorter than half the chord ({half:.6} m)",
                        r.abs()
                    ));
                }
                let h = (r * r - half * half).max(0.0).sqrt();
                // Left of the chord (seen from the normal) for a counter-clockwise arc of at
                // most half a turn; R < 0 asks for the longer arc, whose centre is opposite.
                let left = normal.cross(&(chord / d));
                let side = match (motion, r > 0.0) {
                    (Motion::CounterClockwise, true) | (Motion::Clockwise, false) => 1.0,
                    _ => -1.0,
                };
                let mut center = from + 0.5 * chord + left * (side * h);
                center[self.plane] = from[self.plane];
                Ok((center, axis))
            }
        }
    }
}
