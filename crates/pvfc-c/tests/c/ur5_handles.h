/* The UR5's set-up shared by the C tests that run the real-time calls: the robot from URDF, a
 * joint-space controller on three waypoints, a Cartesian circle, a task-space controller on it
 * and a passive controller of that one (torque limits 150/150/150/28/28/28 N·m). */
#ifndef PVFC_TEST_UR5_HANDLES_H
#define PVFC_TEST_UR5_HANDLES_H

#include "pvfc.h"

#include <stddef.h>

#define DOF 6

typedef struct {
  pvfc_robot *robot;
  pvfc_controller *joint, *task;
  pvfc_contour *circle;
  pvfc_passive *passive;
} Ur5Handles;

/* Builds every handle of `h` from the URDF at `urdf`: NULL, or the name of what failed (the
 * message is in pvfc_last_error()). */
static inline const char *ur5_handles_new(const char *urdf, Ur5Handles *h) {
  if (pvfc_robot_from_urdf_file(urdf, NULL, "tool0", &h->robot) != PVFC_OK) return "robot";
  const double waypoints[3 * DOF] = {
      0.0, -1.2, 1.4, -1.8, -1.57, 0.0,
      0.3, -1.0, 1.2, -1.7, -1.57, 0.2,
      -0.2, -1.3, 1.5, -1.9, -1.57, -0.1,
  };
  pvfc_settings s = pvfc_settings_default();
  s.energy = 40.0;
  s.self_pacing = 50.0;
  if (pvfc_controller_new_waypoints(h->robot, waypoints, 3, DOF, 1.5, NULL, 0, &s, &h->joint) !=
      PVFC_OK)
    return "joint controller";
  const double seed[DOF] = {0.0, -1.2, 1.4, -1.8, -1.57, 0.0};
  const double center[3] = {0.55, 0.0, 0.3}, normal[3] = {0.0, 0.0, 1.0};
  pvfc_cartesian_options o = pvfc_cartesian_options_default();
  o.seed = seed;
  o.seed_len = DOF;
  o.fixed_orientation = true;
  o.task_field = true;
  if (pvfc_contour_cartesian_circle(center, normal, 0.1, NULL, 0.0, 10.0, &o, &h->circle) !=
      PVFC_OK)
    return "circle";
  if (pvfc_controller_new(h->robot, h->circle, NULL, 0, &s, &h->task) != PVFC_OK)
    return "task controller";
  const double limit[DOF] = {150, 150, 150, 28, 28, 28};
  pvfc_passive_options po = pvfc_passive_options_default();
  po.torque_limit = limit;
  po.n = DOF;
  if (pvfc_passive_new(h->task, &po, &h->passive) != PVFC_OK) return "passive";
  return NULL;
}

/* Frees every handle of `h` (NULL ones too). */
static inline void ur5_handles_free(Ur5Handles *h) {
  pvfc_passive_destroy(h->passive);
  pvfc_controller_destroy(h->task);
  pvfc_controller_destroy(h->joint);
  pvfc_contour_destroy(h->circle);
  pvfc_robot_destroy(h->robot);
}

#endif
