//! The Python exception tree, mirroring the Rust error kinds.

use pvfc_core::ErrorKind;
use pvfc_sim::SimError;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _pvfc,
    PvfcError,
    PyException,
    "Base class of every error raised by pvfc."
);
create_exception!(
    _pvfc,
    NonFiniteError,
    PvfcError,
    "An input was NaN or infinite."
);
create_exception!(
    _pvfc,
    EnergyTooLowError,
    PvfcError,
    "The energy level Ē is not above the kinetic energy of the suspended field (eq. 6)."
);
create_exception!(
    _pvfc,
    InvalidNavigationMatrixError,
    PvfcError,
    "A navigation matrix P (eq. 26) breaks the conditions on its eigenvalues."
);
create_exception!(
    _pvfc,
    InvalidParameterError,
    PvfcError,
    "A parameter is out of range."
);
create_exception!(
    _pvfc,
    SingularInertiaError,
    PvfcError,
    "The inertia matrix is not positive definite."
);
create_exception!(
    _pvfc,
    DimensionMismatchError,
    PvfcError,
    "A size does not fit."
);
create_exception!(
    _pvfc,
    NoConvergenceError,
    PvfcError,
    "An iterative construction did not converge."
);
create_exception!(
    _pvfc,
    ScenarioError,
    PvfcError,
    "A scenario is malformed; the message names the field (and the line, for TOML)."
);
create_exception!(
    _pvfc,
    UrdfError,
    PvfcError,
    "A URDF is malformed or not a planar two-link arm."
);
create_exception!(
    _pvfc,
    LogError,
    PvfcError,
    "Writing or reading an MCAP log failed."
);
create_exception!(
    _pvfc,
    PvfcIOError,
    PvfcError,
    "Reading or writing a file failed."
);

/// A core error as the matching Python exception.
pub fn core_err(e: pvfc_core::Error) -> PyErr {
    let m = e.to_string();
    match e.kind() {
        ErrorKind::NonFinite => NonFiniteError::new_err(m),
        ErrorKind::EnergyTooLow => EnergyTooLowError::new_err(m),
        ErrorKind::InvalidNavigationMatrix => InvalidNavigationMatrixError::new_err(m),
        ErrorKind::InvalidParameter => InvalidParameterError::new_err(m),
        ErrorKind::SingularInertia => SingularInertiaError::new_err(m),
        ErrorKind::DimensionMismatch => DimensionMismatchError::new_err(m),
        ErrorKind::NoConvergence => NoConvergenceError::new_err(m),
        _ => PvfcError::new_err(m),
    }
}

/// A simulation error as the matching Python exception.
pub fn sim_err(e: SimError) -> PyErr {
    match e {
        SimError::Core(c) => core_err(c),
        SimError::Scenario { .. } => ScenarioError::new_err(e.to_string()),
        SimError::Urdf { .. } => UrdfError::new_err(e.to_string()),
        SimError::Io { .. } => PvfcIOError::new_err(e.to_string()),
        SimError::Mcap(_) => LogError::new_err(e.to_string()),
        SimError::Setting(_) => InvalidParameterError::new_err(e.to_string()),
        SimError::Waypoint { .. } => InvalidParameterError::new_err(e.to_string()),
        SimError::PartProgram { .. } => InvalidParameterError::new_err(e.to_string()),
        _ => PvfcError::new_err(e.to_string()),
    }
}

/// Registers the exceptions in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("PvfcError", py.get_type::<PvfcError>())?;
    m.add("NonFiniteError", py.get_type::<NonFiniteError>())?;
    m.add("EnergyTooLowError", py.get_type::<EnergyTooLowError>())?;
    m.add(
        "InvalidNavigationMatrixError",
        py.get_type::<InvalidNavigationMatrixError>(),
    )?;
    m.add(
        "InvalidParameterError",
        py.get_type::<InvalidParameterError>(),
    )?;
    m.add(
        "SingularInertiaError",
        py.get_type::<SingularInertiaError>(),
    )?;
    m.add(
        "DimensionMismatchError",
        py.get_type::<DimensionMismatchError>(),
    )?;
    m.add("NoConvergenceError", py.get_type::<NoConvergenceError>())?;
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("UrdfError", py.get_type::<UrdfError>())?;
    m.add("LogError", py.get_type::<LogError>())?;
    m.add("PvfcIOError", py.get_type::<PvfcIOError>())?;
    Ok(())
}
