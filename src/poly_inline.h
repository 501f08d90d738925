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

/* POLY_HOT_INLINE: a small function of the CPU's hot loops inlined by order where GCC would keep it a call (the GPU
 * build takes it as POLY_INLINE). */
#if defined(__GNUC__) && !defined(__CUDACC__)
#define POLY_HOT_INLINE static inline __attribute__((always_inline))
#else
#define POLY_HOT_INLINE POLY_INLINE
#endif

#endif
