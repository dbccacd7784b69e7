/* The uwbsim command line, as a function so tests can drive it in-process. */
#ifndef UWBSIM_CLI_H
#define UWBSIM_CLI_H

#include <stdio.h>

/* Returns the process exit status: 0 done, 1 failure, 2 usage error. */
int uwbsim_cli(int argc, char **argv, FILE *out, FILE *errout);

#endif
