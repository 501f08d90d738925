/* What the CPU benchmarks (tools/bench_overlap.c, tools/bench_cylinder.c, tools/bench_pile_pairs.c) and
 * tests/unit/clip_sides_bits.c share: a fixed, portable random sequence, random rotations, a clock, the median
 * time of a repeated workload, and loading a shape file. Include after _POSIX_C_SOURCE is defined (for
 * clock_gettime). */
#ifndef BENCH_COMMON_H
#define BENCH_COMMON_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "poly_shape.h"

static const double PI = 3.14159265358979323846;

/* splitmix64: a fixed, portable sequence. */
static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static inline double uniform(void)
{
  uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* Uniform random rotation (Shoemake). */
static inline void random_quaternion(double q[4])
{
  double u1 = uniform(), u2 = 2.0 * PI * uniform(), u3 = 2.0 * PI * uniform();
  double a = sqrt(1.0 - u1), b = sqrt(u1);
  q[0] = a * sin(u2); q[1] = a * cos(u2); q[2] = b * sin(u3); q[3] = b * cos(u3);
}

static inline double now(void)
{
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static inline int compare_doubles(const void *a, const void *b)
{
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Median over `repeats` of the time per item (microseconds) of run(context), a workload of `items` items,
 * run as many times in a row as makes a repeat last at least 20 ms (counted on a first, warm-up run);
 * *fastest (when not NULL) gets the fastest repeat's. */
static inline double median_time_us(void (*run)(void *context), void *context, int items, int repeats, double *fastest)
{
  double *samples = (double *)malloc(sizeof(double) * (size_t)repeats);
  int rounds = 1;
  for (int r = -1; r < repeats; r++) { /* r = -1: warm-up and calibration */
    double start = now();
    for (int round = 0; round < rounds; round++) run(context);
    double elapsed = now() - start;
    if (r < 0) {
      while (elapsed * rounds < 0.02) rounds *= 2;
      continue;
    }
    samples[r] = 1e6 * elapsed / ((double)rounds * items);
  }
  qsort(samples, (size_t)repeats, sizeof(double), compare_doubles);
  double median = repeats % 2 ? samples[repeats / 2] : 0.5 * (samples[repeats / 2 - 1] + samples[repeats / 2]);
  if (fastest) *fastest = samples[0];
  free(samples);
  return median;
}

/* The arguments SHAPES_DIR [poses] [repeats] (defaults 64 and 5, repeats at least least_repeats); 0 when they
 * are usable. */
static inline int read_arguments(int argc, char **argv, int *poses, int *repeats, int least_repeats)
{
  if (argc < 2) {
    fprintf(stderr, "usage: %s SHAPES_DIR [poses] [repeats]\n", argv[0]);
    return 2;
  }
  *poses = argc > 2 ? atoi(argv[2]) : 64;
  *repeats = argc > 3 ? atoi(argv[3]) : 5;
  return *poses < 1 || *repeats < least_repeats ? 2 : 0;
}

/* Loads the shape file `file` (in `dir` unless an absolute path) at `scale` into *shape: 0, or 1 with the loader's
 * message on stderr. */
static inline int load_shape(const char *dir, const char *file, double scale, poly_shape *shape)
{
  char path[4096], message[512];
  if (file[0] == '/') snprintf(path, sizeof path, "%s", file);
  else snprintf(path, sizeof path, "%s/%s", dir, file);
  if (poly_shape_load(path, scale, shape, message, sizeof message) == POLY_OK) return 0;
  fprintf(stderr, "%s\n", message);
  return 1;
}

#endif
