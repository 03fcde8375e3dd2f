// A part program on a robot, from C++: the bracket of scenarios/parts/bracket.nc (G1 lines, G2
// and G3 arcs of both senses, feeds of 100 and 30 mm/s), placed on the table in the part's
// frame, turned into the joint contour by inverse kinematics (adaptive sampling, 10 um),
// followed by PVFC paced by the program's feeds (a contour read from a part program carries
// them), with gravity compensation, in a 1 kHz loop against the robot's own dynamics
// (semi-implicit Euler, M v' = T - C v - g). The UR5 (6 joints, tip tool0) or the Panda
// (7 joints, tip panda_hand_tcp), each with its own seed and part placement. The same
// program is part_program.rs and part_program.py; the three print the same numbers.
//   part_program models/ur5/ur5_robot.urdf tool0
#include <pvfc.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

// x with M x = b (M symmetric positive definite, row-major n x n), by Cholesky with the loops
// in the order of the Rust and Python programs.
std::vector<double> solve(const std::vector<double> &m, const std::vector<double> &b) {
  const std::size_t n = b.size();
  std::vector<double> l(n * n, 0.0), y(n, 0.0), x(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j <= i; ++j) {
      double s = m[i * n + j];
      for (std::size_t k = 0; k < j; ++k) s -= l[i * n + k] * l[j * n + k];
      l[i * n + j] = i == j ? std::sqrt(s) : s / l[j * n + j];
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    double s = b[i];
    for (std::size_t k = 0; k < i; ++k) s -= l[i * n + k] * y[k];
    y[i] = s / l[i * n + i];
  }
  for (std::size_t i = n; i-- > 0;) {
    double s = y[i];
    for (std::size_t k = i + 1; k < n; ++k) s -= l[k * n + i] * x[k];
    x[i] = s / l[i * n + i];
  }
  return x;
}

}  // namespace

int main(int argc, char **argv) {
  const std::string urdf = argc > 1 ? argv[1] : "models/ur5/ur5_robot.urdf";
  const std::string tip = argc > 2 ? argv[2] : "tool0";
  try {
    const pvfc::Robot robot = pvfc::Robot::from_urdf_file(urdf, tip);
    const std::size_t n = robot.dof();
    // The seed of the inverse kinematics and the part's place on the table, per robot.
    const char *ur5 =
        "seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]\n"
        "part = { xyz = [0.45, -0.15, 0.30], rpy = [0.0, 0.0, 0.1] }\n";
    const char *panda =
        "seed = [0.0, -0.3, 0.0, -2.2, 0.0, 1.9, 0.785]\n"
        "part = { xyz = [0.35, -0.175, 0.30], rpy = [0.0, 0.0, 0.0] }\n";
    const std::string table = std::string("gcode = \"scenarios/parts/bracket.nc\"\n") +
                              "fixed_orientation = true\n" + (n == 6 ? ur5 : panda);
    const pvfc::Contour contour = pvfc::Contour::cartesian_toml(table, 12.0);
    pvfc::Settings s;
    s.self_pacing = 50.0;
    s.energy = 400.0;
    s.flywheel_inertia = 1.0;
    s.coupling_rate = 400.0;
    s.nominal_speed_c = 0.5;
    s.nominal_speed_r = 1.0;
    pvfc::Controller ctl(robot, contour, std::vector<double>(n, 16.0), s);
    std::vector<double> q = ctl.contour_point(0.0), v(n, 0.0), torque(n, 0.0);
    for (double &x : q) x += 0.02;
    std::vector<double> m(n * n), c(n * n), g(n), unused_m(n * n), unused_g(n), b(n);
    const double dt = 1e-3;
    std::printf("part_program (C++)\n");
    for (int k = 0; k <= 4000; ++k) {
      const pvfc_diagnostics d = ctl.step(q, v, dt, torque);
      if (k % 500 == 0) {
        const std::vector<double> xd = ctl.contour_point(d.tau);
        double e = 0.0;
        for (std::size_t i = 0; i < n; ++i) e += (q[i] - xd[i]) * (q[i] - xd[i]);
        std::printf("t %.1f tau %.6e tau_dot %.6e error %.6e\n", k * dt, d.tau, d.tau_dot,
                    std::sqrt(e));
      }
      robot.inertia(q, m);
      robot.dynamics(q, v, unused_m, c, unused_g);
      robot.gravity(q, g);
      for (std::size_t i = 0; i < n; ++i) {
        double sum = torque[i] - g[i];
        for (std::size_t j = 0; j < n; ++j) sum -= c[i * n + j] * v[j];
        b[i] = sum;
      }
      const std::vector<double> a = solve(m, b);
      for (std::size_t i = 0; i < n; ++i) {
        v[i] += dt * a[i];
        q[i] += dt * v[i];
      }
    }
    return 0;
  } catch (const pvfc::Error &e) {
    std::fprintf(stderr, "pvfc error %d: %s\n", static_cast<int>(e.status()), e.what());
    return 1;
  }
}
