// The C++ header (pvfc.hpp) against the C library, with GoogleTest: RAII handles, exceptions
// by kind with the library's messages, views over std::array, std::vector and raw pointers,
// and the same torques as the C ABI. The URDF's path comes from the environment
// (PVFC_UR5_URDF) or the repository layout.
#include "pvfc.hpp"

#include <gtest/gtest.h>

#if __has_include(<Eigen/Core>)
#include <Eigen/Core>
#define PVFC_TEST_EIGEN 1
#endif

#include <array>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace {

std::string ur5_urdf() {
  const char *p = std::getenv("PVFC_UR5_URDF");
  return p ? p : "models/ur5/ur5_robot.urdf";
}

const std::vector<double> kWaypoints = {
    0.0, -1.2, 1.4, -1.8, -1.57, 0.0,   //
    0.3, -1.0, 1.2, -1.7, -1.57, 0.2,   //
    -0.2, -1.3, 1.5, -1.9, -1.57, -0.1,
};

pvfc::Settings settings() {
  pvfc::Settings s;
  s.energy = 40.0;
  s.self_pacing = 50.0;
  return s;
}

template <class E>
void expect_throw_containing(void (*f)(), const std::string &fragment) {
  try {
    f();
    ADD_FAILURE() << "no exception";
  } catch (const E &e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

}  // namespace

TEST(Robot, ReadsTheUr5AndNamesWhatIsWrong) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  EXPECT_EQ(robot.dof(), 6u);
  try {
    pvfc::Robot::from_urdf_file("/nonexistent/robot.urdf");
    ADD_FAILURE() << "no exception";
  } catch (const pvfc::IoError &e) {
    EXPECT_EQ(e.status(), PVFC_ERROR_IO);
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.urdf"), std::string::npos);
  }
  EXPECT_THROW(pvfc::Robot::from_urdf_file(ur5_urdf(), "nowhere"), pvfc::UrdfError);
  EXPECT_THROW(pvfc::Robot::from_urdf_string("<robot", "", "", "broken.urdf"), pvfc::UrdfError);
  // Every kind is a pvfc::Error and a std::runtime_error.
  EXPECT_THROW(pvfc::Robot::from_urdf_file(ur5_urdf(), "nowhere"), std::runtime_error);
}

TEST(Controller, StepsWithArraysAndVectorsAsTheCAbiDoes) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  pvfc::Controller ctl = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  ASSERT_EQ(ctl.dof(), 6u);
  // The same controller through the C ABI.
  pvfc_settings s = settings();
  pvfc_controller *c = nullptr;
  ASSERT_EQ(pvfc_controller_new_waypoints(robot.get(), kWaypoints.data(), 3, 6, 1.5, nullptr, 0,
                                          &s, &c),
            PVFC_OK);
  std::array<double, 6> q = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  const std::vector<double> v = {0.2, -0.1, 0.05, 0.0, 0.1, -0.2};
  std::array<double, 6> torque{};
  double expected[6];
  for (int k = 0; k < 20; ++k) {
    const pvfc_diagnostics d = ctl.step(q, v, 1e-3, torque);
    ASSERT_EQ(pvfc_controller_step(c, q.data(), v.data(), 6, 1e-3, expected, 6, nullptr), PVFC_OK);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(torque[i], expected[i]);
    EXPECT_TRUE(std::isfinite(d.beta));
    q[0] += 1e-3;
  }
  pvfc_controller_destroy(c);
  // A raw pointer and a length are a view too.
  std::vector<double> out(6);
  ctl.step(pvfc::In(q.data(), q.size()), v, 1e-3, pvfc::Out(out.data(), out.size()));
  const std::vector<double> xd = ctl.contour_point(0.0);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(xd[i], kWaypoints[i], 1e-12);
}

