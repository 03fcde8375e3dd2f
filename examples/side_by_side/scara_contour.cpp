// The SCARA of models/scara.urdf on the paper's Lissajous contour, from C++: the robot read
// from its URDF, the controller built, and a 1 kHz loop that steps it against the robot's own
// dynamics (semi-implicit Euler, M v' = T - C v - g). The same program is scara_contour.rs and
// scara_contour.py; the three print the same numbers.
//   scara_contour models/scara.urdf
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
  const std::string urdf = argc > 1 ? argv[1] : "models/scara.urdf";
  try {
    const pvfc::Robot robot = pvfc::Robot::from_urdf_file(urdf, "tool");
    const std::vector<double> amplitude = {1.0, 1.5}, periods = {3.0, 6.0},
                              phase = {0.0, M_PI / 2}, offset = {0.0, 0.0};
    const pvfc::Contour contour = pvfc::Contour::lissajous(amplitude, periods, 6.0, phase, offset);
    pvfc::Settings s;
    s.self_pacing = 5.0;
    s.energy = 50.0;
    s.flywheel_inertia = 1.0;
    s.gamma = 1.0;
    pvfc::Controller ctl(robot, contour, std::vector<double>{1.0, 1.0}, s);
    const std::size_t n = robot.dof();
    std::vector<double> q = ctl.contour_point(0.0), v(n, 0.0), torque(n, 0.0);
    for (double &x : q) x += 0.1;
    std::vector<double> m(n * n), c(n * n), g(n), unused_m(n * n), unused_g(n), b(n);
    const double dt = 1e-3;
    std::printf("scara_contour (C++)\n");
    for (int k = 0; k <= 6000; ++k) {
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
