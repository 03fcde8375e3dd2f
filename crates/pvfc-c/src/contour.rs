//! The contour handle: what a controller follows. A closed curve in joint space (waypoints, a
//! Lissajous curve, an ellipse) or a tool path in Cartesian space (a polygon with rounded
//! corners, a circle or ellipse, or any `[contour.cartesian]` table of a scenario file),
//! followed through its joint contour (inverse kinematics) or with the task-space field. A
//! Cartesian path's inverse kinematics is solved for the robot when a controller is made.

use crate::args::*;
use crate::status::*;
use pvfc_control::model::arm::{DynJointContour, JointContourSpec};
use pvfc_control::model::arm_field::FieldSpec;
use pvfc_control::model::cartesian::{CartesianSpec, CircleSpec, TaskSpec};
use pvfc_control::model::contour::ContourSpec;
use pvfc_control::model::feeds::FeedProfile;
use pvfc_control::model::robot::Robot;
use pvfc_control::model::tool_path::ToolPath;
use pvfc_control::model::MAX_WAYPOINTS;
use std::ffi::c_char;
use std::path::PathBuf;

/// A contour (opaque).
pub struct pvfc_contour {
    kind: Kind,
}

enum Kind {
    Joint(JointContourSpec),
    Cartesian {
        spec: Box<CartesianSpec>,
        path: ToolPath,
        base_dir: PathBuf,
    },
}

impl pvfc_contour {
    /// Whether the contour is a Cartesian tool path (its pace is the tool's speed).
    pub(crate) fn is_cartesian(&self) -> bool {
        matches!(self.kind, Kind::Cartesian { .. })
    }

    /// A part program's feeds along the path (moves without F at `fallback`), `None` for a
    /// contour without them.
    pub(crate) fn feeds(&self, fallback: Option<f64>) -> Result<Option<FeedProfile>, Failure> {
        match &self.kind {
            Kind::Joint(_) => Ok(None),
            Kind::Cartesian { spec, base_dir, .. } => Ok(spec.feeds(base_dir, fallback)?),
        }
    }

    /// The joint contour and the field `robot` follows it with (a Cartesian path's inverse
    /// kinematics solved on `robot`).
    pub(crate) fn resolve(&self, robot: &Robot) -> Result<(JointContourSpec, FieldSpec), Failure> {
        match &self.kind {
            Kind::Joint(j) => Ok((j.clone(), FieldSpec::Joint)),
            Kind::Cartesian { spec, base_dir, .. } => {
                let contour = spec.joint_contour(robot, base_dir)?;
                let field = spec
                    .task_field(robot, base_dir)?
                    .map_or(FieldSpec::Joint, |t| FieldSpec::Task(Box::new(t)));
                Ok((contour, field))
            }
        }
    }
}

fn positive(x: f64, name: &str) -> Result<f64, Failure> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(Failure(
            PVFC_ERROR_INVALID_ARGUMENT,
            format!("{name}: finite and > 0, got {x}").into(),
        ))
    }
}

/// `n` rows of `columns` doubles at `p` (row-major).
///
/// # Safety
/// `p` points to `n × columns` readable doubles.
unsafe fn rows(
    p: *const f64,
    n: usize,
    columns: usize,
    name: &'static str,
) -> Result<Vec<Vec<f64>>, Failure> {
    let total = n
        .checked_mul(columns)
        .ok_or_else(|| Failure(PVFC_ERROR_WRONG_SIZE, format!("{name}: too many").into()))?;
    // SAFETY: forwarded from the caller.
    let flat = unsafe { doubles(p, total, name) }?;
    Ok(flat.chunks(columns.max(1)).map(<[f64]>::to_vec).collect())
}

/// Stores a joint contour.
///
/// # Safety
/// `out` is NULL or writable.
unsafe fn joint(out: *mut *mut pvfc_contour, spec: JointContourSpec) -> Result<(), Failure> {
    // Built once to check it where it enters (the number of waypoints, the lists, the
    // period), as a controller would build it.
    DynJointContour::new(&spec, None)?;
    // SAFETY: as documented.
    unsafe {
        give(
            out,
            pvfc_contour {
                kind: Kind::Joint(spec),
            },
        )
    }
}

