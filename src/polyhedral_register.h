/* Registration of the polyhedral styles with a prebuilt LIGGGHTS (see the .cpp). */
#ifndef POLYHEDRAL_REGISTER_H
#define POLYHEDRAL_REGISTER_H

#include <stdio.h>

/* 1 if the style hooks are active in this process, else prints an ERROR line
 * per missing hook to stderr and returns 0. */
extern "C" int polyhedral_verify_hooks(void);

/* Prints the styles this package adds to LIGGGHTS, as LIGGGHTS' -help lists
 * its own (liggghts-poly -h prints it after them). */
void polyhedral_print_styles(FILE *out);

#endif
