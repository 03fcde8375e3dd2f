// The UR5 on an independent simulator, from C++: MuJoCo (its own import of the UR5's URDF,
// RK4 at 10 kHz, standard gravity) driven at 1 kHz by pvfc's passive controller through
// pvfc.hpp, with gravity compensation, on the rounded rectangle of scenarios/ur5_cartesian.toml
// followed with the task-space field. The controller is written in the shape of a ros2_control
// controller: everything that allocates happens in on_configure() and on_activate(); update()
// reads the state interfaces, writes the effort commands, and allocates nothing (counted here
// by replacing the global operator new).
//
// It prints, and checks (exit status 1 if one fails):
//   * the model: MuJoCo's kinetic energy equals ½ q̇ᵀ M q̇ with pvfc's M (same inertias);
//   * convergence: the tool's distance to the exact path over the last 5 s;
//   * passivity: MuJoCo's energy (kinetic + potential) + the controller's storage − the
//     add-ons' work (the gravity compensation, as the controller reports it) stays within
//     1e-6 of its start, relative to the energy in play at the start (the arm's kinetic energy
//     and the controller's storage), over 30 s of free motion;
//   * update() allocated nothing, and a NaN from a sensor afterwards fails update() with the
//     library's message, allocating nothing either.
//
//   mujoco_ur5 path/to/ur5_robot.urdf [seconds]
#include <pvfc.hpp>

#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <new>
#include <sstream>
#include <string>
#include <vector>

// Every allocation of the program is counted: update() must add none.
static std::atomic<long> g_allocations{0};
void *operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void *p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
void operator delete(void *p) noexcept { std::free(p); }
void operator delete(void *p, std::size_t) noexcept { std::free(p); }

namespace {

constexpr std::size_t kDof = 6;

// ros2_control's hardware interfaces, reduced to what a controller sees: a state value to
// read (position or velocity of a joint) and a command value to write (its effort).
struct StateInterface {
  const double *value;
  double get_value() const { return *value; }
};
struct CommandInterface {
  double *value;
  void set_value(double v) { *value = v; }
};

// The shape of a ros2_control controller_interface::ControllerInterface.
class PvfcContourController {
 public:
  // on_configure: read the robot, make the contour and the controller (allocates; may throw).
  void on_configure(const std::string &urdf) {
    robot_ = pvfc::Robot::from_urdf_file(urdf, "tool0");
    const std::array<double, kDof> seed = {0.0, -1.2, 1.4, -1.8, -1.57, 0.0};
    pvfc::CartesianOptions options;
    options.with_seed(seed);
    options.fixed_orientation = true;
    options.task_field = true;
    const std::array<double, 12> corners = {0.45, -0.15, 0.30, 0.65, -0.15, 0.30,
                                            0.65, 0.20,  0.30, 0.45, 0.20,  0.30};
    contour_ = pvfc::Contour::cartesian_polygon(corners, 0.03, 12.0, options);
    pvfc::Settings s;
    s.energy = 40.0;
    s.self_pacing = 50.0;
    s.gamma = 10.0;
    s.gravity_compensation = true;
    const std::array<double, kDof> h = {4, 4, 4, 4, 4, 4};
    controller_ = pvfc::Controller(*robot_, *contour_, h, s);
  }

  // on_activate: the passive digital controller, with the UR5's torque limits.
  void on_activate() {
    static const std::array<double, kDof> limit = {150, 150, 150, 28, 28, 28};
    pvfc::PassiveOptions o;
    o.torque_limit = limit.data();
    o.n = kDof;
    passive_ = pvfc::PassiveController(*controller_, o);
  }

  // update: the real-time part. State interfaces in, effort commands out; no allocation, no
  // lock, no system call (pvfc's step makes none).
  bool update(double /*time*/, double period) {
    for (std::size_t i = 0; i < kDof; ++i) {
      q_[i] = positions[i].get_value();
      v_[i] = velocities[i].get_value();
    }
    // try_step: no exception; a failure (a NaN from a sensor, an overflow) is a status, its
    // message in pvfc_last_error(), and allocates nothing either.
    if (passive_->try_step(q_, period, torque_, v_, {}, &account_) != PVFC_OK) {
      for (auto &c : efforts) c.set_value(0.0);  // a safe command: no torque
      return false;
    }
    for (std::size_t i = 0; i < kDof; ++i) efforts[i].set_value(torque_[i]);
    return true;
  }

