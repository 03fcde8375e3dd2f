"""pvfc's rigid-body models against Pinocchio, the reference implementation, on the UR5 and
the Franka Panda of ``example-robot-data`` and six more of its arms (UR3, UR10, xArm 7, Z1,
SO-101, TALOS's left arm): M, C, Ṁ = C + Cᵀ, g, RNEA, the tool pose and the tool Jacobian at
1,000 random states each.

Conventions matched: Pinocchio's ``crba`` (upper triangle, mirrored), ``computeCoriolisMatrix``
(Christoffel-consistent, like pvfc's), ``computeGeneralizedGravity`` with Pinocchio's gravity
(−9.81 z; pvfc is given the same), the tool frame's ``oMf`` and its Jacobian in
``LOCAL_WORLD_ALIGNED`` (pvfc's ``frame="world"``) and ``LOCAL`` (``frame="local"``), rows
[linear; angular]. The Panda's finger joints are locked at 0 in Pinocchio
(``buildReducedModel``), as pvfc folds side branches.

The error measure is max|pvfc − Pinocchio| / max(1, max|Pinocchio|) per quantity and state.
"""

import os
import pathlib

import numpy as np
import pytest

import pvfc

try:
    import example_robot_data  # noqa: F401
except ImportError:  # the wheel of example-robot-data installs its files under cmeel.prefix
    pass

try:
    import pinocchio as pin
except ImportError:  # pragma: no cover - CI installs it (scripts/test.sh)
    if os.environ.get("CI"):
        raise
    pytest.skip("pinocchio (pip install pin) is not installed", allow_module_level=True)

REPO = pathlib.Path(__file__).resolve().parents[3]
STATES = 1000
TOL = 1e-10


def erd_robots() -> pathlib.Path:
    """The URDF folder of the installed example-robot-data."""
    import site
    import sys

    for base in [*site.getsitepackages(), sys.prefix]:
        p = pathlib.Path(base) / "cmeel.prefix" / "share" / "example-robot-data" / "robots"
        if p.is_dir():
            return p
    if os.environ.get("CI"):
        raise FileNotFoundError("example-robot-data is not installed")
    pytest.skip("example-robot-data is not installed")


# name: (the package's URDF, the copy shipped under models/ or None, the tip link, the
# joints Pinocchio locks at 0: a list, or None for every joint pvfc does not move).
ROBOTS = {
    "ur5": ("ur_description/urdf/ur5_robot.urdf", "ur5/ur5_robot.urdf", "tool0", []),
    "panda": (
        "panda_description/urdf/panda.urdf",
        "panda/panda.urdf",
        "panda_hand_tcp",
        ["panda_finger_joint1", "panda_finger_joint2"],
    ),
    # More arms of the package, read as a user would (none is shipped): the UR3 and UR10,
    # UFactory's xArm 7, Unitree's Z1, the SO-101 (its gripper frame a point mass fixed to
    # the wrist, folded in) and TALOS's left arm (the gripper locked, with the point masses
    # of its force sensor).
    "ur3": ("ur_description/urdf/ur3_robot.urdf", None, "tool0", []),
    "ur10": ("ur_description/urdf/ur10_robot.urdf", None, "tool0", []),
    "xarm7": ("xarm_description/urdf/xarm7.urdf", None, "link_eef", []),
    "z1": ("z1_description/urdf/z1.urdf", None, "gripperMover", []),
    "so101": ("so_arm_description/urdf/so101.urdf", None, "gripper_frame_link", None),
    "talos_left_arm": ("talos_data/robots/talos_left_arm.urdf", None, "arm_left_7_link", None),
}


def models(name: str):
    package_path, shipped, tip, locked = ROBOTS[name]
    urdf = erd_robots() / package_path
    if shipped is not None:
        # The copy shipped under models/ (used by the Rust tests and scenarios) is the
        # package's.
        assert (REPO / "models" / shipped).read_bytes() == urdf.read_bytes()
    model = pin.buildModelFromUrdf(str(urdf))
    robot = pvfc.Robot.from_urdf(str(urdf), tip=tip)
    if locked is None:
        locked = [j for j in model.names[1:] if j not in robot.joint_names]
    if locked:
        ids = [model.getJointId(j) for j in locked]
        model = pin.buildReducedModel(model, ids, pin.neutral(model))
    robot = robot.with_gravity(model.gravity.linear)
    assert robot.dof == model.nv == model.nq
    assert robot.joint_names == [model.names[i] for i in range(1, model.njoints)]
    assert sorted(robot.locked_joints) == sorted(locked)
    return robot, model, model.getFrameId(tip)


def rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(1.0, float(np.max(np.abs(b)))))


