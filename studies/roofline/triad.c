/* STREAM-like triad a = b + s c on one core, best of 10 passes, for arrays
   of the given total size: the bandwidth the sweeps could reach from the
   cache level (or memory) their working set lives in.
   cc -O3 -o triad triad.c && ./triad 3 256     # MB of the three arrays */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

int main(int argc, char **argv)
{
  for (int k = 1; k < argc; k++) {
    const double mb = atof(argv[k]);
    const size_t n = (size_t) (mb * 1e6 / (3 * sizeof(double)));
    double *a = malloc(n * sizeof(double)), *b = malloc(n * sizeof(double)),
           *c = malloc(n * sizeof(double));
    for (size_t i = 0; i < n; i++) a[i] = 0.0, b[i] = 1.0, c[i] = 2.0;
    // repeat small arrays so that each timing lasts long enough
    const int reps = (int) (1 + 2e8 / (3.0 * n * sizeof(double)));
    double best = 1e30;
    for (int pass = 0; pass < 10; pass++) {
      const double t0 = now();
      for (int r = 0; r < reps; r++) {
        for (size_t i = 0; i < n; i++) a[i] = b[i] + 3.0 * c[i];
        __asm__ volatile("" : : "r"(a) : "memory");
      }
      const double t = (now() - t0) / reps;
      if (t < best) best = t;
    }
    printf("triad %8.2f MB: %6.2f GB/s (best of 10; check %g)\n", mb,
           3.0 * n * sizeof(double) / best / 1e9, a[n / 2]);
    free(a), free(b), free(c);
  }
  return 0;
}
