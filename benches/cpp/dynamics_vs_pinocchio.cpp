// pvfc beside Pinocchio's C++, in one program, on the same states: the UR5 and the Panda
// (fingers locked), 1,000 random states each (and, for the control step, 1,000 states of a
// robot tracking the contour), every function timed over all states in turn,
// pvfc and Pinocchio interleaved, 31 rounds; the medians of the per-call time per round, and
// the ratio Pinocchio / pvfc (above 1: pvfc is faster). pvfc is called through its C ABI
// (pvfc.h), with its argument checks; Pinocchio through its C++ API.
//
// Before timing, the two models are checked against each other on every state: M, C, g and
// RNEA agree to 1e-9 (relative), so the two libraries compute the same quantities of the same
// robot.
//
//   dynamics_vs_pinocchio MODELS_DIR [states] [rounds]
#include <pvfc.h>

#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>
#include <pinocchio/parsers/urdf.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

// The CPU's model name, as /proc/cpuinfo gives it.
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown CPU";
}

void ok(pvfc_status s) {
  if (s != PVFC_OK) {
    std::fprintf(stderr, "pvfc: %s\n", pvfc_last_error());
    std::exit(1);
  }
}

// Keeps the compiler from dropping a result.
volatile double g_sink = 0.0;

struct Arm {
  std::string name, urdf, tip;
  std::vector<std::string> locked;
};

// One function timed on both sides: nanoseconds per call, per round. `pvfc_setup`, if set,
// runs before each of pvfc's rounds, outside the clock.
struct Row {
  std::string what, pin_name, pvfc_name;
  std::function<void(std::size_t)> pin, pvfc;
  std::function<void()> pvfc_setup;
  std::vector<double> pin_ns, pvfc_ns;
};

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  const std::size_t n = x.size();
  return n % 2 ? x[n / 2] : 0.5 * (x[n / 2 - 1] + x[n / 2]);
}

template <class F>
double per_call_ns(std::size_t states, F &&f, const std::function<void()> &setup = {}) {
  if (setup) setup();
  const auto t0 = Clock::now();
  for (std::size_t k = 0; k < states; ++k) f(k);
  const auto t1 = Clock::now();
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / states;
}

