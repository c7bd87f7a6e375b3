/* A user kernel for tests/exec_kernel_test.cpp: Moller-Trumbore in double over the line protocol
 * (docs/kernel_protocol.md), answering coarsely (`hit T B1 B2` or `miss`), with a misbehaviour on
 * the cases whose origin x is 777:
 *   mt       no misbehaviour          crash    raises SIGSEGV      hang   stops answering forever
 *   exit     exits with status 3      garbage  answers `banana`    eof    reads all input first
 * Any mode followed by `header` prints the declaration line first. Output is fully buffered (as C
 * stdio is on a pipe), so answers reach rayproof in blocks. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char* mode = "mt";

static void sub(const double* a, const double* b, double* r) { r[0] = a[0] - b[0], r[1] = a[1] - b[1], r[2] = a[2] - b[2]; }
static void cross(const double* a, const double* b, double* r) {
  r[0] = a[1] * b[2] - a[2] * b[1], r[1] = a[2] * b[0] - a[0] * b[2], r[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void answer(char* line) {
  double v[15];
  char* p = line;
  if (strncmp(p, "triangle ", 9) != 0) { fputs("miss\n", stdout); return; }
  p += 9;
  for (int i = 0; i < 15; ++i) v[i] = strtod(p, &p);
  if (v[0] == 777) {
    if (!strcmp(mode, "crash")) {
      signal(SIGSEGV, SIG_DFL);  /* a sanitizer build installs its own handler, which would exit(1) */
      raise(SIGSEGV);
    }
    if (!strcmp(mode, "hang")) for (;;) pause();
    if (!strcmp(mode, "exit")) exit(3);
    if (!strcmp(mode, "garbage")) { fputs("banana\n", stdout); return; }
  }
  const double *o = v, *d = v + 3, *p0 = v + 6, *p1 = v + 9, *p2 = v + 12;
  double e1[3], e2[3], pv[3], tv[3], qv[3];
  sub(p1, p0, e1), sub(p2, p0, e2), cross(d, e2, pv);
  const double det = dot(e1, pv);
  if (det == 0) { fputs("miss\n", stdout); return; }
  const double inv = 1 / det;
  sub(o, p0, tv);
  const double u = dot(tv, pv) * inv;
  if (u < 0 || u > 1) { fputs("miss\n", stdout); return; }
  cross(tv, e1, qv);
  const double w = dot(d, qv) * inv;
  if (w < 0 || u + w > 1) { fputs("miss\n", stdout); return; }
  const double t = dot(e2, qv) * inv;
  if (!(t >= 0)) { fputs("miss\n", stdout); return; }
  printf("hit %.17g %.17g %.17g\n", t, u, w);
}

int main(int argc, char** argv) {
  if (argc > 1) mode = argv[1];
  if (argc > 2 && !strcmp(argv[2], "header")) {
    puts("rayproof-kernel 1 double triangle");
    fflush(stdout);
  }
  char line[4096];
  if (!strcmp(mode, "eof")) {
    size_t n = 0, cap = 1024;
    char** all = malloc(cap * sizeof *all);
    while (fgets(line, sizeof line, stdin)) {
      if (n == cap) all = realloc(all, (cap *= 2) * sizeof *all);
      all[n++] = strdup(line);
    }
    for (size_t i = 0; i < n; ++i) answer(all[i]), free(all[i]);
    free(all);
    return 0;
  }
  while (fgets(line, sizeof line, stdin)) answer(line);
  return 0;
}