TEST(Controller, BadInputThrowsTheErrorOfItsKindAndChangesNothing) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  pvfc::Controller ctl = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  std::array<double, 6> q = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  const std::array<double, 6> v{};
  std::array<double, 6> first{}, again{};
  ctl.step(q, v, 1e-3, first);
  ctl.reset();
  std::array<double, 6> bad = q;
  bad[2] = std::numeric_limits<double>::quiet_NaN();
  try {
    ctl.step(bad, v, 1e-3, again);
    ADD_FAILURE() << "no exception";
  } catch (const pvfc::NonFiniteError &e) {
    EXPECT_NE(std::string(e.what()).find("q[2]"), std::string::npos) << e.what();
  }
  std::array<double, 5> short_q{};
  std::array<double, 5> short_v{};
  EXPECT_THROW(ctl.step(short_q, short_v, 1e-3, again), pvfc::WrongSizeError);
  EXPECT_THROW(ctl.step(q, v, -1.0, again), pvfc::InvalidArgumentError);
  std::array<double, 3> small{};
  EXPECT_THROW(ctl.step(q, v, 1e-3, small), pvfc::WrongSizeError);
  ctl.step(q, v, 1e-3, again);
  EXPECT_EQ(first, again);
  pvfc::Settings s = settings();
  s.energy = -1.0;
  EXPECT_THROW(pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, s),
               pvfc::InvalidArgumentError);
  const std::vector<double> ragged(kWaypoints.begin(), kWaypoints.end() - 1);
  EXPECT_THROW(pvfc::Controller::waypoints(robot, ragged, 1.5), pvfc::WrongSizeError);
}

TEST(Controller, TryStepReturnsTheStatusInsteadOfThrowing) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  pvfc::Controller ctl = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  const std::array<double, 6> q = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  const std::array<double, 6> v{};
  std::array<double, 6> thrown{}, tried{};
  const pvfc_diagnostics d = ctl.step(q, v, 1e-3, thrown);
  ctl.reset();
  pvfc_diagnostics e{};
  EXPECT_EQ(ctl.try_step(q, v, 1e-3, tried, &e), PVFC_OK);
  EXPECT_EQ(thrown, tried);
  EXPECT_EQ(d.potential, e.potential);
  std::array<double, 6> bad = q;
  bad[2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(ctl.try_step(bad, v, 1e-3, tried), PVFC_ERROR_NON_FINITE);
  EXPECT_NE(std::string(pvfc_last_error()).find("q[2] is NaN"), std::string::npos);
  EXPECT_EQ(ctl.try_step(q, v, -1.0, tried), PVFC_ERROR_INVALID_ARGUMENT);
  const std::array<double, 5> short_v{};
  EXPECT_EQ(ctl.try_step(q, short_v, 1e-3, tried), PVFC_ERROR_WRONG_SIZE);
  std::array<double, 3> small{};
  EXPECT_EQ(ctl.try_step(q, v, 1e-3, small), PVFC_ERROR_WRONG_SIZE);
  EXPECT_NE(std::string(pvfc_last_error()).find("torque_out: room for 3"), std::string::npos);

  pvfc::PassiveController p(ctl);
  pvfc_energy_account a{};
  EXPECT_EQ(p.try_step(q, 1e-3, tried, v, {}, &a), PVFC_OK);
  EXPECT_TRUE(std::isfinite(a.storage));
  EXPECT_EQ(p.try_step(bad, 1e-3, tried), PVFC_ERROR_NON_FINITE);
  EXPECT_EQ(p.try_step(q, 1e-3, tried, short_v), PVFC_ERROR_WRONG_SIZE);
}

TEST(Handles, MoveAndFreeOnce) {
  pvfc::Robot a = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  pvfc::Robot b = std::move(a);
  EXPECT_EQ(b.dof(), 6u);
  EXPECT_EQ(a.dof(), 0u);  // NOLINT: a moved-from handle is empty
  pvfc::Controller c = pvfc::Controller::waypoints(b, kWaypoints, 1.5);
  pvfc::Controller d = std::move(c);
  EXPECT_EQ(d.dof(), 6u);
  d = pvfc::Controller::waypoints(b, kWaypoints, 2.0);
  EXPECT_EQ(d.dof(), 6u);
}

TEST(Passive, StaysWithinItsTorqueLimits) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  const pvfc::Controller ctl = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  const std::array<double, 6> limit = {150, 150, 150, 28, 28, 28};
  pvfc::PassiveOptions o;
  o.torque_limit = limit.data();
  o.n = limit.size();
  pvfc::PassiveController p(ctl, o);
  const std::array<double, 6> q = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  std::array<double, 6> torque{};
  for (int k = 0; k < 10; ++k) {
    const pvfc_energy_account a = p.step(q, 1e-3, torque);
    for (int i = 0; i < 6; ++i) EXPECT_LE(std::abs(torque[i]), limit[i]);
    EXPECT_GE(a.scale, 0.0);
    EXPECT_LE(a.scale, 1.0);
  }
  EXPECT_TRUE(std::isfinite(p.storage()));
  o.n = 2;
  EXPECT_THROW(pvfc::PassiveController(ctl, o), pvfc::WrongSizeError);
}

