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
//! - Accepted and without effect on the path: comments, line numbers (N), tool changes (T),
//!   spindle speeds (S), M0–M9 and M30, G40, G49, G54, G80, G94. Any other word is an error.

use nalgebra::{Unit, Vector3};

use super::tool_path::{Segment, ToolPath};

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
    /// The line it is on (1-based).
    pub line: usize,
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
                words.argument(w.letter, &w.value, w.span, source, &lines)?;
            }
            // Modal settings first (a block may set the units and move).
            state.apply(&words);
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
                    });
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
                    });
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
            (40 | 49 | 54 | 80 | 94, 0) => {}
            _ => {
                return Err(lines.error(at, format!("G{}: not supported", show(g.number))));
            }
        }
        for a in &g.args {
            self.argument(a.letter, &a.value, a.span, lines.source, lines)?;
        }
        Ok(())
    }

    fn argument(
        &mut self,
        letter: char,
        value: &gcode::Value,
        span: gcode::core::Span,
        source: &str,
        lines: &LineStarts<'_>,
    ) -> Result<(), ProgramError> {
        let at = span.start;
        let letter = letter.to_ascii_uppercase();
        // The literal's own digits in f64 (the parser keeps an f32: 0.1 µm on a 1 m part).
        let number = match value {
            gcode::Value::Literal(x) => source
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
            'S' | 'T' | 'P' | 'N' => return Ok(()),
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
