/* uwbd: the winding-displacement appliance. This entry point only picks
 * the mode; each lives in src/cli/ and the work in the library. */
#include "uwb/cli.h"

#include <string.h>

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "ctl") == 0)
        return uwbd_ctl_main(argc - 1, argv + 1);
    if (uwbd_wants_daemon(argc, argv))
        return uwbd_daemon_main(argc, argv);
    return uwbd_replay_main(argc, argv);
}