@pytest.mark.parametrize("name", list(ROBOTS))
def test_dynamics_and_kinematics_match_pinocchio(name: str) -> None:
    robot, model, frame = models(name)
    data = model.createData()
    rng = np.random.default_rng(7)
    worst: dict = {}

    def record(what: str, e: float) -> None:
        worst[what] = max(worst.get(what, 0.0), e)

    for _ in range(STATES):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        v = rng.uniform(-2.0, 2.0, model.nv)
        a = rng.uniform(-5.0, 5.0, model.nv)
        m_pin = pin.crba(model, data, q).copy()
        m_pin = np.triu(m_pin) + np.triu(m_pin, 1).T
        record("M", rel(robot.inertia(q), m_pin))
        c_pin = pin.computeCoriolisMatrix(model, data, q, v).copy()
        c = robot.coriolis(q, v)
        record("C", rel(c, c_pin))
        record("g", rel(robot.gravity(q), pin.computeGeneralizedGravity(model, data, q)))
        record("rnea", rel(robot.rnea(q, v, a), pin.rnea(model, data, q, v, a)))
        pin.framesForwardKinematics(model, data, q)
        record("tool pose", rel(robot.tool_pose(q), data.oMf[frame].homogeneous))
        pin.computeJointJacobians(model, data, q)
        for f, ref in [("world", pin.LOCAL_WORLD_ALIGNED), ("local", pin.LOCAL)]:
            j_pin = pin.getFrameJacobian(model, data, frame, ref)
            record(f"J {f}", rel(robot.jacobian(q, frame=f), j_pin))
        # Ṁ = C + Cᵀ against a 4th-order central difference of Pinocchio's M along v.
        h = 1e-3

        def m_at(t: float) -> np.ndarray:
            m = pin.crba(model, data, q + t * v).copy()
            return np.triu(m) + np.triu(m, 1).T

        m_dot = (m_at(-2 * h) - 8 * m_at(-h) + 8 * m_at(h) - m_at(2 * h)) / (12 * h)
        record("Ṁ = C + Cᵀ (vs FD)", rel(c + c.T, m_dot))

    print(name, {k: f"{e:.1e}" for k, e in worst.items()})
    fd = worst.pop("Ṁ = C + Cᵀ (vs FD)")
    assert fd < 1e-8, f"{name}: Ṁ = C + Cᵀ off by {fd:.2e} against finite differences"
    bad = {k: e for k, e in worst.items() if e > TOL}
    assert not bad, f"{name}: pvfc differs from Pinocchio: {bad}"


def test_pinocchio_check_can_fail() -> None:
    """The comparison is sensitive: a wrong gravity (9.80665 instead of Pinocchio's 9.81)
    is seen."""
    robot, model, _ = models("ur5")
    data = model.createData()
    q = np.full(model.nq, 0.4)
    off = robot.with_gravity([0.0, 0.0, -9.80665])
    assert rel(off.gravity(q), pin.computeGeneralizedGravity(model, data, q)) > 1e-5


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_the_tool_centre_point_is_pinocchios_frame(name: str) -> None:
    """``Robot.with_tool(xyz, rpy)`` against the same tool added to Pinocchio's model as a
    fixed frame on the tip's joint (placement: the tip frame's, then the TCP's): its pose
    ``oMf`` and its Jacobians (world and local) at 1,000 random states, to 1e-12."""
    robot, model, tip = models(name)
    xyz, rpy = [0.015, -0.02, 0.12], [0.3, -0.45, 0.8]
    tool = robot.with_tool(xyz, rpy)
    tcp = pin.SE3(pin.rpy.rpyToMatrix(*rpy), np.array(xyz))
    np.testing.assert_allclose(tool.tcp, tcp.homogeneous, rtol=0, atol=1e-15)
    parent = model.frames[tip]
    frame = model.addFrame(
        pin.Frame("tcp", parent.parentJoint, tip, parent.placement * tcp, pin.FrameType.OP_FRAME)
    )
    data = model.createData()
    rng = np.random.default_rng(13)
    worst = {"pose": 0.0, "J world": 0.0, "J local": 0.0, "tip moved": 0.0}
    for _ in range(STATES):
        q = rng.uniform(-np.pi, np.pi, model.nq)
        pin.framesForwardKinematics(model, data, q)
        pin.computeJointJacobians(model, data, q)
        worst["pose"] = max(worst["pose"], rel(tool.tool_pose(q), data.oMf[frame].homogeneous))
        for f, ref in [("world", pin.LOCAL_WORLD_ALIGNED), ("local", pin.LOCAL)]:
            j = pin.getFrameJacobian(model, data, frame, ref)
            worst[f"J {f}"] = max(worst[f"J {f}"], rel(tool.jacobian(q, frame=f), j))
        # The TCP is 12 cm and more from the flange: a check that confused the two would fail.
        worst["tip moved"] = max(worst["tip moved"], rel(robot.tool_pose(q), data.oMf[frame].homogeneous))
    print(name, {k: f"{e:.1e}" for k, e in worst.items()})
    assert worst.pop("tip moved") > 0.1
    bad = {k: e for k, e in worst.items() if e > 1e-12}
    assert not bad, f"{name}: the TCP differs from Pinocchio's frame: {bad}"
    with pytest.raises(pvfc.InvalidParameterError, match="xyz and rpy must be finite"):
        robot.with_tool([0.0, float("nan"), 0.1])
    with pytest.raises(ValueError):
        robot.with_tool([0.0, 0.1])


