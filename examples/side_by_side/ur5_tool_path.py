"""The UR5 on a Cartesian tool path, from Python: a rounded rectangle 20 × 35 cm at 30 cm
height, the tool pointing down, turned into the joint contour by inverse kinematics (adaptive
sampling, 10 µm), followed by PVFC with gravity compensation in a 1 kHz loop against the
robot's own dynamics (semi-implicit Euler, `M v̇ = T − C v − g`). The same program is
`ur5_tool_path.rs` and `ur5_tool_path.cpp`; the three print the same numbers.

    python examples/side_by_side/ur5_tool_path.py models/ur5/ur5_robot.urdf
"""

import math
import sys

import pvfc


def solve(m, b):
    """x with M x = b (M symmetric positive definite), by Cholesky with the loops in the
    order of the Rust and C++ programs."""
    n = len(b)
    l = [[0.0] * n for _ in range(n)]
    for i in range(n):
        for j in range(i + 1):
            s = float(m[i][j])
            for k in range(j):
                s -= l[i][k] * l[j][k]
            l[i][j] = math.sqrt(s) if i == j else s / l[j][j]
    y = [0.0] * n
    for i in range(n):
        s = float(b[i])
        for k in range(i):
            s -= l[i][k] * y[k]
        y[i] = s / l[i][i]
    x = [0.0] * n
    for i in reversed(range(n)):
        s = y[i]
        for k in range(i + 1, n):
            s -= l[k][i] * x[k]
        x[i] = s / l[i][i]
    return x


def main() -> None:
    urdf = sys.argv[1] if len(sys.argv) > 1 else "models/ur5/ur5_robot.urdf"
    robot = pvfc.Robot.from_urdf(urdf, tip="tool0")
    corners = [[0.45, -0.15, 0.30], [0.65, -0.15, 0.30], [0.65, 0.20, 0.30], [0.45, 0.20, 0.30]]
    path = pvfc.CartesianPath(points=corners, corner_radius=0.03)
    waypoints = path.joint_waypoints(robot, [0.0, -1.2, 1.4, -1.8, -1.57, 0.0], fixed_orientation=True)
    contour = pvfc.WaypointCurve(waypoints, 12.0 / len(waypoints))
    settings = pvfc.ControllerSettings(self_pacing=50.0, energy=40.0, flywheel_inertia=1.0, gamma=10.0)
    ctl = pvfc.Controller.compose(robot, contour, pvfc.JointNavigation([4.0] * 6), settings)
    n = robot.dof
    q = [float(x) + 0.02 for x in ctl.contour_point(0.0)]
    v = [0.0] * n
    dt = 1e-3
    print("ur5_tool_path (Python)")
    for k in range(4001):
        tau, tau_dot, _, _ = ctl.state
        torque = ctl.step(q, v, dt)
        if k % 500 == 0:
            xd = ctl.contour_point(tau)
            e = math.sqrt(sum((a - float(b)) * (a - float(b)) for a, b in zip(q, xd)))
            print(f"t {k * dt:.1f} tau {tau:.6e} tau_dot {tau_dot:.6e} error {e:.6e}")
        m, c, g = robot.inertia(q), robot.coriolis(q, v), robot.gravity(q)
        b = [0.0] * n
        for i in range(n):
            s = float(torque[i]) - float(g[i])
            for j in range(n):
                s -= float(c[i][j]) * v[j]
            b[i] = s
        a = solve(m, b)
        for i in range(n):
            v[i] += dt * a[i]
            q[i] += dt * v[i]


if __name__ == "__main__":
    main()