/// A closed joint-space contour: the periodic C² spline through `n_waypoints` waypoints
/// (row-major, `n_waypoints × dof` doubles, 3 to 1024 rows), one every `spacing` of `τ`.
///
/// # Safety
/// `waypoints` points to `n_waypoints × dof` readable doubles; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_contour_waypoints(
    waypoints: *const f64,
    n_waypoints: usize,
    dof: usize,
    spacing: f64,
    out: *mut *mut pvfc_contour,
) -> pvfc_status {
    guard(|| {
        if !(3..=MAX_WAYPOINTS).contains(&n_waypoints) {
            return Err(Failure(
                PVFC_ERROR_INVALID_ARGUMENT,
                format!("n_waypoints = {n_waypoints}: 3 to {MAX_WAYPOINTS} waypoints").into(),
            ));
        }
        // SAFETY: as documented.
        let points = unsafe { rows(waypoints, n_waypoints, dof, "waypoints") }?;
        let spacing = positive(spacing, "spacing")?;
        unsafe { joint(out, JointContourSpec::Waypoints { points, spacing }) }
    })
}

/// A Lissajous curve in joint space, `x_i = c_i + a_i sin(2πτ/T_i + φ_i)` for `i < n`,
/// closed with the common period `period` (a multiple of every `T_i`): `amplitude` `a`,
/// `periods` `T`, `phase` `φ` (NULL: zeros), `offset` `c` (NULL: zeros), `n` each.
///
/// # Safety
/// The arrays are NULL (where allowed) or hold `n` readable doubles; `out` is writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pvfc_contour_lissajous(
    amplitude: *const f64,
    periods: *const f64,
    phase: *const f64,
    offset: *const f64,
    n: usize,
    period: f64,
    out: *mut *mut pvfc_contour,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let required = |p: *const f64, name: &'static str| -> Result<Vec<f64>, Failure> {
            unsafe { optional(p, n, name) }?.ok_or_else(|| null(name))
        };
        let or_zeros = |p: *const f64, name: &'static str| -> Result<Vec<f64>, Failure> {
            Ok(unsafe { optional(p, n, name) }?.unwrap_or_else(|| vec![0.0; n]))
        };
        let spec = JointContourSpec::Lissajous {
            amplitude: required(amplitude, "amplitude")?,
            periods: required(periods, "periods")?,
            phase: or_zeros(phase, "phase")?,
            offset: or_zeros(offset, "offset")?,
            period: Some(positive(period, "period")?),
        };
        unsafe { joint(out, spec) }
    })
}

/// An ellipse in joint space, `x_d(τ) = c + u cos(2πτ/T) + w sin(2πτ/T)`: `center` `c`,
/// the conjugate semi-axes `u` and `w` (`n` doubles each), the period `T` in `τ`.
///
/// # Safety
/// The arrays hold `n` readable doubles; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_contour_ellipse(
    center: *const f64,
    u: *const f64,
    w: *const f64,
    n: usize,
    period: f64,
    out: *mut *mut pvfc_contour,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let vector = |p: *const f64, name: &'static str| -> Result<Vec<f64>, Failure> {
            unsafe { optional(p, n, name) }?.ok_or_else(|| null(name))
        };
        let spec = JointContourSpec::Ellipse {
            center: vector(center, "center")?,
            u: vector(u, "u")?,
            w: vector(w, "w")?,
            period: positive(period, "period")?,
        };
        unsafe { joint(out, spec) }
    })
}

