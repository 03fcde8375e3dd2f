"""pvfc.CartesianPath: a closed tool path sampled and turned into joint waypoints by inverse
kinematics; the tool lands on the sampled points; failures name the waypoint."""

import numpy as np
import pytest

import pvfc

RECTANGLE = [[0.45, -0.15, 0.30], [0.65, -0.15, 0.30], [0.65, 0.20, 0.30], [0.45, 0.20, 0.30]]
SEED = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]


@pytest.fixture(scope="module")
def ur5(repo):
    return pvfc.Robot.from_urdf(repo / "models" / "ur5" / "ur5_robot.urdf", tip="tool0")


def test_the_tool_lands_on_the_sampled_path(ur5):
    for path in (
        pvfc.CartesianPath(points=RECTANGLE, corner_radius=0.03, samples=24),
        pvfc.CartesianPath(circle=([0.55, 0.02, 0.30], 0.1, [0.0, 0.0, 1.0]), samples=16),
    ):
        p = path.sample()
        q = path.joint_waypoints(ur5, SEED, fixed_orientation=True)
        assert q.shape == (p.shape[0], 6)
        tool = np.array([ur5.tool_pose(qk)[:3, 3] for qk in q])
        np.testing.assert_allclose(tool, p, atol=1e-6)
        assert np.max(path.distances(p)) < 1e-9
        # The tool keeps the seed's orientation.
        r0 = ur5.tool_pose(SEED)[:3, :3]
        for qk in q:
            np.testing.assert_allclose(ur5.tool_pose(qk)[:3, :3], r0, atol=1e-6)


def test_a_tool_leaning_along_the_path_keeps_its_roll_free(ur5):
    # The tool's axis against the table (the part's +z), leaning 0.2 rad towards the
    # direction of travel: at each waypoint the axis is 0.2 rad from the downward vertical,
    # leaning along the path's direction (the chord through the neighbouring samples stands
    # in for the tangent: within 0.3 rad on the corners).
    path = pvfc.CartesianPath(points=RECTANGLE, corner_radius=0.03, samples=32, tool_frame=(0.2, 0.0, None))
    p = path.sample()
    q = path.joint_waypoints(ur5, SEED)
    n = len(p)
    for k, qk in enumerate(q):
        pose = ur5.tool_pose(qk)
        np.testing.assert_allclose(pose[:3, 3], p[k], atol=1e-6)
        axis = pose[:3, 2]
        assert abs(np.arccos(-axis[2]) - 0.2) < 1e-6
        chord = p[(k + 1) % n] - p[k - 1]
        lean = axis[:2] / np.linalg.norm(axis[:2])
        assert lean @ chord[:2] / np.linalg.norm(chord[:2]) > np.cos(0.3)
    # The joints come back after the lap: no joint winds with the frame.
    assert np.max(np.abs(q[0] - q[-1])) < 0.3
    with pytest.raises(pvfc.InvalidParameterError, match="turns sharply"):
        pvfc.CartesianPath(points=RECTANGLE, tool_frame=(0.2, 0.0, None))
    with pytest.raises(pvfc.InvalidParameterError, match="give one of"):
        pvfc.CartesianPath(points=RECTANGLE, corner_radius=0.03, orientations=[[np.pi, 0, 0]] * 4, tool_frame=(0.0, 0.0, None))


