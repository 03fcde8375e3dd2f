//! The time series of a run ([`Trace`], [`ContactTrace`]) and their columns, defined once.
//!
//! Every column is named, documented, shaped and given its log width in one list,
//! [`trace_columns!`](crate::trace_columns). From it come the structs' fields, the rows the
//! run loops push, the tables [`TRACE_COLUMNS`] and [`CONTACT_COLUMNS`] that the MCAP log
//! ([`crate::log`]) writes from, and the Python bindings' getters (`pvfc-py` expands the same
//! list). A column added to the list appears in all of them.

pub mod clearance;
pub mod feed_speeds;
pub mod metrics;
pub mod path_budget;
pub mod series;

use crate::contact::ContactForces;
use crate::trace::series::JointSeries;
use nalgebra::Vector2;

/// Calls the macro `$callback` with the columns of a run: `trace { … } contact { … }`, each
/// entry `name as python_name: Shape Log "doc";` with `Shape` one of `Scalar` (one number
/// per sample), `Joints` (one per joint), `Workspace` (2 numbers for the planar arm, 3 in
/// 3-D), and `Precision` one of `Time` (the log's timestamp, not a field), `Plot` (values to
/// plot: seven digits suffice), `Audit` (the energy audit's columns, whose residuals are
/// 1e-15 of the energy). The order is the order of the fields in the log's messages.
#[macro_export]
macro_rules! trace_columns {
    ($callback:ident) => {
        $callback! {
            trace {
                t as t: Scalar Time "Time (s).";
                q as q: Joints Plot
                    "Joint positions (rad, or m for prismatic joints), one row per sample.";
                v as qdot: Joints Plot "Joint velocities (rad/s, m/s), one row per sample.";
                energy as energy: Scalar Audit
                    "Augmented kinetic energy κ_a (J): arm + ½τ̇² + flywheel (eq. 5).";
                tau as tau: Scalar Plot "Contour parameter τ, unwrapped.";
                tau_dot as tau_dot: Scalar Plot "Its rate dτ/dt.";
                flywheel_speed as flywheel_speed: Scalar Plot
                    "Flywheel speed q̇_F (rad/s; 0 for the timed baseline).";
                beta as beta: Scalar Plot "β = √(κ_a/Ē): the speed along the field.";
                w_beta as w_beta: Scalar Plot
                    "W_β = ½‖q̇_a − βV_a‖²_a (eq. 12, J): the energy of the velocity-field tracking error, the Lyapunov function of Remark 1 (0 for the timed baseline).";
                potential as potential: Scalar Plot
                    "The contour error U(E) of eq. (17); with obstacles, its composition φ with their barrier (Remark 3).";
                lambda1 as lambda1: Scalar Plot "Self-pacing gain λ₁ (eq. 21).";
                lambda2 as lambda2: Scalar Plot "Self-pacing gain λ₂ (eq. 21).";
                torque as torque: Joints Plot "Motor torques (N·m, N), one row per sample.";
                friction_power as friction_power: Scalar Plot
                    "Power of the plant's friction on the arm, F_fᵀq̇ ≤ 0 (W).";
                fault as fault: Scalar Plot
                    "The fault the passive controller's supervision found at the sample (pvfc_core::supervision::Fault::code): 0 none, 1 a non-finite reading, 2 a period out of bounds, 3 beyond the speed bound, 4 beyond the acceleration bound, 5 a frozen encoder.";
            }
            contact {
                work_contact as work_contact: Scalar Audit
                    "∫ F_eᵀq̇ dt: the work the environment (the contact, and the scenario's disturbance torque) did on the arm (J); its negative is the energy the arm pumped into it.";
                work_friction as work_friction: Scalar Audit
                    "∫ F_fᵀq̇ dt: the work of the plant's joint friction (J, ≤ 0).";
                work_controller as work_controller: Scalar Audit
                    "The work of everything in the motor torques that is not the workless PVFC coupling: the add-ons (35) and (36) for PVFC, all of ∫ uᵀq̇ dt for the timed baseline (J).";
                work_gravity as work_gravity: Scalar Audit
                    "−∫ g(q)ᵀq̇ dt: the work of gravity on the arm (J; 0 for the horizontal SCARA).";
                force as force: Workspace Plot
                    "The sum of the Cartesian contact forces on the arm (N; 2 numbers per sample for the planar arm, 3 for a URDF arm).";
                normal_force as normal_force: Scalar Plot
                    "The sum of the contact normal forces (N): the measured contact force.";
                depth as depth: Scalar Plot "The deepest penetration (m).";
                torque as torque: Joints Plot
                    "The environment's joint torques F_e = Jᵀf (N·m), one per joint.";
                tool as tool: Workspace Plot "The tool centre (m; 2 or 3 numbers, as force).";
                nominal_speed as nominal_speed: Scalar Plot
                    "The nominal speed r of (36) in force (scheduled on the contact force); 0 without.";
            }
        }
    };
}

