/* uwbsim: write a simulated uwbscan/1 file of a configurable winding scene. */
#include <stdio.h>

#include "cli.h"

int main(int argc, char **argv)
{
    return uwbsim_cli(argc, argv, stdout, stderr);
}