/// How a Cartesian tool path becomes a controller's contour. Get them from
/// [`pvfc_cartesian_options_default`], then set at least `seed`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct pvfc_cartesian_options {
    /// `sizeof(pvfc_cartesian_options)` as the caller was compiled with.
    pub size: usize,
    /// The joint posture the inverse kinematics starts from at the path's first point (the
    /// robot's joints; required).
    pub seed: *const f64,
    /// The number of entries at `seed`.
    pub seed_len: usize,
    /// How many joint waypoints the path is sampled into (4 to 1024; 0: as many as it takes
    /// for the joint contour to stay within `tolerance` of the path).
    pub samples: usize,
    /// The adaptive sampling's largest distance between the path and the joint contour (m).
    pub tolerance: f64,
    /// Hold the tool's orientation at the seed's (else it is free).
    pub fixed_orientation: bool,
    /// Follow the exact path with the task-space field (else the joint contour through the
    /// waypoints).
    pub task_field: bool,
    /// The task-space field's `k` of `U = ½ k |e|²` (1/s).
    pub task_stiffness: f64,
    /// The task-space field's `k_R` of `U_R = k_R (1 − cos θ)` (1/s; 0: `task_stiffness`).
    pub task_orientation_stiffness: f64,
    /// The damping `μ` of the task-space field's Jacobian inverse (m).
    pub task_damping: f64,
    /// The task-space field's pull towards the seed in the task's null space (1/s), for
    /// arms with more joints than the task has coordinates.
    pub task_rest_gain: f64,
    /// The distance `ℓ` (m) at which the task-space field's position function saturates,
    /// `U = kℓ²(√(1 + |e|²/ℓ²) − 1)` (its pull below `kℓ`); 0: `½ k |e|²`.
    pub task_saturation: f64,
}

/// The default options: no seed (set it), adaptive sampling to 10 µm, the orientation free,
/// the joint contour (not the task-space field), and the task-space field's defaults
/// `k = 4/s`, `k_R = k`, `μ = 0.01 m`, rest gain 1/s, no saturation.
#[no_mangle]
pub extern "C" fn pvfc_cartesian_options_default() -> pvfc_cartesian_options {
    pvfc_cartesian_options {
        size: std::mem::size_of::<pvfc_cartesian_options>(),
        seed: std::ptr::null(),
        seed_len: 0,
        samples: 0,
        tolerance: pvfc_control::model::cartesian::DEFAULT_TOLERANCE,
        fixed_orientation: false,
        task_field: false,
        task_stiffness: pvfc_control::model::cartesian::DEFAULT_TASK_STIFFNESS,
        task_orientation_stiffness: 0.0,
        task_damping: pvfc_control::model::cartesian::DEFAULT_TASK_DAMPING,
        task_rest_gain: 1.0,
        task_saturation: 0.0,
    }
}

/// Stores a Cartesian contour made from `spec` and `options` (NULL: defaults, which lack the
/// seed), traced once every `period` of `τ`.
///
/// # Safety
/// `options` is NULL or readable, its `seed` as documented; `out` is NULL or writable.
unsafe fn cartesian(
    mut spec: CartesianSpec,
    options: *const pvfc_cartesian_options,
    period: f64,
    out: *mut *mut pvfc_contour,
) -> Result<(), Failure> {
    // SAFETY: as documented.
    let o = unsafe { sized(options, pvfc_cartesian_options_default(), "options") }?;
    if o.seed.is_null() {
        return Err(null("options.seed"));
    }
    spec.seed = unsafe { doubles(o.seed, o.seed_len, "options.seed") }?.to_vec();
    spec.samples = o.samples;
    spec.tolerance = Some(o.tolerance);
    spec.fixed_orientation = o.fixed_orientation;
    if o.task_field {
        spec.task = Some(TaskSpec {
            stiffness: Some(o.task_stiffness),
            orientation_stiffness: (o.task_orientation_stiffness != 0.0)
                .then_some(o.task_orientation_stiffness),
            damping: Some(o.task_damping),
            rest_gain: Some(o.task_rest_gain),
            saturation: (o.task_saturation != 0.0).then_some(o.task_saturation),
        });
    }
    unsafe { store(spec, PathBuf::new(), period, None, out) }
}

/// Checks a Cartesian spec's path and stores it. With fixed `samples` the waypoints are
/// `spacing` apart in `τ` (`None`: `period / samples`); adaptive sampling fits them into the
/// `period`.
///
/// # Safety
/// `out` is NULL or writable.
unsafe fn store(
    mut spec: CartesianSpec,
    base_dir: PathBuf,
    period: f64,
    spacing: Option<f64>,
    out: *mut *mut pvfc_contour,
) -> Result<(), Failure> {
    let spacing = match (spec.samples, spacing) {
        (0, _) => None,
        (_, Some(s)) => Some(positive(s, "spacing")?),
        (n, None) => Some(period / n as f64),
    };
    spec.period = Some(positive(period, "period")?);
    spec.spacing = spacing;
    spec.tolerance()?;
    let path = spec.path(&base_dir)?;
    // SAFETY: as documented.
    unsafe {
        give(
            out,
            pvfc_contour {
                kind: Kind::Cartesian {
                    spec: Box::new(spec),
                    path,
                    base_dir,
                },
            },
        )
    }
}

