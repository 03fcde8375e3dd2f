"""pvfc: Passive Velocity Field Control (Li & Horowitz) for contour following.

Robots, contours, navigation functions, the PVFC controller, scenarios and simulations
with numpy arrays, MCAP logs, and the paper's figures (``pvfc.plot``, needs matplotlib).

>>> import pvfc
>>> result = pvfc.simulate(pvfc.Scenario.preset("fig8_R100"))
>>> result.q.shape[1]
2
"""

from ._pvfc import (
    ArmController,
    CartesianPath,
    TaskSpaceField,
    Controller,
    ControllerSettings,
    PassiveController,
    DimensionMismatchError,
    Ellipse,
    EnergyTooLowError,
    InvalidNavigationMatrixError,
    InvalidParameterError,
    JointNavigation,
    Lissajous,
    LogError,
    NoConvergenceError,
    NonFiniteError,
    PvfcError,
    PvfcIOError,
    Robot,
    Scara,
    Scenario,
    ScenarioError,
    Study,
    SimulationResult,
    SingularInertiaError,
    So3ConstantRate,
    So3Navigation,
    TorusNavigation,
    UrdfError,
    WaypointCurve,
    __version__,
    read_mcap,
    simulate,
    simulate_many,
    simulate_timed,
)
from .study import sweep

__all__ = [
    "ArmController",
    "CartesianPath",
    "TaskSpaceField",
    "Controller",
    "ControllerSettings",
    "PassiveController",
    "DimensionMismatchError",
    "Ellipse",
    "EnergyTooLowError",
    "InvalidNavigationMatrixError",
    "InvalidParameterError",
    "JointNavigation",
    "Lissajous",
    "LogError",
    "NoConvergenceError",
    "NonFiniteError",
    "PvfcError",
    "PvfcIOError",
    "Robot",
    "Scara",
    "Scenario",
    "ScenarioError",
    "Study",
    "SimulationResult",
    "SingularInertiaError",
    "So3ConstantRate",
    "So3Navigation",
    "TorusNavigation",
    "UrdfError",
    "WaypointCurve",
    "__version__",
    "read_mcap",
    "simulate",
    "simulate_many",
    "simulate_timed",
    "sweep",
]
