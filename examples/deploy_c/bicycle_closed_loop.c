/* Agent 'east' of examples/bicycles.yaml in closed loop with its exported funnel controller, and
 * the runtime monitor watching it: the kinematic bicycle is simulated here in plain C (RK4, 20
 * substeps per sampling period) under a random disturbance in W, redrawn every substep; the
 * controller is what
 *   marsyn solve examples/bicycles.yaml --out OUT
 *   marsyn export OUT/east.ctrl --format c --prefix bicycle --out OUT/c
 * writes. Build and run (docs/deploy.md):
 *   gcc -std=c99 -Wall -Wextra -pedantic -O2 -I OUT/c examples/deploy_c/bicycle_closed_loop.c OUT/c/bicycle.c -lm
 *   ./a.out [seed [kick]] > trajectory.csv
 * With a kick (a push of that many metres sideways at step 20, beyond W) the monitor must report
 * that the state left the verified set. Exit code 0 when every step had an input, the monitor
 * accepted every sampled state and x_T is in the goal box (kick 0), or when the monitor flagged the
 * kick at step 20 (kick > 0); 1 otherwise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bicycle.h"
#include "rk4_period.h"

#define WHEELBASE 0.5 /* the model's default, which bicycles.yaml keeps */
#define SUBSTEPS 20
#define KICK_STEP 20

static const double W[5] = {0.005, 0.005, 0.005, 0.01, 0.005};
static const double goal_centre[5] = {6, 2, 0, 0.75, 0}, goal_radius[5] = {0.4, 0.4, 0.6, 1.0, 0.4};

static void field(const double *x, const double *u, const double *w, double *dx)
{
  dx[0] = x[3] * cos(x[2]) + w[0];
  dx[1] = x[3] * sin(x[2]) + w[1];
  dx[2] = x[3] * tan(x[4]) / WHEELBASE + w[2];
  dx[3] = u[0] + w[3];
  dx[4] = u[1] + w[4];
}

static void draw(double *w)
{
  int i;
  for (i = 0; i < 5; ++i) w[i] = W[i] * (2.0 * rand() / (double)RAND_MAX - 1.0);
}

int main(int argc, char **argv)
{
  double x[BICYCLE_STATE_DIM] = {0, 2, 0, 0, 0}, u[BICYCLE_INPUT_DIM];
  const double kick = argc > 2 ? atof(argv[2]) : 0.0;
  int k, i, status = BICYCLE_OK, in_goal = 1, monitor = 1;
  srand(argc > 1 ? (unsigned)atoi(argv[1]) : 1u);
  printf("k,t,x,y,theta,v,delta,accel,steer_rate,inside\n");
  for (k = 0; k < BICYCLE_HORIZON; ++k) {
    if (kick != 0.0 && k == KICK_STEP) x[1] += kick;
    monitor = bicycle_inside(x, k);
    if (!monitor) break; /* left the verified set: a real robot would switch to a safe fallback here */
    status = bicycle_input(x, k, u);
    if (status != BICYCLE_OK) break;
    printf("%d,%.2f,%.6f,%.6f,%.6f,%.6f,%.6f,%.4f,%.4f,1\n", k, k * BICYCLE_TAU, x[0], x[1], x[2], x[3], x[4], u[0], u[1]);
    rk4_period(x, u, BICYCLE_STATE_DIM, BICYCLE_TAU, SUBSTEPS, field, draw);
  }
  if (monitor && status == BICYCLE_OK) monitor = bicycle_inside(x, k);
  for (i = 0; i < 5; ++i) in_goal = in_goal && fabs(x[i] - goal_centre[i]) <= goal_radius[i];
  printf("%d,%.2f,%.6f,%.6f,%.6f,%.6f,%.6f,,,%d\n", k, k * BICYCLE_TAU, x[0], x[1], x[2], x[3], x[4], monitor);
  if (kick != 0.0) {
    fprintf(stderr, "kick of %g m at step %d: the monitor %s at step %d\n", kick, KICK_STEP,
            monitor ? "did NOT flag it" : "flagged it", k);
    return !monitor && k == KICK_STEP ? 0 : 1;
  }
  fprintf(stderr, "stopped at k = %d (%s); monitor %s; x_T = (%.3f, %.3f, %.3f, %.3f, %.3f): %s\n", k,
          !monitor ? "left the verified set" : status == BICYCLE_OK ? "end of the horizon" : "no input", monitor ? "inside" : "OUTSIDE",
          x[0], x[1], x[2], x[3], x[4], in_goal ? "in the goal" : "NOT in the goal");
  return monitor && status == BICYCLE_OK && k == BICYCLE_HORIZON && in_goal ? 0 : 1;
}
