/* Registration of the polyhedral styles with a prebuilt LIGGGHTS (see the .cpp). */
#ifndef POLYHEDRAL_REGISTER_H
#define POLYHEDRAL_REGISTER_H

/* 1 if the style hooks are active in this process, else prints an ERROR line
 * per missing hook to stderr and returns 0. */
extern "C" int polyhedral_verify_hooks(void);

#endif