@pytest.mark.parametrize("name", ["ur5", "panda"])
def test_inverse_kinematics_lands_where_pinocchio_says(name: str) -> None:
    """pvfc's inverse kinematics, checked with Pinocchio's forward kinematics: the tool frame
    of the solution is at the target point (orientation free) or pose, to 1e-8."""
    robot, model, frame = models(name)
    data = model.createData()
    rng = np.random.default_rng(11)
    for _ in range(20):
        q_star = rng.uniform(-1.5, 1.5, model.nq)
        seed = q_star + rng.uniform(-0.2, 0.2, model.nq)
        pin.framesForwardKinematics(model, data, q_star)
        target = data.oMf[frame].homogeneous.copy()
        for goal in (target[:3, 3], target):
            q = robot.inverse_kinematics(goal, seed)
            pin.framesForwardKinematics(model, data, q)
            reached = data.oMf[frame].homogeneous
            if goal.shape == (3,):
                assert np.linalg.norm(reached[:3, 3] - goal) < 1e-8
            else:
                assert np.max(np.abs(reached - goal)) < 1e-8
        assert robot.manipulability(q_star) > 0.0
    with pytest.raises(pvfc.NoConvergenceError):
        robot.inverse_kinematics([5.0, 0.0, 0.0], np.zeros(model.nq))


# The same closed joint contour as the Rust tests and test_arm.py.
from test_arm import UR5_WAYPOINTS  # noqa: E402


@pytest.mark.parametrize("rate", [1000.0, 100.0])
def test_passive_arm_controller_on_a_pinocchio_plant(rate: float) -> None:
    """The passive digital mode of a ``Controller.arm`` drives the UR5 simulated by Pinocchio
    (``aba``, RK4 at 10 kHz, with gravity) at 1 kHz and 100 Hz, with gravity compensation and
    torque limits. At every sample the energy balance closes: kinetic + potential energy of
    the robot + the controller's storage, less what the add-ons (gravity compensation) put in,
    stays at its initial value to 1e-8 of Ē (the plant integrator's error); and U falls."""
    robot, model, _ = models("ur5")
    data = model.createData()
    energy = 20.0
    arm = pvfc.Controller.arm(
        robot, UR5_WAYPOINTS, 1.0, h=[4.0] * 6, self_pacing=20.0, energy=energy, gamma=1.0
    )
    limits = np.array([150.0, 150.0, 150.0, 28.0, 28.0, 28.0])
    ctl = pvfc.PassiveController(arm, torque_limit=limits)
    assert ctl.dof == 6
    q = np.array(UR5_WAYPOINTS[0]) + 0.2
    v = np.zeros(6)

    def robot_energy(q: np.ndarray, v: np.ndarray) -> float:
        return pin.computeKineticEnergy(model, data, q, v) + pin.computePotentialEnergy(
            model, data, q
        )

    def f(x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.concatenate([x[6:], pin.aba(model, data, x[:6], x[6:], u)])

    start = robot_energy(q, v) + ctl.storage
    add_ons, worst = 0.0, 0.0
    period, substeps = 1.0 / rate, int(round(1e4 / rate))
    h = period / substeps
    potentials = []
    x = np.concatenate([q, v])
    for _ in range(int(2.0 * rate)):
        u = ctl.step(x[:6], x[6:], period)
        assert np.all(np.abs(u) <= limits)
        e = ctl.energy
        add_ons += e["add_ons"]
        worst = max(worst, abs(robot_energy(x[:6], x[6:]) + e["storage"] - start - add_ons))
        potentials.append(arm.evaluate(x[:6], x[6:], *ctl.state[:3])["potential"])
        for _ in range(substeps):
            k1 = f(x, u)
            k2 = f(x + 0.5 * h * k1, u)
            k3 = f(x + 0.5 * h * k2, u)
            k4 = f(x + h * k3, u)
            x = x + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    # Gravity compensation did real work, so an account that left it out would fail.
    assert abs(add_ons) > 1e-2
    assert worst < 1e-8 * energy, worst
    assert potentials[-1] < 0.5 * potentials[0]


def test_passive_arm_controller_checks_its_arguments() -> None:
    robot, _, _ = models("ur5")
    arm = pvfc.Controller.arm(robot, UR5_WAYPOINTS, 1.0)
    with pytest.raises(ValueError, match="torque_limit"):
        pvfc.PassiveController(arm, torque_limit=[1.0] * 5)
    with pytest.raises(pvfc.InvalidParameterError):
        pvfc.PassiveController(arm, torque_limit=[1.0] * 5 + [-1.0])
    with pytest.raises(TypeError):
        pvfc.PassiveController(robot)
    ctl = pvfc.PassiveController(arm, velocity_filter=0.01)
    with pytest.raises(ValueError, match="applied"):
        ctl.step(np.zeros(6), None, 1e-3, applied=np.zeros(3))
    before = (ctl.state, ctl.storage)
    with pytest.raises(pvfc.NonFiniteError):
        ctl.step([np.nan] * 6, None, 1e-3)
    assert (ctl.state, ctl.storage) == before
    ctl.step(np.zeros(6), None, 1e-3)
    ctl.reset()
    assert (ctl.state, ctl.storage) == before and ctl.energy is None
