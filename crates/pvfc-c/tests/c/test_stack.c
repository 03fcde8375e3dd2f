/* The stack pvfc needs: a thread whose whole stack is SETUP_KIB KiB (pthread_attr_setstacksize)
 * reads the UR5 and builds a joint-space controller on waypoints, a Cartesian circle, a
 * task-space controller on it and a passive controller; then a thread of STEP_KIB KiB runs
 * 100 periods of the two controllers' steps, the passive step, the dynamics, the tool pose
 * and the distance to the path, and fails a step with a NaN. A call that needed more would
 * overflow the stack into its guard page and kill the process.
 *   test_stack path/to/ur5_robot.urdf [SETUP_KIB [STEP_KIB]] */
#define _POSIX_C_SOURCE 200809L
#include "pvfc.h"
#include "ur5_handles.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


typedef struct {
  Ur5Handles u;
  int ok;
} Handles;

static void *periods(void *arg) {
  Handles *h = arg;
  double q[DOF] = {0.1, -1.1, 1.3, -1.7, -1.5, 0.1};
  double v[DOF] = {0.2, -0.1, 0.05, 0.0, 0.1, -0.2};
  double torque[DOF], held[DOF], m[DOF * DOF], c[DOF * DOF], g[DOF], p[3], d;
  pvfc_diagnostics diag;
  pvfc_energy_account account;
  int ok = 1;
  for (int k = 0; k < 100 && ok; k++) {
    ok = pvfc_controller_step(h->u.joint, q, v, DOF, 1e-3, torque, DOF, &diag) == PVFC_OK &&
         pvfc_controller_step(h->u.task, q, v, DOF, 1e-3, torque, DOF, &diag) == PVFC_OK &&
         pvfc_passive_step(h->u.passive, q, NULL, NULL, DOF, 1e-3, held, DOF, &account) ==
             PVFC_OK &&
         pvfc_robot_dynamics(h->u.robot, q, v, DOF, m, c, g) == PVFC_OK &&
         pvfc_robot_tool_pose(h->u.robot, q, DOF, NULL, p) == PVFC_OK &&
         pvfc_contour_distance(h->u.circle, p, &d, NULL) == PVFC_OK;
    for (int i = 0; i < DOF; i++) q[i] += 1e-3 * v[i];
  }
  q[2] = 0.0 / 0.0;
  ok = ok &&
       pvfc_controller_step(h->u.joint, q, v, DOF, 1e-3, torque, DOF, &diag) ==
           PVFC_ERROR_NON_FINITE &&
       strstr(pvfc_last_error(), "q[2] is NaN") != NULL;
  h->ok = ok;
  return NULL;
}

static void fail(const char *what) {
  fprintf(stderr, "%s: %s\n", what, pvfc_last_error());
  exit(1);
}

static const char *g_urdf;

static void *setup(void *arg) {
  Handles *h = arg;
  const char *failed = ur5_handles_new(g_urdf, &h->u);
  if (failed != NULL) fail(failed);
  return NULL;
}

/* Runs `f(h)` in a thread whose stack is `kib` KiB. */
static void in_thread(void *(*f)(void *), Handles *h, size_t kib, const char *what) {
  pthread_attr_t attr;
  pthread_t thread;
  if (pthread_attr_init(&attr) != 0 || pthread_attr_setstacksize(&attr, kib * 1024) != 0 ||
      pthread_create(&thread, &attr, f, h) != 0 || pthread_join(thread, NULL) != 0) {
    fprintf(stderr, "test_stack: no thread of %zu KiB for %s\n", kib, what);
    exit(1);
  }
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: %s ur5_robot.urdf [setup KiB [step KiB]]\n", argv[0]);
    return 2;
  }
  g_urdf = argv[1];
  const size_t setup_kib = argc > 2 ? (size_t)atoi(argv[2]) : 128;
  const size_t step_kib = argc > 3 ? (size_t)atoi(argv[3]) : 32;
  Handles h = {0};
  in_thread(setup, &h, setup_kib, "the set-up");
  in_thread(periods, &h, step_kib, "the periods");
  ur5_handles_free(&h.u);
  if (!h.ok) {
    fprintf(stderr, "test_stack: a call failed (or a failure was not reported)\n");
    return 1;
  }
  printf("test_stack: the set-up in a thread of %zu KiB of stack, 100 periods and a failure in "
         "one of %zu KiB\n",
         setup_kib, step_kib);
  return 0;
}
