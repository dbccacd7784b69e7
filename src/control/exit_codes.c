/* From the rig's error classes to exit statuses (see exit_codes.h). */
#include "control/exit_codes.h"

#include "uwb/rig.h"

int uwbd_exit_for_rig_open(int rig_error, int detail)
{
    switch (rig_error) {
    case UWB_RIG_ERR_GPIO:
        switch (detail) {
        case UWB_GPIO_ERR_CHIP:
        case UWB_GPIO_ERR_IO: return UWBD_EXIT_GPIO_CHIP;
        case UWB_GPIO_ERR_LINE:
        case UWB_GPIO_ERR_BUSY: return UWBD_EXIT_GPIO_LINE;
        case UWB_GPIO_ERR_CONFIG: return UWBD_EXIT_CONFIG;
        default: return UWBD_EXIT_GPIO_CHIP;
        }
    case UWB_RIG_ERR_LINK: return detail == UWB_LINK_ERR_ENDPOINT ? UWBD_EXIT_CONFIG : UWBD_EXIT_DIGITISER;
    case UWB_RIG_ERR_CONFIG: return UWBD_EXIT_CONFIG;
    default: return UWBD_EXIT_SOFTWARE;
    }
}
