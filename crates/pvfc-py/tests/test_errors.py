"""Bad inputs raise the documented exceptions; nothing reachable raises PanicException."""

import math
import pathlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import pvfc


@pytest.fixture(scope="module")
def ctl():
    return pvfc.Controller(pvfc.Scenario.preset("fig8_R100"))


def test_exception_tree():
    for e in [pvfc.NonFiniteError, pvfc.EnergyTooLowError, pvfc.InvalidNavigationMatrixError, pvfc.InvalidParameterError,
              pvfc.SingularInertiaError, pvfc.DimensionMismatchError, pvfc.NoConvergenceError, pvfc.ScenarioError,
              pvfc.UrdfError, pvfc.LogError, pvfc.PvfcIOError]:
        assert issubclass(e, pvfc.PvfcError)
    assert issubclass(pvfc.PvfcError, Exception)


@pytest.mark.parametrize("bad", [[1.0], [1.0, 2.0, 3.0], [[1.0, 2.0]], np.zeros((2, 2)), []])
def test_wrong_shapes_raise_value_error_naming_the_argument(ctl, bad):
    with pytest.raises(ValueError, match="qdot"):
        ctl.step([0.0, 0.0], bad, 1e-3)
    with pytest.raises(ValueError, match="^q:"):
        ctl.torque(bad, [0.0, 0.0], 0.0, 0.0, 1.0)


def test_any_layout_and_dtype_is_accepted(ctl):
    a = ctl.torque(np.array([0.1, 0.2], dtype=np.float32), (0.0, 0.1), 0.0, 0.0, 60.0)
    base = np.arange(4.0)[::2] * 0.1  # a strided view
    b = ctl.torque(base, [0.0, 0.1], 0.0, 0.0, 60.0)
    c = ctl.torque([0, 0.2], np.asfortranarray([0.0, 0.1]), 0.0, 0.0, 60.0)
    assert a.shape == b.shape == c.shape == (4,)


def test_strings_raise_type_error(ctl):
    with pytest.raises(TypeError, match="q"):
        ctl.step("0.1", [0.0, 0.0], 1e-3)
    with pytest.raises(TypeError, match="q"):
        ctl.step(["a", "b"], [0.0, 0.0], 1e-3)
    with pytest.raises(TypeError):
        ctl.step([0.0, 0.0], [0.0, 0.0], "fast")


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_states_raise_non_finite_error(ctl, bad):
    before = ctl.state
    with pytest.raises(pvfc.NonFiniteError):
        ctl.step([bad, 0.0], [0.0, 0.0], 1e-3)
    assert ctl.state == before
    with pytest.raises(pvfc.NonFiniteError):
        ctl.torque([0.0, 0.0], [0.0, 0.0], bad, 0.0, 1.0)


def test_energy_too_low():
    d = pvfc.Scenario.preset("fig8_R100").to_dict()
    d["controller"]["energy"] = 1e-3
    c = pvfc.Controller(pvfc.Scenario.from_dict(d))
    with pytest.raises(pvfc.EnergyTooLowError, match="Ē"):
        c.torque([0.0, 1.5], [0.0, 0.0], 0.0, 0.0, 0.0)


def test_invalid_parameters():
    with pytest.raises(pvfc.InvalidNavigationMatrixError):
        pvfc.So3Navigation(np.eye(3))
    with pytest.raises(pvfc.InvalidParameterError):
        pvfc.TorusNavigation([1.0, -1.0])
    with pytest.raises(ValueError, match="convention"):
        pvfc.TorusNavigation([1.0, 1.0], "eq99")
    with pytest.raises(pvfc.InvalidParameterError):
        pvfc.Scara(m1=-1, m2=1, l1=1, l2=1, lc1=0.5, lc2=0.5, i1=1, i2=1)
    with pytest.raises(pvfc.NonFiniteError):
        pvfc.Lissajous([1, math.nan], [3, 6])
    with pytest.raises(pvfc.InvalidParameterError):
        pvfc.Lissajous([1, 1], [0, 6])
    with pytest.raises(ValueError, match="waypoints"):
        pvfc.WaypointCurve([[0, 0], [1, 1]], 1.0)
    with pytest.raises(pvfc.InvalidParameterError):
        pvfc.Controller(pvfc.Scenario.preset("fig8_R100")).step([0, 0], [0, 0], -1.0)