/// A closed polygon of the tool's position through `n_corners` corners (row-major `x, y, z`,
/// m, in the robot's base frame; the last joins the first) with its corners rounded to
/// `corner_radius` (m; 0: sharp), traced once every `period` of `τ`, with `options` (NULL:
/// the defaults, which lack the seed).
///
/// # Safety
/// `corners` holds `3 × n_corners` readable doubles; `options` is NULL or readable; `out` is
/// writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_contour_cartesian_polygon(
    corners: *const f64,
    n_corners: usize,
    corner_radius: f64,
    period: f64,
    options: *const pvfc_cartesian_options,
    out: *mut *mut pvfc_contour,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let points = unsafe { rows(corners, n_corners, 3, "corners") }?
            .into_iter()
            .map(|p| [p[0], p[1], p[2]])
            .collect();
        let spec = CartesianSpec {
            points,
            corner_radius,
            ..Default::default()
        };
        unsafe { cartesian(spec, options, period, out) }
    })
}

/// A circle of the tool's position (`semi_minor` 0), or an ellipse: `center` and `normal`
/// (3 doubles each; it turns right-handed about the normal), `radius` the semi-axis along
/// `major_axis` (3 doubles, NULL: any direction in the plane; the path starts there),
/// `semi_minor` the other; traced once every `period` of `τ`, with `options`.
///
/// # Safety
/// `center`, `normal` hold 3 readable doubles, `major_axis` is NULL or does; `options` is
/// NULL or readable; `out` is writable.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn pvfc_contour_cartesian_circle(
    center: *const f64,
    normal: *const f64,
    radius: f64,
    major_axis: *const f64,
    semi_minor: f64,
    period: f64,
    options: *const pvfc_cartesian_options,
    out: *mut *mut pvfc_contour,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let three = |p: *const f64, name: &'static str| -> Result<[f64; 3], Failure> {
            unsafe { triple(p, name) }?.ok_or_else(|| null(name))
        };
        let circle = CircleSpec {
            center: three(center, "center")?,
            radius,
            normal: three(normal, "normal")?,
            semi_minor: (semi_minor != 0.0).then_some(semi_minor),
            major_axis: unsafe { triple(major_axis, "major_axis") }?,
        };
        let spec = CartesianSpec {
            circle: Some(circle),
            ..Default::default()
        };
        unsafe { cartesian(spec, options, period, out) }
    })
}

/// Any Cartesian tool path a scenario file can give: `toml` holds the keys of its
/// `[contour.cartesian]` table (points, circle, csv, gcode, part, orientations, tool_frame, rest,
/// `[task]`, …; the user's manual lists them), a CSV file's or part program's name relative
/// to `base_dir` (NULL: the working directory). A part program's feeds (F) are the pace of a
/// controller made on it (`pvfc_settings.pace_speed` on moves without F). Traced once every
/// `period` of `τ` with adaptive sampling; with fixed `samples`, `spacing` is the `τ` between
/// waypoints (0: `period / samples`).
///
/// # Safety
/// `toml` is a NUL-terminated string, `base_dir` NULL or one; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_contour_cartesian_toml(
    toml: *const c_char,
    base_dir: *const c_char,
    period: f64,
    spacing: f64,
    out: *mut *mut pvfc_contour,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let table = unsafe { text(toml, "toml") }?.ok_or_else(|| null("toml"))?;
        let base_dir = PathBuf::from(unsafe { text(base_dir, "base_dir") }?.unwrap_or(""));
        let spec: CartesianSpec = ::toml::from_str(table).map_err(|e| {
            Failure(
                PVFC_ERROR_INVALID_ARGUMENT,
                format!("contour.cartesian: {e}").into(),
            )
        })?;
        let spacing = (spacing != 0.0).then_some(spacing);
        unsafe { store(spec, base_dir, period, spacing, out) }
    })
}