int run(const Arm &arm, std::size_t states, int rounds) {
  // Pinocchio: the URDF, the fingers locked at their neutral position, pvfc's gravity.
  pinocchio::Model full;
  pinocchio::urdf::buildModel(arm.urdf, full);
  std::vector<pinocchio::JointIndex> lock;
  for (const auto &j : arm.locked) lock.push_back(full.getJointId(j));
  pinocchio::Model model =
      lock.empty() ? full : pinocchio::buildReducedModel(full, lock, pinocchio::neutral(full));
  model.gravity.linear() << 0.0, 0.0, -9.80665;
  pinocchio::Data data(model);
  const int n = model.nv;

  pvfc_robot *robot = nullptr;
  ok(pvfc_robot_from_urdf_file(arm.urdf.c_str(), nullptr, arm.tip.c_str(), &robot));
  if (static_cast<int>(pvfc_robot_dof(robot)) != n) {
    std::fprintf(stderr, "%s: pvfc has %zu joints, Pinocchio %d\n", arm.name.c_str(),
                 pvfc_robot_dof(robot), n);
    return 1;
  }
  // pvfc's whole control step: a closed joint contour through three postures around the
  // states' centre, self-pacing, gravity compensation (the benchmark's serial_arm settings).
  std::vector<double> waypoints(3 * n);
  for (int i = 0; i < n; ++i) {
    waypoints[i] = 0.0;
    waypoints[n + i] = 0.3;
    waypoints[2 * n + i] = -0.2;
  }
  pvfc_settings settings = pvfc_settings_default();
  settings.energy = 40.0;
  settings.self_pacing = 50.0;
  pvfc_controller *ctl = nullptr;
  ok(pvfc_controller_new_waypoints(robot, waypoints.data(), 3, n, 1.5, nullptr, 0, &settings,
                                   &ctl));

  // The states: q uniform in [−π, π], v in [−2, 2], a in [−5, 5] (fixed seed).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uq(-M_PI, M_PI), uv(-2.0, 2.0), ua(-5.0, 5.0);
  std::vector<Eigen::VectorXd> Q, V, A;
  for (std::size_t k = 0; k < states; ++k) {
    Eigen::VectorXd q(n), v(n), a(n);
    for (int i = 0; i < n; ++i) q[i] = uq(rng), v[i] = uv(rng), a[i] = ua(rng);
    Q.push_back(q), V.push_back(v), A.push_back(a);
  }

  // States of a robot tracking the contour: each q within ±0.02 rad of the contour's point at
  // the controller's own τ (read from the step before), v in [−0.2, 0.2]: the regime of a
  // control loop, where the uniform states above put the robot anywhere. Each timed round
  // starts from the controller reset (outside the clock), so that its τ runs as it ran here.
  pvfc_controller *tracking = nullptr;
  ok(pvfc_controller_new_waypoints(robot, waypoints.data(), 3, n, 1.5, nullptr, 0, &settings,
                                   &tracking));
  std::uniform_real_distribution<double> near(-0.02, 0.02), slow(-0.2, 0.2);
  std::vector<Eigen::VectorXd> Qt, Vt;
  {
    std::vector<double> point(n), out(n);
    pvfc_diagnostics d{};
    double tau = 0.0;
    for (std::size_t k = 0; k < states; ++k) {
      ok(pvfc_controller_contour_point(tracking, tau, point.data(), n));
      Eigen::VectorXd q(n), v(n);
      for (int i = 0; i < n; ++i) q[i] = point[i] + near(rng), v[i] = slow(rng);
      ok(pvfc_controller_step(tracking, q.data(), v.data(), n, 1e-3, out.data(), n, &d));
      tau = d.tau;
      Qt.push_back(q), Vt.push_back(v);
    }
  }

  // The same quantities: M, C, g, RNEA on every state (Eigen is column-major, pvfc's
  // matrices row-major).
  std::vector<double> m(n * n), c(n * n), g(n), tau(n), torque(n);
  double worst = 0.0;
  for (std::size_t k = 0; k < states; ++k) {
    ok(pvfc_robot_dynamics(robot, Q[k].data(), V[k].data(), n, m.data(), c.data(), g.data()));
    ok(pvfc_robot_rnea(robot, Q[k].data(), V[k].data(), A[k].data(), n, tau.data()));
    pinocchio::crba(model, data, Q[k]);
    data.M.triangularView<Eigen::StrictlyLower>() = data.M.transpose();
    pinocchio::computeCoriolisMatrix(model, data, Q[k], V[k]);
    pinocchio::computeGeneralizedGravity(model, data, Q[k]);
    const Eigen::VectorXd r = pinocchio::rnea(model, data, Q[k], V[k], A[k]);
    const double scale = 1.0 + data.M.norm() + data.C.norm() + data.g.norm() + r.norm();
    for (int i = 0; i < n; ++i) {
      worst = std::max(worst, std::abs(g[i] - data.g[i]) / scale);
      worst = std::max(worst, std::abs(tau[i] - r[i]) / scale);
      for (int j = 0; j < n; ++j) {
        worst = std::max(worst, std::abs(m[n * i + j] - data.M(i, j)) / scale);
        worst = std::max(worst, std::abs(c[n * i + j] - data.C(i, j)) / scale);
      }
    }
  }
  if (worst > 1e-9) {
    std::fprintf(stderr, "%s: pvfc and Pinocchio differ by %.3e (relative)\n", arm.name.c_str(),
                 worst);
    return 1;
  }

  std::vector<Row> rows;
  rows.push_back({"M (CRBA)", "crba", "pvfc_robot_inertia",
                  [&](std::size_t k) { pinocchio::crba(model, data, Q[k]); g_sink = data.M(0, 0); },
                  [&](std::size_t k) {
                    pvfc_robot_inertia(robot, Q[k].data(), n, m.data(), n * n);
                    g_sink = m[0];
                  }});
  rows.push_back({"C", "computeCoriolisMatrix", "pvfc_robot_dynamics (M, C, g)",
                  [&](std::size_t k) {
                    pinocchio::computeCoriolisMatrix(model, data, Q[k], V[k]);
                    g_sink = data.C(0, 0);
                  },
                  [&](std::size_t k) {
                    pvfc_robot_dynamics(robot, Q[k].data(), V[k].data(), n, m.data(), c.data(),
                                        g.data());
                    g_sink = c[0];
                  }});
  rows.push_back({"g", "computeGeneralizedGravity", "pvfc_robot_gravity",
                  [&](std::size_t k) {
                    pinocchio::computeGeneralizedGravity(model, data, Q[k]);
                    g_sink = data.g[0];
                  },
                  [&](std::size_t k) {
                    pvfc_robot_gravity(robot, Q[k].data(), n, g.data());
                    g_sink = g[0];
                  }});
  rows.push_back({"RNEA", "rnea", "pvfc_robot_rnea",
                  [&](std::size_t k) {
                    pinocchio::rnea(model, data, Q[k], V[k], A[k]);
                    g_sink = data.tau[0];
                  },
                  [&](std::size_t k) {
                    pvfc_robot_rnea(robot, Q[k].data(), V[k].data(), A[k].data(), n, tau.data());
                    g_sink = tau[0];
                  }});
  rows.push_back({"M, C, g together", "crba + computeCoriolisMatrix + gravity",
                  "pvfc_robot_dynamics",
                  [&](std::size_t k) {
                    pinocchio::crba(model, data, Q[k]);
                    pinocchio::computeCoriolisMatrix(model, data, Q[k], V[k]);
                    pinocchio::computeGeneralizedGravity(model, data, Q[k]);
                    g_sink = data.M(0, 0) + data.C(0, 0) + data.g[0];
                  },
                  [&](std::size_t k) {
                    pvfc_robot_dynamics(robot, Q[k].data(), V[k].data(), n, m.data(), c.data(),
                                        g.data());
                    g_sink = m[0] + c[0] + g[0];
                  }});
  // Pinocchio's inputs to a computed-torque step, and pvfc's whole step, on the states
  // (qs, vs). Every timed round of pvfc's step starts from the controller reset (outside the
  // clock) and steps the same states in the same order, so it repeats the pass checked here:
  // every step succeeds. (Without the reset, the uniform states, which are no trajectory,
  // drive the internal states to overflow within a few thousand steps, and the step then
  // times its error path.)
  using States = std::vector<Eigen::VectorXd>;
  auto pin_step = [&](const States &qs, const States &vs) {
    return [&model, &data, &qs, &vs](std::size_t k) {
      pinocchio::crba(model, data, qs[k]);
      pinocchio::nonLinearEffects(model, data, qs[k], vs[k]);
      g_sink = data.M(0, 0) + data.nle[0];
    };
  };
  auto pvfc_step = [&](pvfc_controller *c, const States &qs, const States &vs) {
    ok(pvfc_controller_reset(c));
    for (std::size_t k = 0; k < qs.size(); ++k) {
      ok(pvfc_controller_step(c, qs[k].data(), vs[k].data(), n, 1e-3, torque.data(), n,
                              nullptr));
    }
    return [c, &qs, &vs, n, &torque](std::size_t k) {
      pvfc_controller_step(c, qs[k].data(), vs[k].data(), n, 1e-3, torque.data(), n, nullptr);
      g_sink = torque[0];
    };
  };
  auto reset = [](pvfc_controller *c) {
    return [c] { pvfc_controller_reset(c); };
  };
  rows.push_back({"a control step", "crba + nonLinearEffects (computed torque's inputs)",
                  "pvfc_controller_step (the whole PVFC law)", pin_step(Q, V),
                  pvfc_step(ctl, Q, V), reset(ctl)});
  rows.push_back({"a step, tracking", "crba + nonLinearEffects",
                  "pvfc_controller_step, near the contour", pin_step(Qt, Vt),
                  pvfc_step(tracking, Qt, Vt), reset(tracking)});

  // Warm up once, then the rounds, each function's two sides back to back.
  for (auto &r : rows) {
    per_call_ns(states, r.pin);
    per_call_ns(states, r.pvfc, r.pvfc_setup);
  }
  for (int round = 0; round < rounds; ++round) {
    for (auto &r : rows) {
      r.pin_ns.push_back(per_call_ns(states, r.pin));
      r.pvfc_ns.push_back(per_call_ns(states, r.pvfc, r.pvfc_setup));
    }
  }
  std::printf("\n%s (%d joints), medians over %d rounds of %zu states; pvfc and Pinocchio agree "
              "to %.1e\n\n",
              arm.name.c_str(), n, rounds, states, worst);
  std::printf("| %-18s | %-50s | %11s | %-42s | %9s | %14s |\n", "quantity", "Pinocchio",
              "Pinocchio", "pvfc (C ABI)", "pvfc", "Pinocchio/pvfc");
  std::printf("|%s|%s|%s|%s|%s|%s|\n", std::string(20, '-').c_str(),
              std::string(52, '-').c_str(), std::string(12, '-').append(":").c_str(),
              std::string(44, '-').c_str(), std::string(10, '-').append(":").c_str(),
              std::string(15, '-').append(":").c_str());
  for (const auto &r : rows) {
    const double a = median(r.pin_ns), b = median(r.pvfc_ns);
    std::printf("| %-18s | %-50s | %8.0f ns | %-42s | %6.0f ns | %13.2fx |\n", r.what.c_str(),
                r.pin_name.c_str(), a, r.pvfc_name.c_str(), b, a / b);
  }
  pvfc_controller_destroy(ctl);
  pvfc_controller_destroy(tracking);
  pvfc_robot_destroy(robot);
  return 0;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s MODELS_DIR [states] [rounds]\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  const std::size_t states = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 1000;
  const int rounds = argc > 3 ? std::atoi(argv[3]) : 31;
  std::printf("CPU: %s; pvfc %s; Pinocchio %s\n", cpu_model().c_str(), pvfc_version(),
              PINOCCHIO_VERSION);
  const Arm arms[] = {
      {"UR5", dir + "/ur5/ur5_robot.urdf", "tool0", {}},
      {"Panda", dir + "/panda/panda.urdf", "panda_hand_tcp",
       {"panda_finger_joint1", "panda_finger_joint2"}},
  };
  for (const auto &arm : arms) {
    if (const int rc = run(arm, states, rounds)) return rc;
  }
  return 0;
}