  std::vector<StateInterface> positions, velocities;
  std::vector<CommandInterface> efforts;
  const pvfc_energy_account &account() const { return account_; }
  double storage() const { return passive_->storage(); }
  const pvfc::Robot &robot() const { return *robot_; }
  const pvfc::Contour &contour() const { return *contour_; }

 private:
  // Empty until on_configure and on_activate build them (the handles have no empty state).
  std::optional<pvfc::Robot> robot_;
  std::optional<pvfc::Contour> contour_;
  std::optional<pvfc::Controller> controller_;
  std::optional<pvfc::PassiveController> passive_;
  std::array<double, kDof> q_{}, v_{}, torque_{};
  pvfc_energy_account account_{};
};

// The URDF without its meshes (MuJoCo would look for the STL files; the dynamics need only
// the inertias), written beside the temporary directory for mj_loadXML.
std::string mesh_free_urdf(const std::string &path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string s = ss.str();
  for (const char *tag : {"visual", "collision"}) {
    const std::string open = std::string("<") + tag, close = std::string("</") + tag + ">";
    for (std::size_t a; (a = s.find(open)) != std::string::npos;) {
      const std::size_t b = s.find(close, a);
      if (b == std::string::npos) throw std::runtime_error("unclosed <" + std::string(tag));
      s.erase(a, b + close.size() - a);
    }
  }
  const char *dir = std::getenv("TMPDIR");
  const std::string out = std::string(dir ? dir : "/tmp") + "/pvfc_ur5_mujoco.urdf";
  std::ofstream(out) << s;
  return out;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s ur5_robot.urdf [seconds]\n", argv[0]);
    return 2;
  }
  const double duration = argc > 2 ? std::atof(argv[2]) : 30.0;
  const double control_dt = 1e-3;
  const int substeps = 10;

  char error[1000] = "";
  const std::string urdf = mesh_free_urdf(argv[1]);
  mjModel *m = mj_loadXML(urdf.c_str(), nullptr, error, sizeof error);
  if (!m) {
    std::fprintf(stderr, "MuJoCo cannot load %s: %s\n", urdf.c_str(), error);
    return 1;
  }
  m->opt.timestep = control_dt / substeps;
  m->opt.integrator = mjINT_RK4;
  m->opt.gravity[2] = -9.80665;  // pvfc's standard gravity
  m->opt.enableflags |= mjENBL_ENERGY;
  mjData *d = mj_makeData(m);
  if (m->nv != static_cast<int>(kDof)) {
    std::fprintf(stderr, "expected 6 joints, MuJoCo has %ld\n", static_cast<long>(m->nv));
    return 1;
  }

  PvfcContourController ctl;
  try {
    ctl.on_configure(argv[1]);
  } catch (const pvfc::Error &e) {
    std::fprintf(stderr, "pvfc: %s\n", e.what());
    return 1;
  }
  std::array<double, kDof> command{};
  for (std::size_t i = 0; i < kDof; ++i) {
    ctl.positions.push_back({&d->qpos[i]});
    ctl.velocities.push_back({&d->qvel[i]});
    ctl.efforts.push_back({&command[i]});
  }

  // At rest at the inverse kinematics' seed, off the path.
  const std::array<double, kDof> q0 = {0.0, -1.2, 1.4, -1.8, -1.57, 0.0};
  std::copy(q0.begin(), q0.end(), d->qpos);
  mj_forward(m, d);
  ctl.on_activate();

  // The model: MuJoCo's kinetic energy against ½ vᵀ M v with pvfc's M.
  {
    const std::array<double, kDof> v = {0.4, -0.3, 0.2, 0.5, -0.6, 0.1};
    std::copy(v.begin(), v.end(), d->qvel);
    mj_forward(m, d);
    std::array<double, kDof * kDof> mass{};
    ctl.robot().inertia(q0, mass);
    double half_vmv = 0.0;
    for (std::size_t i = 0; i < kDof; ++i)
      for (std::size_t j = 0; j < kDof; ++j) half_vmv += 0.5 * v[i] * mass[kDof * i + j] * v[j];
    const double diff = std::abs(d->energy[1] - half_vmv) / half_vmv;
    std::printf("model: MuJoCo's kinetic energy %.12f J, pvfc's 1/2 v'Mv %.12f J (rel. %.1e)\n",
                d->energy[1], half_vmv, diff);
    if (diff > 1e-12) return 1;
    std::fill(d->qvel, d->qvel + kDof, 0.0);
    mj_forward(m, d);
  }

