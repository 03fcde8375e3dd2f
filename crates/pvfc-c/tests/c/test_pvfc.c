/* The C ABI from C: a UR5 from URDF, a controller on a joint contour, its step, the passive
 * controller, and every kind of bad input as an error code with a message. Plain C99 with
 * assert-like checks; run under valgrind in CI (no invalid access, no leak).
 *   usage: test_pvfc path/to/ur5_robot.urdf */
#include "pvfc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond)                                                              \
  do {                                                                           \
    if (!(cond)) {                                                               \
      fprintf(stderr, "%s:%d: CHECK failed: %s (last error: %s)\n", __FILE__,    \
              __LINE__, #cond, pvfc_last_error());                               \
      failures++;                                                                \
    }                                                                            \
  } while (0)

#define CHECK_ERROR(call, status, fragment)                                      \
  do {                                                                           \
    pvfc_status s_ = (call);                                                     \
    CHECK(s_ == (status));                                                       \
    CHECK(strstr(pvfc_last_error(), (fragment)) != NULL);                        \
  } while (0)

#define DOF 6

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s ur5_robot.urdf\n", argv[0]);
    return 2;
  }
  CHECK(strlen(pvfc_version()) > 0);
  /* The header and the library are the same version. */
  {
    char header_version[32];
    snprintf(header_version, sizeof header_version, "%d.%d.%d", PVFC_VERSION_MAJOR,
             PVFC_VERSION_MINOR, PVFC_VERSION_PATCH);
    CHECK(strcmp(header_version, pvfc_version()) == 0);
  }

  /* The robot, and the errors of reading one. */
  pvfc_robot *robot = NULL;
  CHECK(pvfc_robot_from_urdf_file(argv[1], NULL, "tool0", &robot) == PVFC_OK);
  CHECK(pvfc_robot_dof(robot) == DOF);
  CHECK(pvfc_robot_dof(NULL) == 0);
  pvfc_robot *none = NULL;
  CHECK_ERROR(pvfc_robot_from_urdf_file("/nonexistent/robot.urdf", NULL, NULL, &none),
              PVFC_ERROR_IO, "/nonexistent/robot.urdf");
  CHECK(none == NULL);
  CHECK_ERROR(pvfc_robot_from_urdf_file(argv[1], NULL, "nowhere", &none), PVFC_ERROR_URDF,
              "nowhere");
  CHECK_ERROR(pvfc_robot_from_urdf_string("<robot name='r'><link name='a'/>", "broken.urdf",
                                          NULL, NULL, &none),
              PVFC_ERROR_URDF, "broken.urdf");
  CHECK_ERROR(pvfc_robot_from_urdf_file(NULL, NULL, NULL, &none), PVFC_ERROR_NULL_POINTER,
              "path");
  CHECK_ERROR(pvfc_robot_from_urdf_file(argv[1], NULL, "tool0", NULL),
              PVFC_ERROR_NULL_POINTER, "out");

  /* A controller on a closed contour through three postures. */
  const double waypoints[3 * DOF] = {
      0.0, -1.2, 1.4, -1.8, -1.57, 0.0,
      0.3, -1.0, 1.2, -1.7, -1.57, 0.2,
      -0.2, -1.3, 1.5, -1.9, -1.57, -0.1,
  };
  const double h[DOF] = {4, 4, 4, 4, 4, 4};
  pvfc_settings settings = pvfc_settings_default();
  settings.energy = 40.0;
  settings.self_pacing = 50.0;
  pvfc_controller *ctl = NULL;
  CHECK(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &settings, &ctl) ==
        PVFC_OK);
  CHECK(pvfc_controller_dof(ctl) == DOF);
  pvfc_controller *bad = NULL;
  CHECK_ERROR(pvfc_controller_new_waypoints(robot, waypoints, 3, 5, 1.5, h, DOF, &settings, &bad),
              PVFC_ERROR_WRONG_SIZE, "waypoints");
  CHECK_ERROR(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, 2, &settings, &bad),
              PVFC_ERROR_WRONG_SIZE, "h");
  CHECK_ERROR(pvfc_controller_new_waypoints(NULL, waypoints, 3, DOF, 1.5, h, DOF, NULL, &bad),
              PVFC_ERROR_NULL_POINTER, "robot");
  pvfc_settings wrong = settings;
  wrong.size = 8;
  CHECK_ERROR(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &wrong, &bad),
              PVFC_ERROR_WRONG_SIZE, "settings");
  wrong = settings;
  wrong.energy = -1.0;
  CHECK_ERROR(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &wrong, &bad),
              PVFC_ERROR_INVALID_ARGUMENT, "");
  double nan_waypoints[3 * DOF];
  memcpy(nan_waypoints, waypoints, sizeof waypoints);
  nan_waypoints[7] = NAN;
  CHECK_ERROR(pvfc_controller_new_waypoints(robot, nan_waypoints, 3, DOF, 1.5, h, DOF, &settings, &bad),
              PVFC_ERROR_NON_FINITE, "waypoints[7]");
  CHECK(bad == NULL);

  /* Steps: finite torques; the contour's point; bad inputs change nothing. */
  double q[DOF] = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  double v[DOF] = {0};
  double torque[DOF], again[DOF];
  pvfc_diagnostics d;
  CHECK(pvfc_controller_step(ctl, q, v, DOF, 1e-3, torque, DOF, &d) == PVFC_OK);
  for (int i = 0; i < DOF; i++) CHECK(isfinite(torque[i]));
  CHECK(d.potential > 0.0 && isfinite(d.beta) && d.kinetic_energy > 0.0);
  double xd[DOF];
  CHECK(pvfc_controller_contour_point(ctl, 0.0, xd, DOF) == PVFC_OK);
  for (int i = 0; i < DOF; i++) CHECK(fabs(xd[i] - waypoints[i]) < 1e-12);
  CHECK(pvfc_controller_reset(ctl) == PVFC_OK);
  double q_nan[DOF];
  memcpy(q_nan, q, sizeof q);
  q_nan[2] = NAN;
  CHECK_ERROR(pvfc_controller_step(ctl, q_nan, v, DOF, 1e-3, torque, DOF, NULL),
              PVFC_ERROR_NON_FINITE, "q[2]");
  CHECK_ERROR(pvfc_controller_step(ctl, q, v, 5, 1e-3, torque, DOF, NULL), PVFC_ERROR_WRONG_SIZE,
              "q: 5 entries");
  CHECK_ERROR(pvfc_controller_step(ctl, q, v, DOF, 1e-3, torque, 3, NULL), PVFC_ERROR_WRONG_SIZE,
              "torque_out");
  CHECK_ERROR(pvfc_controller_step(ctl, q, NULL, DOF, 1e-3, torque, DOF, NULL),
              PVFC_ERROR_NULL_POINTER, "qdot");
  CHECK_ERROR(pvfc_controller_step(ctl, q, v, DOF, 1e-3, NULL, DOF, NULL),
              PVFC_ERROR_NULL_POINTER, "torque_out");
  CHECK_ERROR(pvfc_controller_step(ctl, q, v, DOF, -1.0, torque, DOF, NULL),
              PVFC_ERROR_INVALID_ARGUMENT, "dt");
  CHECK_ERROR(pvfc_controller_step(NULL, q, v, DOF, 1e-3, torque, DOF, NULL),
              PVFC_ERROR_NULL_POINTER, "ctl");
  /* After the errors the controller is where the reset put it: the same torque again. */
  CHECK(pvfc_controller_step(ctl, q, v, DOF, 1e-3, again, DOF, NULL) == PVFC_OK);
  for (int i = 0; i < DOF; i++) CHECK(again[i] == torque[i]);

  /* The coupling rate γβĒ in place of γ: 40 /s at Ē = 40 (β = 1) is γ = 1, the default's
     controller, step for step; a rate ≤ 0 is refused, naming it. */
  {
    pvfc_settings by_rate = settings;
    by_rate.gamma = 1e9; /* not read */
    by_rate.coupling_rate = 40.0;
    pvfc_controller *rated = NULL;
    CHECK(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &by_rate,
                                        &rated) == PVFC_OK);
    double rated_torque[DOF];
    CHECK(pvfc_controller_step(rated, q, v, DOF, 1e-3, rated_torque, DOF, NULL) == PVFC_OK);
    for (int i = 0; i < DOF; i++) CHECK(rated_torque[i] == torque[i]);
    pvfc_controller_destroy(rated);
    by_rate.coupling_rate = -1.0;
    CHECK_ERROR(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &by_rate,
                                              &bad),
                PVFC_ERROR_INVALID_ARGUMENT, "coupling_rate");
    /* The nominal speed's integral: a negative gain is refused. */
    pvfc_settings integral = pvfc_settings_default();
    integral.nominal_speed_c = 0.5;
    integral.nominal_speed_r = 1.0;
    integral.nominal_speed_integral = -1.0;
    CHECK_ERROR(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &integral,
                                              &bad),
                PVFC_ERROR_INVALID_ARGUMENT, "integral");
    integral.nominal_speed_integral = 0.5;
    pvfc_controller *with_integral = NULL;
    CHECK(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &integral,
                                        &with_integral) == PVFC_OK);
    pvfc_controller_destroy(with_integral);
    /* An energy level below the field's: refused at the step; with the field bounded at half
       of it, the step is made; a share outside (0, 1) is refused, naming it. */
    pvfc_settings low = pvfc_settings_default();
    low.energy = 1e-6;
    pvfc_controller *starved = NULL;
    CHECK(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &low, &starved) ==
          PVFC_OK);
    double far[DOF] = {0, 0, 0, 0, 0, 0}, still[DOF] = {0, 0, 0, 0, 0, 0}, t[DOF];
    CHECK(pvfc_controller_step(starved, far, still, DOF, 1e-3, t, DOF, NULL) ==
          PVFC_ERROR_ENERGY_TOO_LOW);
    pvfc_controller_destroy(starved);
    low.field_energy_bound = 0.5;
    pvfc_controller *bounded = NULL;
    CHECK(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &low, &bounded) ==
          PVFC_OK);
    CHECK(pvfc_controller_step(bounded, far, still, DOF, 1e-3, t, DOF, NULL) == PVFC_OK);
    for (int i = 0; i < DOF; i++) CHECK(isfinite(t[i]));
    pvfc_controller_destroy(bounded);
    low.field_energy_bound = 1.5;
    CHECK_ERROR(pvfc_controller_new_waypoints(robot, waypoints, 3, DOF, 1.5, h, DOF, &low, &bad),
                PVFC_ERROR_INVALID_ARGUMENT, "field_energy_bound");
  }

  /* The passive digital controller with torque limits. */
  const double limit[DOF] = {150, 150, 150, 28, 28, 28};
  pvfc_passive_options options = pvfc_passive_options_default();
  options.torque_limit = limit;
  options.n = DOF;
  pvfc_passive *passive = NULL;
  CHECK(pvfc_passive_new(ctl, &options, &passive) == PVFC_OK);
  pvfc_energy_account account;
  for (int k = 0; k < 10; k++) {
    CHECK(pvfc_passive_step(passive, q, NULL, NULL, DOF, 1e-3, torque, DOF, &account) ==
          PVFC_OK);
    for (int i = 0; i < DOF; i++) CHECK(fabs(torque[i]) <= limit[i]);
    CHECK(account.storage >= 0.0 && account.scale >= 0.0 && account.scale <= 1.0);
  }
  CHECK(isfinite(pvfc_passive_storage(passive)));
  CHECK(isnan(pvfc_passive_storage(NULL)));
  options.n = 2;
  pvfc_passive *bad_passive = NULL;
  CHECK_ERROR(pvfc_passive_new(ctl, &options, &bad_passive), PVFC_ERROR_WRONG_SIZE,
              "options.torque_limit");
  CHECK(bad_passive == NULL);

  /* Supervision: a NaN reading and a spike are faults answered with zero torque; the
   * controller resumes at the next good reading. */
  {
    const double max_speed[DOF] = {3, 3, 3, 6, 6, 6};
    pvfc_passive_options watched = pvfc_passive_options_default();
    watched.max_speed = max_speed;
    watched.n = DOF;
    pvfc_passive *bad_watch = NULL;
    CHECK_ERROR(pvfc_passive_new(ctl, &watched, &bad_watch), PVFC_ERROR_INVALID_ARGUMENT,
                "period");
    CHECK(bad_watch == NULL);
    watched.min_period = 5e-4;
    watched.max_period = 3e-3;
    pvfc_passive *sup = NULL;
    CHECK(pvfc_passive_new(ctl, &watched, &sup) == PVFC_OK);
    double r[DOF];
    for (int i = 0; i < DOF; i++) r[i] = q[i];
    CHECK(pvfc_passive_step(sup, r, NULL, NULL, DOF, 1e-3, torque, DOF, &account) == PVFC_OK);
    CHECK(account.fault == PVFC_FAULT_NONE && account.fault_joint == -1);
    r[4] = NAN;
    CHECK_ERROR(pvfc_passive_step(sup, r, NULL, NULL, DOF, 1e-3, torque, DOF, &account),
                PVFC_FAULT, "non-finite reading");
    CHECK(account.fault == PVFC_FAULT_NON_FINITE);
    for (int i = 0; i < DOF; i++) CHECK(torque[i] == 0.0);
    CHECK(account.unseen > 0.0);
    r[4] = q[4] + 0.5; /* half a radian in a millisecond */
    CHECK_ERROR(pvfc_passive_step(sup, r, NULL, NULL, DOF, 1e-3, torque, DOF, &account),
                PVFC_FAULT, "joint 4");
    CHECK(account.fault == PVFC_FAULT_SPEED && account.fault_joint == 4);
    r[4] = q[4];
    CHECK_ERROR(pvfc_passive_step(sup, r, NULL, NULL, DOF, 0.1, torque, DOF, &account),
                PVFC_FAULT, "period");
    CHECK(account.fault == PVFC_FAULT_PERIOD);
    CHECK(pvfc_passive_step(sup, r, NULL, NULL, DOF, 1e-3, torque, DOF, &account) == PVFC_OK);
    CHECK(account.fault == PVFC_FAULT_NONE);
    pvfc_passive_destroy(sup);
  }

  /* The pace throttle: on drives too weak for the command (here for gravity alone) the
   * field's pace falls below 1; it needs torque limits, and a bad setting is named. */
  {
    const double weak[DOF] = {2, 2, 2, 1, 1, 1};
    pvfc_passive_options throttled = pvfc_passive_options_default();
    throttled.pace_throttle_time_constant = 0.05;
    throttled.pace_throttle_threshold = 0.8;
    throttled.pace_throttle_floor = 0.05;
    pvfc_passive *thr = NULL;
    CHECK_ERROR(pvfc_passive_new(ctl, &throttled, &thr), PVFC_ERROR_INVALID_ARGUMENT,
                "torque_limit");
    CHECK(thr == NULL);
    throttled.torque_limit = weak;
    throttled.n = DOF;
    throttled.pace_throttle_threshold = 1.0;
    CHECK_ERROR(pvfc_passive_new(ctl, &throttled, &thr), PVFC_ERROR_INVALID_ARGUMENT,
                "pace_throttle.threshold");
    throttled.pace_throttle_threshold = 0.8;
    CHECK(pvfc_passive_new(ctl, &throttled, &thr) == PVFC_OK);
    CHECK(pvfc_passive_pace_scale(thr) == 1.0);
    for (int k = 0; k < 20; k++)
      CHECK(pvfc_passive_step(thr, q, NULL, NULL, DOF, 1e-3, torque, DOF, &account) ==
            PVFC_OK);
    const double scale = pvfc_passive_pace_scale(thr);
    CHECK(scale >= 0.05 && scale < 0.9);
    CHECK(pvfc_passive_pace_scale(passive) == 1.0);
    CHECK(isnan(pvfc_passive_pace_scale(NULL)));
    pvfc_passive_destroy(thr);
    /* The learned pace: it needs torque limits, a pace planned along a closed contour
     * (this controller has none), and a rule in range. */
    pvfc_passive_options learned = pvfc_passive_options_default();
    learned.pace_learning_target = 1.0;
    thr = NULL;
    CHECK_ERROR(pvfc_passive_new(ctl, &learned, &thr), PVFC_ERROR_INVALID_ARGUMENT,
                "torque_limit");
    learned.torque_limit = weak;
    learned.n = DOF;
    learned.pace_learning_fall = 1.0;
    CHECK_ERROR(pvfc_passive_new(ctl, &learned, &thr), PVFC_ERROR_INVALID_ARGUMENT,
                "pace_learning.fall");
    learned.pace_learning_fall = 0.3;
    CHECK_ERROR(pvfc_passive_new(ctl, &learned, &thr), PVFC_ERROR_INVALID_ARGUMENT,
                "no pace to learn");
    CHECK(thr == NULL);
    /* The torque the model misses, learned beside it (pace_learning_miss, in [0, 1]): it
       plans on the controller's pace within the drives' limits, refused by name without one
       (tests/abi.rs steps one that has it). */
    const double drives[DOF] = {150, 150, 150, 28, 28, 28};
    learned.torque_limit = drives;
    learned.pace_learning_miss = 1.5;
    CHECK_ERROR(pvfc_passive_new(ctl, &learned, &thr), PVFC_ERROR_INVALID_ARGUMENT,
                "pace_learning.miss");
    learned.pace_learning_miss = 0.5;
    CHECK_ERROR(pvfc_passive_new(ctl, &learned, &thr), PVFC_ERROR_INVALID_ARGUMENT,
                "pace_learning.miss plans against a pace");
    CHECK(thr == NULL);
  }

  /* Dynamics: M symmetric, rnea(q, v, 0) = C v + g. */
  double m[DOF * DOF], c[DOF * DOF], g[DOF], tau[DOF], zero[DOF] = {0};
  const double vel[DOF] = {0.4, -0.3, 0.2, 0.5, -0.6, 0.1};
  CHECK(pvfc_robot_dynamics(robot, q, vel, DOF, m, c, g) == PVFC_OK);
  CHECK(pvfc_robot_rnea(robot, q, vel, zero, DOF, tau) == PVFC_OK);
  for (int i = 0; i < DOF; i++) {
    double cv = g[i];
    for (int j = 0; j < DOF; j++) {
      CHECK(m[i * DOF + j] == m[j * DOF + i]);
      cv += c[i * DOF + j] * vel[j];
    }
    CHECK(fabs(tau[i] - cv) < 1e-10 * (1.0 + fabs(cv)));
  }
  CHECK_ERROR(pvfc_robot_inertia(robot, q, DOF, m, DOF), PVFC_ERROR_WRONG_SIZE, "m_out");
  CHECK_ERROR(pvfc_robot_gravity(robot, q, DOF, NULL), PVFC_ERROR_NULL_POINTER, "g_out");

  /* A Cartesian circle, followed with the task-space field; the tool's distance to it. */
  const double center[3] = {0.55, 0.0, 0.3}, normal[3] = {0.0, 0.0, 1.0};
  const double seed[DOF] = {0.0, -1.2, 1.4, -1.8, -1.57, 0.0};
  pvfc_cartesian_options cartesian = pvfc_cartesian_options_default();
  pvfc_contour *circle = NULL;
  CHECK_ERROR(pvfc_contour_cartesian_circle(center, normal, 0.1, NULL, 0.0, 10.0, &cartesian,
                                            &circle),
              PVFC_ERROR_NULL_POINTER, "options.seed");
  cartesian.seed = seed;
  cartesian.seed_len = DOF;
  cartesian.fixed_orientation = true;
  cartesian.task_field = true;
  CHECK(pvfc_contour_cartesian_circle(center, normal, 0.1, NULL, 0.0, 10.0, &cartesian,
                                      &circle) == PVFC_OK);
  pvfc_controller *task = NULL;
  CHECK(pvfc_controller_new(robot, circle, NULL, 0, &settings, &task) == PVFC_OK);
  CHECK(pvfc_controller_step(task, q, v, DOF, 1e-3, torque, DOF, &d) == PVFC_OK);
  CHECK(d.potential > 0.0);
  double p[3], distance = -1.0;
  CHECK(pvfc_robot_tool_pose(robot, seed, DOF, NULL, p) == PVFC_OK);
  CHECK(pvfc_contour_distance(circle, p, &distance, NULL) == PVFC_OK);
  CHECK(distance > 0.0 && distance < 1.0);
  /* Saturated at 2 cm: the same field with its pull bounded, U below ½k|e|² off the path; a
     negative distance is refused. */
  const double plain_potential = d.potential;
  cartesian.task_saturation = 0.02;
  pvfc_contour *soft = NULL;
  pvfc_controller *saturated = NULL;
  CHECK(pvfc_contour_cartesian_circle(center, normal, 0.1, NULL, 0.0, 10.0, &cartesian, &soft) ==
        PVFC_OK);
  CHECK(pvfc_controller_new(robot, soft, NULL, 0, &settings, &saturated) == PVFC_OK);
  CHECK(pvfc_controller_step(saturated, q, v, DOF, 1e-3, torque, DOF, &d) == PVFC_OK);
  CHECK(d.potential > 0.0 && d.potential < plain_potential);
  pvfc_controller_destroy(saturated);
  pvfc_contour_destroy(soft);
  cartesian.task_saturation = -1.0;
  soft = NULL;
  saturated = NULL;
  if (pvfc_contour_cartesian_circle(center, normal, 0.1, NULL, 0.0, 10.0, &cartesian, &soft) ==
      PVFC_OK) {
    CHECK(pvfc_controller_new(robot, soft, NULL, 0, &settings, &saturated) != PVFC_OK);
    CHECK(saturated == NULL);
    pvfc_contour_destroy(soft);
  }
  cartesian.task_saturation = 0.0;
  pvfc_controller_destroy(task);
  pvfc_contour_destroy(circle);
  pvfc_contour_destroy(NULL);

  /* The tool centre point: a cone 12 cm along the flange's z, tilted; the tool pose moves by
     R·(0, 0, 0.12) and turns by the tilt; bad input leaves the robot as it was. */
  {
    pvfc_robot *cone = NULL;
    CHECK(pvfc_robot_from_urdf_file(argv[1], NULL, "tool0", &cone) == PVFC_OK);
    double r0[9], p0[3], r1[9], p1[3];
    CHECK(pvfc_robot_tool_pose(cone, seed, DOF, r0, p0) == PVFC_OK);
    const double xyz[3] = {0.0, 0.0, 0.12}, rpy[3] = {0.0, 0.35, 0.0};
    CHECK(pvfc_robot_set_tool(cone, xyz, rpy) == PVFC_OK);
    CHECK(pvfc_robot_tool_pose(cone, seed, DOF, r1, p1) == PVFC_OK);
    for (int i = 0; i < 3; i++) {
      CHECK(fabs(p1[i] - (p0[i] + 0.12 * r0[3 * i + 2])) < 1e-12);
      /* The new x axis is R0·(cos 0.35, 0, −sin 0.35). */
      CHECK(fabs(r1[3 * i] - (cos(0.35) * r0[3 * i] - sin(0.35) * r0[3 * i + 2])) < 1e-12);
    }
    const double bad[3] = {0.0, NAN, 0.12};
    CHECK_ERROR(pvfc_robot_set_tool(cone, bad, NULL), PVFC_ERROR_NON_FINITE, "xyz[1] is NaN");
    CHECK_ERROR(pvfc_robot_set_tool(NULL, xyz, NULL), PVFC_ERROR_NULL_POINTER, "robot");
    double p2[3];
    CHECK(pvfc_robot_tool_pose(cone, seed, DOF, NULL, p2) == PVFC_OK);
    CHECK(p2[0] == p1[0] && p2[1] == p1[1] && p2[2] == p1[2]);
    /* A part program on a part placed on the table, followed by the cone: its feeds are the
       pace, so the energy level can be sized from them (energy = 0); the same program
       without F has no pace to size it from. */
    const char *program =
        "gcode = \"scenarios/parts/bracket.nc\"\n"
        "part = { xyz = [0.45, -0.15, 0.30], rpy = [0.0, 0.0, 0.1] }\n"
        "seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]\nfixed_orientation = true\ntolerance = 1.0e-5\n";
    pvfc_contour *part = NULL;
    CHECK(pvfc_contour_cartesian_toml(program, NULL, 12.0, 0.0, &part) == PVFC_OK);
    pvfc_settings paced = pvfc_settings_default();
    paced.energy = 0.0;
    pvfc_controller *deburr = NULL;
    CHECK(pvfc_controller_new(cone, part, NULL, 0, &paced, &deburr) == PVFC_OK);
    double t6[DOF], q6[DOF], v6[DOF] = {0};
    memcpy(q6, seed, sizeof q6);
    pvfc_diagnostics dd;
    CHECK(pvfc_controller_step(deburr, q6, v6, DOF, 1e-3, t6, DOF, &dd) == PVFC_OK);
    /* Its pace is planned along a closed path: the passive controller can learn it. */
    {
      const double drives[DOF] = {150, 150, 150, 28, 28, 28};
      pvfc_passive_options learned = pvfc_passive_options_default();
      learned.torque_limit = drives;
      learned.n = DOF;
      learned.pace_learning_target = 1.0;
      pvfc_passive *lp = NULL;
      CHECK(pvfc_passive_new(deburr, &learned, &lp) == PVFC_OK);
      CHECK(pvfc_passive_step(lp, q6, v6, NULL, DOF, 1e-3, t6, DOF, NULL) == PVFC_OK);
      pvfc_passive_destroy(lp);
    }
    pvfc_controller_destroy(deburr);
    pvfc_contour_destroy(part);
    FILE *f = fopen("target/c/bracket_without_feeds.nc", "w");
    CHECK(f != NULL);
    if (f) {
      fputs("G0 X0 Y0\nG1 X0.1\nG3 X0.1 Y0.1 R0.05\nG1 X0\nG1 Y0\n", f);
      fclose(f);
      pvfc_contour *bare = NULL;
      CHECK(pvfc_contour_cartesian_toml(
                "gcode = \"bracket_without_feeds.nc\"\n"
                "part = { xyz = [0.45, -0.15, 0.30], rpy = [0.0, 0.0, 0.1] }\n"
                "seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]\nfixed_orientation = true\n",
                "target/c", 12.0, 0.0, &bare) == PVFC_OK);
      deburr = NULL;
      CHECK_ERROR(pvfc_controller_new(cone, bare, NULL, 0, &paced, &deburr),
                  PVFC_ERROR_INVALID_ARGUMENT, "give a pace");
      CHECK(deburr == NULL);
      pvfc_contour_destroy(bare);
    }
    /* The cone's axis along the path's frame, leaning 0.2 rad towards the direction of
       travel, its roll free: on a rounded rectangle and on the bracket (tangent everywhere)
       a controller is made and steps; on a program with a sharp corner the frame would
       jump and is refused. */
    {
      pvfc_contour *leaning = NULL;
      CHECK(pvfc_contour_cartesian_toml(
                "points = [[0.45, -0.15, 0.30], [0.65, -0.15, 0.30], [0.65, 0.20, 0.30], [0.45, 0.20, 0.30]]\n"
                "corner_radius = 0.03\nsamples = 64\n"
                "seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]\n"
                "tool_frame = { lead = 0.2 }\n",
                NULL, 12.0, 0.0, &leaning) == PVFC_OK);
      pvfc_controller *lean = NULL;
      CHECK(pvfc_controller_new(cone, leaning, NULL, 0, &paced, &lean) == PVFC_ERROR_INVALID_ARGUMENT);
      pvfc_settings level = pvfc_settings_default();
      CHECK(pvfc_controller_new(cone, leaning, NULL, 0, &level, &lean) == PVFC_OK);
      CHECK(pvfc_controller_step(lean, q6, v6, DOF, 1e-3, t6, DOF, &dd) == PVFC_OK);
      pvfc_controller_destroy(lean);
      pvfc_contour_destroy(leaning);
      pvfc_contour *bracket = NULL;
      CHECK(pvfc_contour_cartesian_toml(
                "gcode = \"scenarios/parts/bracket.nc\"\nsamples = 64\n"
                "part = { xyz = [0.45, -0.15, 0.30], rpy = [0.0, 0.0, 0.1] }\n"
                "seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]\n"
                "tool_frame = { lead = 0.2 }\n",
                NULL, 12.0, 0.0, &bracket) == PVFC_OK);
      CHECK(pvfc_controller_new(cone, bracket, NULL, 0, &paced, &lean) == PVFC_OK);
      CHECK(pvfc_controller_step(lean, q6, v6, DOF, 1e-3, t6, DOF, &dd) == PVFC_OK);
      pvfc_controller_destroy(lean);
      pvfc_contour_destroy(bracket);
      pvfc_contour *sharp = NULL;
      CHECK(pvfc_contour_cartesian_toml(
                "gcode = \"bracket_without_feeds.nc\"\n"
                "part = { xyz = [0.45, -0.15, 0.30], rpy = [0.0, 0.0, 0.1] }\n"
                "seed = [0.0, -1.2, 1.4, -1.8, -1.57, 0.0]\n"
                "tool_frame = { lead = 0.2 }\n",
                "target/c", 12.0, 0.0, &sharp) == PVFC_OK);
      lean = NULL;
      CHECK_ERROR(pvfc_controller_new(cone, sharp, NULL, 0, &level, &lean),
                  PVFC_ERROR_INVALID_ARGUMENT, "turns sharply");
      CHECK(lean == NULL);
      pvfc_contour_destroy(sharp);
    }
    /* NULL for both: back to the flange. */
    CHECK(pvfc_robot_set_tool(cone, NULL, NULL) == PVFC_OK);
    CHECK(pvfc_robot_tool_pose(cone, seed, DOF, NULL, p2) == PVFC_OK);
    CHECK(p2[0] == p0[0] && p2[1] == p0[1] && p2[2] == p0[2]);
    pvfc_robot_destroy(cone);
  }

  pvfc_passive_destroy(passive);
  pvfc_controller_destroy(ctl);
  pvfc_robot_destroy(robot);
  pvfc_passive_destroy(NULL);
  pvfc_controller_destroy(NULL);
  pvfc_robot_destroy(NULL);

  if (failures) {
    fprintf(stderr, "%d checks failed\n", failures);
    return 1;
  }
  printf("test_pvfc: all checks passed\n");
  return 0;
}
