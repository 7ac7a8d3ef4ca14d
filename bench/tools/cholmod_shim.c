/* LD_PRELOAD instrument for hencky's CHOLMOD calls (no change to hencky itself).
 *
 *   cc -O2 -shared -fPIC -I/usr/include/suitesparse bench/tools/cholmod_shim.c -o cholmod_shim.so -ldl
 *   LD_PRELOAD=$PWD/cholmod_shim.so CHOLMOD_SHIM_LOG=shim.log hencky run case.yaml
 *
 * Logs the wall time of cholmod_l_analyze (the fill-reducing ordering and the symbolic
 * factorization), cholmod_l_factorize (numeric), cholmod_l_solve and cholmod_l_rcond, with the
 * ordering chosen, the factor's nonzeros and flops, and for a supernodal factor the number of
 * supernodes, the entries actually stored (xsize: includes the explicit zeros of relaxed
 * supernodes), the integer pattern (ssize) and the largest update matrix (maxcsize). CHOLMOD_SHIM_ORDERING=amd|metis|nesdis|
 * default forces one ordering (CHOLMOD's default tries AMD, then METIS when AMD's fill is
 * high, and keeps the better one), to compare orderings on hencky's own matrices.
 */
#define _GNU_SOURCE
#include <cholmod.h>
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static FILE *out(void) {
  static FILE *f;
  if (!f) {
    const char *p = getenv("CHOLMOD_SHIM_LOG");
    f = p ? fopen(p, "a") : NULL;
    if (!f) f = stderr;
  }
  return f;
}

static void *real(const char *name) {
  void *p = dlsym(RTLD_NEXT, name);
  if (!p) {
    fprintf(stderr, "cholmod_shim: %s not found\n", name);
    abort();
  }
  return p;
}

static const char *ordering_name(int m) {
  switch (m) {
    case CHOLMOD_NATURAL: return "natural";
    case CHOLMOD_GIVEN: return "given";
    case CHOLMOD_AMD: return "amd";
    case CHOLMOD_METIS: return "metis";
    case CHOLMOD_NESDIS: return "nesdis";
    case CHOLMOD_COLAMD: return "colamd";
    default: return "?";
  }
}

cholmod_factor *cholmod_l_analyze(cholmod_sparse *A, cholmod_common *c) {
  static cholmod_factor *(*f)(cholmod_sparse *, cholmod_common *);
  if (!f) f = real("cholmod_l_analyze");
  const char *o = getenv("CHOLMOD_SHIM_ORDERING");
  if (o && strcmp(o, "default") != 0) {
    int m = !strcmp(o, "amd") ? CHOLMOD_AMD
            : !strcmp(o, "metis") ? CHOLMOD_METIS
            : !strcmp(o, "nesdis") ? CHOLMOD_NESDIS
            : -1;
    if (m < 0) {
      fprintf(stderr, "cholmod_shim: unknown CHOLMOD_SHIM_ORDERING=%s\n", o);
      abort();
    }
    c->nmethods = 1;
    c->method[0].ordering = m;
  }
  const double t = now();
  cholmod_factor *L = f(A, c);
  const double dt = now() - t;
  fprintf(out(), "analyze seconds=%.6f n=%ld nnz(A)=%ld ordering=%s lnz=%.0f flops=%.0f", dt,
          (long)A->nrow, (long)cholmod_l_nnz(A, c),
          c->selected >= 0 ? ordering_name(c->method[c->selected].ordering) : "?", c->lnz, c->fl);
  if (L && L->is_super)  /* storage of the supernodal factor: values incl. relaxed-supernode zeros */
    fprintf(out(), " supernodes=%ld xsize=%ld ssize=%ld maxcsize=%ld", (long)L->nsuper,
            (long)L->xsize, (long)L->ssize, (long)L->maxcsize);
  fprintf(out(), "\n");
  fflush(out());
  return L;
}

int cholmod_l_factorize(cholmod_sparse *A, cholmod_factor *L, cholmod_common *c) {
  static int (*f)(cholmod_sparse *, cholmod_factor *, cholmod_common *);
  if (!f) f = real("cholmod_l_factorize");
  const double t = now();
  const int r = f(A, L, c);
  fprintf(out(), "factorize seconds=%.6f\n", now() - t);
  fflush(out());
  return r;
}

cholmod_dense *cholmod_l_solve(int sys, cholmod_factor *L, cholmod_dense *B, cholmod_common *c) {
  static cholmod_dense *(*f)(int, cholmod_factor *, cholmod_dense *, cholmod_common *);
  if (!f) f = real("cholmod_l_solve");
  const double t = now();
  cholmod_dense *x = f(sys, L, B, c);
  fprintf(out(), "solve seconds=%.6f\n", now() - t);
  fflush(out());
  return x;
}

double cholmod_l_rcond(cholmod_factor *L, cholmod_common *c) {
  static double (*f)(cholmod_factor *, cholmod_common *);
  if (!f) f = real("cholmod_l_rcond");
  const double t = now();
  const double r = f(L, c);
  fprintf(out(), "rcond seconds=%.6f\n", now() - t);
  fflush(out());
  return r;
}
