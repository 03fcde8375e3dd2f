// pvfc from C++17: header-only RAII classes over the C ABI of pvfc.h.
//
// * Move-only handles (`pvfc::Robot`, `pvfc::Contour`, `pvfc::Controller`,
//   `pvfc::PassiveController`) free their C objects when they go out of scope.
// * Every error is an exception derived from `pvfc::Error` (itself a `std::runtime_error`),
//   one class per kind of `pvfc_status`, with the library's message (which names the
//   argument, joint, link or URDF element).
// * Arrays are passed as views (`pvfc::In`, `pvfc::Out`) built without copying from
//   `std::array`, `std::vector`, Eigen vectors and maps, or a pointer and a length.
// * The step functions and the dynamics allocate nothing (the C ABI does not; these wrappers
//   add nothing). An exception allocates: a real-time loop calls the steps' `try_step`
//   forms, which return the status and allocate nothing, even when they fail.
#ifndef PVFC_HPP
#define PVFC_HPP

#include "pvfc.h"

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pvfc {

/// Any error of pvfc: `status()` is the C status, `what()` the message.
class Error : public std::runtime_error {
 public:
  Error(pvfc_status status, const std::string &message)
      : std::runtime_error(message), status_(status) {}
  pvfc_status status() const noexcept { return status_; }

 private:
  pvfc_status status_;
};

/// A pointer that must not be NULL was.
class NullPointerError : public Error { using Error::Error; };
/// An array's length (or a struct's `size`) does not match.
class WrongSizeError : public Error { using Error::Error; };
/// An input was NaN or infinite.
class NonFiniteError : public Error { using Error::Error; };
/// An argument or setting is out of its range.
class InvalidArgumentError : public Error { using Error::Error; };
/// A file could not be read.
class IoError : public Error { using Error::Error; };
/// A URDF is malformed or not a serial chain.
class UrdfError : public Error { using Error::Error; };
/// A waypoint of a Cartesian path is unreachable, singular, beyond a limit or a branch jump.
class WaypointError : public Error { using Error::Error; };
/// The energy level is too low for the velocity field (eq. 6).
class EnergyTooLowError : public Error { using Error::Error; };
/// A numerical failure.
class NumericalError : public Error { using Error::Error; };
/// A bug in pvfc (a caught panic).
class InternalError : public Error { using Error::Error; };

/// Throws the exception of `status` (nothing for PVFC_OK), with the last error's message.
inline void check(pvfc_status status) {
  if (status == PVFC_OK) return;
  const std::string message = pvfc_last_error();
  switch (status) {
    case PVFC_ERROR_NULL_POINTER: throw NullPointerError(status, message);
    case PVFC_ERROR_WRONG_SIZE: throw WrongSizeError(status, message);
    case PVFC_ERROR_NON_FINITE: throw NonFiniteError(status, message);
    case PVFC_ERROR_INVALID_ARGUMENT: throw InvalidArgumentError(status, message);
    case PVFC_ERROR_IO: throw IoError(status, message);
    case PVFC_ERROR_URDF: throw UrdfError(status, message);
    case PVFC_ERROR_WAYPOINT: throw WaypointError(status, message);
    case PVFC_ERROR_ENERGY_TOO_LOW: throw EnergyTooLowError(status, message);
    case PVFC_ERROR_NUMERICAL: throw NumericalError(status, message);
    case PVFC_ERROR_INTERNAL: throw InternalError(status, message);
    default: throw Error(status, message);
  }
}

/// A read-only view of doubles: a pointer and a length (no copy).
class In {
 public:
  In() = default;
  In(const double *data, std::size_t size) : data_(data), size_(size) {}
  /// Anything with `data()` and `size()`: std::array, std::vector, Eigen vectors and maps.
  template <class C, class = decltype(std::declval<const C &>().data())>
  In(const C &c) : data_(c.data()), size_(static_cast<std::size_t>(c.size())) {}
  const double *data() const noexcept { return data_; }
  std::size_t size() const noexcept { return size_; }

 private:
  const double *data_ = nullptr;
  std::size_t size_ = 0;
};

/// A writable view of doubles: a pointer and a length (no copy).
class Out {
 public:
  Out(double *data, std::size_t size) : data_(data), size_(size) {}
  template <class C, class = decltype(std::declval<C &>().data())>
  Out(C &c) : data_(c.data()), size_(static_cast<std::size_t>(c.size())) {}
  double *data() const noexcept { return data_; }
  std::size_t size() const noexcept { return size_; }

 private:
  double *data_;
  std::size_t size_;
};

namespace detail {
/// Throws WrongSizeError unless the view has `n` entries (for arrays whose length the C
/// function takes from another argument).
template <class View>
inline void size_check(const View &x, std::size_t n, const char *name) {
  if (x.size() != n) {
    throw WrongSizeError(PVFC_ERROR_WRONG_SIZE, std::string(name) + ": " +
                                                    std::to_string(x.size()) + " entries, " +
                                                    std::to_string(n) + " needed");
  }
}

/// A move-only owner of a C handle freed by `Destroy`.
template <class T, void (*Destroy)(T *)>
class Handle {
 public:
  explicit Handle(T *p = nullptr) noexcept : p_(p) {}
  Handle(Handle &&o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
  Handle &operator=(Handle &&o) noexcept {
    if (this != &o) {
      Destroy(p_);
      p_ = std::exchange(o.p_, nullptr);
    }
    return *this;
  }
  Handle(const Handle &) = delete;
  Handle &operator=(const Handle &) = delete;
  ~Handle() { Destroy(p_); }
  T *get() const noexcept { return p_; }

 private:
  T *p_;
};
}  // namespace detail

using detail::size_check;

/// A serial arm read from URDF.
class Robot {
 public:
  /// From a URDF file; `tip` and `base` name the links (empty: the only leaf, the root).
  static Robot from_urdf_file(const std::string &path, const std::string &tip = "",
                              const std::string &base = "") {
    pvfc_robot *p = nullptr;
    check(pvfc_robot_from_urdf_file(path.c_str(), base.empty() ? nullptr : base.c_str(),
                                    tip.empty() ? nullptr : tip.c_str(), &p));
    return Robot(p);
  }
  /// From the text of a URDF (`name` names it in error messages).
  static Robot from_urdf_string(const std::string &urdf, const std::string &tip = "",
                                const std::string &base = "",
                                const std::string &name = "urdf") {
    pvfc_robot *p = nullptr;
    check(pvfc_robot_from_urdf_string(urdf.c_str(), name.c_str(),
                                      base.empty() ? nullptr : base.c_str(),
                                      tip.empty() ? nullptr : tip.c_str(), &p));
    return Robot(p);
  }
  /// From numbers: `n` joints (`pvfc_joint_spec`, URDF's conventions), the tool frame's
  /// position and roll, pitch, yaw in the last link (3 each, or empty: zeros).
  static Robot from_arrays(const pvfc_joint_spec *joints, std::size_t n, In tool_xyz = In(),
                           In tool_rpy = In()) {
    if (tool_xyz.size()) size_check(tool_xyz, 3, "tool_xyz");
    if (tool_rpy.size()) size_check(tool_rpy, 3, "tool_rpy");
    pvfc_robot *p = nullptr;
    check(pvfc_robot_from_arrays(joints, n, tool_xyz.size() ? tool_xyz.data() : nullptr,
                                 tool_rpy.size() ? tool_rpy.data() : nullptr, &p));
    return Robot(p);
  }
  std::size_t dof() const noexcept { return pvfc_robot_dof(h_.get()); }
  /// `M(q)` (CRBA) into `m` (dof², row-major).
  void inertia(In q, Out m) const {
    check(pvfc_robot_inertia(h_.get(), q.data(), q.size(), m.data(), m.size()));
  }
  /// `g(q)` into `g` (dof).
  void gravity(In q, Out g) const {
    size_check(g, q.size(), "g");
    check(pvfc_robot_gravity(h_.get(), q.data(), q.size(), g.data()));
  }
  /// Inverse dynamics (RNEA), `M a + C v + g`, into `tau`.
  void rnea(In q, In v, In a, Out tau) const {
    size_check(v, q.size(), "v");
    size_check(a, q.size(), "a");
    size_check(tau, q.size(), "tau");
    check(pvfc_robot_rnea(h_.get(), q.data(), v.data(), a.data(), q.size(), tau.data()));
  }
  /// `M(q)`, `C(q, v)` (dof², row-major) and `g(q)` in one pass.
  void dynamics(In q, In v, Out m, Out c, Out g) const {
    const std::size_t n = q.size();
    size_check(v, n, "v");
    size_check(m, n * n, "m");
    size_check(c, n * n, "c");
    size_check(g, n, "g");
    check(pvfc_robot_dynamics(h_.get(), q.data(), v.data(), n, m.data(), c.data(), g.data()));
  }
  /// The tool's rotation (9, row-major; may be empty) and position (3; may be empty).
  void tool_pose(In q, Out rotation, Out position) const {
    size_check(rotation, rotation.size() ? 9 : 0, "rotation");
    size_check(position, position.size() ? 3 : 0, "position");
    check(pvfc_robot_tool_pose(h_.get(), q.data(), q.size(),
                               rotation.size() ? rotation.data() : nullptr,
                               position.size() ? position.data() : nullptr));
  }
  /// Sets the tool centre point: `xyz` (m) and `rpy` (rad) in the tip link's frame (3 each;
  /// `rpy` may be empty: zeros). Contours and controllers made afterwards use it.
  void set_tool(In xyz, In rpy = {}) {
    size_check(xyz, 3, "xyz");
    if (rpy.size()) size_check(rpy, 3, "rpy");
    check(pvfc_robot_set_tool(h_.get(), xyz.data(), rpy.size() ? rpy.data() : nullptr));
  }
  const pvfc_robot *get() const noexcept { return h_.get(); }

 private:
  explicit Robot(pvfc_robot *p) : h_(p) {}
  detail::Handle<pvfc_robot, pvfc_robot_destroy> h_;
};

/// The settings of a controller, starting from `pvfc_settings_default()`.
struct Settings : pvfc_settings {
  Settings() : pvfc_settings(pvfc_settings_default()) {}
};

/// The options of the passive controller, starting from `pvfc_passive_options_default()`.
struct PassiveOptions : pvfc_passive_options {
  PassiveOptions() : pvfc_passive_options(pvfc_passive_options_default()) {}
};

/// How a Cartesian path becomes a contour, starting from `pvfc_cartesian_options_default()`:
/// set `seed` (the robot's joints) and what else you need.
struct CartesianOptions : pvfc_cartesian_options {
  CartesianOptions() : pvfc_cartesian_options(pvfc_cartesian_options_default()) {}
  /// The inverse kinematics' start (kept by pointer: it must outlive the contour's making).
  CartesianOptions &with_seed(In q) {
    seed = q.data();
    seed_len = q.size();
    return *this;
  }
};

/// What a controller follows: a closed curve in joint space or a tool path in Cartesian space.
class Contour {
 public:
  /// The periodic C² spline through `waypoints` (row-major, `dof` columns), one every
  /// `spacing` of τ.
  static Contour waypoints(In waypoints, std::size_t dof, double spacing) {
    if (dof == 0 || waypoints.size() % dof != 0) {
      throw WrongSizeError(PVFC_ERROR_WRONG_SIZE,
                           "waypoints: " + std::to_string(waypoints.size()) +
                               " values are not whole rows of " + std::to_string(dof));
    }
    return make(pvfc_contour_waypoints, waypoints.data(), waypoints.size() / dof, dof, spacing);
  }
  /// `x_i = c_i + a_i sin(2πτ/T_i + φ_i)`, closed with `period`; `phase`, `offset` may be
  /// empty (zeros).
  static Contour lissajous(In amplitude, In periods, double period, In phase = In(),
                           In offset = In()) {
    const std::size_t n = amplitude.size();
    size_check(periods, n, "periods");
    if (phase.size()) size_check(phase, n, "phase");
    if (offset.size()) size_check(offset, n, "offset");
    return make(pvfc_contour_lissajous, amplitude.data(), periods.data(),
                phase.size() ? phase.data() : nullptr, offset.size() ? offset.data() : nullptr,
                n, period);
  }
  /// `x_d(τ) = c + u cos(2πτ/T) + w sin(2πτ/T)`.
  static Contour ellipse(In center, In u, In w, double period) {
    size_check(u, center.size(), "u");
    size_check(w, center.size(), "w");
    return make(pvfc_contour_ellipse, center.data(), u.data(), w.data(), center.size(), period);
  }
  /// A closed polygon of the tool's position (corners row-major `x, y, z`, m, base frame)
  /// with rounded corners, traced once every `period` of τ.
  static Contour cartesian_polygon(In corners, double corner_radius, double period,
                                   const CartesianOptions &options) {
    if (corners.size() % 3 != 0) {
      throw WrongSizeError(PVFC_ERROR_WRONG_SIZE, "corners: not whole rows of x, y, z");
    }
    return make(pvfc_contour_cartesian_polygon, corners.data(), corners.size() / 3,
                corner_radius, period, &options);
  }
  /// A circle of the tool's position (`semi_minor` 0) or an ellipse, about `normal`.
  static Contour cartesian_circle(In center, In normal, double radius, double period,
                                  const CartesianOptions &options, double semi_minor = 0.0,
                                  In major_axis = In()) {
    size_check(center, 3, "center");
    size_check(normal, 3, "normal");
    if (major_axis.size()) size_check(major_axis, 3, "major_axis");
    return make(pvfc_contour_cartesian_circle, center.data(), normal.data(), radius,
                major_axis.size() ? major_axis.data() : nullptr, semi_minor, period, &options);
  }
  /// Any `[contour.cartesian]` table of a scenario file, as TOML text.
  static Contour cartesian_toml(const std::string &toml, double period,
                                const std::string &base_dir = "", double spacing = 0.0) {
    return make(pvfc_contour_cartesian_toml, toml.c_str(),
                base_dir.empty() ? nullptr : base_dir.c_str(), period, spacing);
  }
  /// Any contour of a scenario file's `[contour]`, of any kind: the table's content as TOML
  /// text (`[lissajous] …`, `[waypoints] …`, `[cartesian] …`).
  static Contour from_toml(const std::string &toml, const std::string &base_dir = "") {
    return make(pvfc_contour_toml, toml.c_str(), base_dir.empty() ? nullptr : base_dir.c_str());
  }
  /// The distance (m) from `point` (3) to a Cartesian contour's exact path.
  double distance(In point) const {
    size_check(point, 3, "point");
    double d = 0.0;
    check(pvfc_contour_distance(h_.get(), point.data(), &d, nullptr));
    return d;
  }
  const pvfc_contour *get() const noexcept { return h_.get(); }

 private:
  explicit Contour(pvfc_contour *p) : h_(p) {}
  template <class F, class... A>
  static Contour make(F f, A... args) {
    pvfc_contour *p = nullptr;
    check(f(args..., &p));
    return Contour(p);
  }
  detail::Handle<pvfc_contour, pvfc_contour_destroy> h_;
};

/// A PVFC controller of an arm.
class Controller {
 public:
  /// Follows `contour` (a Cartesian path's inverse kinematics is solved here), with
  /// navigation weights `h` (empty: all 1).
  Controller(const Robot &robot, const Contour &contour, In h = In(),
             const Settings &settings = Settings()) {
    pvfc_controller *p = nullptr;
    check(pvfc_controller_new(robot.get(), contour.get(), h.size() ? h.data() : nullptr,
                              h.size(), &settings, &p));
    h_ = detail::Handle<pvfc_controller, pvfc_controller_destroy>(p);
  }
  /// On the closed joint contour through `waypoints` (row-major, `dof` columns), one every
  /// `spacing` of τ, with navigation weights `h` (empty: all 1).
  static Controller waypoints(const Robot &robot, In waypoints, double spacing, In h = In(),
                              const Settings &settings = Settings()) {
    const std::size_t dof = robot.dof();
    if (dof == 0 || waypoints.size() % dof != 0) {
      throw WrongSizeError(PVFC_ERROR_WRONG_SIZE,
                           "waypoints: " + std::to_string(waypoints.size()) +
                               " values are not whole rows of " + std::to_string(dof));
    }
    pvfc_controller *p = nullptr;
    check(pvfc_controller_new_waypoints(robot.get(), waypoints.data(), waypoints.size() / dof,
                                        dof, spacing, h.size() ? h.data() : nullptr, h.size(),
                                        &settings, &p));
    return Controller(p);
  }
  /// One control step: the torques into `torque`; returns the step's numbers.
  pvfc_diagnostics step(In q, In qdot, double dt, Out torque) {
    if (q.size() != qdot.size()) {
      throw WrongSizeError(PVFC_ERROR_WRONG_SIZE, "q and qdot differ in length");
    }
    pvfc_diagnostics d;
    check(pvfc_controller_step(h_.get(), q.data(), qdot.data(), q.size(), dt, torque.data(),
                               torque.size(), &d));
    return d;
  }
  /// `step` for a real-time loop: no exception, nothing allocated even on failure. Returns
  /// `PVFC_OK` or the error's kind, with its message in `pvfc_last_error()`; `q` and `qdot`
  /// of different lengths are `PVFC_ERROR_WRONG_SIZE` without a message. `diagnostics`, if
  /// not NULL, receives the step's numbers. On failure nothing changes.
  pvfc_status try_step(In q, In qdot, double dt, Out torque,
                       pvfc_diagnostics *diagnostics = nullptr) noexcept {
    if (q.size() != qdot.size()) return PVFC_ERROR_WRONG_SIZE;
    return pvfc_controller_step(h_.get(), q.data(), qdot.data(), q.size(), dt, torque.data(),
                                torque.size(), diagnostics);
  }
  /// The joint contour's point at `tau`.
  std::vector<double> contour_point(double tau) const {
    std::vector<double> x(dof());
    check(pvfc_controller_contour_point(h_.get(), tau, x.data(), x.size()));
    return x;
  }
  /// Back to the initial internal states.
  void reset() { check(pvfc_controller_reset(h_.get())); }
  std::size_t dof() const noexcept { return pvfc_controller_dof(h_.get()); }
  const pvfc_controller *get() const noexcept { return h_.get(); }

 private:
  explicit Controller(pvfc_controller *p) : h_(p) {}
  detail::Handle<pvfc_controller, pvfc_controller_destroy> h_;
};

/// The passive digital controller: passive by construction at its samples.
class PassiveController {
 public:
  /// The passive form of `ctl` (its internal states as they are now).
  explicit PassiveController(const Controller &ctl,
                             const PassiveOptions &options = PassiveOptions()) {
    pvfc_passive *p = nullptr;
    check(pvfc_passive_new(ctl.get(), &options, &p));
    h_ = detail::Handle<pvfc_passive, pvfc_passive_destroy>(p);
  }
  /// One step at the measured positions `q` (velocities `qdot`, or empty to estimate them;
  /// `applied` the torque the drive applied, or empty for the last command). With
  /// supervision, a fault is not an exception: the torque is the safe torque (zero) and the
  /// account's `fault` says which.
  pvfc_energy_account step(In q, double dt, Out torque, In qdot = In(), In applied = In()) {
    if ((qdot.size() && qdot.size() != q.size()) ||
        (applied.size() && applied.size() != q.size())) {
      throw WrongSizeError(PVFC_ERROR_WRONG_SIZE, "q, qdot and applied differ in length");
    }
    pvfc_energy_account a;
    const pvfc_status status =
        pvfc_passive_step(h_.get(), q.data(), qdot.size() ? qdot.data() : nullptr,
                          applied.size() ? applied.data() : nullptr, q.size(), dt,
                          torque.data(), torque.size(), &a);
    if (status != PVFC_FAULT) check(status);
    return a;
  }
  /// `step` for a real-time loop: no exception, nothing allocated even on failure. Returns
  /// `PVFC_OK`, `PVFC_FAULT` (supervision: the safe torque was written) or the error's kind,
  /// with its message in `pvfc_last_error()`; arrays of
  /// different lengths are `PVFC_ERROR_WRONG_SIZE` without a message. `account`, if not NULL,
  /// receives the period's energy account. On failure nothing changes.
  pvfc_status try_step(In q, double dt, Out torque, In qdot = In(), In applied = In(),
                       pvfc_energy_account *account = nullptr) noexcept {
    if ((qdot.size() && qdot.size() != q.size()) ||
        (applied.size() && applied.size() != q.size())) {
      return PVFC_ERROR_WRONG_SIZE;
    }
    return pvfc_passive_step(h_.get(), q.data(), qdot.size() ? qdot.data() : nullptr,
                             applied.size() ? applied.data() : nullptr, q.size(), dt,
                             torque.data(), torque.size(), account);
  }
  /// The storage as accounted (J).
  double storage() const noexcept { return pvfc_passive_storage(h_.get()); }
  /// The scale of the field's pace the next step uses (the pace throttle's; 1 without one).
  double pace_scale() const noexcept { return pvfc_passive_pace_scale(h_.get()); }

 private:
  detail::Handle<pvfc_passive, pvfc_passive_destroy> h_;
};

/// The library's version.
inline std::string version() { return pvfc_version(); }

}  // namespace pvfc

#endif  // PVFC_HPP
