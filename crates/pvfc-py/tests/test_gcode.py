"""pvfc.CartesianPath(gcode=..., part=...): a part program's cutting moves as the tool path,
placed by the part's frame; the tool lands on it; a bad program names its line and column."""

import math

import numpy as np
import pytest

import pvfc

SEED = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]
PART = ([0.45, -0.15, 0.30], [0.0, 0.0, 0.1])


@pytest.fixture(scope="module")
def ur5(repo):
    return pvfc.Robot.from_urdf(repo / "models" / "ur5" / "ur5_robot.urdf", tip="tool0")


def test_the_bracket_program_is_its_exact_outline_placed_on_the_table(repo, ur5):
    program = repo / "scenarios" / "parts" / "bracket.nc"
    in_part = pvfc.CartesianPath(gcode=program, samples=64)
    placed = pvfc.CartesianPath(gcode=program, part=PART, samples=64)
    # Straight 820 mm, four 30 mm and four 10 mm quarter circles.
    exact = 0.820 + 2 * math.pi * (0.030 + 0.010)
    assert in_part.length == pytest.approx(exact, rel=1e-13)
    assert placed.length == pytest.approx(exact, rel=1e-13)
    # The placed samples are the part's, moved by the pose (yaw 0.1 rad, then the offset).
    c, s = math.cos(0.1), math.sin(0.1)
    rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    by_hand = in_part.sample() @ rotation.T + np.array(PART[0])
    np.testing.assert_allclose(placed.sample(), by_hand, atol=1e-15)
    # The UR5 reaches it with the tool pointing down, every waypoint on the path.
    q = placed.joint_waypoints(ur5, SEED, fixed_orientation=True)
    tool = np.array([ur5.tool_pose(qk)[:3, 3] for qk in q])
    assert np.max(placed.distances(tool)) < 1e-6


def test_a_bad_program_names_its_line_and_column(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text("G21 G90\nG0 X0 Y0\nG1 X10 F100\nG1 Y10 A3\nG1 X0 Y0\n")
    with pytest.raises(pvfc.InvalidParameterError, match=r"bad\.nc: line 4, column 8: A3"):
        pvfc.CartesianPath(gcode=bad)
    with pytest.raises(pvfc.InvalidParameterError, match="exactly one of"):
        pvfc.CartesianPath(gcode=bad, points=[[0, 0, 0], [1, 0, 0], [1, 1, 0]])
    with pytest.raises(pvfc.InvalidParameterError, match="contour.cartesian.part: xyz and rpy must be finite"):
        pvfc.CartesianPath(points=[[0, 0, 0], [1, 0, 0], [1, 1, 0]], part=([0, 0, math.nan], [0, 0, 0]))


def test_g64_blends_the_plates_sharp_corners_and_a_bad_g64_is_named(repo, tmp_path):
    plate = pvfc.CartesianPath(gcode=repo / "scenarios" / "parts" / "plate.nc", samples=64)
    sharp_text = (repo / "scenarios" / "parts" / "plate.nc").read_text().replace(" G64 P0.5", "")
    sharp = tmp_path / "sharp.nc"
    sharp.write_text(sharp_text)
    # Each blend shortens the path by 2 r tan(θ/2) − r θ, r = P / (1/cos(θ/2) − 1), P = 0.5 mm:
    # four corners of 90° (the rectangle's three, one where the contour closes, and the
    # notch's bottom) and four of 45° (the chamfer's two and the notch's mouth).
    def saved(turn):
        r = 0.5e-3 / (1.0 / math.cos(turn / 2) - 1.0)
        return 2 * r * math.tan(turn / 2) - r * turn

    exact = pvfc.CartesianPath(gcode=sharp, samples=64).length
    expected = exact - 4 * saved(math.pi / 2) - 4 * saved(math.pi / 4)
    assert plate.length == pytest.approx(expected, rel=1e-12)
    bad = tmp_path / "bad.nc"
    bad.write_text("G0 X0 Y0\nG64\nG1 X10\nG1 Y10\nG1 X0 Y0\n")
    with pytest.raises(pvfc.InvalidParameterError, match=r"bad\.nc: line 2, column 1: G64 needs P"):
        pvfc.CartesianPath(gcode=bad)


def test_a_part_programs_feeds_pace_the_field(repo, ur5):
    """``Controller.compose(..., pace={"feeds": path})``: on the contour the tool centre point's
    field velocity is the feed of the stretch it is on (the bracket's outline at F6000, its
    relief at F1800) away from the changes of speed, and never faster than the feed."""
    cone = ur5.with_tool([0.0, 0.0, 0.12], [0.0, 0.35, 0.0])
    path = pvfc.CartesianPath(
        gcode=repo / "scenarios" / "parts" / "bracket.nc", part=PART, tolerance=1e-5
    )
    q = path.joint_waypoints(cone, SEED, fixed_orientation=True)
    contour = pvfc.WaypointCurve(q, 12.0 / len(q))
    settings = pvfc.ControllerSettings(self_pacing=0.0, energy=0.0, gamma=1.0)
    ctl = pvfc.Controller.compose(cone, contour, settings=settings, pace={"feeds": path})
    taus = np.linspace(0.0, contour.period, 600, endpoint=False)
    speed, tool = [], []
    for tau in taus:
        qk = contour.sample(float(tau))[0]
        e = ctl.evaluate(qk, np.zeros(6), float(tau), 0.0, 1.0)
        speed.append(np.linalg.norm(cone.jacobian(qk)[:3] @ e["field_velocity"][:6]))
        tool.append(cone.tool_pose(qk)[:3, 3])
    speed = np.array(speed)
    along = path.closest(np.array(tool))["along"]
    outline = (along > 0.03) & (along < 0.11)  # inside the first straight edge (0–140 mm)
    relief = (along > 0.315) & (along < 0.372)  # inside the relief (307–380 mm)
    assert outline.sum() > 20 and relief.sum() > 10
    np.testing.assert_allclose(speed[outline], 0.1, rtol=0.01)
    np.testing.assert_allclose(speed[relief], 0.03, rtol=0.05)
    assert np.all(speed <= 0.1 * (1 + 1e-6))
    # feeds take a CartesianPath with F words; tool_speed covers moves without F.
    with pytest.raises(TypeError, match="feeds"):
        pvfc.Controller.compose(cone, contour, pace={"feeds": 0.1})
    circle = pvfc.CartesianPath(circle=([0.5, 0.0, 0.3], 0.1, [0.0, 0.0, 1.0]))
    with pytest.raises(ValueError, match="not a part program with F"):
        pvfc.Controller.compose(cone, contour, pace={"feeds": circle})
