/* POLY_INLINE: how the header-only core's functions are declared, for gcc (CPU) and nvcc (host and device) alike. */
#ifndef POLY_INLINE_H
#define POLY_INLINE_H

#ifndef POLY_INLINE
#ifdef __CUDACC__
#define POLY_INLINE static inline __host__ __device__
#else
#define POLY_INLINE static inline
#endif
#endif

/* POLY_HOT_INLINE: a small function of the CPU's hot loops inlined by order where GCC would keep it a call;
 * POLY_CPU_OUT_OF_LINE: a rare case of one kept out of line, so that what is inlined stays small (the GPU build
 * takes both as POLY_INLINE). */
#if defined(__GNUC__) && !defined(__CUDACC__)
#define POLY_HOT_INLINE static inline __attribute__((always_inline))
#define POLY_CPU_OUT_OF_LINE static __attribute__((noinline, cold, unused))
#else
#define POLY_HOT_INLINE POLY_INLINE
#define POLY_CPU_OUT_OF_LINE POLY_INLINE
#endif

#endif
