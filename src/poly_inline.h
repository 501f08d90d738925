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

#endif
