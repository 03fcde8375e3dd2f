// The UR5 on a closed joint contour through three postures, from C++ through the installed
// CMake package: build the controller, step it at a measured state, print the torque and the
// controller's numbers. In a real loop, q and qdot come from the robot at every period.
//   ur5_contour path/to/ur5_robot.urdf
#include <pvfc.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s ur5_robot.urdf\n", argv[0]);
    return 2;
  }
  try {
    const pvfc::Robot robot = pvfc::Robot::from_urdf_file(argv[1], "tool0");
    const std::vector<double> waypoints = {
        0.0, -1.2, 1.4, -1.8, -1.57, 0.0,   //
        0.3, -1.0, 1.2, -1.7, -1.57, 0.2,   //
        -0.2, -1.3, 1.5, -1.9, -1.57, -0.1,
    };
    pvfc::Settings s;
    s.energy = 40.0;
    s.self_pacing = 50.0;
    pvfc::Controller ctl = pvfc::Controller::waypoints(robot, waypoints, 1.5, {}, s);
    const std::array<double, 6> q = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
    const std::array<double, 6> qdot{};
    std::array<double, 6> torque{};
    const pvfc_diagnostics d = ctl.step(q, qdot, 1e-3, torque);
    std::printf("pvfc %s: U = %.4f, beta = %.4f, torque =", pvfc::version().c_str(), d.potential,
                d.beta);
    bool finite = true;
    for (double t : torque) {
      std::printf(" %.2f", t);
      finite = finite && std::isfinite(t);
    }
    std::printf(" N·m\n");
    return finite ? 0 : 1;
  } catch (const pvfc::Error &e) {
    std::fprintf(stderr, "pvfc error %d: %s\n", static_cast<int>(e.status()), e.what());
    return 1;
  }
}