/// How a column is shaped: what one sample of it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// One number.
    Scalar,
    /// One number per joint.
    Joints,
    /// A point or vector of the workspace (2 numbers for the planar arm, 3 in 3-D).
    Workspace,
}

/// A column's samples.
#[derive(Clone, Copy, Debug)]
pub enum Values<'a> {
    /// One number per sample.
    Scalar(&'a [f64]),
    /// One vector per sample.
    Vectors(&'a JointSeries),
}

impl<'a> From<&'a Vec<f64>> for Values<'a> {
    fn from(v: &'a Vec<f64>) -> Self {
        Values::Scalar(v)
    }
}

impl<'a> From<&'a JointSeries> for Values<'a> {
    fn from(v: &'a JointSeries) -> Self {
        Values::Vectors(v)
    }
}

impl Values<'_> {
    /// Sample `i` as a slice (one number for a scalar column), if there is one.
    pub fn sample(&self, i: usize) -> Option<&[f64]> {
        match self {
            Values::Scalar(v) => v.get(i..i + 1),
            Values::Vectors(s) => s.get(i),
        }
    }
}

/// The precision a column's values need, which the log chooses its encoding from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// Values to plot: seven significant digits suffice (`float32` in the log).
    Plot,
    /// The energy audit's columns (κ_a and the works), whose residuals are 1e-15 of the
    /// energy (`float64` in the log).
    Audit,
}

/// One column of a trace `S` ([`Trace`] or [`ContactTrace`]), as the log and the bindings
/// see it.
#[derive(Debug)]
pub struct Column<S> {
    /// The field's name (in the Rust struct and the log's message).
    pub name: &'static str,
    /// The attribute's name in Python.
    pub python: &'static str,
    /// What it is, with its unit.
    pub doc: &'static str,
    /// One number, one per joint, or a workspace vector per sample.
    pub shape: Shape,
    /// The precision its values need (`None`: the log's timestamp, not a field).
    pub precision: Option<Precision>,
    /// Its samples.
    pub get: fn(&S) -> Values<'_>,
}

// (By hand: a derive would ask `S: Copy`, and a trace is not.)
impl<S> Clone for Column<S> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<S> Copy for Column<S> {}

macro_rules! column_type {
    (Scalar) => { Vec<f64> };
    (Joints) => { JointSeries };
    (Workspace) => { JointSeries };
}

macro_rules! row_type {
    ($a:lifetime, Scalar) => {
        f64
    };
    ($a:lifetime, Joints) => {
        &$a[f64]
    };
    ($a:lifetime, Workspace) => {
        &$a[f64]
    };
}

macro_rules! column_new {
    (Scalar, $n:expr, $dof:expr, $dim:expr) => {
        Vec::with_capacity($n)
    };
    (Joints, $n:expr, $dof:expr, $dim:expr) => {
        JointSeries::with_capacity($dof, $n)
    };
    (Workspace, $n:expr, $dof:expr, $dim:expr) => {
        JointSeries::with_capacity($dim, $n)
    };
}

macro_rules! precision {
    (Time) => {
        None
    };
    (Plot) => {
        Some(Precision::Plot)
    };
    (Audit) => {
        Some(Precision::Audit)
    };
}

/// The table of the columns of the struct `$s`.
macro_rules! column_table {
    ($s:ident; $($n:ident $p:ident $shape:ident $log:ident $doc:literal;)*) => {
        &[$(Column {
            name: stringify!($n),
            python: stringify!($p),
            doc: $doc,
            shape: Shape::$shape,
            precision: precision!($log),
            get: {
                fn get(t: &$s) -> Values<'_> {
                    Values::from(&t.$n)
                }
                get
            },
        },)*]
    };
}