  const double start = d->energy[0] + d->energy[1] + ctl.storage();
  const double scale = d->energy[1] + ctl.storage();
  double add_ons = 0.0, worst = 0.0, worst_plain = 0.0;
  double sum_distance = 0.0, max_distance = 0.0, u_first = -1.0;
  long tail = 0;
  long allocations_in_update = 0;
  const long steps = std::lround(duration / control_dt);
  for (long k = 0; k <= steps; ++k) {
    mj_forward(m, d);  // positions, velocities and energies of this sample
    // The balance at this sample: the add-ons' work over the last period is in the account
    // of the step that follows it.
    const long before = g_allocations.load(std::memory_order_relaxed);
    if (!ctl.update(k * control_dt, control_dt)) {
      std::fprintf(stderr, "pvfc step failed at %ld: %s\n", k, pvfc_last_error());
      return 1;
    }
    allocations_in_update += g_allocations.load(std::memory_order_relaxed) - before;
    add_ons += ctl.account().add_ons;
    const double energy = d->energy[0] + d->energy[1] + ctl.storage();
    worst = std::max(worst, std::abs(energy - add_ons - start));
    worst_plain = std::max(worst_plain, std::abs(energy - start));
    if (u_first < 0.0) u_first = ctl.account().potential;
    if (k * control_dt >= duration - 5.0) {
      std::array<double, 3> p{};
      ctl.robot().tool_pose(std::array<double, kDof>{d->qpos[0], d->qpos[1], d->qpos[2],
                                                     d->qpos[3], d->qpos[4], d->qpos[5]},
                            pvfc::Out(nullptr, 0), p);
      const double dist = ctl.contour().distance(p);
      sum_distance += dist;
      max_distance = std::max(max_distance, dist);
      ++tail;
    }
    std::copy(command.begin(), command.end(), d->qfrc_applied);
    for (int s = 0; s < substeps; ++s) mj_step(m, d);
  }
  const double drift = worst / scale;
  std::printf("pvfc %s on MuJoCo %s, %.1f s at 1 kHz (plant RK4 at 10 kHz)\n",
              pvfc::version().c_str(), mj_versionString(), duration);
  std::printf("tool to path over the last 5 s: mean %.4f mm, max %.4f mm (U %.3e -> %.3e)\n",
              1e3 * sum_distance / tail, 1e3 * max_distance, u_first, ctl.account().potential);
  std::printf("energy: |E_mujoco + storage - add-ons' work - start| <= %.3e J = %.2e of %.2f J"
              " (without the add-ons' term: %.3e J)\n",
              worst, drift, scale, worst_plain);
  std::printf("allocations in update(): %ld\n", allocations_in_update);
  // A sensor fault: the elbow's position reads NaN. update() fails with the library's
  // message, commands no torque, and allocates nothing.
  d->qpos[2] = std::nan("");
  const long before_fault = g_allocations.load(std::memory_order_relaxed);
  const bool fault_passed = ctl.update(duration, control_dt);
  const long fault_allocations = g_allocations.load(std::memory_order_relaxed) - before_fault;
  const bool fault_ok = !fault_passed && fault_allocations == 0 &&
                        std::string(pvfc_last_error()).find("q[2]") != std::string::npos &&
                        std::all_of(command.begin(), command.end(),
                                    [](double c) { return c == 0.0; });
  std::printf("a NaN position: update() %s (\"%s\"), %ld allocations\n",
              fault_passed ? "passed" : "failed", pvfc_last_error(), fault_allocations);
  mj_deleteData(d);
  mj_deleteModel(m);
  const bool ok = drift <= 1e-6 && allocations_in_update == 0 && fault_ok &&
                  (duration < 20.0 || max_distance < 1e-3);
  std::printf("%s\n", ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
