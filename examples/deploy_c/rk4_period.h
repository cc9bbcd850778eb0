/* The closed-loop examples' plant: one sampling period under a constant input (zero-order hold),
 * integrated by RK4 with `substeps` steps, the disturbance redrawn by `draw` at every step (a
 * piecewise-constant w, one of the measurable disturbances the guarantee covers). Plain C99. */
#ifndef RK4_PERIOD_H_
#define RK4_PERIOD_H_

#define RK4_MAX_DIM 8

typedef void (*rk4_field)(const double *x, const double *u, const double *w, double *dx);

static void rk4_period(double *x, const double *u, int n, double tau, int substeps, rk4_field field, void (*draw)(double *w))
{
  const double h = tau / substeps;
  int s, i;
  for (s = 0; s < substeps; ++s) {
    double k1[RK4_MAX_DIM], k2[RK4_MAX_DIM], k3[RK4_MAX_DIM], k4[RK4_MAX_DIM], y[RK4_MAX_DIM], w[RK4_MAX_DIM];
    draw(w);
    field(x, u, w, k1);
    for (i = 0; i < n; ++i) y[i] = x[i] + 0.5 * h * k1[i];
    field(y, u, w, k2);
    for (i = 0; i < n; ++i) y[i] = x[i] + 0.5 * h * k2[i];
    field(y, u, w, k3);
    for (i = 0; i < n; ++i) y[i] = x[i] + h * k3[i];
    field(y, u, w, k4);
    for (i = 0; i < n; ++i) x[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
}

#endif /* RK4_PERIOD_H_ */