TEST(Passive, AThrottledPaceSlowsOnWeakDrives) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  const pvfc::Controller ctl = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  const std::array<double, 6> weak = {2, 2, 2, 1, 1, 1};
  pvfc::PassiveOptions o;
  o.torque_limit = weak.data();
  o.n = weak.size();
  o.pace_throttle_time_constant = 0.05;
  pvfc::PassiveController p(ctl, o);
  EXPECT_EQ(p.pace_scale(), 1.0);
  const std::array<double, 6> q = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  std::array<double, 6> torque{};
  for (int k = 0; k < 20; ++k) p.step(q, 1e-3, torque);
  EXPECT_LT(p.pace_scale(), 0.9);
  EXPECT_GE(p.pace_scale(), o.pace_throttle_floor);
  o.pace_throttle_floor = 0.0;
  EXPECT_THROW(pvfc::PassiveController(ctl, o), pvfc::InvalidArgumentError);
}

TEST(Passive, APaceIsLearnedOnlyWhereOneIsPlannedAlongAClosedContour) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  // Waypoints at a uniform pace: no planned pace to learn, a named error.
  const pvfc::Controller ctl = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  const std::array<double, 6> drives = {150, 150, 150, 28, 28, 28};
  pvfc::PassiveOptions o;
  o.torque_limit = drives.data();
  o.n = drives.size();
  o.pace_learning_target = 1.0;
  try {
    pvfc::PassiveController p(ctl, o);
    ADD_FAILURE() << "a controller without a planned pace learned one";
  } catch (const pvfc::InvalidArgumentError &e) {
    EXPECT_NE(std::string(e.what()).find("no pace to learn"), std::string::npos) << e.what();
  }
  o.pace_learning_slope = 0.0;
  EXPECT_THROW(pvfc::PassiveController(ctl, o), pvfc::InvalidArgumentError);
}

TEST(Passive, AFaultIsTheSafeTorqueNotAnException) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  const pvfc::Controller ctl = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  const std::array<double, 6> max_speed = {3, 3, 3, 6, 6, 6};
  pvfc::PassiveOptions o;
  o.max_speed = max_speed.data();
  o.n = max_speed.size();
  o.min_period = 5e-4;
  o.max_period = 3e-3;
  pvfc::PassiveController p(ctl, o);
  std::array<double, 6> q = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  std::array<double, 6> torque{};
  EXPECT_EQ(p.step(q, 1e-3, torque).fault, PVFC_FAULT_NONE);
  q[3] = std::numeric_limits<double>::infinity();
  pvfc_energy_account a{};
  EXPECT_NO_THROW(a = p.step(q, 1e-3, torque));
  EXPECT_EQ(a.fault, PVFC_FAULT_NON_FINITE);
  for (double t : torque) EXPECT_EQ(t, 0.0);
  q[3] = -1.7 + 0.4;  // 0.4 rad in 2 ms: beyond 6 rad/s
  EXPECT_EQ(p.try_step(q, 1e-3, torque, {}, {}, &a), PVFC_FAULT);
  EXPECT_EQ(a.fault, PVFC_FAULT_SPEED);
  EXPECT_EQ(a.fault_joint, 3);
  EXPECT_NE(std::string(pvfc_last_error()).find("joint 3"), std::string::npos);
  q[3] = -1.7;
  EXPECT_EQ(p.try_step(q, 1e-3, torque, {}, {}, &a), PVFC_OK);
  EXPECT_EQ(a.fault, PVFC_FAULT_NONE);
}

