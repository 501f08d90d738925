/* Reading the numbers of a command's arguments strictly. LIGGGHTS' force->numeric passes "1e400" (atof's inf) and
 * atof reads "2500x" as 2500; a wall at infinity, an infinite modulus or a truncated number runs on silently
 * with wrong results. These take all of the text, finite, or stop with an ERROR: naming the command and keyword. */
#ifndef POLYHEDRAL_INPUT_H
#define POLYHEDRAL_INPUT_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "error.h"

// Whether all of `text` is one finite number, into *value.
inline bool polyhedral_parse_finite(const char *text, double *value)
{
  char *end = NULL;
  *value = strtod(text, &end);
  return end != text && *end == '\0' && isfinite(*value);
}

// All of `text` as a finite number, or an error "<command>: <keyword> needs a finite number, got '<text>'".
inline double polyhedral_finite_number(LAMMPS_NS::Error *error, const char *command, const char *keyword,
                                       const char *text)
{
  double value;
  if (!polyhedral_parse_finite(text, &value)) {
    char message[512];
    snprintf(message, sizeof message, "%s: %s needs a finite number, got '%s'", command, keyword, text);
    error->all(__FILE__, __LINE__, message);
  }
  return value;
}

#endif
