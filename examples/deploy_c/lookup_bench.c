/* Time of an exported controller's <prefix>_input (docs/deploy.md, docs/benchmarks.md): the mean
 * over 4e6 calls in one timed loop, then each of the first 1e6 calls timed on its own
 * (clock_gettime; the timer's own cost, measured around an empty statement, is printed and not
 * subtracted): median, 99.9th percentile and worst of single calls, and the same of the best of 3
 * repetitions of each call, which takes out the preemptions of a loaded machine (a single call's
 * worst is then the scheduler's, not the controller's). Build with the controller's source:
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
#define TIMED 1000000

static double centres[MAXK][N];

static long elapsed_ns(const struct timespec *a, const struct timespec *b)
{
  return (long)(b->tv_sec - a->tv_sec) * 1000000000L + (b->tv_nsec - a->tv_nsec);
}

static int by_value(const void *a, const void *b)
{
  const long x = *(const long *)a, y = *(const long *)b;
  return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
  FILE *f;
  int steps = 0, i, q, ok = 0;
  double spread, *xs, u[M], sink = 0.0, ns;
  int *ks;
  long *each, *best, *idle;
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
  each = malloc(sizeof(long) * TIMED);
  best = malloc(sizeof(long) * TIMED);
  idle = malloc(sizeof(long) * TIMED);
  if (!xs || !ks || !each || !best || !idle) return 2;
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
  ns = (double)elapsed_ns(&t0, &t1) / QUERIES;
  printf("%.1f ns per call, %d of %d queries with an input (checksum %g)\n", ns, ok, QUERIES, sink);
  for (q = 0; q < TIMED; ++q) {
    int r;
    for (r = 0; r < 3; ++r) {
      long t;
      clock_gettime(CLOCK_MONOTONIC, &t0);
      if (CTRL_INPUT(xs + q * N, ks[q], u) == 0) sink += u[0];
      clock_gettime(CLOCK_MONOTONIC, &t1);
      t = elapsed_ns(&t0, &t1);
      if (r == 0) each[q] = best[q] = t;
      else if (t < best[q]) best[q] = t;
    }
    clock_gettime(CLOCK_MONOTONIC, &t0);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    idle[q] = elapsed_ns(&t0, &t1);
  }
  qsort(each, TIMED, sizeof(long), by_value);
  qsort(best, TIMED, sizeof(long), by_value);
  qsort(idle, TIMED, sizeof(long), by_value);
  printf("each of %d calls: median %ld ns, 99.9%% %ld ns, worst %ld ns; best of 3: median %ld ns, 99.9%% %ld ns, worst %ld ns "
         "(timer alone: median %ld ns, worst %ld ns; checksum %g)\n",
         TIMED, each[TIMED / 2], each[TIMED - TIMED / 1000], each[TIMED - 1], best[TIMED / 2], best[TIMED - TIMED / 1000],
         best[TIMED - 1], idle[TIMED / 2], idle[TIMED - 1], sink);
  free(xs);
  free(ks);
  free(each);
  free(best);
  free(idle);
  return 0;
}
