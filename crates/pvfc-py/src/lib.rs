//! Python bindings of pvfc: the native module `pvfc._pvfc` of the `pvfc` wheel.

#![forbid(unsafe_code)]
#![allow(missing_docs)] // The Python API is documented in the `.pyi` stubs and docstrings.

mod arm;
mod attitude;
mod cartesian;
mod contours;
mod controller;
mod convert;
mod deprecated;
mod errors;
mod navigation;
mod passive;
mod pickle;
mod robots;
mod runs;
mod scara;
mod settings;
mod study;

use pyo3::prelude::*;

#[pymodule]
fn _pvfc(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    m.add_class::<scara::Scara>()?;
    m.add_class::<robots::Robot>()?;
    m.add_class::<cartesian::CartesianPath>()?;
    m.add_class::<cartesian::TaskSpaceField>()?;
    m.add_class::<deprecated::ArmController>()?;
    m.add_class::<contours::Lissajous>()?;
    m.add_class::<contours::JointCurve>()?;
    m.add_class::<contours::Ellipse>()?;
    m.add_class::<contours::WaypointCurve>()?;
    m.add_class::<contours::So3ConstantRate>()?;
    m.add_class::<navigation::TorusNavigation>()?;
    m.add_class::<navigation::So3Navigation>()?;
    m.add_class::<navigation::JointNavigation>()?;
    m.add_class::<settings::ControllerSettings>()?;
    m.add_class::<runs::Scenario>()?;
    m.add_class::<runs::SimulationResult>()?;
    m.add_class::<study::Study>()?;
    m.add_class::<controller::Controller>()?;
    m.add_class::<deprecated::AttitudeController>()?;
    m.add_class::<passive::PassiveController>()?;
    m.add_function(wrap_pyfunction!(runs::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(runs::simulate_many, m)?)?;
    m.add_function(wrap_pyfunction!(runs::simulate_timed, m)?)?;
    m.add_function(wrap_pyfunction!(runs::read_mcap, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
