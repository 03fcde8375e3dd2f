"""The SCARA of `models/scara.urdf` on the paper's Lissajous contour, from Python: the robot
read from its URDF, the controller built, and a 1 kHz loop that steps it against the robot's
own dynamics (semi-implicit Euler, `M v̇ = T − C v − g`). The same program is
`scara_contour.rs` and `scara_contour.cpp`; the three print the same numbers.

    python examples/side_by_side/scara_contour.py models/scara.urdf
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
    urdf = sys.argv[1] if len(sys.argv) > 1 else "models/scara.urdf"
    robot = pvfc.Robot.from_urdf(urdf, tip="tool")
    contour = pvfc.Lissajous([1.0, 1.5], [3.0, 6.0], phase=[0.0, math.pi / 2], offset=[0.0, 0.0], period=6.0)
    settings = pvfc.ControllerSettings(self_pacing=5.0, energy=50.0, flywheel_inertia=1.0, gamma=1.0)
    ctl = pvfc.Controller.compose(robot, contour, pvfc.JointNavigation([1.0, 1.0]), settings)
    n = robot.dof
    q = [float(x) + 0.1 for x in ctl.contour_point(0.0)]
    v = [0.0] * n
    dt = 1e-3
    print("scara_contour (Python)")
    for k in range(6001):
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