/// The names of a baseline's runs (defined with the scenario's baseline, which names them).
pub use crate::scenario::{SCALED_SUFFIX, TIMED_SUFFIX};

macro_rules! define_traces {
    (
        trace { $($n:ident as $p:ident : $shape:ident $log:ident $doc:literal;)* }
        contact { $($cn:ident as $cp:ident : $cshape:ident $clog:ident $cdoc:literal;)* }
    ) => {
        /// The time series of one run, sampled at the controller's rate.
        #[derive(Clone, Debug, Default, PartialEq)]
        pub struct Trace {
            /// The scenario's name (and `-timed` for the baseline).
            pub name: String,
            $(#[doc = $doc] pub $n: column_type!($shape),)*
            /// The contact columns, for a run with an environment.
            pub contact: Option<ContactTrace>,
        }

        /// One sample of a [`Trace`] (the joint columns as slices of the robot's dimension).
        pub(crate) struct Row<'a> {
            $(pub(crate) $n: row_type!('a, $shape),)*
        }

        impl Trace {
            /// Whether this is the timed baseline's run (its name ends in
            /// [`TIMED_SUFFIX`]).
            pub fn is_timed(&self) -> bool {
                self.name.ends_with(TIMED_SUFFIX)
            }

            /// An empty trace of a `dof`-joint robot named `name`, with room for `n` samples
            /// (no reallocation in the run).
            pub(crate) fn with_capacity(name: String, dof: usize, n: usize) -> Self {
                Trace {
                    name,
                    $($n: column_new!($shape, n, dof, 0),)*
                    contact: None,
                }
            }

            /// Appends one sample.
            pub(crate) fn push(&mut self, row: Row<'_>) {
                $(self.$n.push(row.$n);)*
            }
        }

        /// The columns of a [`Trace`], in the order of [`trace_columns!`](crate::trace_columns).
        pub const TRACE_COLUMNS: &[Column<Trace>] =
            column_table!(Trace; $($n $p $shape $log $doc;)*);

        /// The contact columns of a [`Trace`], and the work of every force on the arm, each
        /// integrated by the RK4 quadrature of the state's own stages (so that
        /// `energy − energy[0] − work_contact − work_friction − work_controller − work_gravity`
        /// is integration error only: [`ContactTrace::audit_residual`]).
        #[derive(Clone, Debug, Default, PartialEq)]
        pub struct ContactTrace {
            $(#[doc = $cdoc] pub $cn: column_type!($cshape),)*
        }

        /// One sample of a [`ContactTrace`].
        pub(crate) struct ContactRow<'a> {
            $(pub(crate) $cn: row_type!('a, $cshape),)*
        }

        impl ContactTrace {
            /// Empty columns for `n` samples of an arm with `dof` joints in a `dim`-D
            /// workspace.
            pub(crate) fn with_capacity(n: usize, dof: usize, dim: usize) -> Self {
                ContactTrace {
                    $($cn: column_new!($cshape, n, dof, dim),)*
                }
            }

            /// Appends one sample.
            pub(crate) fn push_row(&mut self, row: ContactRow<'_>) {
                $(self.$cn.push(row.$cn);)*
            }
        }

        /// The columns of a [`ContactTrace`], in the order of
        /// [`trace_columns!`](crate::trace_columns).
        pub const CONTACT_COLUMNS: &[Column<ContactTrace>] =
            column_table!(ContactTrace; $($cn $cp $cshape $clog $cdoc;)*);
    };
}

trace_columns!(define_traces);

impl ContactTrace {
    /// One sample of the planar arm's contact.
    pub(crate) fn push(&mut self, c: &ContactForces, tool: Vector2<f64>, w: &Work, r: f64) {
        self.push_sample(
            &ContactSample {
                force: &[c.force.x, c.force.y],
                normal_force: c.normal_force,
                depth: c.depth,
                torque: c.torque.as_slice(),
                tool: &[tool.x, tool.y],
            },
            w,
            r,
        );
    }

    /// One sample: the contact, the works so far, the nominal speed in force.
    pub(crate) fn push_sample(&mut self, c: &ContactSample<'_>, w: &Work, r: f64) {
        let [work_contact, work_friction, work_controller, work_gravity] = w.0;
        self.push_row(ContactRow {
            work_contact,
            work_friction,
            work_controller,
            work_gravity,
            force: c.force,
            normal_force: c.normal_force,
            depth: c.depth,
            torque: c.torque,
            tool: c.tool,
            nominal_speed: r,
        });
    }

    /// `true` when the arm touches something at sample `i`.
    pub fn contacts_at(&self, i: usize) -> bool {
        self.depth.get(i).is_some_and(|d| *d > 0.0)
    }

    /// The energy audit `E(t) − E(0) − W_contact − W_friction − W_controller − W_gravity` at
    /// every sample, for the trace's `energy` column `E` (`κ_a` for PVFC, the arm's kinetic
    /// energy for the baseline).
    pub fn audit_residual(&self, energy: &[f64]) -> Vec<f64> {
        let e0 = energy.first().copied().unwrap_or(0.0);
        energy
            .iter()
            .zip(&self.work_contact)
            .zip(&self.work_friction)
            .zip(&self.work_controller)
            .zip(&self.work_gravity)
            .map(|((((e, c), f), u), g)| e - e0 - c - f - u - g)
            .collect()
    }
}

/// The contact at one sample, as the trace logs it (any workspace and number of joints).
pub(crate) struct ContactSample<'a> {
    pub(crate) force: &'a [f64],
    pub(crate) normal_force: f64,
    pub(crate) depth: f64,
    pub(crate) torque: &'a [f64],
    pub(crate) tool: &'a [f64],
}

/// Works `[contact, friction, controller, gravity]` accumulated along a run.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Work(pub(crate) [f64; 4]);

impl Trace {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// `true` when there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)] // tests: a failure is the point
mod tests {
    use super::*;

    #[test]
    fn every_column_reads_its_own_field() {
        // A row whose every number is distinct, in the list's order: each table entry must
        // read the field it names, and the tables keep the list's order.
        let mut t = Trace::with_capacity("x".into(), 2, 1);
        let mut c = ContactTrace::with_capacity(1, 2, 3);
        t.push(Row {
            t: 1.0,
            q: &[2.0, 3.0],
            v: &[4.0, 5.0],
            energy: 6.0,
            tau: 7.0,
            tau_dot: 8.0,
            flywheel_speed: 9.0,
            beta: 10.0,
            w_beta: 11.0,
            potential: 12.0,
            lambda1: 13.0,
            lambda2: 14.0,
            torque: &[15.0, 16.0],
            friction_power: 17.0,
            fault: 18.0,
        });
        let flat: Vec<f64> = TRACE_COLUMNS
            .iter()
            .flat_map(|col| (col.get)(&t).sample(0).unwrap().to_vec())
            .collect();
        assert_eq!(flat, (1..=18).map(f64::from).collect::<Vec<_>>());
        assert_eq!(t.v[0], [4.0, 5.0]);
        assert_eq!(t.friction_power, [17.0]);
        assert_eq!(t.fault, [18.0]);
        c.push_sample(
            &ContactSample {
                force: &[5.0, 6.0, 7.0],
                normal_force: 8.0,
                depth: 9.0,
                torque: &[10.0, 11.0],
                tool: &[12.0, 13.0, 14.0],
            },
            &Work([1.0, 2.0, 3.0, 4.0]),
            15.0,
        );
        let flat: Vec<f64> = CONTACT_COLUMNS
            .iter()
            .flat_map(|col| (col.get)(&c).sample(0).unwrap().to_vec())
            .collect();
        assert_eq!(flat, (1..=15).map(f64::from).collect::<Vec<_>>());
        assert_eq!(c.nominal_speed, [15.0]);
        assert_eq!(c.work_gravity, [4.0]);
    }

    #[test]
    fn names_are_unique_and_the_log_has_one_timestamp() {
        for names in [
            TRACE_COLUMNS.iter().map(|c| c.python).collect::<Vec<_>>(),
            CONTACT_COLUMNS.iter().map(|c| c.name).collect::<Vec<_>>(),
        ] {
            let mut sorted = names.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), names.len(), "{names:?}");
        }
        let stamps: Vec<_> = TRACE_COLUMNS
            .iter()
            .filter(|c| c.precision.is_none())
            .collect();
        assert_eq!(stamps.len(), 1);
        assert_eq!(stamps[0].name, "t");
        assert!(CONTACT_COLUMNS.iter().all(|c| c.precision.is_some()));
    }
}
