/* Lookup time of an exported controller: ns per <prefix>_input call over states drawn around
 * the tube (docs/deploy.md, docs/benchmarks.md). Build with the controller's source:
 *   gcc -std=c99 -O2 -I OUT -DCTRL_HEADER='"pendulum.h"' -DCTRL_INPUT=pendulum_input \
 *       -DN=2 -DM=1 examples/deploy_c/lookup_bench.c OUT/pendulum.c -lm
 *   ./a.out CENTRES.csv SPREAD
 * CENTRES.csv: one nominal state per line (k = line number, comma-separated); SPREAD scales the
 * uniform offsets (in state units) around each centre. */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include CTRL_HEADER

#define MAXK 4096
#define QUERIES 4000000

static double centres[MAXK][N];

int main(int argc, char **argv)
{
  FILE *f;
  int steps = 0, i, q, ok = 0;
  double spread, *xs, u[M], sink = 0.0, ns;
  int *ks;
  struct timespec t0, t1;
  if (argc != 3 || !(f = fopen(argv[1], "r"))) {
    fprintf(stderr, "usage: %s CENTRES.csv SPREAD\n", argv[0]);
    return 2;
  }
  spread = atof(argv[2]);
  while (steps < MAXK) {
    for (i = 0; i < N; ++i)
      if (fscanf(f, " %lf ,", &centres[steps][i]) != 1) break;
    if (i < N) break;
    ++steps;
  }
  fclose(f);
  if (steps == 0) return 2;
  xs = malloc(sizeof(double) * N * QUERIES);
  ks = malloc(sizeof(int) * QUERIES);
  if (!xs || !ks) return 2;
  srand(1);
  for (q = 0; q < QUERIES; ++q) {
    ks[q] = rand() % steps;
    for (i = 0; i < N; ++i) xs[q * N + i] = centres[ks[q]][i] + spread * (2.0 * rand() / (double)RAND_MAX - 1.0);
  }
  clock_gettime(CLOCK_MONOTONIC, &t0);
  for (q = 0; q < QUERIES; ++q) {
    if (CTRL_INPUT(xs + q * N, ks[q], u) == 0) {
      ++ok;
      sink += u[0];
    }
  }
  clock_gettime(CLOCK_MONOTONIC, &t1);
  ns = ((t1.tv_sec - t0.tv_sec) * 1e9 + (t1.tv_nsec - t0.tv_nsec)) / QUERIES;
  printf("%.1f ns per call, %d of %d queries with an input (checksum %g)\n", ns, ok, QUERIES, sink);
  free(xs);
  free(ks);
  return 0;
}
