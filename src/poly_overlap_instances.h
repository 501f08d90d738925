/* The three instances of the overlap computation (poly_overlap_impl.h):
 * double (_d), single (_f) and mixed (_m: single geometry, double sums).
 * Included once by the CPU build (poly_overlap.c) and once by the CUDA build
 * (gpu/poly_gpu.cu), so both compile the same functions. */
#ifndef POLY_OVERLAP_INSTANCES_H
#define POLY_OVERLAP_INSTANCES_H

#include "poly_overlap.h"

#define POLY_REAL double
#define POLY_FN(name) poly_##name##_d
#include "poly_overlap_impl.h"
#undef POLY_REAL
#undef POLY_FN

#define POLY_REAL float
#define POLY_FN(name) poly_##name##_f
#include "poly_overlap_impl.h"
#undef POLY_REAL
#undef POLY_FN

#define POLY_REAL float
#define POLY_ACCUM double
#define POLY_FN(name) poly_##name##_m
#include "poly_overlap_impl.h"
#undef POLY_REAL
#undef POLY_ACCUM
#undef POLY_FN

#endif