def test_urdf_errors(tmp_path, repo):
    with pytest.raises(pvfc.PvfcIOError):
        pvfc.Scara.from_urdf(tmp_path / "missing.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text((repo / "models" / "scara.urdf").read_text().replace('<axis xyz="0 0 1"/>', "", 1))
    with pytest.raises(pvfc.UrdfError, match="shoulder"):
        pvfc.Scara.from_urdf(bad)
    bad.write_text("<robot name='x'><link")
    with pytest.raises(pvfc.UrdfError):
        pvfc.Scara.from_urdf(bad)


def test_scenario_errors_name_the_field(tmp_path):
    with pytest.raises(pvfc.ScenarioError, match="gama"):
        pvfc.Scenario.from_toml('name = "x"\nduration = 1.0\n[controller]\ngama = 0.1\n')
    with pytest.raises(pvfc.ScenarioError, match="line 2"):
        pvfc.Scenario.from_toml('name = "x"\nduration = "ten"\n')
    with pytest.raises(pvfc.ScenarioError, match="gama"):
        pvfc.Scenario.from_dict({"name": "x", "duration": 1.0, "controller": {"gama": 0.1}})
    with pytest.raises(pvfc.ScenarioError, match="duration"):
        pvfc.Scenario.from_dict({"name": "x", "duration": -1.0})
    with pytest.raises(pvfc.PvfcIOError):
        pvfc.Scenario.from_file(tmp_path / "missing.toml")
    with pytest.raises(ValueError, match="name"):
        pvfc.Scenario.preset("fig99")


def test_log_errors(tmp_path):
    p = tmp_path / "bad.mcap"
    p.write_bytes(b"not an mcap file")
    with pytest.raises(pvfc.LogError):
        pvfc.read_mcap(p)


anything = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-10**6, 10**6),
    st.text(max_size=3),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4),
    st.lists(st.lists(st.floats(-1e6, 1e6), max_size=3), max_size=3),
    st.none(),
)


@settings(max_examples=500, deadline=None)
@given(q=anything, v=anything, dt=anything)
def test_fuzzed_inputs_raise_only_documented_exceptions(q, v, dt):
    c = pvfc.Controller(pvfc.Scenario.preset("fig9_R100"))
    try:
        out = c.step(q, v, dt)
    except (ValueError, TypeError, pvfc.PvfcError):
        return
    assert out.shape == (2,) and np.all(np.isfinite(out))


def test_huge_dt_is_an_error_not_a_hang():
    # Found by the fuzz test above: τ ~ 1e300 made the period wrap loop endless.
    c = pvfc.Controller(pvfc.Scenario.preset("fig9_R100"))
    before = c.state
    with pytest.raises(pvfc.NonFiniteError, match="dt"):
        c.step([0.0, 1.5], [0.5, 0.5], 1e300)
    assert c.state == before


# Issue "Faults survived": the inputs that hung, aborted or panicked are named errors.
CYCLE = """<robot name="r">
  <link name="r"/><link name="a"/><link name="b"/>
  <joint name="ab" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
  <joint name="ba" type="continuous"><parent link="b"/><child link="a"/><axis xyz="0 0 1"/></joint>
</robot>
"""


def test_a_urdf_whose_joints_form_a_cycle_is_an_error(tmp_path) -> None:
    f = tmp_path / "cycle.urdf"
    f.write_text(CYCLE, encoding="utf-8")
    with pytest.raises(pvfc.UrdfError, match="cycle"):
        pvfc.Robot.from_urdf(f, tip="a", base="r")


def test_a_bad_number_in_a_urdf_is_named_with_its_line(tmp_path, repo) -> None:
    text = (repo / "models" / "scara.urdf").read_text(encoding="utf-8")
    f = tmp_path / "bad.urdf"
    f.write_text(text.replace('<mass value="', '<mass value="x', 1), encoding="utf-8")
    with pytest.raises(pvfc.UrdfError, match=r"<mass> of link .*line \d+.*is not a number"):
        pvfc.Robot.from_urdf(f, tip="tool")


@pytest.mark.parametrize(
    "points",
    [
        [[1e308, 0.0, 0.0], [-1e308, 0.0, 0.0], [0.0, 1e308, 0.0]],
        [[0.0, 0.0, 0.0], [1e308, 1e308, 0.0], [-1e308, 1e308, 0.0]],
    ],
)
def test_a_path_whose_geometry_overflows_is_an_error_not_a_panic(points) -> None:
    with pytest.raises(pvfc.PvfcError, match="overflows"):
        pvfc.CartesianPath(points=points, corner_radius=0.01).length


@pytest.mark.parametrize("tau0", [math.nan, math.inf])
def test_a_contour_start_that_is_not_a_number_is_named(tau0) -> None:
    curve = pvfc.Lissajous([1.0, 1.5], [3.0, 6.0], period=6.0)
    settings = pvfc.ControllerSettings(energy=20.0, tau0=tau0)
    urdf = pathlib.Path(__file__).resolve().parents[3] / "models" / "scara.urdf"
    with pytest.raises((pvfc.PvfcError, ValueError), match="tau0"):
        pvfc.Controller.compose(pvfc.Robot.from_urdf(urdf, tip="tool"), curve, settings=settings)


@pytest.mark.parametrize("energy, inertia, gamma", [(1e308, 1.0, 1.0), (20.0, 1e-308, 1.0), (20.0, 1.0, 1e308)])
def test_settings_beyond_a_double_are_refused_when_built(repo, energy, inertia, gamma) -> None:
    curve = pvfc.Lissajous([1.0, 1.5], [3.0, 6.0], period=6.0)
    settings = pvfc.ControllerSettings(energy=energy, flywheel_inertia=inertia, gamma=gamma)
    robot = pvfc.Robot.from_urdf(repo / "models" / "scara.urdf", tip="tool")
    with pytest.raises((pvfc.PvfcError, ValueError), match="settings|energy|inertia|gamma"):
        pvfc.Controller.compose(robot, curve, settings=settings)
