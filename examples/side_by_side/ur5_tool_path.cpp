// The UR5 on a Cartesian tool path, from C++: a rounded rectangle 20 x 35 cm at 30 cm height,
// the tool pointing down, turned into the joint contour by inverse kinematics (adaptive
// sampling, 10 um), followed by PVFC with gravity compensation in a 1 kHz loop against the
// robot's own dynamics (semi-implicit Euler, M v' = T - C v - g). The same program is
// ur5_tool_path.rs and ur5_tool_path.py; the three print the same numbers.
//   ur5_tool_path models/ur5/ur5_robot.urdf
#include <pvfc.hpp>

#include <cmath>
#include <cstdio>
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
  try {
    const pvfc::Robot robot = pvfc::Robot::from_urdf_file(urdf, "tool0");
    const std::vector<double> corners = {0.45, -0.15, 0.30, 0.65, -0.15, 0.30,
                                         0.65, 0.20,  0.30, 0.45, 0.20,  0.30};
    const std::vector<double> seed = {0.0, -1.2, 1.4, -1.8, -1.57, 0.0};
    pvfc::CartesianOptions options;
    options.with_seed(seed);
    options.fixed_orientation = true;
    const pvfc::Contour contour = pvfc::Contour::cartesian_polygon(corners, 0.03, 12.0, options);
    pvfc::Settings s;
    s.self_pacing = 50.0;
    s.energy = 40.0;
    s.flywheel_inertia = 1.0;
    s.gamma = 10.0;
    pvfc::Controller ctl(robot, contour, std::vector<double>(6, 4.0), s);
    const std::size_t n = robot.dof();
    std::vector<double> q = ctl.contour_point(0.0), v(n, 0.0), torque(n, 0.0);
    for (double &x : q) x += 0.02;
    std::vector<double> m(n * n), c(n * n), g(n), unused_m(n * n), unused_g(n), b(n);
    const double dt = 1e-3;
    std::printf("ur5_tool_path (C++)\n");
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
