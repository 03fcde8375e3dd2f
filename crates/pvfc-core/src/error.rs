//! The error type of pvfc-core: small, `Copy`, allocation-free, with a [`kind`](Error::kind).

use core::fmt;

/// What went wrong, in categories a caller can match on.
///
/// The enum is non-exhaustive: new kinds may be added without a breaking change.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum ErrorKind {
    /// An input (state, parameter or gain) was NaN or infinite.
    NonFinite,
    /// The energy level Ē of the augmented field (eq. 6) is not larger than the kinetic energy
    /// of the suspended field ½ V̄ᵀM̄V̄ at the state at hand, so the flywheel speed V_F would be
    /// imaginary or zero.
    EnergyTooLow,
    /// A navigation-function matrix (P of eq. 26) breaks the conditions on its eigenvalues.
    InvalidNavigationMatrix,
    /// A parameter is outside its valid range (a negative mass, a zero period, ...).
    InvalidParameter,
    /// The inertia matrix is not positive definite at the state at hand.
    SingularInertia,
    /// A size given at run time does not fit the dimensions fixed at compile time.
    DimensionMismatch,
    /// An iterative construction (e.g. an interpolating spline) did not converge.
    NoConvergence,
}

impl ErrorKind {
    /// A short, stable, human-readable name of the kind.
    pub const fn as_str(self) -> &'static str {
        match self {
            ErrorKind::NonFinite => "non-finite input",
            ErrorKind::EnergyTooLow => "energy level too low for the velocity field",
            ErrorKind::InvalidNavigationMatrix => "invalid navigation matrix",
            ErrorKind::InvalidParameter => "invalid parameter",
            ErrorKind::SingularInertia => "inertia matrix not positive definite",
            ErrorKind::DimensionMismatch => "dimension mismatch",
            ErrorKind::NoConvergence => "no convergence",
        }
    }
}

/// An error of pvfc-core: a [`ErrorKind`] and a static description of what was checked.
///
/// ```
/// use pvfc_core::{Error, ErrorKind};
/// let e = Error::new(ErrorKind::EnergyTooLow, "flywheel: Ē ≤ ½ V̄ᵀM̄V̄");
/// assert_eq!(e.kind(), ErrorKind::EnergyTooLow);
/// assert!(format!("{e}").contains("flywheel"));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Error {
    kind: ErrorKind,
    context: &'static str,
    value: Option<f64>,
}

impl Error {
    /// A new error of the given kind, with a static description of the failed check.
    pub const fn new(kind: ErrorKind, context: &'static str) -> Self {
        Error {
            kind,
            context,
            value: None,
        }
    }

    /// The same error, carrying the offending number (e.g. the energy deficit).
    pub const fn with_value(mut self, value: f64) -> Self {
        self.value = Some(value);
        self
    }

    /// The category of the error.
    pub const fn kind(&self) -> ErrorKind {
        self.kind
    }

    /// The static description of the check that failed.
    pub const fn context(&self) -> &'static str {
        self.context
    }

    /// The offending number, when one was recorded.
    pub const fn value(&self) -> Option<f64> {
        self.value
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.kind.as_str(), self.context)?;
        if let Some(v) = self.value {
            write!(f, " (value {v})")?;
        }
        Ok(())
    }
}

impl core::error::Error for Error {}

/// The result type of pvfc-core.
pub type Result<T> = core::result::Result<T, Error>;

/// Returns `Err(NonFinite)` with the given context unless every value is finite.
#[inline]
pub(crate) fn ensure_finite<'a, T: crate::Real + 'a>(
    xs: impl IntoIterator<Item = &'a T>,
    context: &'static str,
) -> Result<()> {
    if crate::scalar::all_finite(xs) {
        Ok(())
    } else {
        Err(Error::new(ErrorKind::NonFinite, context))
    }
}