def test_failures_name_the_waypoint(ur5):
    far = pvfc.CartesianPath(points=RECTANGLE[:2] + [[3.0, 0.2, 0.3]] + RECTANGLE[3:], samples=24)
    with pytest.raises(pvfc.InvalidParameterError, match="waypoint"):
        far.joint_waypoints(ur5, SEED, max_jump=10.0)
    path = pvfc.CartesianPath(points=RECTANGLE, samples=24)
    with pytest.raises(pvfc.InvalidParameterError, match="waypoint 1 .*branch jump"):
        path.joint_waypoints(ur5, SEED, max_jump=1e-3)
    with pytest.raises(ValueError):
        pvfc.CartesianPath(points=[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    with pytest.raises(pvfc.PvfcError):
        pvfc.CartesianPath(points=RECTANGLE, samples=2)
    with pytest.raises(ValueError):
        path.joint_waypoints(ur5, [0.0, 0.0])


def test_a_path_in_se3_and_a_rest_posture(ur5, repo):
    # The tool pointing down as at the seed (roll π about x), turned about z per corner.
    yaw = [0.0, 0.4, -0.3, 0.2]
    r0 = ur5.tool_pose(SEED)[:3, :3]

    def rpy(r):
        return [np.arctan2(r[2, 1], r[2, 2]), -np.arcsin(r[2, 0]), np.arctan2(r[1, 0], r[0, 0])]

    def rz(a):
        return np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])

    orientations = [rpy(rz(a) @ r0) for a in yaw]
    path = pvfc.CartesianPath(points=RECTANGLE, corner_radius=0.03, samples=24, orientations=orientations)
    q = path.joint_waypoints(ur5, SEED)
    # At the first sample (on corner 0's rounding) the tool is near corner 0's orientation;
    # the path turns the tool away from the seed's by more than 0.3 rad somewhere.
    angles = [
        np.arccos(np.clip((np.trace(ur5.tool_pose(qk)[:3, :3] @ r0.T) - 1) / 2, -1, 1)) for qk in q
    ]
    assert max(angles) > 0.3
    with pytest.raises(pvfc.InvalidParameterError, match="orientations"):
        pvfc.CartesianPath(points=RECTANGLE, orientations=orientations[:3])
    with pytest.raises(ValueError, match="orientations"):
        pvfc.CartesianPath(points=RECTANGLE, orientations=[[0.0, 0.0]] * 4)
    # A 7-joint arm pulled towards a rest posture in the null space still reaches the points.
    panda = pvfc.Robot.from_urdf(repo / "models" / "panda" / "panda.urdf", tip="panda_hand_tcp")
    seed = [0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8]
    p0 = panda.tool_pose(seed)[:3, 3]
    circle = pvfc.CartesianPath(circle=(p0 + [0.0, 0.1, 0.0], 0.1, [0.0, 0.0, 1.0]), samples=16)
    rest = [0.0, -0.3, 0.8, -2.2, 0.0, 2.0, 0.8]
    free = circle.joint_waypoints(panda, seed)
    pulled = circle.joint_waypoints(panda, seed, rest=rest, rest_gain=0.5)
    for qs in (free, pulled):
        tool = np.array([panda.tool_pose(qk)[:3, 3] for qk in qs])
        np.testing.assert_allclose(tool, circle.sample(), atol=1e-6)
    assert np.linalg.norm(pulled - rest, axis=1).mean() < 0.7 * np.linalg.norm(free - rest, axis=1).mean()
    with pytest.raises(ValueError, match="rest"):
        circle.joint_waypoints(panda, seed, rest=[0.0] * 6)


def test_an_ellipse_path(ur5):
    center, normal = np.array([0.55, 0.02, 0.30]), np.array([0.0, 0.0, 1.0])
    path = pvfc.CartesianPath(ellipse=(center, 0.12, 0.06, normal, [1.0, 0.0, 0.0]), samples=24)
    p = path.sample() - center
    np.testing.assert_allclose(p[0], [0.12, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose((p[:, 0] / 0.12) ** 2 + (p[:, 1] / 0.06) ** 2, 1.0, atol=1e-3)
    q = path.joint_waypoints(ur5, SEED, fixed_orientation=True)
    tool = np.array([ur5.tool_pose(qk)[:3, 3] for qk in q])
    np.testing.assert_allclose(tool, path.sample(), atol=1e-6)
    with pytest.raises(ValueError, match="not both"):
        pvfc.CartesianPath(circle=(center, 0.1, normal), ellipse=(center, 0.12, 0.06, normal, [1, 0, 0]))