TEST(Contour, ACartesianCircleWithTheTaskFieldFromEigenFreeViews) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  const std::array<double, 6> seed = {0.0, -1.2, 1.4, -1.8, -1.57, 0.0};
  pvfc::CartesianOptions options;
  options.with_seed(seed);
  options.fixed_orientation = true;
  options.task_field = true;
  const std::array<double, 3> center = {0.55, 0.0, 0.3}, normal = {0.0, 0.0, 1.0};
  const pvfc::Contour circle =
      pvfc::Contour::cartesian_circle(center, normal, 0.1, 10.0, options);
  pvfc::Controller ctl(robot, circle, {}, settings());
  std::array<double, 6> torque{};
  const std::array<double, 6> qdot{};
  const pvfc_diagnostics d = ctl.step(seed, qdot, 1e-3, torque);
  EXPECT_GT(d.potential, 0.0);
  // The same circle from its TOML table: the same controller.
  const pvfc::Contour same = pvfc::Contour::cartesian_toml(
      "seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]\nfixed_orientation = true\ntask = {}\n"
      "circle = { center = [0.55, 0.0, 0.3], radius = 0.1, normal = [0.0, 0.0, 1.0] }\n",
      10.0);
  pvfc::Controller twin(robot, same, {}, settings());
  std::array<double, 6> torque2{};
  twin.step(seed, qdot, 1e-3, torque2);
  EXPECT_EQ(torque, torque2);
  // The tool at the seed is off the circle by a known amount.
  std::array<double, 3> p{};
  robot.tool_pose(seed, pvfc::Out(nullptr, 0), p);
  const double radial = std::hypot(p[0] - 0.55, p[1]) - 0.1;
  EXPECT_NEAR(circle.distance(p), std::hypot(radial, p[2] - 0.3), 1e-12);
  EXPECT_THROW(pvfc::Contour::cartesian_toml("radious = 1", 10.0), pvfc::InvalidArgumentError);
  // A circle beyond the UR5's reach: the waypoint is named.
  const pvfc::Contour far = pvfc::Contour::cartesian_circle(center, normal, 1.0, 10.0, options);
  try {
    pvfc::Controller unreachable(robot, far);
    ADD_FAILURE() << "no exception";
  } catch (const pvfc::WaypointError &e) {
    EXPECT_NE(std::string(e.what()).find("waypoint"), std::string::npos) << e.what();
  }
}

TEST(Robot, TheToolCentrePointMovesTheToolPose) {
  pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  const std::array<double, 6> q = {0.2, -1.1, 1.2, -0.5, 1.0, 0.3};
  std::array<double, 9> r0{};
  std::array<double, 3> p0{}, p1{};
  robot.tool_pose(q, r0, p0);
  robot.set_tool(std::vector<double>{0.0, 0.0, 0.12});
  robot.tool_pose(q, pvfc::Out(nullptr, 0), p1);
  for (int i = 0; i < 3; i++) EXPECT_NEAR(p1[i], p0[i] + 0.12 * r0[3 * i + 2], 1e-12);
  EXPECT_THROW(robot.set_tool(std::vector<double>{0.0, 0.12}), pvfc::WrongSizeError);
  EXPECT_THROW(robot.set_tool(std::vector<double>{0.0, NAN, 0.12}), pvfc::NonFiniteError);
  std::array<double, 3> p2{};
  robot.tool_pose(q, pvfc::Out(nullptr, 0), p2);
  EXPECT_EQ(p1, p2);
}

TEST(Contour, JointCurvesAreTheirFormulas) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  const std::vector<double> c = {0.0, -1.2, 1.4, -1.8, -1.57, 0.0};
  const std::vector<double> u = {0.1, 0, 0, 0, 0, 0}, w = {0, 0.2, 0, 0, 0, 0};
  const pvfc::Controller ellipse(robot, pvfc::Contour::ellipse(c, u, w, 3.0));
  const std::vector<double> x = ellipse.contour_point(0.75);  // a quarter turn: c + w
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(x[i], c[i] + w[i], 1e-12);
  const std::vector<double> a = {0.2, 0.1, 0.1, 0.1, 0.1, 0.1}, t = {4, 4, 4, 4, 4, 4};
  const pvfc::Controller lissajous(robot, pvfc::Contour::lissajous(a, t, 4.0, {}, c));
  const std::vector<double> y = lissajous.contour_point(1.0);  // sin(π/2) = 1
  for (std::size_t i = 0; i < 6; ++i) EXPECT_NEAR(y[i], c[i] + a[i], 1e-12);
  EXPECT_THROW(pvfc::Contour::ellipse(c, u, std::vector<double>{0.0}, 3.0), pvfc::WrongSizeError);
}

