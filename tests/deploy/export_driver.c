/* Links an exported controller (marsyn export --format c) and answers queries from a file:
 * records of (int32 k, double x[N]) in, records of (int32 status, double u[M], int32 inside) out,
 * native byte order; `inside` is the monitor <prefix>_inside(x, k). Built by the export tests
 * (tests/deploy/c_answers.hpp) with -DCTRL_INPUT=<prefix>_input -DCTRL_INSIDE=<prefix>_inside
 * -DCTRL_HEADER="<prefix>.h" -DN=<state dim> -DM=<input dim>, under gcc -std=c99 -Wall -Wextra
 * -Werror -pedantic -Wconversion. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include CTRL_HEADER

int main(int argc, char **argv)
{
  FILE *in, *out;
  int32_t k, status, inside;
  double x[N], u[M];
  long count = 0;
  if (argc != 3) {
    fprintf(stderr, "usage: %s QUERIES ANSWERS\n", argv[0]);
    return 2;
  }
  in = fopen(argv[1], "rb");
  out = fopen(argv[2], "wb");
  if (!in || !out) {
    fprintf(stderr, "cannot open files\n");
    return 2;
  }
  while (fread(&k, sizeof k, 1, in) == 1 && fread(x, sizeof x, 1, in) == 1) {
    memset(u, 0, sizeof u);
    status = CTRL_INPUT(x, (int)k, u);
    inside = CTRL_INSIDE(x, (int)k);
    if (fwrite(&status, sizeof status, 1, out) != 1 || fwrite(u, sizeof u, 1, out) != 1 ||
        fwrite(&inside, sizeof inside, 1, out) != 1)
      return 3;
    ++count;
  }
  fclose(in);
  if (fclose(out) != 0) return 3;
  fprintf(stderr, "%ld queries\n", count);
  return 0;
}
