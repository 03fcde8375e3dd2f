"""A part program on a robot, from Python: the bracket of `scenarios/parts/bracket.nc` (G1
lines, G2 and G3 arcs of both senses, feeds of 100 and 30 mm/s), placed on the table in the
part's frame, turned into the joint contour by inverse kinematics (adaptive sampling, 10 µm),
followed by PVFC paced by the program's feeds, with gravity compensation, in a 1 kHz loop
against the robot's own dynamics (semi-implicit Euler, `M v̇ = T − C v − g`). The UR5 (6
joints, tip `tool0`) or the Panda (7 joints, tip `panda_hand_tcp`), each with its own seed and
part placement. The same program is `part_program.rs` and `part_program.cpp`; the three print
the same numbers.

    python examples/side_by_side/part_program.py models/ur5/ur5_robot.urdf tool0
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
    tip = sys.argv[2] if len(sys.argv) > 2 else "tool0"
    robot = pvfc.Robot.from_urdf(urdf, tip=tip)
    n = robot.dof
    # The seed of the inverse kinematics and the part's place on the table, per robot.
    if n == 6:
        seed, part = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0], [0.45, -0.15, 0.30, 0.1]
    else:
        seed, part = [0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785], [0.35, -0.175, 0.30, 0.0]
    path = pvfc.CartesianPath(
        gcode="scenarios/parts/bracket.nc", part=(part[:3], [0.0, 0.0, part[3]])
    )
    waypoints = path.joint_waypoints(robot, seed, fixed_orientation=True)
    contour = pvfc.WaypointCurve(waypoints, 12.0 / len(waypoints))
    settings = pvfc.ControllerSettings(
        self_pacing=50.0, energy=400.0, coupling_rate=400.0, nominal_speed=(0.5, 1.0)
    )
    ctl = pvfc.Controller.compose(
        robot, contour, pvfc.JointNavigation([16.0] * n), settings, pace={"feeds": path}
    )
    q = [float(x) + 0.02 for x in ctl.contour_point(0.0)]
    v = [0.0] * n
    dt = 1e-3
    print("part_program (Python)")
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
