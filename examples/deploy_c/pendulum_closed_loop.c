/* The pendulum swing-up (examples/pendulum.yaml) in closed loop with its exported controller:
 * the plant is simulated here in plain C (RK4, 20 substeps per sampling period) under a random
 * disturbance in W = [0, 0] x [-0.01, 0.01], redrawn every substep; the controller is what
 *   marsyn track examples/pendulum.yaml --agent pendulum --out OUT
 *   marsyn export OUT/pendulum.ctrl --format c --out OUT
 * writes. Build and run (docs/deploy.md):
 *   gcc -std=c99 -Wall -Wextra -pedantic -O2 -I OUT examples/deploy_c/pendulum_closed_loop.c OUT/pendulum.c -lm
 *   ./a.out [seed] > trajectory.csv
 * Exit code 0 when every step had an input and x_T is in the goal box, 1 otherwise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "pendulum.h"
#include "rk4_period.h"

#define GAIN 0.2   /* the model's input_gain */
#define W1 0.01    /* disturbance bound on the angular rate */
#define SUBSTEPS 20

static void draw(double *w)
{
  w[0] = 0.0;
  w[1] = W1 * (2.0 * rand() / (double)RAND_MAX - 1.0);
}

static void field(const double *x, const double *u, const double *w, double *dx)
{
  dx[0] = x[1];
  dx[1] = GAIN * u[0] - sin(x[0]) + w[1];
}

int main(int argc, char **argv)
{
  double x[PENDULUM_STATE_DIM] = {0.0, 0.0}, u[PENDULUM_INPUT_DIM];
  int k, status = PENDULUM_OK, in_goal;
  srand(argc > 1 ? (unsigned)atoi(argv[1]) : 1u);
  printf("k,t,theta,omega,u\n");
  for (k = 0;; ++k) {
    status = pendulum_input(x, k, u);
    if (status != PENDULUM_OK) break;
    printf("%d,%.2f,%.6f,%.6f,%.3f\n", k, k * PENDULUM_TAU, x[0], x[1], u[0]);
    rk4_period(x, u, PENDULUM_STATE_DIM, PENDULUM_TAU, SUBSTEPS, field, draw);
  }
  printf("%d,%.2f,%.6f,%.6f,\n", k, k * PENDULUM_TAU, x[0], x[1]);
  in_goal = fabs(x[0] - 3.141592653589793) <= 0.3 && fabs(x[1]) <= 0.3;
  fprintf(stderr, "stopped at k = %d (%s); x_T = (%.4f, %.4f): %s\n", k,
          status == PENDULUM_OUTSIDE_HORIZON ? "end of the horizon" : "no input: outside the winning domain", x[0], x[1],
          in_goal ? "in the goal" : "NOT in the goal");
  return status == PENDULUM_OUTSIDE_HORIZON && k == PENDULUM_HORIZON && in_goal ? 0 : 1;
}