/// Any contour a scenario file's `[contour]` can hold, of any kind: `toml` is the table's
/// content, one table named for its kind (`[lissajous]`, `[waypoints]`, `[ellipse]`,
/// `[cartesian]` with its `period` or `spacing`, …; the user's manual lists them), a CSV
/// file's name relative to `base_dir` (NULL: the working directory). A joint-space kind the
/// library adds reaches C through this function without a new one.
///
/// # Safety
/// `toml` is a NUL-terminated string, `base_dir` NULL or one; `out` is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_contour_toml(
    toml: *const c_char,
    base_dir: *const c_char,
    out: *mut *mut pvfc_contour,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let table = unsafe { text(toml, "toml") }?.ok_or_else(|| null("toml"))?;
        let base_dir = PathBuf::from(unsafe { text(base_dir, "base_dir") }?.unwrap_or(""));
        let invalid = |e: String| Failure(PVFC_ERROR_INVALID_ARGUMENT, e.into());
        let spec: ContourSpec = ::toml::from_str(table).map_err(|e| invalid(e.to_string()))?;
        match spec {
            // SAFETY: as documented.
            ContourSpec::Joint(j) => unsafe { joint(out, j) },
            ContourSpec::Cartesian(c) => {
                let period = c.period_in_tau().ok_or_else(|| {
                    invalid(
                        "contour.cartesian: give its period (adaptive sampling) or its spacing (fixed samples)"
                            .into(),
                    )
                })?;
                let spacing = c.spacing;
                // SAFETY: as documented.
                unsafe { store(*c, base_dir, period, spacing, out) }
            }
            ContourSpec::Attitude(_) => Err(invalid(
                "contour.attitude: a rigid body's; a robot arm follows a joint-space curve or a Cartesian path".into(),
            )),
        }
    })
}

/// The distance (m) from `point` (3 doubles, base frame) to a Cartesian contour's exact path,
/// into `*distance`, and the closest point into `closest` (3 doubles; NULL: not wanted).
/// Allocates nothing. An error for a joint-space contour.
///
/// # Safety
/// `contour` is NULL or a live handle; `point` holds 3 readable doubles; `closest` is NULL
/// or has room for 3; `distance` is writable.
#[no_mangle]
pub unsafe extern "C" fn pvfc_contour_distance(
    contour: *const pvfc_contour,
    point: *const f64,
    distance: *mut f64,
    closest: *mut f64,
) -> pvfc_status {
    guard(|| {
        // SAFETY: as documented.
        let c = unsafe { object(contour, "contour") }?;
        let Kind::Cartesian { path, .. } = &c.kind else {
            return Err(Failure(
                PVFC_ERROR_INVALID_ARGUMENT,
                "contour: a joint-space contour has no tool path".into(),
            ));
        };
        if point.is_null() {
            return Err(null("point"));
        }
        let p = unsafe { doubles(point, 3, "point") }?;
        let d = unsafe { distance.as_mut() }.ok_or_else(|| null("distance"))?;
        let nearest = path.closest(&nalgebra::Vector3::new(p[0], p[1], p[2]));
        *d = nearest.distance;
        if !closest.is_null() {
            // SAFETY: room for 3 doubles.
            let o = unsafe { std::slice::from_raw_parts_mut(closest, 3) };
            o.copy_from_slice(nearest.point.as_slice());
        }
        Ok(())
    })
}

/// Frees a contour (NULL: nothing). Controllers made from it keep what they need.
///
/// # Safety
/// `contour` is NULL or a live handle, not used afterwards.
#[no_mangle]
pub unsafe extern "C" fn pvfc_contour_destroy(contour: *mut pvfc_contour) {
    if !contour.is_null() {
        // SAFETY: a handle made by Box::into_raw in this library, freed once.
        drop(unsafe { Box::from_raw(contour) });
    }
}

impl SizedStruct for pvfc_cartesian_options {
    fn size(&self) -> usize {
        self.size
    }
}
