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
