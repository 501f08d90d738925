/* Internal to the shape core: formats a one-line error message and returns the status. */
#ifndef POLY_MESSAGE_H
#define POLY_MESSAGE_H

#include <stddef.h>

#include "poly_shape.h"

#if defined(__GNUC__)
#define POLY_PRINTF_FORMAT(f, a) __attribute__((format(printf, f, a)))
#else
#define POLY_PRINTF_FORMAT(f, a)
#endif

poly_status poly_fail(char *message, size_t message_size, poly_status status, const char *format, ...)
    POLY_PRINTF_FORMAT(4, 5);

#endif