TEST(Robot, DynamicsInOnePassAndRnea) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  const std::array<double, 6> q = {0.3, -1.1, 1.2, -0.7, -1.4, 0.5};
  const std::array<double, 6> v = {0.4, -0.3, 0.2, 0.5, -0.6, 0.1};
  const std::array<double, 6> a = {1.0, -0.5, 0.3, 0.0, 2.0, -1.0};
  std::array<double, 36> m{}, c{}, m2{};
  std::array<double, 6> g{}, tau{};
  robot.dynamics(q, v, m, c, g);
  robot.inertia(q, m2);
  robot.rnea(q, v, a, tau);
  for (std::size_t i = 0; i < 6; ++i) {
    double expected = g[i];
    for (std::size_t j = 0; j < 6; ++j) {
      EXPECT_NEAR(m[6 * i + j], m2[6 * i + j], 1e-12);
      expected += m[6 * i + j] * a[j] + c[6 * i + j] * v[j];
    }
    EXPECT_NEAR(tau[i], expected, 1e-10 * (1.0 + std::abs(expected)));
  }
  std::array<double, 5> small{};
  EXPECT_THROW(robot.gravity(q, small), pvfc::WrongSizeError);
}

#ifdef PVFC_TEST_EIGEN
TEST(Views, TakeEigenVectorsAndMapsWithoutCopying) {
  const pvfc::Robot robot = pvfc::Robot::from_urdf_file(ur5_urdf(), "tool0");
  pvfc::Controller a = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  pvfc::Controller b = pvfc::Controller::waypoints(robot, kWaypoints, 1.5, {}, settings());
  Eigen::Matrix<double, 6, 1> q;
  q << 0.1, -1.1, 1.3, -1.7, -1.5, 0.1;
  const Eigen::VectorXd qdot = Eigen::VectorXd::Constant(6, 0.1);
  Eigen::VectorXd torque(6);
  a.step(q, qdot, 1e-3, torque);
  // A map over a raw buffer, and a std::array: the same torque.
  std::array<double, 12> buffer{};
  Eigen::Map<Eigen::VectorXd> out(buffer.data() + 3, 6);
  const std::array<double, 6> q_array = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  b.step(q_array, qdot, 1e-3, out);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(torque[i], buffer[3 + i]);
  EXPECT_EQ(buffer[0], 0.0);
  EXPECT_EQ(buffer[9], 0.0);
  // The views point at the Eigen storage itself.
  const pvfc::In view(q);
  EXPECT_EQ(view.data(), q.data());
  // M into a row-major Eigen matrix.
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> m;
  pvfc::Out m_view(m.data(), 36);
  robot.inertia(q, m_view);
  EXPECT_NEAR((m - m.transpose()).cwiseAbs().maxCoeff(), 0.0, 1e-15);
}
#endif

TEST(Robot, FromArraysIsTheScaraOfItsUrdf) {
  pvfc_joint_spec joints[2] = {};
  joints[0].origin_xyz[2] = 0.5;
  joints[1].origin_xyz[0] = 0.4;
  const double mass[2] = {15.0, 6.0}, com[2] = {0.2, 0.15}, ixx[2] = {0.05, 0.02},
               iyy[2] = {0.4, 0.15};
  for (int i = 0; i < 2; ++i) {
    joints[i].axis[2] = 1.0;
    joints[i].mass = mass[i];
    joints[i].com[0] = com[i];
    joints[i].inertia[0] = ixx[i];
    joints[i].inertia[3] = iyy[i];
    joints[i].inertia[5] = iyy[i];
  }
  const pvfc::Robot a =
      pvfc::Robot::from_arrays(joints, 2, std::array<double, 3>{0.35, 0.0, 0.0});
  const char *p = std::getenv("PVFC_UR5_URDF");
  const std::string dir = p ? std::string(p).substr(0, std::string(p).rfind("/ur5/")) : "models";
  const pvfc::Robot b = pvfc::Robot::from_urdf_file(dir + "/scara.urdf", "tool");
  const std::array<double, 2> q = {0.3, -1.2};
  std::array<double, 4> ma{}, mb{};
  a.inertia(q, ma);
  b.inertia(q, mb);
  EXPECT_EQ(ma, mb);
  joints[1].mass = -1.0;
  EXPECT_THROW(pvfc::Robot::from_arrays(joints, 2), pvfc::UrdfError);
}

TEST(Version, IsNotEmpty) { EXPECT_FALSE(pvfc::version().empty()); }
