"""A contour in one place: `[contour]` holds one table named for its kind; `pvfc.JointCurve`
builds any joint-space kind from its dict, as the scenario files and the C ABI read it."""

import numpy as np
import pytest

import pvfc


def test_a_joint_curve_from_its_dict_is_the_typed_curve() -> None:
    center, u, w = [0.0, -1.4, 1.6], [0.5, 0.2, 0.0], [0.0, 0.2, 0.3]
    by_dict = pvfc.JointCurve({"ellipse": {"center": center, "u": u, "w": w, "period": 8.0}})
    typed = pvfc.Ellipse(center, u, w, 8.0)
    assert by_dict.kind == "ellipse" and by_dict.dim == 3 and by_dict.period == 8.0
    for tau in [0.0, 1.3, 4.0, 7.9]:
        for a, b in zip(by_dict.sample(tau), typed.sample(tau)):
            np.testing.assert_array_equal(a, b)
    again = pvfc.JointCurve(by_dict.to_dict())
    np.testing.assert_array_equal(again.sample(2.5)[0], typed.sample(2.5)[0])
    lissajous = pvfc.JointCurve({"lissajous": {"amplitude": [1.0, 1.5], "periods": [3.0, 6.0]}})
    np.testing.assert_array_equal(
        lissajous.sample(1.0)[0], pvfc.Lissajous([1.0, 1.5], [3.0, 6.0]).sample(1.0)[0]
    )


def test_a_joint_curve_is_the_typed_curve_to_the_drive_limited_pace(repo) -> None:
    robot = pvfc.Robot.from_urdf(repo / "models" / "scara.urdf")
    spec = {"amplitude": [1.0, 1.5], "periods": [3.0, 6.0], "phase": [0.0, 1.5707963267948966], "period": 6.0}
    curve = pvfc.JointCurve({"lissajous": spec})
    typed = pvfc.Lissajous(spec["amplitude"], spec["periods"], phase=spec["phase"], period=6.0)
    limits = [60.0, 20.0]
    np.testing.assert_array_equal(
        robot.drive_limited_rates(curve, limits, points=64),
        robot.drive_limited_rates(typed, limits, points=64),
    )


@pytest.mark.parametrize(
    "spec, named",
    [
        ({"spiral": {"turns": 3}}, "unknown variant `spiral`"),
        ({"ellipse": {"center": [0.0], "u": [1.0], "period": 2.0}}, "contour.ellipse: missing field `w`"),
        ({"lissajous": {"amplitude": [1.0], "periods": [1.0]}, "ellipse": {}}, "one kind of contour"),
        ({"attitude": {"rate": [0.0, 0.0, 1.0]}}, "not a joint-space curve"),
        ({"ellipse": {"center": [0.0, 0.0], "u": [1.0], "w": [0.0, 1.0], "period": 2.0}}, "ellipse.u"),
    ],
)
def test_a_bad_dict_names_what_is_wrong(spec: dict, named: str) -> None:
    with pytest.raises((ValueError, pvfc.PvfcError), match=named):
        pvfc.JointCurve(spec)


def test_a_scenario_dict_in_the_form_before_kinds_warns() -> None:
    d = pvfc.Scenario.preset("fig8_R100").to_dict()
    assert list(d["contour"]) == ["lissajous"]
    old = dict(d)
    old["contour"] = dict(d["contour"]["lissajous"])
    with pytest.warns(DeprecationWarning, match=r"\[contour.lissajous\]"):
        s = pvfc.Scenario.from_dict(old)
    assert s.to_dict()["contour"] == d["contour"]
